#!/usr/bin/python3
"""Casadei et al. 2006: the items of the one-command report (tools/report/papers.py) for Figs. 6-7,
9-10, 19-20, 21, 22-24, 25, 35-36 and Table 5, each measured on the SIL or from the paper's
equations with the configured machine, as status.json entries.

    items(ctx) -> list of dict

ctx: out_dir (figures are written under out_dir/casadei/), short (ctest short mode: fewer sweep
points), dtc_sil (the dtc-sil binary; sil_im_casadei is taken from the same folder), jobs (cores),
progress(msg). Each entry: paper, item, status ("reproduced" | "deviates" | "not applicable"),
measured ({"summary": text}), paper_values ({"description": what the paper says}), reason, figure
(relative to out_dir), paper_figure_note: the entry format of papers.py's status.json.

Standalone: /usr/bin/python3 tools/report/casadei_items.py --out DIR [--short] [--exe build/host/bin/dtc-sil]
writes DIR/casadei_items.json; exit status 1 when an item's run failed or its figure is missing.
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import types

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import im_linear  # noqa: E402

SCN = os.path.join(ROOT, "tools", "scenarios", "im_dtc_speed.toml")
SCN2 = os.path.join(ROOT, "tools", "scenarios", "im_second_machine.toml")


def _toml(path):
    import tomllib
    with open(path, "rb") as f:
        return tomllib.load(f)


def _entry(item, status, measured, paper_says, reason="", figure=None, note=""):
    e = {"paper": "casadei", "item": item, "status": status, "measured": {"summary": measured},
         "paper_values": {"description": paper_says}, "reason": reason, "paper_figure_note": note}
    if figure:
        e["figure"] = figure
    return e


def _held_sets(rpm, torque, extra=(), duration=None, window=0.2):
    """Torque mode from standstill; the dynamometer takes the rotor to rpm after the magnetisation."""
    s = {"control.mode": "torque", "control.torque_ref_nm": "%.6g" % torque, "load.type": "speed",
         "load.speed_rpm": "%.6g" % rpm, "load.speed_ramp_start_s": 0.6, "load.speed_ramp_s": 0.3,
         "load.step_time_s": 0, "metrics_window_s": window, "duration_s": duration or (0.9 + 0.2 + window)}
    s.update(dict(extra))
    return s


def _run(ctx, scenario, sets, name, trace=False, decimate=1):
    out = os.path.join(ctx.work, name)
    shutil.rmtree(out, ignore_errors=True)
    cmd = [ctx.dtc_sil, "run", scenario, "--out", out, "--quiet"]
    cmd += ["--decimate", str(decimate)] if trace else ["--no-trace"]
    for k, v in sets.items():
        cmd += ["--set", "%s=%s" % (k, v)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if not os.path.exists(os.path.join(out, "metrics.json")):
        raise RuntimeError("%s: %s" % (name, (p.stderr or p.stdout).strip()[-400:]))
    with open(os.path.join(out, "metrics.json")) as f:
        m = json.load(f)
    tr = np.genfromtxt(os.path.join(out, "trace.csv"), delimiter=",", names=True) if trace else None
    return m, tr


def _sweep(ctx, scenario, sets, grids, name):
    out = os.path.join(ctx.work, name)
    shutil.rmtree(out, ignore_errors=True)
    cmd = [ctx.dtc_sil, "sweep", scenario, "--out", out, "-q", "--jobs", str(ctx.jobs)]
    for k, v in sets.items():
        cmd += ["--set", "%s=%s" % (k, v)]
    for k, vals in grids:
        cmd += ["--grid", "%s=%s" % (k, ",".join("%.6g" % v for v in vals))]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 3):
        raise RuntimeError("%s: %s" % (name, p.stderr.strip()[-400:]))
    with open(os.path.join(out, "summary.csv")) as f:
        return list(csv.DictReader(f))


# ---- Casadei Fig. 21 ----------------------------------------------------------------------------------
# The SIL points of tests/sil/test_im_stability.cpp: (w_s rad/s, tau s), slip 5 rad/s, SFVC, ideal
# devices (Casadei eqs. 26-28 assume no mismatch).
FIG21_POINTS = [(-40.0, 0.003), (-40.0, 0.0005), (-30.0, 0.002), (-30.0, 0.001), (-20.0, 0.01), (-20.0, 0.001),
                (-10.0, 0.01), (-10.0, 0.002), (20.0, 0.001)]


def fig21(ctx):
    sc = _toml(SCN)
    mach = im_linear.Machine.from_scenario(SCN)
    psir = sc["control"]["rotor_flux_ref_wb"]
    w_sl = 5.0
    torque = 1.5 * mach.p * psir * psir * w_sl / mach.rr
    marks, rows, agree = [], [], 0
    for ws, tau in FIG21_POINTS:
        w0 = ws - w_sl
        rpm = w0 * 30.0 / math.pi / mach.p
        re_ = mach.dominant_re(w0, w_sl, tau)
        m, tr = _run(ctx, SCN, _held_sets(rpm, torque, {"control.scheme": "sfvc", "control.observer_tau_s": tau,
                                                        "inverter.drops": "false", "control.compensation": "none"},
                                          duration=3.0, window=2.0), "fig21_%g_%g" % (ws, tau), trace=True, decimate=25)
        w = tr["t_s"] >= 1.0
        psi = np.hypot(tr["psi_alpha_wb"][w], tr["psi_beta_wb"][w])
        spread = (psi.max() - psi.min()) / psi[0]
        sil_stable = spread < 0.05 and m["fault"] == "none"
        agree += int(sil_stable == (re_ < 0))
        marks.append((ws, tau, sil_stable, ""))
        rows.append("w_s %+.0f rad/s (%.0f rpm), tau %g s: map %+.2f 1/s, SIL |phi_s| spread %.0f %%%s" %
                    (ws, rpm, tau, re_, 100 * spread, ", " + m["fault"] if m["fault"] != "none" else ""))
    png = os.path.join("casadei", "fig21.png")
    im_linear.plot_fig21(mach, os.path.join(ctx.out_dir, png), w_sl, marks,
                         "Fig. 21, default IM, slip 5 rad/s: Re of the dominant pole (hatched/red: unstable);\n"
                         "SIL at T* = %.1f N*m: o held, x lost (ideal devices)" % torque)
    chk = subprocess.run([ctx.dtc_sil, "check", SCN], capture_output=True, text=True).stderr.strip()
    ok = agree == len(FIG21_POINTS)
    return [_entry("Fig. 21", "reproduced" if ok else "deviates",
                   "map from eqs. 26-28 for the configured machine (tools/report/im_linear.py, C twin "
                   "tools/config/im_tau_check.c); stable for every w_s > 0, unstable for small negative w_s with a "
                   "short tau, a longer tau removes it; SIL agrees at %d of %d points: %s. dtc-sil check on "
                   "im_dtc_speed.toml: %s" % (agree, len(FIG21_POINTS), "; ".join(rows), chk or "no warning"),
                   "for positive w_s always stable; for negative w_s the instability region can be avoided by a "
                   "suitable tau (slip 5 rad/s)",
                   "" if ok else "SIL and map disagree at some points (listed)."
                   " With the plant's device drops (simple compensation) two map-stable points at -30 and -10 "
                   "rad/s lose their flux too (sil.ImStability prints them): the drops' residual voltage error is "
                   "a mismatch eqs. 26-28 leave out",
                   png, "Casadei Fig. 21: contour lines over (w_s, tau), hatched unstable area at negative w_s")]


# ---- Casadei Figs. 6-7 --------------------------------------------------------------------------------
def figs6_7(ctx):
    out = []
    png = os.path.join("casadei", "figs6_7.png")
    fig, axes = plt.subplots(2, 2, figsize=(10, 7.5))
    verdicts = []
    for row, (scn, label) in enumerate(((SCN, "default IM (4 kW, 220 V)"), (SCN2, "second machine (400 V)"))):
        sc = _toml(scn)
        rated = sc["motor"].get("rated_torque_nm", 26.5)
        rated_rpm = sc["motor"].get("rated_speed_rpm", 1440.0)
        flux = sc["control"].get("flux_ref_wb", 0.55)
        fb = [0.0, 0.05, 0.10] if ctx.short else [0.0, 0.02, 0.05, 0.10]
        tb = [0.0, 0.10, 0.20] if ctx.short else [0.0, 0.05, 0.10, 0.20]
        rows = _sweep(ctx, scn, _held_sets(0.5 * rated_rpm, rated, {"control.table": "st-a"}),
                      [("control.flux_band_wb", [f * flux for f in fb]), ("control.torque_band_nm", [t * rated for t in tb])],
                      "figs6_7_%d" % row)
        thd = np.full((len(fb), len(tb)), np.nan)
        fsw = np.full((len(fb), len(tb)), np.nan)
        for r in rows:
            i = int(np.argmin([abs(float(r["control.flux_band_wb"]) - f * flux) for f in fb]))
            j = int(np.argmin([abs(float(r["control.torque_band_nm"]) - t * rated) for t in tb]))
            if r["status"] == "ok":
                thd[i, j] = float(r["thd_total_pct"])
                fsw[i, j] = float(r["switching_freq_hz"])
        # THD falls and f_sw rises as each band narrows (every step of either axis, the other held)
        thd_ok = bool(np.all(np.diff(thd, axis=0) > 0) and np.all(np.diff(thd, axis=1) > 0))
        fsw_ok = bool(np.all(np.diff(fsw, axis=0) < 0) and np.all(np.diff(fsw, axis=1) < 0))
        # the paper's "mainly": the flux band moves the THD more than the torque band, the torque band the f_sw more
        main_thd = (thd[-1, 0] - thd[0, 0]) > (thd[0, -1] - thd[0, 0])
        main_fsw = (fsw[0, 0] - fsw[0, -1]) > (fsw[0, 0] - fsw[-1, 0])
        verdicts.append(thd_ok and fsw_ok)
        for j, t in enumerate(tb):
            axes[row][0].plot([100 * f for f in fb], thd[:, j], "o-", label="torque band %g %%" % (100 * t))
            axes[row][1].plot([100 * f for f in fb], fsw[:, j], "o-", label="torque band %g %%" % (100 * t))
        axes[row][0].set_ylabel("stator-current THD, %% (%s)" % label.split(" (")[0])
        axes[row][1].set_ylabel("mean switching frequency, Hz")
        for a in axes[row]:
            a.set_xlabel("flux band, % of phi_s*")
            a.legend(fontsize=7)
            a.set_title(label + ", ST-A, rated torque, half rated speed", fontsize=8)
        out.append("%s: THD %.1f..%.1f %% (%s), f_sw %.0f..%.0f Hz (%s); flux band mainly THD: %s, torque band "
                   "mainly f_sw: %s" % (label, np.nanmin(thd), np.nanmax(thd), "falls with each band" if thd_ok else
                                        "NOT monotonic", np.nanmin(fsw), np.nanmax(fsw),
                                        "rises as each band narrows" if fsw_ok else "NOT monotonic", main_thd, main_fsw))
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out_dir, png), dpi=100)
    plt.close(fig)
    ok = all(verdicts)
    st = "reproduced" if ok else "deviates"
    meas = "; ".join(out)
    return [_entry("Fig. 6", st, meas, "THD of the stator current against the two bands (ST-A): the flux band mainly "
                   "influences the THD, a significant increase when enlarging it", "" if ok else "see measured", png,
                   "Casadei Fig. 6: THD surface over the flux and torque bands"),
            _entry("Fig. 7", st, meas, "average switching frequency against the two bands (ST-A): the torque band "
                   "mainly influences the switching frequency", "" if ok else "see measured", png,
                   "Casadei Fig. 7: switching-frequency surface over the two bands")]


# ---- Casadei Figs. 9-10 -------------------------------------------------------------------------------
def figs9_10(ctx):
    """Casadei eqs. 13-15 with the configured machine at rated torque and eq. 19's rotor flux."""
    sc = _toml(SCN)
    m = im_linear.Machine.from_scenario(SCN)
    d = im_linear.plant_defaults()
    rs = m.rs
    torque = sc["motor"].get("rated_torque_nm", d["PLANT_DEF_IM_RATED_TORQUE_NM"])
    rated_rpm = sc["motor"].get("rated_speed_rpm", d["PLANT_DEF_IM_RATED_SPEED_RPM"])
    vdc = sc.get("inverter", {}).get("vdc_v", d["PLANT_DEF_IM_VDC_V"])
    ts = sc.get("ts_s", d["PLANT_DEF_IM_TS_S"])
    psir = sc["control"]["rotor_flux_ref_wb"]
    iq = torque * m.lr / (1.5 * m.p * m.m * psir)
    phis = complex(m.ls / m.m * psir, m.sigma * m.ls * iq)  # Casadei eq. 19, rotor-flux frame
    rot = np.exp(-1j * np.angle(phis))  # Casadei Fig. 8: phi_s on the d axis
    phis, phir = phis * rot, psir * rot
    v_amp = 2.0 / 3.0 * vdc  # an active vector of the six-switch inverter
    ang = np.radians(np.arange(0, 360, 15))
    kk = m.m / (m.sigma * m.ls * m.lr)
    res = {}
    for w_label, w in (("zero speed", 0.0), ("rated speed", rated_rpm * math.pi / 30 * m.p)):
        dt1 = -torque * (rs / m.ls + m.rr / m.lr) * ts / m.sigma  # Casadei eq. 14
        v = v_amp * np.exp(1j * ang)
        a = v - 1j * w * phis
        b = 1j * phir
        # Casadei eq. 15 with eq. 12's 3/2 p (amplitude-invariant; eq. 15 prints p); "." the scalar product
        dt2 = 1.5 * m.p * kk * (a.real * b.real + a.imag * b.imag) * ts
        res[w_label] = dt1 + dt2
    png = os.path.join("casadei", "figs9_10.png")
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.8))
    for ax, (lbl, dT) in zip(axes, res.items()):
        for th, x in zip(ang, dT):
            ax.plot([0, abs(x) * math.cos(th)], [0, abs(x) * math.sin(th)], color="g" if x > 0 else "r", lw=2)
        ax.plot([0, 1.1 * max(abs(dT))], [0, 0], "k--", lw=0.6)
        ax.set_aspect("equal")
        ax.set_title("Fig. %s: torque change per 40 us, %s, rated torque\n(green up, red down; segment along v)" %
                     ("9" if lbl == "zero speed" else "10", lbl), fontsize=8)
        ax.set_xlabel("N*m along the voltage direction (phi_s on the d axis)")
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out_dir, png), dpi=100)
    plt.close(fig)
    z, r = res["zero speed"], res["rated speed"]
    pos_z, pos_r = int(np.sum(z > 0)), int(np.sum(r > 0))
    flips = [int(round(math.degrees(t))) for t, a, b in zip(ang, z, r) if a > 0 > b]
    ok = pos_r < pos_z and len(flips) > 0
    meas = ("eqs. 13-15, default IM at rated torque, |v| = 2/3 V_dc, T_c = %g us: torque rises for %d of 24 voltage "
            "directions at zero speed, %d at rated speed; directions %s deg from phi_s raise the torque at zero speed "
            "and lower it at rated speed; largest rise %.2f / %.2f N*m per period" %
            (ts * 1e6, pos_z, pos_r, flips, z.max(), r.max()))
    says = ("along some directions the same stator voltage produces positive torque variations at low speed and "
            "negative at high speed")
    return [_entry("Fig. 9", "reproduced" if ok else "deviates", meas, says, "", png,
                   "Casadei Fig. 9: segments of torque change against the voltage direction, zero speed"),
            _entry("Fig. 10", "reproduced" if ok else "deviates", meas, says, "", png,
                   "Casadei Fig. 10: the same at rated speed")]


# ---- Casadei Figs. 19-20 ------------------------------------------------------------------------------
def figs19_20(ctx):
    sc = _toml(SCN)
    rated = sc["motor"].get("rated_torque_nm", 26.5)
    out = []
    png = os.path.join("casadei", "figs19_20.png")
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, (item, rpm, window, span) in zip(axes, (("Fig. 19", 0.0, 1.0, 0.25), ("Fig. 20", 1120.0, 0.4, 0.025))):
        m, tr = _run(ctx, SCN, _held_sets(rpm, rated, {"control.scheme": "sfvc"}, duration=0.9 + 0.3 + window,
                                          window=window), "fig19_%d" % rpm, trace=True, decimate=1)
        w = tr["t_s"] >= tr["t_s"][-1] - window
        te, est = tr["torque_nm"][w], tr["torque_est_nm"][w]
        err = (est.mean() - te.mean()) / te.mean()
        i_mag = np.hypot(tr["i_alpha_a"][w], tr["i_beta_a"][w]).mean()
        thd = m.get("thd_total_pct")
        t0 = tr["t_s"][w][0]
        z = (tr["t_s"] >= t0) & (tr["t_s"] <= t0 + span)
        ax.plot(1e3 * (tr["t_s"][z] - t0), tr["i_a_a"][z], lw=0.6, label="i_a, A")
        ax.plot(1e3 * (tr["t_s"][z] - t0), tr["torque_est_nm"][z], lw=0.6, label="estimated torque, N*m")
        ax.plot(1e3 * (tr["t_s"][z] - t0), tr["torque_nm"][z], lw=0.6, label="plant torque, N*m")
        ax.set_title("%s: SFVC, %s" % (item, "locked rotor" if rpm == 0 else "%g rpm" % rpm), fontsize=9)
        ax.set_xlabel("ms")
        ax.legend(fontsize=7)
        ok = m["fault"] == "none" and abs(err) < 0.05 and abs(te.mean() / rated - 1) < 0.05
        out.append((item, ok, "T* %.1f N*m: plant torque %.2f N*m, estimated %.2f N*m (%+.1f %%), |i_s| %.1f A (rated "
                               "%.1f A), current THD %s, f_sw %.0f Hz, fault %s" %
                    (rated, te.mean(), est.mean(), 100 * err, i_mag, sc["motor"].get("rated_current_a", 19.2),
                     "%.2f %%" % thd if thd is not None else "n/a", m.get("switching_freq_hz") or 0, m["fault"])))
    fig.tight_layout()
    fig.savefig(os.path.join(ctx.out_dir, png), dpi=100)
    plt.close(fig)
    res = []
    for item, ok, meas in out:
        res.append(_entry(item, "reproduced" if ok else "deviates", meas,
                          "locked rotor (Fig. 19) and 1120 rpm at rated current (Fig. 20): the current practically "
                          "sinusoidal, the estimated torque matches the measured and the reference",
                          "" if ok else "estimated and plant torque differ by more than 5 %", png,
                          "Casadei %s: motor current and estimated torque traces" % item))
    return res


# ---- tests of sil_im_casadei -------------------------------------------------------------------------
def _gtest(ctx, name):
    exe = os.path.join(os.path.dirname(ctx.dtc_sil), "sil_im_casadei")
    data = os.path.join(ctx.work, "gtest_data")
    os.makedirs(data, exist_ok=True)
    p = subprocess.run([exe, "--gtest_filter=ImCasadei." + name], capture_output=True, text=True,
                       env=dict(os.environ, DTC_FIGURE_DIR=data))
    ok = "[  PASSED  ] 1 test" in p.stdout
    meas = [ln[len("MEASURE "):] for ln in p.stdout.splitlines() if ln.startswith("MEASURE ")]
    return ok, meas, data


def figs22_24(ctx):
    ok, meas, _ = _gtest(ctx, "Figs22To24ImprovedEstimatorErrorBoundedBasicGrows")
    says = ("w = 1 rad/s (electrical: 4.77 rpm here), tau = 0.01 s, rated torque: R_s 10 % low / high: rotor-flux error practically independent "
            "of tau, at the theoretical value; 0.01 A offset: the improved estimator oscillates around the "
            "reference, the basic one grows")
    m = " | ".join(meas)
    res = []
    for item in ("Fig. 22", "Fig. 23"):
        res.append(_entry(item, "reproduced" if ok else "deviates", m, says,
                          "" if ok else "sil.ImCasadei.Figs22To24 failed", None,
                          "Casadei %s: rotor-flux error traces of the improved and the basic estimator" % item))
    f24 = [x for x in meas if x.startswith("Fig24")]
    m24 = re.search(r"at w_s = ([\d.]+) rad/s ([\d.]+) % \(without the offset ([\d.]+) %\)", f24[0]) if f24 else None
    res.append(_entry("Fig. 24", "reproduced" if ok and m24 else "deviates", " | ".join(f24) or m, says,
                      "with 0.25 A (five ADC counts) appearing after the start-up calibration: the paper's 0.01 A is a "
                      "fifth of one count on this rig (+-100 A over 12 bits: 0.049 A), and the firmware measures and "
                      "removes any offset present at start-up with the gates off, so a constant 0.01 A is invisible "
                      "here; scaled linearly from the measured %s %% at 0.25 A, 0.01 A would add about %s %% at w_s, "
                      "below the %s %% the drive shows without an offset. The amplitude eq. 26 predicts is not "
                      "compared (eq. 28's [B] is not in the tools)" %
                      ((m24.group(2), "%.2f" % ((float(m24.group(2)) - float(m24.group(3))) * 0.04), m24.group(3))
                       if m24 else ("?", "?", "?")), None,
                      "Casadei Fig. 24: rotor-flux error with a 0.01 A offset"))
    return res


def fig25(ctx):
    ok, meas, data = _gtest(ctx, "Fig25SensorlessSpeedEstimateFollowsTheSpeed")
    png = None
    try:
        x = np.genfromtxt(os.path.join(data, "fig25.csv"), delimiter=",", names=True)
        png = os.path.join("casadei", "fig25.png")
        fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
        axes[0].plot(x["t_s"], x["speed_rpm"], lw=0.7, label="true speed")
        axes[0].plot(x["t_s"], x["speed_est_rpm"], lw=0.7, label="estimated (no sensor)")
        axes[0].set_ylabel("rpm")
        axes[0].legend(fontsize=7)
        axes[1].plot(x["t_s"], x["te_nm"], lw=0.5)
        axes[1].set_ylabel("plant torque, N*m")
        axes[2].plot(x["t_s"], x["vdc_v"], lw=0.5)
        axes[2].set_ylabel("DC link, V")
        axes[2].set_xlabel("s")
        axes[0].set_title("Fig. 25: sensorless, firmware R_s 10 % low, tau = 0.01 s", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(ctx.out_dir, png), dpi=100)
        plt.close(fig)
    except (OSError, ValueError):
        png = None
    return [_entry("Fig. 25", "reproduced" if ok else "deviates", " | ".join(meas),
                   "sensorless, dR_s = -10 %, tau = 0.01 s: accelerated from 50 to 220 rpm, then decelerated to 0 "
                   "rpm with regenerative braking: the drive follows",
                   ("the speed follows and the braking is regenerative at the shaft (the machine absorbs the rotor's "
                    "kinetic energy); on the DC link no energy comes back: braking at the torque limit on the rotor's "
                    "own inertia (0.0131 kg m^2) lasts a few ms, and its copper and device losses exceed the 3.5 J of "
                    "kinetic energy at 220 rpm (measured above), so the link does not rise")
                   if ok else "sil.ImCasadei.Fig25 failed", png,
                   "Casadei Fig. 25: speed, torque and line current over 2 s")]


def figs35_36(ctx):
    ok, meas, _ = _gtest(ctx, "Figs35And36TorqueStepAt100RpmDtcRisesFasterThanDfoc")
    sc = _toml(SCN)
    rated = sc["motor"].get("rated_torque_nm", 26.5)
    # sec. 13.1: the same mean switching frequency; at 100 rpm, rated torque
    fsw = {}
    for scheme in ("dtc", "dfoc"):
        m, _ = _run(ctx, SCN, _held_sets(100.0, rated, {"control.scheme": scheme}, window=0.3), "fsw35_" + scheme)
        fsw[scheme] = m.get("switching_freq_hz") or 0.0
    m = " | ".join(meas) + " | mean switching frequency at 100 rpm, rated torque: DTC (zero bands) %.0f Hz, DFOC %.0f Hz" % (
        fsw["dtc"], fsw["dfoc"])
    says = "torque step at 100 rpm: DTC better in settling time and maximum overshoot; the PI regulators of DFOC delay it"
    val = {}
    for ln in meas:
        a = re.search(r"(DTC|DFOC), plant torque averaged over ([\d.]+) ms: rise to 90 % ([\d.]+) ms, settling ([\d.-]+) "
                      r"ms, overshoot ([\d.-]+) %", ln)
        if a:
            val[(a.group(1), a.group(2))] = (float(a.group(3)), float(a.group(4)), float(a.group(5)))
    try:
        rise_ok = val[("DTC", "0.48")][0] < val[("DFOC", "0.48")][0]
        settle_ok = val[("DTC", "2")][1] < val[("DFOC", "2")][1]
        over_ok = val[("DTC", "0.48")][2] <= val[("DFOC", "0.48")][2]
    except KeyError:
        rise_ok = settle_ok = over_ok = False
    reproduced = ok and rise_ok and settle_ok and over_ok
    reason = "" if reproduced else (
        "DTC rises faster (the paper's reason, the DFOC's PI delay, shows in the rise: %s) and, on the torque averaged "
        "over 2 ms, settles first (%s); on a 0.48 ms average its settling is late because its torque keeps a "
        "low-frequency wander (the spread spectrum of Fig. 34) whose excursions leave the 5 %% band, not a slow "
        "transient (the trimmed reference is steady from the step on). Overshoot not reproduced: the DFOC's current "
        "PIs have their zero on the stator pole (K_p = sigma L_s w_c, K_i = R_s w_c, w_c = 0.2/Ts, im_dfoc.c), "
        "first-order loops that cannot overshoot; the paper prints no DFOC tuning, and no scenario key sets it. "
        "Equal switching frequency (sec. 13.1) is approached, not met: at 100 rpm the DTC switches at %.0f Hz with "
        "zero bands against the DFOC's %.0f Hz (2/3 of its 6.25 kHz carrier); the 40 us period bounds the DTC, "
        "wider bands only lower it" % ("yes" if rise_ok else "no", "yes" if settle_ok else "no", fsw["dtc"], fsw["dfoc"]))
    res = []
    for item in ("Fig. 35", "Fig. 36"):
        res.append(_entry(item, "reproduced" if reproduced else "deviates", m, says, reason, None,
                          "Casadei %s: %s torque step response" % (item, "DFOC" if item == "Fig. 35" else "DTC")))
    return res


def table5(ctx):
    cmd = [sys.executable, os.path.join(ROOT, "tools", "plot", "casadei_table5.py"), "--exe", ctx.dtc_sil, "--out",
           os.path.join(ctx.work, "table5"), "--jobs", str(ctx.jobs)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    try:
        with open(os.path.join(ctx.work, "table5", "table5.json")) as f:
            cells = json.load(f)
    except OSError:
        cells = []

    def fmt(c):
        r, f = c.get("current_ripple_rms_a"), c.get("switching_freq_hz")
        return "%s %g rpm %g N*m: %s at %s" % (c["scheme"], c["speed_rpm"], c["torque_nm"],
                                               "%.2f A" % r if r is not None else "n/a",
                                               "%.0f Hz" % f if f is not None else "n/a")

    ratio = {}
    for c in cells:
        r = c.get("current_ripple_rms_a")
        if r is None or c["scheme"] not in ("dtc", "dfoc"):
            continue
        i = [1440.0, 720.0, 144.0].index(c["speed_rpm"])
        ref = {"dtc": {26.5: (1.10, 1.57, 1.46), 13.25: (1.09, 1.56, 1.27), 0.0: (1.18, 1.46, 1.21)},
               "dfoc": {26.5: (0.64, 0.63, 0.58), 13.25: (0.64, 0.94, 0.47), 0.0: (0.65, 0.93, 0.34)}}
        ratio.setdefault(c["scheme"], []).append(r / ref[c["scheme"]][c["torque_nm"]][i])
    span = "; ".join("%s/paper %.2f..%.2f" % (k.upper(), min(v), max(v)) for k, v in sorted(ratio.items()))
    return [_entry("Table 5", "deviates", "; ".join(fmt(c) for c in cells) + "; " + span,
                   "three-phase rms current ripple, DFOC 0.34..0.94 A, DTC 1.09..1.57 A, DFOC lower in every cell, "
                   "equal mean switching frequency (4.1 kHz)",
                   ("the paper's finding holds: DFOC below DTC in every cell, also with both at the same switching "
                    "frequency (the DFOC's carrier lowered to the DTC's where the DTC, bounded by its 40 us period, "
                    "cannot reach the DFOC's 4.17 kHz: every cell, 1.1 kHz at 1440 rpm to 4.1 kHz at 144 rpm, as "
                    "the paper notes for high speed). The magnitudes differ (%s): the machine is a substitute for "
                    "the paper's unprinted one (docs/plant.md), whose leakage inductance sets both ripples"
                    % span) if p.returncode == 0 else "tools/plot/casadei_table5.py: " + p.stdout.strip()[-600:],
                   None, "Casadei Table 5")]


def items(ctx):
    ctx.work = os.path.join(ctx.out_dir, "casadei", "runs")
    os.makedirs(ctx.work, exist_ok=True)
    out = []
    for name, fn in (("Fig. 21", fig21), ("Figs. 6-7", figs6_7), ("Figs. 9-10", figs9_10), ("Figs. 19-20", figs19_20),
                     ("Figs. 22-24", figs22_24), ("Fig. 25", fig25), ("Figs. 35-36", figs35_36), ("Table 5", table5)):
        ctx.progress("casadei: %s" % name)
        try:
            out += fn(ctx)
        except Exception as e:  # a failed item is a deviation with its reason, never a missing entry
            out.append(_entry(name, "deviates", "", "", "the run failed: %s" % e))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "casadei_items"))
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "host", "bin", "dtc-sil"))
    ap.add_argument("--short", action="store_true")
    ap.add_argument("--only", help="comma-separated function names (fig21, figs6_7, ...)")
    a = ap.parse_args()
    os.makedirs(os.path.join(a.out, "casadei"), exist_ok=True)
    ctx = types.SimpleNamespace(out_dir=a.out, short=a.short, dtc_sil=a.exe, jobs=os.cpu_count() or 1,
                                progress=lambda s: print(s, file=sys.stderr))
    if a.only:
        ctx.work = os.path.join(a.out, "casadei", "runs")
        os.makedirs(ctx.work, exist_ok=True)
        res = []
        for n in a.only.split(","):
            res += globals()[n](ctx)
    else:
        res = items(ctx)
    with open(os.path.join(a.out, "casadei_items.json"), "w") as f:
        json.dump(res, f, indent=1)
    bad = 0
    for e in res:
        print("%-8s %-10s %s" % (e["item"], e["status"], e["measured"]["summary"][:300]))
        if e["status"] not in ("reproduced", "deviates", "not applicable") or e["reason"].startswith("the run failed"):
            print("  FAILED: %s" % e["reason"])
            bad = 1
        if e.get("figure") and not os.path.isfile(os.path.join(a.out, e["figure"])):
            print("  FAILED: figure %s missing" % e["figure"])
            bad = 1
    return bad


if __name__ == "__main__":
    sys.exit(main())
