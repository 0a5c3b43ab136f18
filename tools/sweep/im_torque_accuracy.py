#!/usr/bin/python3
"""The IM drive's torque accuracy over the operating grid (issue target: the plant's mean torque
within 1.5 % of the reference for every IM law, 10 to 100 % rated torque, 5 to 100 % rated speed).

Torque mode, the rotor held at each speed by the dynamometer (load.type = "speed"), from standstill:
the drive magnetises, then holds T*. The plant's mean torque over the last 0.84 s of 2 s (two
electrical periods at 5 % of rated speed, four at 10 %) against T*, and the firmware's own estimate
beside it; at 5 % of rated speed over the last 8.33 s of 9.2 s (20 electrical periods): there the
plant's torque swings slowly (DSVM, 4 kW, 10 % torque: its 0.14 s means range 2.2 .. 3.2 N*m for
2.65) and a 0.84 s mean scatters by about +-1.5 % of T* with the held speed moved by 0.02 rpm, as
wide as the target (docs/sil.md, the IM torque accuracy).
Each machine runs with the per-leg device-drop compensation (control.compensation = "proposed",
Hoang Table III per leg on the six-switch inverter: the drops of the rig's devices, V_CE when the
leg's switch conducts, V_d when the other switch's diode does) and Casadei eq. 20's reference from the
rotor-flux current model at low speed (control.current_model_ref, the default with the encoder,
firmware/dtc/im_sup.h: without it, --cm false, the rotor-flux trim rings through the estimator's slow
pole at 5 % speed). The shipped IM scenarios keep
Hoang ref. [29]'s one drop ("simple"), which cannot meet the target below 25 % of rated speed at
light load (docs/sil.md: its assumed V_f = V_CE leaves V_d - V_CE per leg uncompensated while a
diode conducts); --compensation simple shows it.

Usage: im_torque_accuracy.py [--exe build/host/bin/dtc-sil] [--out DIR] [--compensation C]
                             [--laws dtc,dsc,...] [--jobs N] [--cm true|false]
Writes DIR/<machine>/w<k>/summary.csv (dtc-sil sweep, one per window of WINDOWS) and prints one table per machine: per law and
speed, the plant's error and the estimate's error in % of T*. Exit status 1 when a point outside
KNOWN_MISSES misses the target, or a run faults; the known misses are printed with their values
(and a known miss that meets the target is reported, so the list cannot go stale unseen).
"""
import argparse
import csv
import os
import subprocess
import sys

TARGET_PCT = 1.5
LAWS = ["dtc", "dsc", "sfvc", "dfoc", "dsvm"]
SPEED_FRACS = [0.05, 0.10, 0.25, 0.50, 1.00]
# (speed fractions, run duration s, metrics window s): the window at least two electrical periods,
# twenty at the lowest speed (see above)
WINDOWS = [([0.05], 9.2, 8.33), ([0.10, 0.25, 0.50, 1.00], 2.0, 0.84)]
TORQUE_FRACS = [0.10, 0.50, 1.00]
# (scenario, rated torque N*m, rated speed rpm)
MACHINES = {
    "4kW": ("im_dtc_speed.toml", 26.5, 1440.0),
    "second": ("im_second_machine.toml", 23.5, 1440.0),
}
# Points that miss the target, each with its measured cause (docs/sil.md, the IM torque accuracy).
# None: the second machine's DFOC at rated torque was one (the torque limit 22.3 N*m while the
# DFOC's excursion was a whole dI; now its SVM ripple, docs/sil.md).
KNOWN_MISSES = set()


def run_machine(exe, out, name, laws, comp, jobs, cm="true"):
    scen, t_rated, n_rated = MACHINES[name]
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenarios", scen)
    rows = []
    for k, (fracs, duration, window) in enumerate(WINDOWS):
        d = os.path.join(out, name, "w%d" % k)
        if os.path.isdir(d):
            subprocess.run(["rm", "-rf", d], check=True)
        cmd = [exe, "sweep", src, "--out", d, "-j", str(jobs), "-q", "--allow-failed-runs",
               "--set", "control.mode=torque", "--set", "load.type=speed", "--set", "load.step_time_s=0",
               "--set", "duration_s=%g" % duration, "--set", "metrics_window_s=%g" % window,
               "--set", "control.compensation=" + comp, "--set", "control.current_model_ref=" + cm,
               "--grid", "control.scheme=" + ",".join(laws),
               "--grid", "load.speed_rpm=" + ",".join("%g" % (f * n_rated) for f in fracs),
               "--grid", "control.torque_ref_nm=" + ",".join("%g" % (f * t_rated) for f in TORQUE_FRACS)]
        subprocess.run(cmd, check=True)
        rows += list(csv.DictReader(open(os.path.join(d, "summary.csv"))))
    res = {}
    for r in rows:
        sf = round(float(r["load.speed_rpm"]) / n_rated, 4)
        tf = round(float(r["control.torque_ref_nm"]) / t_rated, 4)
        t = float(r["control.torque_ref_nm"])
        if r["status"] != "ok" or r["fault"] != "none":
            res[(r["control.scheme"], sf, tf)] = (None, None, r["fault"] or r["status"])
        else:
            res[(r["control.scheme"], sf, tf)] = (100.0 * (float(r["torque_mean_nm"]) / t - 1.0),
                                                  100.0 * (float(r["torque_est_mean_nm"]) / t - 1.0), "")
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", default="build/host/bin/dtc-sil")
    ap.add_argument("--out", default="out/im_torque_accuracy")
    ap.add_argument("--compensation", default="proposed")
    ap.add_argument("--laws", default=",".join(LAWS))
    ap.add_argument("--machines", default=",".join(MACHINES))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cm", default="true", help="control.current_model_ref (true, the default; false: Casadei eq. 20's "
                    "reference at every speed)")
    a = ap.parse_args()
    laws = a.laws.split(",")
    bad, stale = [], []
    for name in a.machines.split(","):
        res = run_machine(a.exe, a.out, name, laws, a.compensation, a.jobs, a.cm)
        print("%s (%s), compensation %s, current_model_ref %s: plant / estimate error, %% of T*"
              % (name, MACHINES[name][0], a.compensation, a.cm))
        print("| law | speed | " + " | ".join("T* %g %%" % (100 * f) for f in TORQUE_FRACS) + " |")
        print("|---|---|" + "---|" * len(TORQUE_FRACS))
        for law in laws:
            for sf in SPEED_FRACS:
                cells = []
                for tf in TORQUE_FRACS:
                    e, est, fault = res[(law, round(sf, 4), round(tf, 4))]
                    known = (name, law, sf, tf) in KNOWN_MISSES
                    if e is None:
                        cells.append(fault + (" (known)" if known else " MISS"))
                        if not known:
                            bad.append((name, law, sf, tf, fault))
                        continue
                    miss = abs(e) > TARGET_PCT
                    cells.append("%+.2f / %+.2f%s" % (e, est, (" (known)" if known else " MISS") if miss else ""))
                    if miss and not known:
                        bad.append((name, law, sf, tf, "%+.2f %%" % e))
                    if known and not miss:
                        stale.append((name, law, sf, tf, "%+.2f %%" % e))
                print("| %s | %g %% | %s |" % (law, 100 * sf, " | ".join(cells)))
        print()
    for s in stale:
        print("known miss now within the target (update KNOWN_MISSES): %s %s %g %% speed %g %% torque: %s"
              % (s[0], s[1], 100 * s[2], 100 * s[3], s[4]))
    for b in bad:
        print("MISS: %s %s at %g %% speed, %g %% torque: %s" % (b[0], b[1], 100 * b[2], 100 * b[3], b[4]))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
