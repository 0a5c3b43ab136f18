#!/usr/bin/python3
"""Sweep benchmark (prints figures; not a test). Run on a quiet machine:

    /usr/bin/python3 tools/sweep/bench_sweep.py build/host/bin/dtc-sil [--mc 10000] [--dask-runs 1000]

Prints, for the default scenario (tools/scenarios/fstp_voltage_proposed_full.toml, trace off):
  * serial throughput (--jobs 1) and --jobs N throughput on the cores present, and their ratio;
  * per-run overhead: wall time per run of a sweep whose runs simulate one control period
    (hand-off to a worker process, scenario parse, metrics, row output);
  * the wall time of a Monte Carlo sweep of --mc runs of the whole scenario;
  * a local Dask cluster of two single-thread workers against `--jobs 2` on --dask-runs runs.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from local_cluster import LocalCluster  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENARIO = os.path.join(ROOT, "tools", "scenarios", "fstp_voltage_proposed_full.toml")


def timed_sweep(exe, out, args):
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.monotonic()
    r = subprocess.run([exe, "sweep", SCENARIO, "--out", out, "-q"] + args, capture_output=True, text=True)
    dt = time.monotonic() - t0
    if r.returncode != 0:
        raise SystemExit(f"sweep failed ({r.returncode}): {r.stderr}")
    return dt


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--runs", type=int, default=200, help="runs for the throughput figures")
    ap.add_argument("--mc", type=int, default=10000, help="runs of the Monte Carlo figure (0: skip)")
    ap.add_argument("--dask-runs", type=int, default=1000, help="runs of the Dask figure (0: skip)")
    a = ap.parse_args()
    exe = os.path.abspath(a.exe)
    cores = os.cpu_count() or 1
    tmp = tempfile.mkdtemp(prefix="bench_sweep_")
    mc = ["--sample", "sensors.current_noise_a_rms=uniform:0:0.02", "--sample", "sensors.vdc_offset_v=normal:0:0.5"]
    try:
        s1 = timed_sweep(exe, os.path.join(tmp, "j1"), mc + ["--n", str(a.runs), "--jobs", "1"])
        sn = timed_sweep(exe, os.path.join(tmp, "jn"), mc + ["--n", str(a.runs), "--jobs", str(cores)])
        print(f"throughput, {a.runs} runs of the 1.5 s scenario: --jobs 1 {a.runs / s1:.1f} runs/s, "
              f"--jobs {cores} {a.runs / sn:.1f} runs/s, ratio {s1 / sn:.2f} (target >= 1.8 on 2 cores)")
        tiny = ["--set", "duration_s=5e-5", "--set", "metrics_window_s=5e-5"]
        n_tiny = 2000
        st = timed_sweep(exe, os.path.join(tmp, "tiny"), mc + tiny + ["--n", str(n_tiny), "--jobs", "1"])
        print(f"per-run overhead (hand-off, parse, metrics, row; one simulated period): {1000 * st / n_tiny:.2f} ms "
              f"(target <= 5 ms)")
        if a.mc > 0:
            smc = timed_sweep(exe, os.path.join(tmp, "mc"), mc + ["--n", str(a.mc)])
            print(f"Monte Carlo, {a.mc} runs of the 1.5 s scenario on {cores} cores: {smc:.1f} s "
                  f"(target <= 60 s for 10000 runs)")
        if a.dask_runs > 0:
            sl = timed_sweep(exe, os.path.join(tmp, "l2"), mc + ["--n", str(a.dask_runs), "--jobs", "2"])
            with LocalCluster(os.path.join(tmp, "cluster"), n_workers=2) as cl:
                sd = timed_sweep(exe, os.path.join(tmp, "dask"), mc + ["--n", str(a.dask_runs), "--dask", cl.address])
            same = open(os.path.join(tmp, "l2", "summary.csv")).read() == \
                open(os.path.join(tmp, "dask", "summary.csv")).read()
            print(f"Dask, 2 single-thread workers, {a.dask_runs} runs: {a.dask_runs / sd:.1f} runs/s vs --jobs 2 "
                  f"{a.dask_runs / sl:.1f} runs/s: {100 * sl / sd:.0f} % (target >= 80 %); "
                  f"summaries identical: {same}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
