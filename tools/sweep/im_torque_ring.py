#!/usr/bin/python3
"""The IM drive's mean torque per stator period over a run, for the settling of the rotor-flux trim.

Runs dtc-sil in the torque accuracy sweep's settings (tools/sweep/im_torque_accuracy.py: torque mode,
the rotor held by the dynamometer, per-leg drop compensation, from standstill) for each machine, law
and speed given, at one torque, and prints the plant's mean torque per stator period (the periods cut
where the plant's rotor-flux angle passes a whole turn) in % of T*, from 0.5 s to the end, and the
largest |error| of the periods after 1 s.

Usage: im_torque_ring.py [--exe build/host/bin/dtc-sil] [--out DIR] [--laws sfvc,dfoc]
                         [--machines 4kW,second] [--cm true|false] [--speeds 0.05,0.10] [--torque 0.10] [--duration 4]
"""
import argparse
import csv
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from im_torque_accuracy import MACHINES  # noqa: E402


def periods(trace):
    t, te, ang = [], [], []
    with open(trace) as f:
        for r in csv.DictReader(f):
            t.append(float(r["t_s"]))
            te.append(float(r["torque_nm"]))
            ang.append(math.atan2(float(r["psi_r_beta_wb"]), float(r["psi_r_alpha_wb"])))
    out, acc, n, start, turn, prev = [], 0.0, 0, t[0], 0.0, ang[0]
    for k in range(1, len(t)):
        d = ang[k] - prev
        d -= 2 * math.pi * round(d / (2 * math.pi))
        prev = ang[k]
        turn += d
        acc += te[k]
        n += 1
        if abs(turn) >= 2 * math.pi:
            out.append((start, t[k], acc / n))
            acc, n, start, turn = 0.0, 0, t[k], 0.0
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default="build/host/bin/dtc-sil")
    ap.add_argument("--out", default="out/im_torque_ring")
    ap.add_argument("--laws", default="sfvc,dfoc")
    ap.add_argument("--machines", default=",".join(MACHINES))
    ap.add_argument("--speeds", default="0.05,0.10")
    ap.add_argument("--torque", type=float, default=0.10)
    ap.add_argument("--duration", type=float, default=4.0)
    ap.add_argument("--cm", default="true", help="control.current_model_ref (true, false)")
    ap.add_argument("--set", action="append", default=[], help="extra dtc-sil --set key=value")
    a = ap.parse_args()
    for name in a.machines.split(","):
        scen, t_rated, n_rated = MACHINES[name]
        src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenarios", scen)
        for law in a.laws.split(","):
            for sf in (float(s) for s in a.speeds.split(",")):
                d = os.path.join(a.out, "%s_%s_%g" % (name, law, sf))
                tref = a.torque * t_rated
                cmd = [a.exe, "run", src, "--out", d, "-q", "--decimate", "4",
                       "--set", "control.mode=torque", "--set", "load.type=speed", "--set", "load.step_time_s=0",
                       "--set", "duration_s=%g" % a.duration, "--set", "metrics_window_s=0.84",
                       "--set", "control.compensation=proposed", "--set", "control.scheme=" + law,
                       "--set", "control.current_model_ref=" + a.cm,
                       "--set", "load.speed_rpm=%g" % (sf * n_rated), "--set", "control.torque_ref_nm=%g" % tref]
                for s in a.set:
                    cmd += ["--set", s]
                subprocess.run(cmd, check=True)
                ps = [p for p in periods(os.path.join(d, "trace.csv")) if p[0] >= 0.5]
                errs = ["%+.1f" % (100.0 * (p[2] / tref - 1.0)) for p in ps]
                late = [abs(100.0 * (p[2] / tref - 1.0)) for p in ps if p[0] >= 1.0]
                print("%s %s %g %% speed, %g %% torque: per stator period from 0.5 s (%% of T*): %s; "
                      "largest after 1 s %.2f %%" % (name, law, 100 * sf, 100 * a.torque, " ".join(errs),
                                                    max(late) if late else float("nan")))
    return 0


if __name__ == "__main__":
    sys.exit(main())
