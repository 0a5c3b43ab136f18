"""What hoang_items.py and hoang_light.py share: the paths, Hoang Table VII and Table IX's
numbers, the sweep runner (zip_sweep, through `dtc-sil sweep`), the per-phase summaries, the
currents figure and the status.json entry's form.
"""
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "plot"))
import plot_run  # noqa: E402
import report  # noqa: E402  (tools/plot/report.py: Hoang Table IX/X data, sweep_series, load_figure)

SCEN = os.path.join(ROOT, "tools", "scenarios")

# Hoang Table VII, V peak at 1500 rpm: fundamental, 3rd, 5th, 7th of phases A, B, C.
TABLE_VII = {"A": (14.0868, 0.0488, 0.2385, 0.2274), "B": (14.2880, 0.0321, 0.2483, 0.2375),
             "C": (14.4254, 0.0364, 0.2209, 0.2472)}
BALANCED_EMF = {"motor.emf_gain": "[1, 1, 1]", "motor.emf_harm_a": "[0, 0, 0]",
                "motor.emf_harm_b": "[0, 0, 0]", "motor.emf_harm_c": "[0, 0, 0]"}
PAPER_IMB = {"none": 26.6, "simple": 6.8, "proposed": 4.6}  # Hoang Table IX, 100 (max/min - 1)

BALANCED_PCT = 10.0  # a phase-current set whose fundamentals differ by less than this is "balanced"


def r(x, nd=2):
    return None if x is None or (isinstance(x, float) and not np.isfinite(x)) else round(float(x), nd)


def imb(f):
    return 100.0 * (max(f) / min(f) - 1.0) if f and min(f) > 0 else None


def fund3(row):
    """Per-phase fundamentals from a sweep summary row or a metrics.json."""
    if "fundamental_a" in row:
        return row["fundamental_a"]
    v = [row.get("fundamental_a[%s]" % p) for p in "ABC"]
    return None if None in v else v


def zip_sweep(ctx, name, stem, cases, sets=(), keep=False):
    """One dtc-sil sweep of tools/scenarios/<stem>.toml over `cases` (dicts key -> TOML value, all
    with the same keys) as --zip axes, on ctx.jobs cores. Returns the summary rows in case order
    (each with "run_dir" when keep)."""
    out = os.path.join(ctx.out_dir, "hoang", name)
    subprocess.run(["rm", "-rf", out], check=True)
    cmd = [ctx.dtc_sil, "sweep", os.path.join(SCEN, stem + ".toml"), "--out", out, "--jobs", str(ctx.jobs), "-q"]
    if keep:
        cmd.append("--keep-runs")
    for k in cases[0]:
        cmd += ["--zip", k + "=" + ",".join(c[k] for c in cases)]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 3):
        raise RuntimeError("%s: %s" % (" ".join(cmd), (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]))
    with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
        rows = sorted(json.load(f)["rows"], key=lambda x: x["run"])
    flat = []
    for row in rows:
        f = dict(row.get("metrics") or {})
        f.update({k: row.get(k) for k in ("run", "status", "fault", "error")})
        f["run_dir"] = os.path.join(out, "runs", str(row["run"]))
        flat.append(f)
    return flat, cmd


def row_summary(row):
    f = fund3(row)
    return {"fault": row.get("fault"), "fundamental_a": [r(x, 3) for x in f] if f else None,
            "imbalance_pct": r(imb(f), 1) if f else None, "thd40_total_pct": r(row.get("thd40_total_pct"), 1),
            "torque_est_nm": r(row.get("torque_est_mean_nm"), 4), "torque_nm": r(row.get("torque_mean_nm"), 4)}


def cmdline(cmd):
    return " ".join(os.path.relpath(c, ROOT) if os.path.isabs(c) and c.startswith(ROOT) else c for c in cmd)


def sequences(run_dir, window_s=0.4):
    """Positive- and negative-sequence amplitudes (A) of the stator current over the last window_s:
    i_alpha + j i_beta demodulated with the plant's electrical angle, e^(-j theta) and e^(+j theta).
    A negative sequence of fixed size at every load is what an unbalanced PM flux under a circular
    flux estimate gives; a drop error grows with the current."""
    tr = plot_run.load_trace(os.path.join(run_dir, "trace.csv"))
    t = tr["t_s"]
    sel = t >= t[-1] - window_s
    i = tr["i_alpha_a"][sel] + 1j * tr["i_beta_a"][sel]
    th = tr["theta_e_rad"][sel]
    return r(abs(np.mean(i * np.exp(-1j * th))), 3), r(abs(np.mean(i * np.exp(1j * th))), 3)


def currents_figure(ctx, name, title, panels):
    """Stacked phase-current panels [(label, run_dir)], as the paper's scope captures."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(panels), 1, figsize=(7, 2.2 * len(panels)), squeeze=False)
    for ax, (label, run_dir) in zip(axes[:, 0], panels):
        try:
            tr = plot_run.load_trace(os.path.join(run_dir, "trace.csv"))
            m = plot_run.load_metrics(run_dir)
        except (OSError, ValueError) as e:
            ax.text(0.5, 0.5, "%s: no run (%s)" % (label, e), transform=ax.transAxes, ha="center", fontsize=7)
            continue
        sel = plot_run.span(tr, m, None, None)
        t = 1e3 * (tr["t_s"][sel] - tr["t_s"][sel][0])
        for col, lab in (("i_a_a", "$i_a$"), ("i_b_a", "$i_b$"), ("i_c_a", "$i_c$")):
            ax.plot(t, tr[col][sel], lw=0.7, label=lab)
        f = m.get("fundamental_a")
        txt = label + ("  fundamental " + " / ".join("%.2f" % x for x in f) + " A (%.1f %%)" % imb(f) if f else "")
        if m.get("fault", "none") != "none":
            txt += "  FAULT: " + m["fault"]
        ax.set_title(txt, fontsize=7, loc="left")
        ax.set_ylabel("A")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, ncol=3, loc="upper right")
    axes[-1, 0].set_xlabel("time (ms)")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    rel = os.path.join("hoang", name + ".png")
    fig.savefig(os.path.join(ctx.out_dir, rel), dpi=100)
    plt.close(fig)
    return rel


# ---------------------------------------------------------------------------------------------
def entry(item, status, measured, paper_values, reason, figure=None):
    e = {"paper": "hoang", "item": item, "status": status, "measured": measured, "paper_values": paper_values,
         "reason": reason}
    if figure:
        e["figure"] = figure
    return e


_KEY_DEFAULTS = {}


def scenario_values(ctx, stem, keys, sets=()):
    """{key: TOML value} of `keys` as the run of tools/scenarios/<stem>.toml with `sets` has them:
    the --set overrides, else the file, else the schema default (`dtc-sil keys`), so that a study's
    "unchanged" case is the scenario itself."""
    import tomllib
    with open(os.path.join(SCEN, stem + ".toml"), "rb") as f:
        flat = report.flat_toml(tomllib.load(f))
    over = dict(s.split("=", 1) for s in sets)
    if not _KEY_DEFAULTS:
        _KEY_DEFAULTS.update(report.key_defaults(ctx.dtc_sil))
    out = {}
    for k in keys:
        if k in over:
            out[k] = over[k]
        elif k in flat:
            out[k] = report.toml_value(flat[k])
        else:
            out[k] = _KEY_DEFAULTS[k].replace(" ", "")
    return out
