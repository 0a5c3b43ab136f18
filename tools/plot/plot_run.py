#!/usr/bin/python3
"""Turn a dtc-sil run folder (trace.csv + metrics.json) into figures like Hoang 2011's.

    /usr/bin/python3 tools/plot/plot_run.py RUN_DIR [--t0 S] [--t1 S] [--out DIR]

Writes into RUN_DIR (or --out):
  currents.png         three phase currents over the last electrical periods (Hoang Figs. 11-17)
  torque.png           estimated vs true electromagnetic torque, with the means (Hoang Table X)
  flux_locus.png       stator-flux locus in the alpha-beta plane, true and estimated (Hoang Fig. 3)
  flux_components.png  estimated (and true) alpha/beta flux components vs time (Hoang Figs. 5-8)
Default time span: the metrics window of metrics.json, at most its last 0.12 s (3 periods at
1500 rpm, like the paper's scope captures); for a run that tripped, the 0.1 s before the trip and
0.02 s after it, with the trip time and reason marked on every figure. Metrics that are null
(undefined: no whole electrical period, a diverged plant) are shown as "n/a".
numpy + matplotlib only (Debian python3-*).
"""
import argparse
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REQUIRED = ["t_s", "i_a_a", "i_b_a", "i_c_a", "torque_nm", "torque_est_nm", "psi_alpha_wb", "psi_beta_wb",
            "psi_alpha_est_wb", "psi_beta_est_wb", "speed_rpm"]


def load_trace(path):
    """Returns {column: ndarray}. Raises ValueError naming the file for a malformed trace."""
    with open(path, "r", encoding="ascii") as f:
        header = f.readline().strip().split(",")
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise ValueError(f"{path}: missing columns {', '.join(missing)}")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[0] < 2:
        raise ValueError(f"{path}: fewer than 2 rows")
    return {name: data[:, i] for i, name in enumerate(header)}


def load_metrics(run_dir):
    p = os.path.join(run_dir, "metrics.json")
    if not os.path.exists(p):
        return {}
    with open(p, "r", encoding="utf-8") as f:
        return json.load(f)


def num(x):
    """A metrics.json number, or NaN for null / missing (printed as "nan")."""
    return float("nan") if x is None else float(x)


def trip_of(tr, m):
    """(time_s, text) of the run's trip, or None: the fault of metrics.json (fault_time_s when the
    runner knows it, otherwise the last trace row with the gates enabled)."""
    fault = m.get("fault", "none")
    if not fault or fault == "none":
        return None
    t = m.get("fault_time_s")
    if t is None and "en" in tr:
        on = np.nonzero(tr["en"] > 0.5)[0]
        if on.size and on[-1] + 1 < tr["en"].size:
            t = float(tr["t_s"][on[-1] + 1])
    text = f"TRIPPED: {fault}"
    if m.get("fault_detail"):
        text += f"\n{m['fault_detail']}"
    return (t, text)


def mark_trip(ax, trip, t_scale=1e3):
    """Draws the trip time (if known and inside the axes) and its reason on a time-axis figure."""
    if trip is None:
        return
    t, text = trip
    if t is not None and t_scale is not None:
        ax.axvline(t * t_scale, color="red", linewidth=1.2, linestyle="--")
        text += f"\nat t = {t * 1e3:.2f} ms"
    ax.text(0.5, 0.97, text, transform=ax.transAxes, fontsize=8, color="red", ha="center", va="top", wrap=True,
            bbox=dict(facecolor="white", alpha=0.9, edgecolor="red"))


def title_of(m, fallback):
    c = m.get("config", {})
    if not c:
        return fallback
    parts = [c.get("topology", "?").upper()]
    if c.get("mode") == "open_loop":
        parts.append("open loop")
    else:
        parts.append(f"{c.get('estimator', '?')} model")
        if c.get("estimator") == "voltage":
            parts.append(f"compensation: {c.get('compensation', '?')}")
    parts.append(f"{c.get('speed_ref_rpm', 0):.0f} rpm" if c.get("mode") == "speed" else c.get("mode", ""))
    parts.append(f"load: {c.get('load', '?')}")
    return f"{m.get('scenario', fallback)}  ({', '.join(p for p in parts if p)})"


def span(tr, m, t0, t1):
    t = tr["t_s"]
    trip = trip_of(tr, m)
    if trip is not None and trip[0] is not None and t0 is None and t1 is None:
        t1 = min(float(t[-1]), trip[0] + 0.02)
        t0 = max(float(t[0]), trip[0] - 0.1)
    if t1 is None:
        t1 = m.get("metrics_window", {}).get("t_end_s", t[-1])
    if t0 is None:
        w0 = m.get("metrics_window", {}).get("t_start_s", t[0])
        t0 = max(w0, t1 - 0.12)
    sel = (t >= t0 - 1e-12) & (t <= t1 + 1e-12)
    if np.count_nonzero(sel) < 2:
        raise ValueError(f"time span [{t0}, {t1}] s holds fewer than 2 trace rows")
    return sel


def has(tr, name, sel):
    return name in tr and np.any(np.isfinite(tr[name][sel]))


def plot_currents(tr, m, sel, title, out):
    fig, ax = plt.subplots(figsize=(8, 4.2))
    t_ms = 1e3 * tr["t_s"][sel]
    for name, label, color in (("i_a_a", "$i_a$", "tab:blue"), ("i_b_a", "$i_b$", "tab:red"),
                               ("i_c_a", "$i_c$", "tab:green")):
        ax.plot(t_ms, tr[name][sel], label=label, color=color, linewidth=0.9)
    fund = m.get("fundamental_a")
    if fund:
        thd = m.get("thd_pct") or [float("nan")] * 3
        txt = "fundamental A/B/C: " + " / ".join(f"{num(x):.2f}" for x in fund) + " A"
        txt += f",  imbalance {num(m.get('imbalance_pct')):.1f} %"
        txt += "\nTHD A/B/C: " + " / ".join(f"{num(x):.1f}" for x in thd) + f" %,  total {num(m.get('thd_total_pct')):.1f} %"
        ax.text(0.01, 0.02, txt, transform=ax.transAxes, fontsize=8, va="bottom",
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="none"))
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("phase current (A)")
    mark_trip(ax, trip_of(tr, m))
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", ncol=3, fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_torque(tr, m, sel, title, out):
    fig, ax = plt.subplots(figsize=(8, 4.2))
    t_ms = 1e3 * tr["t_s"][sel]
    ax.plot(t_ms, tr["torque_nm"][sel], label="true (plant)", color="tab:blue", linewidth=0.8)
    if has(tr, "torque_est_nm", sel):
        ax.plot(t_ms, tr["torque_est_nm"][sel], label="estimated (firmware)", color="tab:orange", linewidth=0.8,
                alpha=0.85)
    txt = f"mean true {num(m.get('torque_mean_nm')):.4f} N·m, TRF {num(m.get('trf_pct')):.1f} %"
    if m.get("torque_est_mean_nm") is not None:
        txt += f"\nmean estimate {num(m['torque_est_mean_nm']):.4f} N·m, TRF {num(m.get('trf_est_pct')):.1f} %"
    ax.text(0.01, 0.02, txt, transform=ax.transAxes, fontsize=8, va="bottom",
            bbox=dict(facecolor="white", alpha=0.8, edgecolor="none"))
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("electromagnetic torque (N·m)")
    mark_trip(ax, trip_of(tr, m))
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_locus(tr, m, sel, title, out):
    fig, ax = plt.subplots(figsize=(5.6, 5.6))
    ax.plot(tr["psi_alpha_wb"][sel], tr["psi_beta_wb"][sel], label="true (plant)", color="tab:blue", linewidth=0.8)
    if has(tr, "psi_alpha_est_wb", sel):
        ax.plot(tr["psi_alpha_est_wb"][sel], tr["psi_beta_est_wb"][sel], label="estimated", color="tab:orange",
                linewidth=0.8, alpha=0.85)
    rr = np.hypot(tr["psi_alpha_wb"][sel], tr["psi_beta_wb"][sel])
    r = float(np.max(rr[np.isfinite(rr)])) if np.any(np.isfinite(rr)) else 0.0
    lim = 1.15 * r if r > 0 else 0.1
    # Sector boundaries. FSTP (Hoang Fig. 3, Table II): sector I is 0..90 deg, bounded by the
    # vectors V1 (0 deg) and V2 (90 deg): from Table II, with the flux in sector I, V2 raises both
    # flux and torque and V1 raises flux and lowers torque, which holds for 0 < theta < 90 deg only.
    # SSTP (Casadei Table 1): sector k is centred on V_k, boundaries at 30 + 60 k deg.
    topo = m.get("config", {}).get("topology", "")
    if topo == "fstp":
        bounds = [math.pi / 2 * k for k in range(4)]
        names = ["I", "II", "III", "IV"]
    elif topo == "sstp":
        bounds = [math.pi / 6 + math.pi / 3 * k for k in range(6)]
        names = ["1", "2", "3", "4", "5", "6"]
    else:
        bounds, names = [], []
    for k, a in enumerate(bounds):
        ax.plot([0, lim * math.cos(a)], [0, lim * math.sin(a)], color="0.6", linewidth=0.6, linestyle="--")
        c = a + math.pi / len(bounds) if topo == "fstp" else a - math.pi / 6
        ax.text(0.9 * lim * math.cos(c), 0.9 * lim * math.sin(c), names[k], color="0.4", ha="center", va="center",
                fontsize=9)
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$\psi_{s\alpha}$ (Wb)")
    ax.set_ylabel(r"$\psi_{s\beta}$ (Wb)")
    mark_trip(ax, trip_of(tr, m), t_scale=None)
    ax.set_title(title.replace("  (", "\n("), fontsize=8)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_components(tr, m, sel, title, out):
    fig, ax = plt.subplots(figsize=(8, 4.2))
    t_ms = 1e3 * tr["t_s"][sel]
    est = has(tr, "psi_alpha_est_wb", sel)
    if est:
        ax.plot(t_ms, tr["psi_alpha_est_wb"][sel], label=r"estimated $\psi_{s\alpha}$", color="tab:blue", linewidth=0.9)
        ax.plot(t_ms, tr["psi_beta_est_wb"][sel], label=r"estimated $\psi_{s\beta}$", color="tab:red", linewidth=0.9)
    ls = ":" if est else "-"
    ax.plot(t_ms, tr["psi_alpha_wb"][sel], label=r"true $\psi_{s\alpha}$", color="tab:blue", linewidth=0.8, linestyle=ls)
    ax.plot(t_ms, tr["psi_beta_wb"][sel], label=r"true $\psi_{s\beta}$", color="tab:red", linewidth=0.8, linestyle=ls)
    if m.get("flux_est_error_rms_pct") is not None:
        ax.text(0.01, 0.02, f"estimation error {m['flux_est_error_rms_pct']:.2f} % rms", transform=ax.transAxes,
                fontsize=8, va="bottom", bbox=dict(facecolor="white", alpha=0.8, edgecolor="none"))
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("stator flux (Wb)")
    mark_trip(ax, trip_of(tr, m))
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", ncol=2, fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_run(run_dir, out_dir=None, t0=None, t1=None):
    """Writes the four PNGs; returns their paths."""
    out_dir = out_dir or run_dir
    os.makedirs(out_dir, exist_ok=True)
    tr = load_trace(os.path.join(run_dir, "trace.csv"))
    m = load_metrics(run_dir)
    sel = span(tr, m, t0, t1)
    title = title_of(m, os.path.basename(os.path.normpath(run_dir)))
    outs = []
    for name, fn in (("currents.png", plot_currents), ("torque.png", plot_torque),
                     ("flux_locus.png", plot_locus), ("flux_components.png", plot_components)):
        p = os.path.join(out_dir, name)
        fn(tr, m, sel, title, p)
        outs.append(p)
    return outs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir", help="dtc-sil output folder (trace.csv, metrics.json)")
    ap.add_argument("--out", help="where to write the PNGs (default: run_dir)")
    ap.add_argument("--t0", type=float, help="start of the plotted span, s")
    ap.add_argument("--t1", type=float, help="end of the plotted span, s")
    a = ap.parse_args(argv)
    try:
        for p in plot_run(a.run_dir, a.out, a.t0, a.t1):
            print(p)
    except (OSError, ValueError) as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
