#!/usr/bin/python3
"""Histograms and worst cases of a sweep (dtc-sil sweep ... --out DIR).

    /usr/bin/python3 tools/plot/plot_sweep.py DIR [--metric imbalance_pct --metric thd_total_pct ...]
                                             [--worst 10] [--higher-is-worse/--lower-is-worse]

Writes DIR/hist_<metric>.png for every metric asked for (default: imbalance_pct, thd_total_pct,
trf_pct, speed_mean_rpm, torque_est_mean_nm), and DIR/worst.md: per metric, the runs with the worst
values with their swept values, and every run that did not end "ok" with its status and reason.
Runs without a value (refused, tripped before the window, ...) are counted, never dropped silently.
"""
import argparse
import csv
import math
import os
import sys

DEFAULT_METRICS = ["imbalance_pct", "thd_total_pct", "trf_pct", "speed_mean_rpm", "torque_est_mean_nm"]
STATUS_COLS = {"run", "status", "fault", "error"}


def read_summary(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    header = list(rows[0].keys())
    axes = header[1:header.index("status")]
    return rows, axes


def value(row, metric):
    try:
        x = float(row.get(metric, ""))
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--metric", action="append", help="metric column (repeatable)")
    ap.add_argument("--worst", type=int, default=10)
    ap.add_argument("--lower-is-worse", action="append", default=[], metavar="METRIC",
                    help="for this metric the smallest values are the worst (default: the largest)")
    a = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows, axes = read_summary(os.path.join(a.dir, "summary.csv"))
    metrics = a.metric or [m for m in DEFAULT_METRICS if m in rows[0]]
    unknown = [m for m in metrics if m not in rows[0]]
    if unknown:
        raise SystemExit(f"plot_sweep: no column {', '.join(unknown)} in {a.dir}/summary.csv")
    not_ok = [r for r in rows if r["status"] != "ok"]
    lines = [f"# Sweep {a.dir}: {len(rows)} runs, {len(rows) - len(not_ok)} ok", ""]
    for m in metrics:
        vals = [(value(r, m), r) for r in rows]
        have = [(x, r) for x, r in vals if x is not None]
        fig, ax = plt.subplots(figsize=(6, 4))
        if have:
            ax.hist([x for x, _ in have], bins=min(50, max(5, int(math.sqrt(len(have))))))
        ax.set_xlabel(m)
        ax.set_ylabel("runs")
        ax.set_title(f"{m}: {len(have)} of {len(rows)} runs have a value")
        fig.tight_layout()
        fig.savefig(os.path.join(a.dir, f"hist_{m.replace('[', '_').replace(']', '')}.png"), dpi=100)
        plt.close(fig)
        lower = m in a.lower_is_worse
        worst = sorted(have, key=lambda t: t[0], reverse=not lower)[:a.worst]
        lines += [f"## {m}: worst {len(worst)} ({'lowest' if lower else 'highest'})", "",
                  "| run | " + " | ".join(axes) + f" | {m} | status |",
                  "|---|" + "---|" * len(axes) + "---|---|"]
        for x, r in worst:
            lines.append(f"| {r['run']} | " + " | ".join(r[k] for k in axes) + f" | {x:.6g} | {r['status']} |")
        lines.append("")
    lines += [f"## Runs that did not end ok: {len(not_ok)}", ""]
    if not_ok:
        lines += ["| run | " + " | ".join(axes) + " | status | fault | error |",
                  "|---|" + "---|" * len(axes) + "---|---|---|"]
        for r in not_ok:
            lines.append(f"| {r['run']} | " + " | ".join(r[k] for k in axes) +
                         f" | {r['status']} | {r['fault']} | {r['error']} |")
    with open(os.path.join(a.dir, "worst.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    print(f"plot_sweep: {len(metrics)} histograms and worst.md in {a.dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
