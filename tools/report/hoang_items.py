"""Hoang, Zhu, Foster 2011 (IEEE TPEL 26(8)) on the SIL: one status.json entry per numbered figure
and table of the paper that shows a result, for tools/report/papers.py.

    items(ctx) -> list of {"paper": "hoang", "item", "status", "measured", "paper_values", "reason",
                           optional "figure" (PNG path relative to ctx.out_dir)}

ctx: out_dir, short (bool), dtc_sil (binary path), jobs, progress(msg) (papers.py Ctx).

Every run goes through `dtc-sil sweep` (docs/sweep.md) on every core: the scenario files of
tools/scenarios/ through tools/plot/report.py's sweep_series (the files stay the one source of the
operating points), and the variants of a study (Hoang Fig. 14's four cases, the bare algorithm's switches,
the light-load causes) as --zip axes on one scenario. Each figure's status is decided by the
paper's statement about it, checked with a stated margin (the CHECKS below); a figure that fails
its check is "deviates" with the measured cause where one was measured.

Hoang Figs. 5-8 (a) are the ITC (indirect torque control) half of the flux figures: they need the ITC law
(control.scheme = "itc"). itc_sets() is the hook: it returns the --set
overrides that select the ITC law once dtc-sil accepts one of ITC_CANDIDATES, and None until then.
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

# Every numbered figure and table of the paper that shows a result (Figs. 1-4 and Tables I-VI, VIII
# are topologies, block diagrams, switching tables and parameters). Figs. 5-8 are split into (a)
# ITC and (b) DTC because the two halves need different control laws.
ITEMS = ["Fig. 5 (a)", "Fig. 5 (b)", "Fig. 6 (a)", "Fig. 6 (b)", "Fig. 7 (a)", "Fig. 7 (b)",
         "Fig. 8 (a)", "Fig. 8 (b)", "Fig. 9 (c)", "Fig. 10", "Fig. 11", "Fig. 12", "Fig. 13", "Fig. 14",
         "Fig. 15", "Fig. 16", "Fig. 17", "Fig. 18", "Fig. 19", "Fig. 20", "Table VII", "Table IX", "Table X"]

# Hoang Table VII, V peak at 1500 rpm: fundamental, 3rd, 5th, 7th of phases A, B, C.
TABLE_VII = {"A": (14.0868, 0.0488, 0.2385, 0.2274), "B": (14.2880, 0.0321, 0.2483, 0.2375),
             "C": (14.4254, 0.0364, 0.2209, 0.2472)}
BALANCED_EMF = {"motor.emf_gain": "[1, 1, 1]", "motor.emf_harm_a": "[0, 0, 0]",
                "motor.emf_harm_b": "[0, 0, 0]", "motor.emf_harm_c": "[0, 0, 0]"}

# Every addition of this project to the paper's voltage-model DTC switched off (docs/sil.md keys),
# on the stiff link the paper's analysis assumes. The start on the current model stays (the paper
# does not say how its drive starts; the bare voltage model does not start from standstill) with
# the hand-over at 941 rpm, the value derived for the uncompensated FSTP, for all three schemes.
BARE = ["control.delay_comp=false", "control.deadtime_comp=false", "control.polarity_mid=false",
        "control.lpf_comp=false", "control.dc_supp=false", "control.vmid_cal=false", "control.cal_hold=false",
        "sensors.vmid_fitted=false", "inverter.finite_dc_link=false", "control.handover_rpm=941"]
# One thing at a time against the bare run: (label, what it changes, overrides).
BARE_STEPS = [
    ("bare", "the paper's algorithm as printed", {}),
    ("delay_comp", "one-period actuation delay compensated (prediction)", {"control.delay_comp": "true"}),
    ("ts_25us", "sampling period halved (25 us)", {"ts_s": "2.5e-05"}),
    ("polarity_mid", "compensation polarity from the period's mean current (sampling instant)",
     {"control.polarity_mid": "true"}),
    ("dead_time_0", "no dead time in the plant (1 us otherwise)", {"inverter.dead_time_s": "0"}),
    ("deadtime_comp", "the plant's dead time compensated", {"control.deadtime_comp": "true"}),
    ("finite_link", "finite split DC link (2 x 4.7 mF, 3.3 kOhm, 25 mOhm)", {"inverter.finite_dc_link": "true"}),
    ("balanced_emf", "balanced sinusoidal back-EMF instead of Table VII", dict(BALANCED_EMF)),
    ("no_noise", "no sensor noise", {"sensors.current_noise_a_rms": "0", "sensors.voltage_noise_v_rms": "0"}),
    ("ideal_devices", "no device drops (R_on, V_CE, V_d = 0)", {"inverter.drops": "false"}),
    ("dead_time_0+balanced_emf", "no dead time and balanced back-EMF",
     dict(BALANCED_EMF, **{"inverter.dead_time_s": "0"})),
    ("dead_time_0+balanced_emf+half_drops", "as above, and the plant's device drops half of Table IV's",
     dict(BALANCED_EMF, **{"inverter.dead_time_s": "0", "inverter.v_ce_v": "0.45", "inverter.v_d_v": "0.625",
                           "inverter.r_on_ohm": "0.0375"})),
]
PAPER_IMB = {"none": 26.6, "simple": 6.8, "proposed": 4.6}  # Hoang Table IX, 100 (max/min - 1)

# Hoang Fig. 14's four simulated cases (the paper's MATLAB model: stiff link, devices of Table IV only).
FIG14 = [("(a)", "balanced back-EMFs, ideal switches", True, False),
         ("(b)", "unbalanced back-EMFs (Table VII), ideal switches", False, False),
         ("(c)", "balanced back-EMFs, non-ideal switches (Table IV)", True, True),
         ("(d)", "unbalanced back-EMFs, non-ideal switches", False, True)]
FIG14_SETS = ["inverter.finite_dc_link=false", "inverter.dead_time_s=0"]

LOAD_FIGS = {"Fig. 12": "fstp_current", "Fig. 15": "fstp_voltage_none", "Fig. 16": "fstp_voltage_simple",
             "Fig. 17": "fstp_voltage_proposed"}
FLUX_FIGS = {"Fig. 5": ("fstp_voltage_none_full", "no compensation"),
             "Fig. 6": ("fstp_voltage_simple_full", "simple compensation (Table V)"),
             "Fig. 7": ("fstp_voltage_proposed_full", "proposed compensation (Table VI)"),
             "Fig. 8": ("fstp_current_full", "current model")}
ITC_CANDIDATES = [["control.scheme=itc"]]

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


# ---------------------------------------------------------------------------------------------
def flux_fundamentals(run_dir, f_e=25.0):
    """Fundamental amplitudes (mWb) and peaks of the estimated alpha/beta stator flux over the last
    whole electrical periods of the trace (Hoang Figs. 5-8), and the alpha/beta imbalance."""
    tr = plot_run.load_trace(os.path.join(run_dir, "trace.csv"))
    m = plot_run.load_metrics(run_dir)
    t = tr["t_s"]
    win = float((m.get("metrics_window") or {}).get("duration_s") or 0.4)
    n_per = max(1, int(win * f_e))
    sel = t >= t[-1] - n_per / f_e
    out = {}
    for comp in ("alpha", "beta"):
        x = tr["psi_%s_est_wb" % comp][sel]
        ph = np.exp(-2j * np.pi * f_e * t[sel])
        a1 = 2.0 * abs(np.mean(x * ph))
        rest = np.sqrt(max(np.mean((x - np.mean(x)) ** 2) - a1 ** 2 / 2.0, 0.0))
        out[comp] = {"fundamental_mwb": 1e3 * a1, "peak_mwb": 1e3 * float(np.max(np.abs(x))),
                     "harmonics_rms_mwb": 1e3 * rest}
    a, b = out["alpha"]["fundamental_mwb"], out["beta"]["fundamental_mwb"]
    pa, pb = out["alpha"]["peak_mwb"], out["beta"]["peak_mwb"]
    return {"psi_alpha_fund_mwb": r(a, 2), "psi_beta_fund_mwb": r(b, 2),
            "psi_alpha_peak_mwb": r(out["alpha"]["peak_mwb"], 2), "psi_beta_peak_mwb": r(out["beta"]["peak_mwb"], 2),
            "alpha_beta_fund_imbalance_pct": r(100.0 * (max(a, b) / min(a, b) - 1.0), 2),
            "alpha_beta_peak_imbalance_pct": r(100.0 * (max(pa, pb) / min(pa, pb) - 1.0), 2),
            "alpha_beta_harm_ratio": r(out["alpha"]["harmonics_rms_mwb"] / max(out["beta"]["harmonics_rms_mwb"], 1e-9), 2)}


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


def flux_figure(ctx, name, title, run_dir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tr = plot_run.load_trace(os.path.join(run_dir, "trace.csv"))
    sel = tr["t_s"] >= tr["t_s"][-1] - 0.12
    t = 1e3 * (tr["t_s"][sel] - tr["t_s"][sel][0])
    fig, ax = plt.subplots(figsize=(7, 3))
    ax.plot(t, 1e3 * tr["psi_alpha_est_wb"][sel], lw=0.8, label=r"$\psi_{s\alpha}$ estimated")
    ax.plot(t, 1e3 * tr["psi_beta_est_wb"][sel], lw=0.8, label=r"$\psi_{s\beta}$ estimated")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("mWb")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title, fontsize=8, loc="left")
    fig.tight_layout()
    rel = os.path.join("hoang", name + ".png")
    fig.savefig(os.path.join(ctx.out_dir, rel), dpi=100)
    plt.close(fig)
    return rel


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


def itc_sets(ctx):
    """HOOK for Figs. 5-8 (a): the --set overrides that select the ITC law, or None while dtc-sil has
    none. Probes `dtc-sil check` with each of ITC_CANDIDATES."""
    for sets in ITC_CANDIDATES:
        cmd = [ctx.dtc_sil, "check", os.path.join(SCEN, "fstp_voltage_none_full.toml")]
        for s in sets:
            cmd += ["--set", s]
        if subprocess.run(cmd, capture_output=True, text=True).returncode == 0:
            return sets
    return None


# ---------------------------------------------------------------------------------------------
def entry(item, status, measured, paper_values, reason, figure=None):
    e = {"paper": "hoang", "item": item, "status": status, "measured": measured, "paper_values": paper_values,
         "reason": reason}
    if figure:
        e["figure"] = figure
    return e


def items(ctx):
    os.makedirs(os.path.join(ctx.out_dir, "hoang"), exist_ok=True)
    out = []
    hdir = os.path.join(ctx.out_dir, "hoang")
    sets = ["metrics.torque_sensor_hz=1000"]
    seeds = ["1"] if ctx.short else ["1", "2", "3"]

    # -- Hoang Tables IX/X, Figs. 11, 13 and the full-load panels: the seven scenario files.
    ctx.progress("hoang: Table IX/X matrix (7 runs)")
    stems = [p[0] for p in report.PAPER]
    table, table_cmd = report.sweep_series(ctx.dtc_sil, SCEN, hdir, "sweep_table", stems, sets, ctx.jobs)
    ctx.progress("hoang: inertial and half load (8 runs)")
    load_stems = ["%s_%s" % (b, ld) for b in LOAD_FIGS.values() for ld in ("inertial", "half")]
    loads, loads_cmd = report.sweep_series(ctx.dtc_sil, SCEN, hdir, "sweep_loads", load_stems, sets, ctx.jobs)
    allm = dict(table)
    allm.update(loads)

    def met(stem):
        return allm.get(stem, (None, "not run"))[0]

    # Hoang Table IX
    paper_ix, ours_ix, ranks_ok = {}, {}, True
    for stem, label, ix, _ in report.PAPER:
        m = met(stem)
        paper_ix[label] = "%s A (%.1f %%)" % (report.fmt3(ix), imb(ix))
        ours_ix[label] = ("%s A (%.1f %%)" % (report.fmt3(m["fundamental_a"]), imb(m["fundamental_a"]))
                          if m and m.get("fundamental_a") else "run failed: %s" % allm.get(stem, (0, "?"))[1])
    fi = {c: imb((met("fstp_voltage_%s_full" % c) or {}).get("fundamental_a")) or float("nan")
          for c in ("none", "simple", "proposed")}
    fi_cur = imb((met("fstp_current_full") or {}).get("fundamental_a"))
    ranks_ok = fi["none"] > fi["simple"] > fi["proposed"] and fi_cur is not None and fi_cur < 5
    # The bare algorithm, one thing at a time (not in --short beyond the bare row and two causes).
    steps = BARE_STEPS if not ctx.short else [s for s in BARE_STEPS if s[0] in ("bare", "dead_time_0", "balanced_emf")]
    bare = {}
    keys = sorted({k for _, _, d in steps for k in d})
    for comp in ("none", "simple", "proposed"):
        ctx.progress("hoang: bare paper algorithm, %s compensation (%d runs)" % (comp, len(steps)))
        stem = "fstp_voltage_%s_full" % comp
        base = scenario_values(ctx, stem, keys, BARE)
        cases = [dict(base, **d) for _, _, d in steps]
        rows, bare_cmd = zip_sweep(ctx, "bare_" + comp, stem, cases, BARE + sets)
        bare[comp] = {lab: row_summary(row) for (lab, _, _), row in zip(steps, rows)}
    bare_tab = {lab + " (" + what + ")": " / ".join(
        "%s" % (bare[c][lab]["imbalance_pct"] if bare[c][lab]["imbalance_pct"] is not None
                else "trip: %s" % bare[c][lab]["fault"]) for c in ("none", "simple", "proposed"))
        for lab, what, _ in steps}
    ours_ix["bare algorithm, imbalance % none / simple / proposed, one change at a time"] = bare_tab
    paper_ix["bare algorithm, imbalance % none / simple / proposed"] = "%.1f / %.1f / %.1f" % (
        PAPER_IMB["none"], PAPER_IMB["simple"], PAPER_IMB["proposed"])
    ix_ok = ranks_ok and all(abs(fi[c] - PAPER_IMB[c]) <= 10.0 for c in fi)
    ours_ix["commands"] = {"matrix": cmdline(table_cmd), "bare (proposed; none and simple alike)": cmdline(bare_cmd)}
    reason_ix = ("ranking none > simple > proposed FSTP and a balanced current model: %s; FSTP imbalance "
                 "none / simple / proposed %.1f / %.1f / %.1f %% against the paper's 26.6 / 6.8 / 4.6 %% "
                 "(margin 10 points). " % ("holds" if ranks_ok else "does NOT hold", fi["none"] or -1,
                                            fi["simple"] or -1, fi["proposed"] or -1)) + bare_finding(bare, steps)
    out.append(entry("Table IX", "reproduced" if ix_ok else "deviates", ours_ix, paper_ix, reason_ix))

    # Hoang Table X
    tx = table_x(allm)
    ctx.progress("hoang: Table X, the uncompensated torque estimate against the device drops (8 runs)")
    table_x_drops(ctx, sets, tx)
    out.append(tx)

    # Hoang Fig. 11 (SSTP current model) and Fig. 13 (SSTP voltage model without / with compensation)
    m11 = met("sstp_current_full")
    ok11 = bool(m11) and imb(m11["fundamental_a"]) < 5.0 and abs(m11["torque_est_mean_nm"] / 0.3 - 1) < 0.03
    fig11 = currents_figure(ctx, "fig11", "Fig. 11: current-model DTC, SSTP, 1500 rpm, full load",
                            [("full load", os.path.join(hdir, "sstp_current_full"))])
    out.append(entry("Fig. 11", "reproduced" if ok11 else "deviates",
                     {"fundamental_a": m11 and [r(x, 3) for x in m11["fundamental_a"]],
                      "imbalance_pct": m11 and r(imb(m11["fundamental_a"]), 1),
                      "torque_est_nm": m11 and r(m11["torque_est_mean_nm"], 4)},
                     {"description": "sinusoidal, balanced phase currents; Table IX 2.22 / 2.20 / 2.29 A",
                      "torque_est_nm": 0.3034},
                     "checked: imbalance below 5 % and estimated torque within 3 % of 0.3 N*m", fig11))
    a, b = met("sstp_voltage_none_full"), met("sstp_voltage_simple_full")
    ok13 = bool(a and b) and a["torque_est_mean_nm"] > 1.05 * 0.3 and abs(b["torque_est_mean_nm"] / 0.3 - 1) < 0.03 \
        and imb(a["fundamental_a"]) < BALANCED_PCT and imb(b["fundamental_a"]) < BALANCED_PCT \
        and min(b["fundamental_a"]) < min(a["fundamental_a"])
    fig13 = currents_figure(ctx, "fig13", "Fig. 13: voltage-model DTC, SSTP, 1500 rpm, full load",
                            [("(a) without compensation", os.path.join(hdir, "sstp_voltage_none_full")),
                             ("(b) with compensation [29]", os.path.join(hdir, "sstp_voltage_simple_full"))])
    out.append(entry("Fig. 13", "reproduced" if ok13 else "deviates",
                     {"(a) torque_est_nm": a and r(a["torque_est_mean_nm"], 4), "(a) fundamental_a": a and [r(x, 3) for x in a["fundamental_a"]],
                      "(b) torque_est_nm": b and r(b["torque_est_mean_nm"], 4), "(b) fundamental_a": b and [r(x, 3) for x in b["fundamental_a"]]},
                     {"description": "(a) estimated torque above 0.3 N*m, currents higher than demanded but "
                      "sinusoidal (the SSTP's drops are balanced); (b) compensation improves it",
                      "(a) torque_est_nm": 0.3296, "(b) torque_est_nm": 0.2984},
                     "checked: (a) estimate > 1.05 x 0.3 N*m, (b) within 3 %, both balanced (< 10 %), (b) smaller currents",
                     fig13))

    # Hoang Figs. 12, 15-17: inertial, half, full load
    for fig, base in LOAD_FIGS.items():
        out.append(load_entry(ctx, fig, base, met, hdir))

    # Light load: the measured cause of Hoang Fig. 17 (a)/(b)'s imbalance
    ctx.progress("hoang: light-load causes (%d runs)" % ((2 * len(LIGHT_VARIANTS) + 4) * len(seeds) + 3))
    light, ideal, share = light_load_study(ctx, seeds, sets)
    for e in out:
        if e["item"] == "Fig. 17":
            e["measured"]["light-load causes (imbalance %, mean over seeds)"] = light
            e["measured"]["ideal law on Table VII's machine (hoang_emf)"] = {
                ld: {"fundamental_a": [r(x, 3) for x in v["fundamental_a"]], "imbalance_pct": r(v["imbalance_pct"], 1),
                     "i_pos_a": r(v["i_pos_a"], 3), "i_neg_a": r(v["i_neg_a"], 3)} for ld, v in ideal.items()}
            e["measured"]["paper's Table VII share k (from its Table IX)"] = {x: r(v, 3) for x, v in share.items()}
            e["figures"] = [light_figure(ctx, e["measured"], light, ideal, share)]
            if e["status"] == "deviates":
                e["reason"] += " " + light_finding(e["measured"], light, ideal, share)

    # Hoang Fig. 14: the four simulated cases
    ctx.progress("hoang: Fig. 14 (4 runs)")
    out.append(fig14(ctx, sets))

    # Hoang Figs. 5-8: estimated alpha/beta flux under DTC (b); ITC (a) through the hook
    out += flux_entries(ctx, hdir)

    # Hoang Figs. 18-20: low speed, 25 % load
    ctx.progress("hoang: low speed, Figs. 18-20 (%d runs)" % (7 + 3 * (len(LOW_CAUSES) + 1) * len(seeds)))
    low_entries, low = low_speed_entries(ctx, hdir, sets, seeds, share["k"])
    out += low_entries

    # report.py's report.md beside the runs: Hoang Tables IX/X, the stiff-link comparison, the low-speed table
    ctx.progress("hoang: stiff-link comparison (4 runs) and report.md")
    stiff, _ = report.sweep_series(ctx.dtc_sil, SCEN, hdir, "sweep_stiff", report.FINITE, sets + report.STIFF_SETS,
                                   ctx.jobs, suffix="_stiff")
    md = os.path.join(hdir, "report.md")
    report.write_report(md, table, ctx.dtc_sil, sets)
    with open(md, "a", encoding="utf-8") as f:
        f.write(report.issue10_tables(stiff, {(rpm, k): v for rpm, res in low.items() for k, v in res.items()}))
    if not ctx.short:
        for stem in stems:
            if table[stem][0] is not None:
                plot_run.plot_run(os.path.join(hdir, stem))

    # The prototype's own measurements
    out.append(entry("Fig. 9 (c)", "not applicable", {"plant_emf": "Table VII's harmonics and per-phase "
                     "amplitudes (normalised to their mean) are the plant's input (motor.emf_gain, motor.emf_harm_*)"},
                     {"description": "measured back-EMF waveforms of the prototype at 1500 rpm (photograph of the rig)"},
                     "a measurement of the paper's prototype machine; the plant takes it as input (Table VII)"))
    mean = np.mean([v[0] for v in TABLE_VII.values()])
    gains = {p: TABLE_VII[p][0] / mean for p in "ABC"}
    out.append(entry("Table VII", "not applicable",
                     dict({"motor.emf_gain": [r(gains[p], 5) for p in "ABC"]},
                          **{"motor.emf_harm_%s" % p.lower(): [r(h / TABLE_VII[p][0], 5) for h in TABLE_VII[p][1:]]
                             for p in "ABC"}),
                     {p: list(v) for p, v in TABLE_VII.items()},
                     "the prototype's measured back-EMF harmonics (V peak, fundamental / 3rd / 5th / 7th): an input of "
                     "the plant (the scenarios' motor.emf_gain and motor.emf_harm_*, amplitudes normalised to their "
                     "mean, harmonics relative to each fundamental), not a result to reproduce"))
    out.append(entry("Fig. 10", "not applicable", {},
                     {"description": "IPM case temperature over one hour, T1-T4 for the four FSTP schemes"},
                     "thermal measurement of the inverter module; the plant has no thermal model"))
    out.sort(key=lambda e: ITEMS.index(e["item"]))
    return out


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


def bare_finding(bare, steps):
    """Table IX's reason for the bare paper algorithm: each switch's change against the bare row, from
    the runs; a switch is named a cause when removing it lowers the simple and the proposed rows by at
    least cause_pts points, and not a cause when it lowers none of the three rows by that much."""
    cause_pts = 2.0
    comps = ("none", "simple", "proposed")

    def v(lab, c):
        x = bare[c][lab]["imbalance_pct"]
        return float("nan") if x is None else x
    delta = {lab: [v(lab, c) - v("bare", c) for c in comps] for lab, _, _ in steps if lab != "bare"}
    what = {lab: w for lab, w, _ in steps}
    trips = {lab: [c for c in comps if bare[c][lab]["imbalance_pct"] is None] for lab in delta}
    causes = [lab for lab, d in delta.items() if not trips[lab] and d[1] <= -cause_pts and d[2] <= -cause_pts]
    not_causes = [lab for lab, d in delta.items() if not trips[lab] and all(x > -cause_pts for x in d)]
    none_vals = [(v(lab, "none"), lab) for lab, _, _ in steps if bare["none"][lab]["imbalance_pct"] is not None]
    none_min, none_min_lab = min(none_vals)
    hd = "dead_time_0+balanced_emf+half_drops"
    return (
        "Why the bare algorithm (every addition off, stiff link) does worse here than on the paper's rig, measured "
        "one switch at a time ('bare algorithm' rows; change against the bare row, none / simple / proposed, "
        "points: %s). Causes (removing it lowers the simple and the proposed rows by %.0f points or more): %s. Not "
        "causes (no row lowered by %.0f points): %s. The Table VII back-EMF acts through the voltage model "
        "(Fig. 17's reason: the ideal law on Table VII's machine gives the proposed row's size at full load); the "
        "1 us dead time is not in the paper's algorithm (Table VI has the device drops only) and its value on "
        "the paper's rig is not printed. A switch that makes a row trip is neither (%s). The uncompensated "
        "row's lowest over the switches is %.1f %% (%s) against the paper's 26.6 %%%s." % (
            "; ".join("%s %s" % (lab, " / ".join("trip (%s)" % bare[c][lab]["fault"] if bare[c][lab]["imbalance_pct"]
                                                 is None else "%+.1f" % x for c, x in zip(comps, d)))
                      for lab, d in delta.items()),
            cause_pts, ", ".join("%s (%s)" % (lab, what[lab]) for lab in causes) or "none",
            cause_pts, ", ".join("%s (%s)" % (lab, what[lab]) for lab in not_causes) or "none",
            ", ".join("%s: %s" % (lab, "/".join(t)) for lab, t in trips.items() if t) or "none tripped",
            none_min, none_min_lab, ": that remainder is not explained (the paper does not state its dead time, "
            "sampling instant or sensor bandwidths)" if none_min > PAPER_IMB["none"] + 5.0 else "")) + (
        " With no dead time, balanced back-EMF and half of Table IV's drops the uncompensated row is %s %% with "
        "the torque estimate %s N*m, against the paper's 0.3345 N*m, which the full drops give (%s N*m): the "
        "paper's imbalance and its torque over-estimate are not both met by one drop size." % (
            bare["none"][hd]["imbalance_pct"], bare["none"][hd]["torque_est_nm"], bare["none"]["bare"]["torque_est_nm"])
        if hd in bare["none"] else "")


# Hoang Fig. 17 (a)/(b): the proposed FSTP at inertial and half load, one cause changed at a time
# (label, overrides); "Table VII x k" scales each phase's back-EMF deviation from the mean by the k
# that the paper's own Table IX implies (light_load_study).
LIGHT_VARIANTS = [("as shipped", {}), ("balanced back-EMF", dict(BALANCED_EMF)), ("ts 10 us", {"ts_s": "1e-05"}),
                  ("balanced back-EMF, ts 10 us", dict(BALANCED_EMF, ts_s="1e-05")),
                  ("SSTP, compensation [29]", {"inverter.topology": "\"sstp\"", "control.compensation": "\"simple\""})]
LOAD_SHARE = {"inertial": 0.25, "half": 0.5, "full": 1.0}  # Hoang sec. IV: inertial load 25 % of full


def ideal_law(ctx, stem, torque_nm, gains=None):
    """hoang_emf.ideal_currents on tools/scenarios/<stem>.toml's machine and flux reference at torque_nm."""
    import tomllib
    import hoang_emf
    with open(os.path.join(SCEN, stem + ".toml"), "rb") as f:
        sc = tomllib.load(f)
    m = sc["motor"]
    harm = [m.get("emf_harm_" + p, [0.0, 0.0, 0.0]) for p in "abc"]
    return hoang_emf.ideal_currents(gains or m.get("emf_gain", [1.0, 1.0, 1.0]), harm, m["ls_h"], m["psi_m_wb"],
                                    sc["control"]["flux_ref_wb"], torque_nm, m["pole_pairs"])


def paper_emf_share():
    """({stem: size %}, the current-model SSTP row): the part of Table VII's back-EMF imbalance that the
    paper's own Table IX shows. The
    current model cannot carry the back-EMF into the current (its flux model has a balanced psi_m), so the
    difference of the negative-sequence signatures (hoang_emf.signature) of the voltage-model SSTP rows
    and the current-model SSTP row, all on the paper's one rig at full load, is the voltage model's own
    part (its size in % of the current, per voltage-model SSTP row); light_load_study divides it by the ideal
    law's signature at full load on Table VII's machine to get the share k."""
    import hoang_emf
    ix = {stem: f for stem, _, f, _ in report.PAPER}
    cur = ix["sstp_current_full"]
    parts = {stem: hoang_emf.signature_diff(ix[stem], cur) for stem in ("sstp_voltage_none_full", "sstp_voltage_simple_full")}
    return parts, cur


def light_load_study(ctx, seeds, sets):
    """Proposed FSTP at inertial and half load: LIGHT_VARIANTS and Table VII's imbalance scaled to what
    the paper's Table IX shows, the mean imbalance over the seeds; the current model; the FSTP's own part
    on an ideal plant; the ideal law of hoang_emf on the scenario's machine. Returns (res, ideal, k)."""
    import hoang_emf
    import tomllib
    parts, cur = paper_emf_share()
    stem_full = "fstp_voltage_proposed_full"
    with open(os.path.join(SCEN, stem_full + ".toml"), "rb") as f:
        motor = tomllib.load(f)["motor"]
    full_torque_nm, g = motor["rated_torque_nm"], motor["emf_gain"]
    ideal = {ld: ideal_law(ctx, "fstp_voltage_proposed_" + ld, share * full_torque_nm)
             for ld, share in LOAD_SHARE.items()}
    s_full = hoang_emf.signature(ideal["full"]["fundamental_a"])[0]
    k = float(np.mean(list(parts.values()))) / s_full
    # signature() is (2/3) sum of the three amplitudes rotated: Table IX's rounding to 0.01 A moves it by
    # at most (2/3) 3 0.005 A over the row's mean, the difference of two rows by twice that
    bound = 2.0 * 100.0 * 0.01 / np.mean(cur)
    share = {"k": k, "k_lo": max(0.0, k - bound / s_full), "k_hi": k + bound / s_full}
    variants = list(LIGHT_VARIANTS)
    gks = {kk: [1.0 + kk * (x - 1.0) for x in g] for kk in (share["k"], share["k_hi"])}
    for kk, gk in gks.items():
        variants.append(("Table VII x %.2f" % kk, {"motor.emf_gain": "[%s]" % ", ".join("%.5f" % x for x in gk)}))
    keys = sorted({kk for _, d in variants for kk in d})
    res = {}
    for ld in ("inertial", "half"):
        base = scenario_values(ctx, "fstp_voltage_proposed_" + ld, keys, sets)
        cases = [dict(base, **d, **{"sensors.seed": s}) for _, d in variants for s in seeds]
        rows, _ = zip_sweep(ctx, "light_" + ld, "fstp_voltage_proposed_" + ld, cases, sets)
        for i, (lab, _) in enumerate(variants):
            vals = [imb(fund3(row)) for row in rows[i * len(seeds):(i + 1) * len(seeds)] if fund3(row)]
            res["%s, %s" % (ld, lab)] = r(np.mean(vals), 1) if vals else None
        for kk, gk in gks.items():
            ik = ideal_law(ctx, "fstp_voltage_proposed_" + ld, LOAD_SHARE[ld] * full_torque_nm, gk)
            res["%s, ideal law, Table VII x %.2f" % (ld, kk)] = r(ik["imbalance_pct"], 1)
    for ld in ("inertial", "half"):
        rows, _ = zip_sweep(ctx, "light_current_" + ld, "fstp_current_" + ld,
                            [dict(BALANCED_EMF, **{"sensors.seed": s}) for s in seeds], sets)
        vals = [imb(fund3(row)) for row in rows if fund3(row)]
        res["%s, current model, balanced back-EMF" % ld] = r(np.mean(vals), 1) if vals else None
    # The FSTP's own part: the current model on an ideal plant (balanced back-EMF, ideal devices, no
    # dead time, stiff link, no noise) at inertial load, FSTP at 50 and 10 us against the SSTP at 50 us.
    ideal_plant = ["inverter.drops=false", "inverter.dead_time_s=0", "inverter.finite_dc_link=false",
                   "sensors.current_noise_a_rms=0", "sensors.voltage_noise_v_rms=0"] + \
        ["%s=%s" % kv for kv in BALANCED_EMF.items()]
    cases = [{"inverter.topology": "fstp", "ts_s": "5e-05"}, {"inverter.topology": "fstp", "ts_s": "1e-05"},
             {"inverter.topology": "sstp", "ts_s": "5e-05"}]
    rows, _ = zip_sweep(ctx, "light_sectors", "fstp_current_inertial", cases, sets + ideal_plant)
    for c, row in zip(cases, rows):
        f = fund3(row)
        res["inertial, current model, ideal plant, %s at %g us" % (c["inverter.topology"].upper(),
                                                                    1e6 * float(c["ts_s"]))] = r(imb(f), 1) if f else None
    return res, ideal, share


def light_figure(ctx, meas, light, ideal, share):
    """Hoang Fig. 17's imbalance against the load: the ideal law on Table VII's machine and at the paper's
    share k, the SIL as shipped, with balanced back-EMF, on the SSTP [29], at k, and the paper's Table IX
    full-load point."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lds = ["inertial", "half", "full"]
    x = [LOAD_SHARE[ld] for ld in lds]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(x, [ideal[ld]["imbalance_pct"] for ld in lds], "k--", label="ideal law, Table VII (hoang_emf)")
    ax.plot(x, [imb(meas[ld]["fundamental_a"]) if isinstance(meas.get(ld), dict) else np.nan for ld in lds], "o-",
            label="SIL proposed FSTP, Table VII (as shipped)")
    k = share["k"]
    for lab, fmt in (("SSTP, compensation [29]", "s-"), ("balanced back-EMF", "^-"), ("Table VII x %.2f" % k, "d-")):
        ax.plot(x[:2], [light.get("%s, %s" % (ld, lab)) or np.nan for ld in lds[:2]], fmt, label="SIL, " + lab)
    ax.plot(x[:2], [light.get("%s, ideal law, Table VII x %.2f" % (ld, k)) or np.nan for ld in lds[:2]], "k:",
            label="ideal law, Table VII x %.2f" % k)
    ax.plot([1.0], [PAPER_IMB["proposed"]], "r*", ms=12, label="paper, Table IX proposed FSTP")
    ax.axhline(BALANCED_PCT, color="gray", lw=0.6)
    from figsave import save_axes_figure
    return save_axes_figure(fig, ax, ctx.out_dir, os.path.join("hoang", "fig17_causes.png"), "load (share of 0.3 N*m)",
                            "imbalance 100 (max/min - 1), %", "Hoang Fig. 17: light-load imbalance and its cause")


def light_finding(meas, light, ideal, share):
    """Hoang Fig. 17's reason, every number from the runs above and from hoang_emf."""
    import hoang_emf
    lds = [ld for ld in ("inertial", "half", "full") if isinstance(meas.get(ld), dict)]
    sig = {ld: hoang_emf.signature(meas[ld]["fundamental_a"]) for ld in lds}
    isig = {ld: hoang_emf.signature(ideal[ld]["fundamental_a"]) for ld in ideal}
    parts, cur = paper_emf_share()
    ix = {stem: f for stem, _, f, _ in report.PAPER}
    g = lambda key: light.get(key)  # noqa: E731
    k, k_hi = share["k"], share["k_hi"]
    return (
        "Measured cause: Table VII's back-EMF imbalance, through the voltage model. (1) The law alone: the "
        "voltage model estimates the machine's true flux, whose PM part is unbalanced, and the DTC holds it on a "
        "circle at constant torque (Hoang eqs. 10, 13-16); solved with no inverter, no sampling and no bands on "
        "this machine (tools/report/hoang_emf.py) it draws %s %% imbalance at inertial / half / full load "
        "(negative-sequence current %s A, fixed, against %s A positive), phase B lowest "
        "(signature %s). (2) The SIL as shipped: %s %% (negative sequence %s A), the same signature (%s): the "
        "SIL is the law on this machine. What the inverter, the sampling and the compensation add shows with "
        "balanced back-EMF: %s / %s %% (inertial / half; the FSTP's own part at 50 us, 'ideal plant' rows), "
        "and at 10 us sampling %s / %s %% with Table VII against %s / %s %% balanced: finer sampling follows "
        "the law more closely. On the SSTP with "
        "compensation [29] (no FSTP, no proposed scheme) Table VII gives %s / %s %%: it is the machine under "
        "the voltage model, not the four-switch inverter. The current model (Fig. 12) is balanced because its "
        "flux model uses a balanced psi_m. (3) Would the paper's figures show it? Its Table IX does not carry "
        "this signature at full load: the voltage-model SSTP rows (%s and %s A) differ from the current-model "
        "SSTP row (%s A, which the back-EMF cannot reach through the estimator) by a negative sequence of "
        "%s %% of the current, against the %.1f %% the law gives on Table VII's machine: the paper's rig "
        "shows k = %.2f of Table VII's imbalance; Table IX's rounding to 0.01 A puts k in %.2f..%.2f. "
        "So Table VII's per-phase amplitudes are not the flux imbalance the paper's machine acts with (or "
        "its phases are not 120 deg apart; the paper does not say). With each phase's deviation scaled by k "
        "the SIL gives %s / %s %% at inertial / half load (the law %s / %s %%), by k = %.2f %s / %s %% (the "
        "law %s / %s %%): %s. Left as deviates: with Table VII as printed, the paper's machine under its own "
        "control law cannot be balanced at light load." % (
            " / ".join("%.1f" % ideal[ld]["imbalance_pct"] for ld in ideal),
            "%.3f" % np.mean([ideal[ld]["i_neg_a"] for ld in ideal]),
            " / ".join("%.2f" % ideal[ld]["i_pos_a"] for ld in ideal),
            ", ".join("%s %.1f %% at %.0f deg" % (ld, *isig[ld]) for ld in isig),
            " / ".join("%.1f" % imb(meas[ld]["fundamental_a"]) for ld in lds),
            " / ".join("%s" % meas[ld].get("i_neg_a") for ld in lds),
            ", ".join("%s %.1f %% at %.0f deg" % (ld, *sig[ld]) for ld in lds),
            g("inertial, balanced back-EMF"), g("half, balanced back-EMF"),
            g("inertial, ts 10 us"), g("half, ts 10 us"),
            g("inertial, balanced back-EMF, ts 10 us"), g("half, balanced back-EMF, ts 10 us"),
            g("inertial, SSTP, compensation [29]"), g("half, SSTP, compensation [29]"),
            report.fmt3(ix["sstp_voltage_none_full"]), report.fmt3(ix["sstp_voltage_simple_full"]), report.fmt3(cur),
            " and ".join("%.1f" % v for v in parts.values()), isig["full"][0], k, share["k_lo"], k_hi,
            g("inertial, Table VII x %.2f" % k), g("half, Table VII x %.2f" % k),
            g("inertial, ideal law, Table VII x %.2f" % k), g("half, ideal law, Table VII x %.2f" % k), k_hi,
            g("inertial, Table VII x %.2f" % k_hi), g("half, Table VII x %.2f" % k_hi),
            g("inertial, ideal law, Table VII x %.2f" % k_hi), g("half, ideal law, Table VII x %.2f" % k_hi),
            "; ".join("at k = %.2f %s" % (kk, "both loads are balanced (<= %.0f %%) as the paper's Fig. 17 (a)/(b)"
                                          % BALANCED_PCT if all((g("%s, Table VII x %.2f" % (ld, kk)) or 1e9)
                                                                <= BALANCED_PCT for ld in ("inertial", "half"))
                                          else "not every load is balanced (<= %.0f %%)" % BALANCED_PCT)
                      for kk in (k, k_hi))))


def load_entry(ctx, fig, base, met, hdir):
    panels = [(lab, os.path.join(hdir, "%s_%s" % (base, ld))) for ld, lab in report.LOADS]
    name = "fig" + fig.split()[1]
    title = {n: t for n, t, _ in report.FIGURES}.get(name, fig) + ", 1500 rpm"
    png = currents_figure(ctx, name, title, panels)
    meas = {}
    imbs = {}
    for ld, _ in report.LOADS:
        m = met("%s_%s" % (base, ld))
        if m and m.get("fundamental_a"):
            imbs[ld] = imb(m["fundamental_a"])
            meas[ld] = {"fundamental_a": [r(x, 3) for x in m["fundamental_a"]], "imbalance_pct": r(imbs[ld], 1),
                        "thd40_total_pct": r(m.get("thd40_total_pct"), 1), "fault": m.get("fault")}
            try:
                meas[ld]["i_pos_a"], meas[ld]["i_neg_a"] = sequences(os.path.join(hdir, "%s_%s" % (base, ld)))
            except (OSError, ValueError, KeyError):
                pass
        else:
            meas[ld] = "run failed"
    full = len(imbs) == 3
    if fig in ("Fig. 12", "Fig. 17"):
        ok = full and all(v <= BALANCED_PCT for v in imbs.values())
        desc = ("sinusoidal, balanced currents at every load; the current model is not affected by the drop imbalance"
                if fig == "Fig. 12" else
                "satisfactory sinusoidal shapes and balanced magnitudes even at inertial and half load")
        crit = "every load balanced: imbalance <= %.0f %%" % BALANCED_PCT
    elif fig == "Fig. 15":
        none_thd = [met("%s_%s" % (base, ld)) for ld, _ in report.LOADS]
        prop = [met("fstp_voltage_proposed_%s" % ld) for ld, _ in report.LOADS]
        ok = full and all(v > 15.0 for v in imbs.values()) and all(
            a and b and a["thd40_total_pct"] > b["thd40_total_pct"] for a, b in zip(none_thd, prop))
        desc = "very non-sinusoidal and unbalanced currents at every load, full load included"
        crit = "every load: imbalance > 15 % and THD 2..40 above the proposed scheme's"
    else:
        none = [met("fstp_voltage_none_%s" % ld) for ld, _ in report.LOADS]
        ok = full and all(a and a.get("fundamental_a") and imbs[ld] < imb(a["fundamental_a"])
                          for (ld, _), a in zip(report.LOADS, none))
        desc = "enhanced against no compensation, but currents still above the demand (Table IX 2.53 / 2.37 / 2.41 A)"
        crit = "every load: imbalance below the uncompensated scheme's"
    return entry(fig, "reproduced" if ok else "deviates", meas, {"description": desc},
                 "checked: " + crit + ("" if ok else "; fails at " + ", ".join(
                     "%s (%.1f %%)" % (k, v) for k, v in imbs.items() if fig in ("Fig. 12", "Fig. 17") and v > BALANCED_PCT)),
                 png)


def table_x(allm):
    """Table X in full, and the paper's conclusion "the FSTP with the proposed compensation performs like
    the SSTP" (it states: THD and TRF lower than the SSTP with compensation [29]) per metric."""
    paper, ours, tol_ok, off = {}, {}, True, []
    for stem, label, _, x in report.PAPER:
        m = allm.get(stem, (None, ""))[0]
        paper[label] = "torque %.4f N*m, THD %.2f %%, TRF %.2f %%" % x
        if not m:
            ours[label] = "run failed"
            tol_ok = False
            continue
        ours[label] = ("torque %.4f N*m (true %.4f), THD %.2f %% (2..40: %.2f %%), TRF %.1f %% (1 kHz sensor %.1f %%, "
                       "estimate %.1f %%)" % (m["torque_est_mean_nm"], m["torque_mean_nm"], m["thd_total_pct"],
                                              m["thd40_total_pct"], m["trf_pct"], m["trf_filtered_pct"], m["trf_est_pct"]))
        if abs(m["torque_est_mean_nm"] / x[0] - 1.0) > 0.05:
            tol_ok = False
            off.append("%s %.4f against %.4f" % (label, m["torque_est_mean_nm"], x[0]))
    p, s = allm.get("fstp_voltage_proposed_full", (None,))[0], allm.get("sstp_voltage_simple_full", (None,))[0]
    concl = {}
    if p and s:
        for key, lab in (("thd_total_pct", "THD full band"), ("thd40_total_pct", "THD 2..40"), ("trf_pct", "TRF true"),
                         ("trf_filtered_pct", "TRF 1 kHz sensor"), ("trf_est_pct", "TRF estimate")):
            concl[lab] = "FSTP proposed %.2f vs SSTP [29] %.2f: %s" % (
                p[key], s[key], "holds (lower)" if p[key] <= s[key] else
                ("like (within 10 %%)" if p[key] <= 1.1 * s[key] else "does NOT hold"))
        e_p, e_s = abs(p["torque_est_mean_nm"] / 0.3 - 1), abs(s["torque_est_mean_nm"] / 0.3 - 1)
        concl["torque estimate error"] = "FSTP proposed %.1f %% vs SSTP [29] %.1f %%: %s" % (
            100 * e_p, 100 * e_s, "holds" if e_p <= e_s + 0.01 else "does NOT hold")
        ip, is_ = imb(p["fundamental_a"]), imb(s["fundamental_a"])
        concl["current imbalance"] = "FSTP proposed %.1f %% vs SSTP [29] %.1f %%: %s" % (
            ip, is_, "holds" if ip <= is_ + 2.0 else "does NOT hold")
    ours["conclusion: FSTP proposed performs like the SSTP, per metric"] = concl
    paper["conclusion"] = ("FSTP with the proposed compensation: THD 7.16 % and TRF 86.27 % lower than the SSTP "
                           "with compensation [29] (8.99 %, 89.15 %)")
    held = [k for k, v in concl.items() if "NOT" not in v]
    ok = tol_ok and len(held) == len(concl) and concl
    reason = ("checked: every predicted torque within 5 %% of the paper's (%s); the conclusion holds for %s%s. "
              "Full-band THD counts the switching ripple the paper's figure leaves out (its definition, eq. 39, "
              "sums to infinity but its analyser's band is not stated); TRF depends on the torque sensor's "
              "bandwidth, not stated." % ("yes" if tol_ok else "no: " + "; ".join(off), ", ".join(held) or "no metric",
                                          "; not for " + ", ".join(k for k in concl if k not in held)
                                          if len(held) < len(concl) else ""))
    return entry("Table X", "reproduced" if ok else "deviates", ours, paper, reason)


# The uncompensated voltage model's torque over-estimate (Hoang Table X) against the size of the device drops
# the estimator leaves out: (label, share of Hoang Table IV's drops, overrides).
DROP_STEPS = [("ideal devices", 0.0, {"inverter.drops": "false"}),
              ("half of Table IV", 0.5, {"inverter.v_ce_v": "0.45", "inverter.v_d_v": "0.625", "inverter.r_on_ohm": "0.0375"}),
              ("Table IV", 1.0, {}),
              ("Table IV, dead time not compensated", 1.0, {"control.deadtime_comp": "false"})]


def table_x_drops(ctx, sets, tx):
    """Adds to Table X's entry the uncompensated rows' predicted torque under DROP_STEPS, and the share of
    Table IV's drops at which each row meets the paper's predicted torque (linear between the steps)."""
    keys = sorted({k for _, _, d in DROP_STEPS for k in d})
    res, share = {}, {}
    for topo, paper_t in (("sstp", 0.3296), ("fstp", 0.3345)):
        stem = "%s_voltage_none_full" % topo
        base = scenario_values(ctx, stem, keys, sets)
        rows, _ = zip_sweep(ctx, "tx_drops_" + topo, stem, [dict(base, **d) for _, _, d in DROP_STEPS], sets)
        res[topo.upper()] = {lab: r(row.get("torque_est_mean_nm"), 4) for (lab, _, _), row in zip(DROP_STEPS, rows)}
        pts = [(f, row.get("torque_est_mean_nm")) for (lab, f, _), row in zip(DROP_STEPS[:3], rows[:3])]
        share[topo.upper()] = None
        for (f0, t0), (f1, t1) in zip(pts, pts[1:]):
            if t0 is not None and t1 is not None and min(t0, t1) <= paper_t <= max(t0, t1) and t1 != t0:
                share[topo.upper()] = f0 + (paper_t - t0) / (t1 - t0) * (f1 - f0)
        if share[topo.upper()] is None and pts[-1][1] is not None and pts[-1][1] < paper_t:
            share[topo.upper()] = "above 1 (Table IV's drops give %.4f N*m)" % pts[-1][1]
    tx["measured"]["uncompensated predicted torque against the device drops (N*m)"] = res
    fmt = lambda v: "%.2f" % v if isinstance(v, float) else str(v)  # noqa: E731
    tx["reason"] += (
        " The uncompensated rows' torque over-estimate is the device drops the estimator leaves out (measured: "
        "SSTP %s N*m, FSTP %s N*m for %s): the paper's SSTP 0.3296 N*m is met at %s of Table IV's drops, its FSTP "
        "0.3345 N*m at %s, so no one drop size gives both rows; with the dead time left uncompensated the SSTP "
        "gives %s N*m (the firmware's dead-time handling enters this estimate too, not isolated further; the paper's "
        "dead time and its compensation are not printed)." % (
            " / ".join(str(v) for v in list(res["SSTP"].values())[:3]),
            " / ".join(str(v) for v in list(res["FSTP"].values())[:3]),
            " / ".join(lab for lab, _, _ in DROP_STEPS[:3]), fmt(share["SSTP"]), fmt(share["FSTP"]),
            res["SSTP"]["Table IV, dead time not compensated"]))


def fig14(ctx, sets):
    cases = []
    for _, _, bal, nonideal in FIG14:
        c = dict(BALANCED_EMF) if bal else scenario_values(ctx, "fstp_voltage_none_full", list(BALANCED_EMF))
        c["inverter.drops"] = "true" if nonideal else "false"
        cases.append(c)
    rows, cmd = zip_sweep(ctx, "fig14", "fstp_voltage_none_full", cases, FIG14_SETS + list(sets), keep=True)
    meas = {}
    for (tag, what, _, _), row in zip(FIG14, rows):
        meas["%s %s" % (tag, what)] = row_summary(row)
    v = [row_summary(row) for row in rows]
    ok = all(x["imbalance_pct"] is not None for x in v) and v[0]["imbalance_pct"] <= 5.0 \
        and v[1]["imbalance_pct"] > v[0]["imbalance_pct"] and v[2]["thd40_total_pct"] > 2 * v[0]["thd40_total_pct"] \
        and v[3]["imbalance_pct"] > v[2]["imbalance_pct"] and v[3]["thd40_total_pct"] >= v[2]["thd40_total_pct"]
    png = currents_figure(ctx, "fig14", "Fig. 14: voltage-model DTC, FSTP, no compensation, 1500 rpm, full load "
                          "(stiff link, no dead time)", [("%s %s" % (t, w), row["run_dir"]) for (t, w, _, _), row in zip(FIG14, rows)])
    return entry("Fig. 14", "reproduced" if ok else "deviates", meas,
                 {"description": "(a) sinusoidal; (b) unbalanced in magnitude; (c) distorted; (d) more severe distortion"},
                 "checked: (a) imbalance <= 5 %; (b) more unbalanced than (a); (c) THD 2..40 more than twice (a)'s; "
                 "(d) more unbalanced and at least as distorted as (c). Command: " + cmdline(cmd), png)


def flux_entries(ctx, hdir):
    out = []
    res = {}
    for fig, (stem, what) in FLUX_FIGS.items():
        run = os.path.join(hdir, stem)
        try:
            res[fig] = flux_fundamentals(run)
            png = flux_figure(ctx, fig.replace(". ", "").lower() + "b", "%s (b): DTC, FSTP, %s, 1500 rpm, full load"
                              % (fig, what), run)
        except (OSError, ValueError) as e:
            res[fig], png = {"error": str(e)}, None
        res[fig]["figure"] = png
    u = {f: v.get("alpha_beta_fund_imbalance_pct") for f, v in res.items()}
    paper = {"Fig. 5": "alpha and beta peaks forced equal by the DTC, fundamentals and harmonics clearly different",
             "Fig. 6": "still a considerable difference between alpha and beta (fundamental and harmonics)",
             "Fig. 7": "imbalance between alpha and beta significantly reduced",
             "Fig. 8": "natural balance between alpha and beta"}
    have = None not in u.values()
    pk5 = res["Fig. 5"].get("alpha_beta_peak_imbalance_pct")
    checks = {"Fig. 5": have and u["Fig. 5"] > 2 * u["Fig. 7"] and u["Fig. 5"] > 3.0 and pk5 is not None
              and pk5 < 0.5 * u["Fig. 5"],
              "Fig. 6": have and u["Fig. 6"] > u["Fig. 7"] and u["Fig. 6"] < u["Fig. 5"],
              "Fig. 7": have and u["Fig. 7"] < 0.5 * u["Fig. 5"],
              "Fig. 8": have and u["Fig. 8"] < 2.0}
    crit = {"Fig. 5": "alpha/beta fundamental imbalance above 3 % and above twice the proposed scheme's; under DTC "
                      "(b) the peaks within half that (the comparators force them equal), under ITC (a) the "
                      "fundamentals further apart than under DTC",
            "Fig. 6": "between the proposed scheme's and the uncompensated one's",
            "Fig. 7": "below half the uncompensated scheme's",
            "Fig. 8": "below 2 %"}
    itc = itc_sets(ctx)
    itc_res = {}
    if itc is not None:
        # Hoang Figs. 5-8 (a): the same four full-load scenarios under ITC, the estimator running as an observer.
        ctx.progress("hoang: Figs. 5-8 (a) under ITC (4 runs)")
        stems = [v[0] for v in FLUX_FIGS.values()]
        runs, _ = report.sweep_series(ctx.dtc_sil, SCEN, hdir, "sweep_itc", stems, list(itc), ctx.jobs, suffix="_itc")
        for fig, (stem, what) in FLUX_FIGS.items():
            run = os.path.join(hdir, stem + "_itc")
            try:
                itc_res[fig] = flux_fundamentals(run)
                itc_res[fig]["fault"] = (runs[stem][0] or {}).get("fault", runs[stem][1])
                itc_res[fig]["figure"] = flux_figure(ctx, fig.replace(". ", "").lower() + "a",
                                                     "%s (a): ITC, FSTP, %s, 1500 rpm, full load" % (fig, what), run)
            except (OSError, ValueError) as e:
                itc_res[fig] = {"error": "%s (%s)" % (e, runs[stem][1])}
    ua = {f: v.get("alpha_beta_fund_imbalance_pct") for f, v in itc_res.items()}
    have_a = len(ua) == 4 and None not in ua.values()
    checks_a = {"Fig. 5": have_a and ua["Fig. 5"] > 2 * ua["Fig. 7"] and ua["Fig. 5"] > 3.0 and have
                and ua["Fig. 5"] > u["Fig. 5"],
                "Fig. 6": have_a and ua["Fig. 7"] < ua["Fig. 6"] < ua["Fig. 5"],
                "Fig. 7": have_a and ua["Fig. 7"] < 0.5 * ua["Fig. 5"],
                "Fig. 8": have_a and ua["Fig. 8"] < 2.0}
    for fig in FLUX_FIGS:
        png = res[fig].pop("figure", None)
        out.append(entry(fig + " (b)", "reproduced" if checks[fig] else "deviates", res[fig],
                         {"description": paper[fig]}, "checked: %s (estimated flux, last 0.4 s)" % crit[fig], png))
        # HOOK: Hoang Figs. 5-8 (a) run when itc_sets() finds the ITC law in dtc-sil.
        if itc is None:
            out.append(entry(fig + " (a)", "deviates", {}, {"description": paper[fig] + " (under ITC)"},
                             "not run: needs the ITC law (control.scheme = \"itc\"), which this "
                             "dtc-sil refuses; hoang_items.itc_sets() is the hook and runs it once it is there"))
        else:
            r_ = dict(itc_res[fig])
            png = r_.pop("figure", None)
            out.append(entry(fig + " (a)", "reproduced" if checks_a[fig] else "deviates", r_,
                             {"description": paper[fig] + " (under ITC)"},
                             "checked under ITC (%s): %s (estimated flux, last 0.4 s)" % (" ".join(itc), crit[fig]), png))
    return out


STIFF = {"inverter.finite_dc_link": "false"}
IDEAL_DEVICES = {"inverter.v_ce_v": "0", "inverter.v_d_v": "0", "inverter.r_on_ohm": "0"}
# Hoang Figs. 18-20: the proposed FSTP's imbalance with one cause removed at a time (label, overrides);
# the figure's own run (Table VII back-EMF, finite link, Table IV devices, 1 us dead time) is the reference.
LOW_CAUSES = [
    ("balanced back-EMF", dict(BALANCED_EMF)),
    ("balanced back-EMF, stiff link", dict(BALANCED_EMF, **STIFF)),
    ("balanced back-EMF, stiff link, ideal devices", dict(BALANCED_EMF, **STIFF, **IDEAL_DEVICES)),
    ("balanced back-EMF, stiff link, polarity from one sample", dict(BALANCED_EMF, **STIFF, **{"control.polarity_mid": "false"})),
    ("balanced back-EMF, no dead time", dict(BALANCED_EMF, **{"inverter.dead_time_s": "0"})),
    ("Table VII back-EMF, stiff link, ideal devices", dict(STIFF, **IDEAL_DEVICES)),
]

def low_finding(c, n_seeds, law, k):
    """The measured reason of a low-speed figure (Hoang Figs. 18-20) from its LOW_CAUSES row c, the ideal
    law (hoang_emf) at the run's torque and the share k of Table VII the paper's Table IX shows."""
    return (
        "Measured ('low-speed causes', imbalance %%, mean over %d seed(s), causes removed from the figure's run): "
        "the back-EMF of Table VII. On the stiff link with ideal devices, where nothing else is left, Table VII's "
        "back-EMF gives %s %%, balanced back-EMF %s %%: the voltage model estimates the true flux, whose PM part is "
        "unbalanced, and the DTC holds that estimate circular, so the current carries the PM flux's negative "
        "sequence, of nearly fixed size, a large part of these 0.6-0.8 A (as at Fig. 17's light loads). With "
        "balanced back-EMF the rest is the plant's: on the finite split link %s %%, on the stiff link %s %% (the "
        "mid-point swings with phase A's current, I / (2 C w), 1.2 V at 700 rpm, and the reconstruction's "
        "restoring part, dtc.c dtc_vmid_beta, leaves an inductance error l_s / 8 on phase A below 1007 rpm); without "
        "the 1 us dead time %s %%. The drop compensation's polarity within a period matters at these "
        "currents: the 50 us ripple (0.55 A pk-pk at zero bands) crosses zero inside about a third of the periods, "
        "where a leg's drop changes by V_CE + V_d; the firmware averages each leg's drop over the period's current "
        "(vcomp.h vcomp_leg_drop_lin), and with the polarity of one sample per period instead the stiff-link "
        "imbalance is %s %%. The ideal law (tools/report/hoang_emf.py: no inverter, no sampling) on Table VII's "
        "machine at this run's %.3f N*m gives %.1f %%; with Table VII's imbalance at the share k = %.2f the "
        "paper's Table IX shows (Fig. 17's reason) the figure's run gives %s %%." % (
            n_seeds, c["Table VII back-EMF, stiff link, ideal devices"], c["balanced back-EMF, stiff link, ideal devices"],
            c["balanced back-EMF"], c["balanced back-EMF, stiff link"], c["balanced back-EMF, no dead time"],
            c["balanced back-EMF, stiff link, polarity from one sample"], law["torque_nm"], law["imbalance_pct"], k,
            c.get("Table VII x %.2f" % k)))


def low_speed_causes(ctx, seeds, sets, k):
    """{rpm: {label: mean imbalance %}} of LOW_CAUSES and of Table VII's imbalance scaled by k for the
    proposed FSTP at each speed of Figs. 18-20."""
    import tomllib
    with open(os.path.join(SCEN, "fstp_voltage_proposed_full.toml"), "rb") as f:
        g = tomllib.load(f)["motor"]["emf_gain"]
    causes = LOW_CAUSES + [("Table VII x %.2f" % k,
                            {"motor.emf_gain": "[%s]" % ", ".join("%.5f" % (1.0 + k * (x - 1.0)) for x in g)})]
    keys = sorted({kk for _, d in causes for kk in d} | {"sensors.seed"})
    res = {}
    for rpm, _ in report.LOW_SPEED:
        rs = sets + report.LOW_SETS + ["control.speed_ref_rpm=%d" % rpm]
        base = scenario_values(ctx, "fstp_voltage_proposed_full", keys, rs)
        cases = [dict(base, **d, **{"sensors.seed": sd}) for _, d in causes for sd in seeds]
        rows, _ = zip_sweep(ctx, "low%d_causes" % rpm, "fstp_voltage_proposed_full", cases, rs)
        res[rpm] = {}
        for i, (lab, _) in enumerate(causes):
            vals = [imb(fund3(row)) for row in rows[i * len(seeds):(i + 1) * len(seeds)] if fund3(row)]
            res[rpm][lab] = r(np.mean(vals), 1) if vals else None
    return res


def low_speed_entries(ctx, hdir, sets, seeds, k):
    out = []
    low = {}
    for rpm, stems in report.LOW_SPEED:
        res, _ = report.sweep_series(ctx.dtc_sil, SCEN, hdir, "sweep_low%d" % rpm, stems,
                                     sets + report.LOW_SETS + ["control.speed_ref_rpm=%d" % rpm], ctx.jobs,
                                     suffix="_low%d" % rpm)
        low[rpm] = res
    causes = low_speed_causes(ctx, seeds, sets, k)
    desc = {700: "sinusoidal with both compensations, clearly better than without (a); proposed (c) lower "
                 "magnitudes than simple (b)",
            300: "simple (a) and proposed (b) run; the uncompensated drive cannot run below 700 rpm",
            200: "proposed compensation: sinusoidal currents at 200 rpm"}
    for fig, rpm in (("Fig. 18", 700), ("Fig. 19", 300), ("Fig. 20", 200)):
        meas, panels = {}, []
        for stem in dict(report.LOW_SPEED)[rpm]:
            m, err = low[rpm].get(stem, (None, "not run"))
            label = stem.replace("fstp_voltage_", "").replace("_full", "")
            panels.append((label, os.path.join(hdir, "%s_low%d" % (stem, rpm))))
            meas[label] = ({"fundamental_a": [r(x, 3) for x in m["fundamental_a"]], "imbalance_pct": r(imb(m["fundamental_a"]), 1),
                            "speed_mean_rpm": r(m["speed_mean_rpm"], 1), "thd40_total_pct": r(m.get("thd40_total_pct"), 1),
                            "fault": m["fault"]} if m and m.get("fundamental_a") else "run failed: %s" % err)
        prop = meas.get("proposed")
        ok = isinstance(prop, dict) and prop["fault"] == "none" and prop["imbalance_pct"] <= BALANCED_PCT \
            and abs(prop["speed_mean_rpm"] / rpm - 1) < 0.01
        meas["low-speed causes (proposed, imbalance %%, mean over %d seeds)" % len(seeds)] = causes[rpm]
        if rpm == 700:
            nn = meas.get("none")
            ok = ok and isinstance(nn, dict) and nn["imbalance_pct"] > prop["imbalance_pct"]
        png = currents_figure(ctx, "fig%s" % fig.split()[1].strip("."), "%s: voltage-model DTC, FSTP, %d rpm, 25 %% load"
                              % (fig, rpm), panels)
        c = causes[rpm]
        law = None
        if isinstance(prop, dict):
            mp = low[rpm][[st for st in dict(report.LOW_SPEED)[rpm] if "proposed" in st][0]][0]
            law = ideal_law(ctx, "fstp_voltage_proposed_full", mp["torque_mean_nm"])
            law["torque_nm"] = mp["torque_mean_nm"]
            meas["ideal law on Table VII's machine at the run's torque (hoang_emf)"] = {
                "torque_nm": r(law["torque_nm"], 4), "imbalance_pct": r(law["imbalance_pct"], 1)}
        out.append(entry(fig, "reproduced" if ok else "deviates", meas, {"description": desc[rpm]},
                         "checked: proposed scheme without fault, mean speed within 1 %%, imbalance <= %.0f %%%s. %s"
                         % (BALANCED_PCT, " and below the uncompensated one's" if rpm == 700 else "",
                            "" if ok or law is None else low_finding(c, len(seeds), law, k)),
                         png))
    return out, low
