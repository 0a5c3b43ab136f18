#!/usr/bin/python3
"""Run Hoang 2011's Table IX/X matrix with dtc-sil and write a side-by-side markdown report.

    /usr/bin/python3 tools/plot/report.py [--exe build/host/bin/dtc-sil] [--out out/report]
                                          [--jobs 2] [--set key=value ...]

For each of the seven operating points of Tables IX and X (1500 rpm, full load 0.3 N*m) it runs
tools/scenarios/<name>.toml into OUT/<name>/, draws that run's figures (plot_run.py), and writes
OUT/report.md: paper vs simulation for the per-phase fundamental currents and their imbalance
(Table IX), the DC component of the predicted (estimated) torque, the total current THD (eq. 39)
and the TRF (eq. 40) (Table X). Exit status 1 if any run failed (its row says why).
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import plot_run  # noqa: E402

# Hoang, Zhu, Foster 2011, Table IX (fundamental phase currents, A peak) and Table X (DC component
# of the predicted torque N*m, current THD %, TRF %), 1500 rpm, full torque 0.3 N*m.
PAPER = [
    # scenario stem,             label,                                  IX (A, B, C),        X (torque, THD, TRF)
    ("sstp_current_full", "Current model, SSTP", (2.22, 2.20, 2.29), (0.3034, 7.84, 86.27)),
    ("fstp_current_full", "Current model, FSTP", (2.05, 2.06, 2.12), (0.2973, 7.40, 60.39)),
    ("sstp_voltage_none_full", "Voltage model, no compensation, SSTP", (2.74, 2.73, 2.89), (0.3296, 7.70, 92.02)),
    ("fstp_voltage_none_full", "Voltage model, no compensation, FSTP", (2.97, 2.37, 3.00), (0.3345, 7.20, 92.02)),
    ("sstp_voltage_simple_full", "Voltage model, compensation, SSTP [29]", (2.13, 2.13, 2.25), (0.2984, 8.99, 89.15)),
    ("fstp_voltage_simple_full", "Voltage model, simple compensation, FSTP", (2.53, 2.37, 2.41), (0.3046, 8.83, 89.15)),
    ("fstp_voltage_proposed_full", "Voltage model, proposed compensation, FSTP", (2.26, 2.16, 2.16),
     (0.2989, 7.16, 86.27)),
]


def imbalance(a):
    return 100.0 * (max(a) / min(a) - 1.0)


def run_one(exe, scen_dir, out_root, stem, sets):
    scen = os.path.join(scen_dir, stem + ".toml")
    out = os.path.join(out_root, stem)
    cmd = [exe, "run", scen, "--out", out, "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if r.returncode != 0:
        msg = (r.stderr.strip().splitlines() or ["exit status %d" % r.returncode])[-1]
        return stem, None, msg, " ".join(cmd)
    with open(os.path.join(out, "metrics.json"), encoding="utf-8") as f:
        m = json.load(f)
    return stem, m, None, " ".join(cmd)


def fmt3(a):
    return " / ".join(f"{x:.2f}" for x in a) if a else "n/a"


def num(x, f="{:.4f}"):
    return f.format(x) if isinstance(x, (int, float)) else "n/a"


def write_report(path, results, exe, sets):
    lines = ["# Hoang 2011 Tables IX and X: paper vs simulation", ""]
    lines += [f"Generated {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M UTC} by "
              f"`tools/plot/report.py` with `{os.path.relpath(exe, ROOT) if os.path.isabs(exe) else exe}`"
              + (f", overrides `{' '.join(sets)}`" if sets else "") + ".", ""]
    lines += ["Paper: measured on the prototype (TMS320F2812, IRAMY20UP60B, Table VIII machine), 1500 rpm, "
              "full load 0.3 N·m. Simulation: the same firmware against the plant model, scenarios in "
              "`tools/scenarios/`, metrics over the last `metrics_window_s` trimmed to whole electrical "
              "periods (docs/sil.md).", ""]
    lines += ["## Table IX: fundamental phase currents (A, peak) and imbalance", "",
              "| scheme | paper A / B / C | sim A / B / C | paper imbalance % | sim imbalance % |",
              "|---|---|---|---|---|"]
    for stem, label, ix, _ in PAPER:
        m, err = results[stem]
        if m is None:
            lines.append(f"| {label} (`{stem}`) | {fmt3(ix)} | run failed: {err} | {imbalance(ix):.1f} | n/a |")
            continue
        f = m.get("fundamental_a")
        lines.append(f"| {label} (`{stem}`) | {fmt3(ix)} | {fmt3(f)} | {imbalance(ix):.1f} | "
                     f"{num(m.get('imbalance_pct'), '{:.1f}')} |")
    lines += ["", "## Table X: predicted torque, current THD (eq. 39), TRF (eq. 40)", "",
              "| scheme | paper predicted torque N·m | sim estimated torque N·m | sim true torque N·m "
              "| paper THD % | sim THD % | paper TRF % | sim TRF % (true) | sim TRF % (estimate) |",
              "|---|---|---|---|---|---|---|---|---|"]
    for stem, label, _, x in PAPER:
        m, err = results[stem]
        if m is None:
            lines.append(f"| {label} | {x[0]:.4f} | run failed | | {x[1]:.2f} | | {x[2]:.2f} | | |")
            continue
        lines.append(f"| {label} | {x[0]:.4f} | {num(m.get('torque_est_mean_nm'))} | {num(m.get('torque_mean_nm'))} "
                     f"| {x[1]:.2f} | {num(m.get('thd_total_pct'), '{:.2f}')} | {x[2]:.2f} "
                     f"| {num(m.get('trf_pct'), '{:.2f}')} | {num(m.get('trf_est_pct'), '{:.2f}')} |")
    lines += ["", "## Runs", "", "| scenario | fault | speed rpm | switching Hz | flux est. error % | figures |",
              "|---|---|---|---|---|---|"]
    for stem, _, _, _ in PAPER:
        m, err = results[stem]
        if m is None:
            lines.append(f"| `{stem}` | run failed: {err} | | | | |")
            continue
        figs = " ".join(f"[{p[:-4]}]({stem}/{p})" for p in
                        ("currents.png", "torque.png", "flux_locus.png", "flux_components.png"))
        lines.append(f"| `{stem}` | {m.get('fault')} | {num(m.get('speed_mean_rpm'), '{:.1f}')} "
                     f"| {num(m.get('switching_freq_hz'), '{:.0f}')} | {num(m.get('flux_est_error_rms_pct'), '{:.2f}')} "
                     f"| {figs} |")
    lines += ["", "Definitions: fundamental = peak of the DFT line at the electrical frequency; imbalance = "
              "100 (max/min - 1); THD = eq. 39 total over all non-fundamental lines; TRF = eq. 40, peak-to-peak "
              "over the window / 0.3 N·m, sampled once per 50 µs period (the paper's torque transducer "
              "bandwidth is not stated, so the simulated TRF of the instantaneous torque is an upper bound).", ""]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "host", "bin", "dtc-sil"))
    ap.add_argument("--scenarios", default=os.path.join(ROOT, "tools", "scenarios"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "report"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--set", action="append", default=[], help="override passed to every run")
    a = ap.parse_args(argv)
    if not os.path.exists(a.exe):
        print(f"report: {a.exe} not found (build it: cmake --build build/host --target dtc-sil)", file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        futs = [pool.submit(run_one, a.exe, a.scenarios, a.out, stem, a.set) for stem, *_ in PAPER]
        for fut in concurrent.futures.as_completed(futs):
            stem, m, err, cmd = fut.result()
            results[stem] = (m, err)
            print(f"{'FAILED' if err else 'ok    '} {stem}" + (f": {err}" if err else ""))
    # Figures in this thread only: matplotlib's text layout is not thread-safe.
    for stem, *_ in PAPER:
        m, err = results[stem]
        if m is not None:
            try:
                plot_run.plot_run(os.path.join(a.out, stem))
            except (OSError, ValueError) as e:
                results[stem] = (m, f"plots failed: {e}")
    path = os.path.join(a.out, "report.md")
    write_report(path, results, a.exe, a.set)
    print(path)
    return 1 if any(err for _, err in results.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
