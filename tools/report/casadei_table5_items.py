#!/usr/bin/python3
"""Casadei et al. 2006, Table 5 (DTC against DFOC: current ripple at equal switching frequency) and
what its figures depend on: the item of the one-command report (casadei_items.py items())."""
import json
import math
import os
import subprocess
import sys

import numpy as np

from casadei_common import ROOT, SCN, SCN2, _entry, _held_sets, _run, _toml, _vdc, im_linear, machine_steady_state  # noqa: F401

# ---- Casadei Table 5: what its figures depend on -------------------------------------------------------
# One cell (720 rpm, rated torque: the DFOC in its linear range, the DTC below the DFOC's switching
# frequency at zero bands) varied one quantity at a time: the leakage inductance (both leakages
# doubled, the firmware's following the plant's), the DC link (x 1.5, trips and sensor ranges
# widened with it), the DTC's sampling period (40 -> 20 us), and the second machine
# (im_second_machine.toml, 400 V, its rated torque). DTC at zero bands, DFOC on its 6.25 kHz
# carrier; the rig's devices and dead time as in Table 5's runs.
T5_VARIANTS = [
    ("default IM", SCN, {}),
    ("leakages x 2", SCN, {"motor.lls_h": 2.0, "motor.llr_h": 2.0}),  # factors of the scenario's machine
    ("DC link x 1.5", SCN, {"inverter.vdc_v": 1.5, "protection.vdc_max_v": 1.5, "sensors.voltage_range_v": 1.6}),
    ("DTC ts 20 us", SCN, {"ts_s": 20e-6}),
    ("second machine", SCN2, {}),
]


def _t5_cell(ctx, scn, extra, scheme, rpm, torque, name):
    f_e = 2 * rpm / 60.0
    window = max(0.2, 3.0 / f_e)
    sets = _held_sets(rpm, torque, dict(extra, **{"control.scheme": scheme, "control.torque_band_nm": 0,
                                                  "control.flux_band_wb": 0}), window=window)
    if scheme == "dfoc":
        sets.pop("control.torque_band_nm")
        sets.pop("control.flux_band_wb")
        sets.pop("ts_s", None)
    m, _ = _run(ctx, scn, sets, name)
    return m


def table5_causes(ctx):
    """[(label, dtc metrics, dfoc metrics)] at 720 rpm, rated torque, for T5_VARIANTS."""
    out = []
    for k, (label, scn, extra) in enumerate(T5_VARIANTS):
        mach = im_linear.Machine.from_scenario(scn)
        base = {"motor.lls_h": mach.lls, "motor.llr_h": mach.llr, "inverter.vdc_v": _vdc(scn),
                "protection.vdc_max_v": _toml(scn).get("protection", {}).get(
                    "vdc_max_v", im_linear.plant_defaults()["PLANT_DEF_IM_VDC_MAX_V"]),
                "sensors.voltage_range_v": _toml(scn).get("sensors", {}).get(
                    "voltage_range_v", im_linear.plant_defaults()["PLANT_DEF_IM_VOLTAGE_RANGE_V"])}
        extra = {key: v * base[key] if key in base else v for key, v in extra.items()}
        rated = _toml(scn)["motor"].get("rated_torque_nm", 26.5)
        d = _t5_cell(ctx, scn, extra, "dtc", 720.0, rated, "t5c_dtc_%d" % k)
        f = _t5_cell(ctx, scn, extra, "dfoc", 720.0, rated, "t5c_dfoc_%d" % k) if "ts_s" not in extra else None
        out.append((label, d, f))
    return out


def table5_equal(ctx):
    """Sec. 13.1's equal switching frequency reached from the DTC's side on the default IM (its period
    halved to 20 us, so that its zero-band frequency exceeds the DFOC's 4167 Hz and its torque band
    is tuned down to it), and Table 5's rated-torque row on the second machine (DTC tuned to the DFOC's
    frequency where it can, else the DFOC's carrier lowered to the DTC's). {(machine, rpm):
    (dtc metrics, dfoc metrics, dfoc at the DTC's frequency or None)}."""
    import concurrent.futures
    sys.path.insert(0, os.path.join(ROOT, "tools", "plot"))
    import casadei_table5 as t5
    target = 2.0 / 3.0 * 6250.0
    jobs = {}
    out = os.path.join(ctx.work, "t5eq")
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, ctx.jobs)) as ex:
        for rpm in t5.SPEEDS:
            jobs[ex.submit(t5.dtc_cell, ctx.dtc_sil, os.path.join(out, "im20"), rpm, 26.5, target, SCN,
                           {"ts_s": 20e-6})] = ("default IM, DTC 20 us", rpm, "dtc")
            jobs[ex.submit(t5.run, ctx.dtc_sil, os.path.join(out, "im20", "dfoc_%d" % rpm), rpm, 26.5,
                           {"control.scheme": "dfoc"}, SCN)] = ("default IM, DTC 20 us", rpm, "dfoc")
            t2 = _toml(SCN2)["motor"]["rated_torque_nm"]
            jobs[ex.submit(t5.dtc_cell, ctx.dtc_sil, os.path.join(out, "m2"), rpm, t2, target, SCN2)] = (
                "second machine", rpm, "dtc")
            jobs[ex.submit(t5.run, ctx.dtc_sil, os.path.join(out, "m2", "dfoc_%d" % rpm), rpm, t2,
                           {"control.scheme": "dfoc"}, SCN2)] = ("second machine", rpm, "dfoc")
        res = {}
        for f in concurrent.futures.as_completed(jobs):
            res[jobs[f]] = f.result()
        eq = {}
        for (mach, rpm, kind), m in list(res.items()):
            f_dtc = m.get("switching_freq_hz") or 0.0
            if kind == "dtc" and "error" not in m and 0.0 < f_dtc < 0.98 * target:
                scn = SCN2 if mach == "second machine" else SCN
                t = _toml(SCN2)["motor"]["rated_torque_nm"] if scn == SCN2 else 26.5
                eq[ex.submit(t5.dfoc_at, ctx.dtc_sil, os.path.join(out, "m2" if scn == SCN2 else "im20"), rpm, t,
                             f_dtc, scn)] = (mach, rpm, "dfoc_eq")
        for f in concurrent.futures.as_completed(eq):
            res[eq[f]] = f.result()
    return res


def _t5_fmt(m):
    if m is None:
        return "-"
    if "error" in m or m.get("fault") != "none":
        return "failed (%s)" % (m.get("error") or m.get("fault"))
    return "%.2f A at %.0f Hz" % (m.get("current_ripple_rms_a") or float("nan"), m.get("switching_freq_hz") or 0.0)


# ---- Casadei Table 5: the DFOC's ripple against the load -------------------------------------------
# The ripple of a PWM inverter on the machine is the volt-seconds each carrier period applies away
# from its mean, over the transient inductance sigma L_s: it depends on the modulation index, the
# voltage vector's angle and the clamping rule, not on the current, so the load moves it only
# through the stator voltage it needs. dpwm_ripple evaluates that for the firmware's two-phase rule
# (svm.h SVM_TWO_PHASE: the leg of the largest |phase voltage| clamped to its rail), centred pulses,
# ideal switches, at the machine's steady state (Casadei eq. 19's stator flux at constant rotor
# flux, v = R_s i + j w_s phi_s in the rotor-flux frame). The SIL measures the same quantity
# (current_ripple_rms_a: the per-phase rms of the current less its fundamental).
def dpwm_ripple(mach, vdc, carrier_hz, v, i=None, rule="voltage", n_angle=240, n_sub=160):
    """Per-phase rms current ripple (A) of centred PWM of the rotor-frame voltage v over one
    electrical turn, ideal switches, one carrier period per angle. rule: "voltage" two-phase, the leg
    of the largest |v_x| clamped (the firmware's); "current" two-phase, of the two legs that can be
    clamped (the highest to its upper rail, the lowest to its lower) the one carrying the larger
    |i_x| (the loss-minimising variant; i the rotor-frame current); "symmetric" min-max injection."""
    tc, sls = 1.0 / carrier_hz, mach.sigma * mach.ls
    th = np.linspace(0.0, 2.0 * math.pi, n_angle, endpoint=False)

    def phases(x):
        x = x * np.exp(1j * th)
        return np.stack([x.real, -0.5 * x.real + math.sqrt(3) / 2 * x.imag, -0.5 * x.real - math.sqrt(3) / 2 * x.imag])
    ph = phases(v) / vdc
    kmax, kmin = ph.argmax(axis=0), ph.argmin(axis=0)
    if rule == "symmetric":
        n0 = -0.5 * (ph.max(axis=0) + ph.min(axis=0))
    else:
        if rule == "current":
            ia = np.abs(phases(i))
            cols = np.arange(n_angle)
            hi = ia[kmax, cols] >= ia[kmin, cols]
        else:
            hi = np.abs(ph.max(axis=0)) >= np.abs(ph.min(axis=0))
        n0 = np.where(hi, 0.5 - ph.max(axis=0), -0.5 - ph.min(axis=0))
    d = np.clip(ph + n0 + 0.5, 0.0, 1.0)  # (3, n_angle)
    t = (np.arange(n_sub) + 0.5) / n_sub * tc
    sw = (np.abs(t[None, None, :] - tc / 2) < d[:, :, None] * tc / 2).astype(float)  # (3, n_angle, n_sub)
    vph = vdc * (sw - sw.mean(axis=0, keepdims=True))
    r = np.cumsum(vph - vph.mean(axis=2, keepdims=True), axis=2) * (tc / n_sub) / sls
    r -= r.mean(axis=2, keepdims=True)
    return float(math.sqrt(np.mean(np.sum(r * r, axis=0) / 3.0)))


T5_PAPER_DFOC = {26.5: (0.64, 0.63, 0.58), 13.25: (0.64, 0.94, 0.47), 0.0: (0.65, 0.93, 0.34)}
# The DFOC at 720 rpm under each change that could bring a load dependence: the devices' drops and
# the dead time (on the rig, off one at a time, both off: Casadei's simulations had neither, sec.
# 13.1), and the current loops at the tuning that reproduces the paper's Fig. 35 (both poles at
# w_c = 0.2/Ts, damping 0.7).
T5_LOAD_VARIANTS = [
    ("rig (drops and dead time)", {}),
    ("no dead time", {"inverter.dead_time": "false", "control.deadtime_comp": "false"}),
    ("ideal devices", {"inverter.drops": "false", "control.compensation": "none"}),
    ("ideal devices, no dead time", {"inverter.drops": "false", "control.compensation": "none",
                                     "inverter.dead_time": "false", "control.deadtime_comp": "false"}),
    ("Fig. 35's placed-pole tuning", {"control.dfoc_bw_hz": 0, "control.dfoc_zeta": 0.7}),
]


def table5_dfoc_load(ctx):
    """The DFOC's ripple at 720 rpm and the three loads under T5_LOAD_VARIANTS (short: the first and
    the fourth), and the two-phase law (dpwm_ripple) at the nine cells: (text, {variant: [A per load]},
    law {(rpm, torque): A})."""
    import concurrent.futures
    mach = im_linear.Machine.from_scenario(SCN)
    sc = _toml(SCN)
    psir = sc["control"]["rotor_flux_ref_wb"]
    vdc, carrier = _vdc(SCN), im_linear.plant_defaults()["PLANT_DEF_IM_CARRIER_HZ"]
    law, other = {}, {}
    for rpm in (1440.0, 720.0, 144.0):
        for t in (26.5, 13.25, 0.0):
            v, i, _ = machine_steady_state(mach, psir, rpm, t)
            law[(rpm, t)] = dpwm_ripple(mach, vdc, carrier, v)
            if rpm == 720.0:
                for rule in ("current", "symmetric"):
                    other.setdefault(rule, []).append(dpwm_ripple(mach, vdc, carrier, v, i, rule))
    variants = [T5_LOAD_VARIANTS[0], T5_LOAD_VARIANTS[3]] if ctx.short else T5_LOAD_VARIANTS
    jobs = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, ctx.jobs)) as ex:
        for k, (label, extra) in enumerate(variants):
            for t in (26.5, 13.25, 0.0):
                jobs[ex.submit(_t5_cell, ctx, SCN, extra, "dfoc", 720.0, t, "t5load_%d_%g" % (k, t))] = (label, t)
        got = {jobs[f]: f.result() for f in concurrent.futures.as_completed(jobs)}
    sil = {label: [(got[(label, t)] or {}).get("current_ripple_rms_a") for t in (26.5, 13.25, 0.0)]
           for label, _ in variants}
    fmt = lambda xs: " / ".join("%.3f" % x if x is not None else "n/a" for x in xs)  # noqa: E731
    ratios = {(rpm, t): T5_PAPER_DFOC[t][(1440.0, 720.0, 144.0).index(rpm)] / law[(rpm, t)] for rpm, t in law}
    txt = ("DFOC at 720 rpm, 26.5 / 13.25 / 0 N*m, A: %s; the paper 0.63 / 0.94 / 0.93. Two-phase modulation's "
           "ripple on this machine (volt-seconds over sigma L_s, ideal switches, tools/report/casadei_items.py "
           "dpwm_ripple): 1440 rpm %s, 720 rpm %s, 144 rpm %s A; the paper's DFOC over it: 1440 rpm %s, 720 rpm %s, "
           "144 rpm %s; at 720 rpm with the loss-minimising two-phase rule (largest current clamped) %s A, with "
           "symmetric SVM %s A" % (
               "; ".join("%s %s" % (label, fmt(v)) for label, v in sil.items()),
               *[fmt([law[(rpm, t)] for t in (26.5, 13.25, 0.0)]) for rpm in (1440.0, 720.0, 144.0)],
               *[" / ".join("%.2f" % ratios[(rpm, t)] for t in (26.5, 13.25, 0.0)) for rpm in (1440.0, 720.0, 144.0)],
               fmt(other["current"]), fmt(other["symmetric"])))
    return txt, sil, law, ratios, other


def table5_load_reason(sil, law, ratios, other):
    """Why the paper's DFOC rises at light load at 720 rpm and ours does not, from table5_dfoc_load's
    measurements (the wording follows the numbers)."""
    j = lambda xs: " / ".join("%.2f" % x for x in xs)  # noqa: E731
    spans = {label: max(v) / min(v) for label, v in sil.items() if all(x for x in v)}
    flat = all(sp < 1.15 for sp in spans.values())
    r720 = [ratios[(720.0, t)] for t in (26.5, 13.25, 0.0)]
    per_speed = {rpm: [ratios[(rpm, t)] for t in (26.5, 13.25, 0.0)] for rpm in (1440.0, 144.0)}
    steady = all(max(v) / min(v) < 1.1 for v in per_speed.values()) and r720[1] / r720[2] < 1.1 and all(
        max(v) / min(v) < 1.15 for v in other.values())
    law720 = [law[(720.0, t)] for t in (26.5, 13.25, 0.0)]
    mach, psir = im_linear.Machine.from_scenario(SCN), _toml(SCN)["control"]["rotor_flux_ref_wb"]
    mi = [abs(machine_steady_state(mach, psir, 720.0, t)[0]) / (_vdc(SCN) / math.sqrt(3)) for t in (26.5, 0.0)]
    law_txt = ("the ripple of a PWM inverter is the volt-seconds each carrier period applies away from its mean over "
               "sigma L_s, so the load reaches it only through the stator voltage; at 720 rpm the modulation index "
               "moves from %.2f to %.2f between rated and no load and two-phase modulation's ripple by %.0f %% (%s A)"
               % (mi[0], mi[1], 100 * (max(law720) / min(law720) - 1), j(law720)))
    sil_txt = ("The SIL follows that law: across the three loads ours changes by at most %.0f %% under every variant "
               "(%s), so neither the dead time nor the device drops (Casadei's Table 5 is simulated without them, sec. "
               "13.1) nor the current loops' tuning makes a load dependence" % (
                   100 * (max(spans.values()) - 1) if spans else float("nan"),
                   ", ".join("%s x %.2f" % (k, v) for k, v in spans.items()))) if flat else (
        "A SIL variant moves with the load by more than 15 %%: %s" % ", ".join(
            "%s x %.2f" % (k, v) for k, v in spans.items()))
    if steady:
        paper_txt = ("The paper's DFOC column is the same law times a factor per speed in eight of its nine cells "
                     "(1440 rpm %s, 144 rpm %s, 720 rpm at half and no load %s: its machine and link, unprinted, set "
                     "the factor); the one cell off the law is 720 rpm at rated torque (x %.2f, where the other two "
                     "720-rpm cells give x %.2f, i.e. %.2f A): the rise at light load is that one low cell, not a load "
                     "dependence that two-phase modulation (either clamping rule) or symmetric SVM of an ideal inverter "
                     "produces (measured)" % (
                         j(per_speed[1440.0]), j(per_speed[144.0]), j(r720[1:]), r720[0], 0.5 * (r720[1] + r720[2]),
                         0.5 * (r720[1] + r720[2]) * law720[0]))
    else:
        paper_txt = ("The paper's DFOC over the law per cell: 1440 rpm %s, 720 rpm %s, 144 rpm %s: no factor per "
                     "speed fits its column" % (j(per_speed[1440.0]), j(r720), j(per_speed[144.0])))
    return "%s. %s. %s" % (law_txt, sil_txt, paper_txt)


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
    causes, cause_txt = table5_causes(ctx), []
    r = lambda m: (m or {}).get("current_ripple_rms_a") or float("nan")  # noqa: E731
    fs = lambda m: (m or {}).get("switching_freq_hz") or float("nan")  # noqa: E731
    base = causes[0]
    for label, d, f in causes:
        cause_txt.append("%s: DTC %s, DFOC %s%s" % (
            label, _t5_fmt(d), _t5_fmt(f),
            "" if label == base[0] else " (x %.2f / %s)" % (r(d) / r(base[1]), "x %.2f" % (r(f) / r(base[2])) if f
                                                           else "-")))
    m2 = _toml(SCN2)["motor"]
    mi = im_linear.Machine.from_scenario(SCN)
    m2i = im_linear.Machine.from_scenario(SCN2)
    vl = (_vdc(SCN2) / (m2i.sigma * m2i.ls)) / (_vdc(SCN) / (mi.sigma * mi.ls))
    meas = ("%s; %s. What the ripples depend on, one quantity at a time at 720 rpm and rated torque (DTC at zero bands, "
            "DFOC on its carrier): %s; V_dc / (sigma L_s) of the second machine (%g V, %s rated %g N*m) is x %.3f of "
            "the default's" % ("; ".join(fmt(c) for c in cells), span, "; ".join(cause_txt),
                               _vdc(SCN2), os.path.basename(SCN2), m2["rated_torque_nm"], vl))
    eq_txt = ""
    if not ctx.short:
        eqr = table5_equal(ctx)
        pd = {1440.0: (1.10, 0.64), 720.0: (1.57, 0.63), 144.0: (1.46, 0.58)}
        rows = []
        for mach in ("default IM, DTC 20 us", "second machine"):
            for rpm in (1440.0, 720.0, 144.0):
                d, f, q = eqr.get((mach, rpm, "dtc")), eqr.get((mach, rpm, "dfoc")), eqr.get((mach, rpm, "dfoc_eq"))
                ref = q if q is not None else f
                rows.append("%s %g rpm: DTC %s (%s), DFOC %s%s; DTC/DFOC at equal f_sw %.2f (paper %.2f)" % (
                    mach, rpm, _t5_fmt(d), (d or {}).get("tuning", ""), _t5_fmt(f),
                    ", at the DTC's frequency %s" % _t5_fmt(q) if q is not None else "", r(d) / r(ref),
                    pd[rpm][0] / pd[rpm][1]))
        eq_txt = ("; sec. 13.1's equal switching frequency at rated torque: " + "; ".join(rows))
        meas += eq_txt
    load_txt, load_sil, law, ratios, other = table5_dfoc_load(ctx)
    meas += "; the DFOC's ripple against the load: " + load_txt
    load_reason = table5_load_reason(load_sil, law, ratios, other)
    reason = ("the paper's finding holds: DFOC below DTC in every cell, also with both at the same switching frequency "
              "(the DFOC's carrier lowered to the DTC's where the DTC, bounded by its 40 us period, cannot reach the "
              "DFOC's 4.17 kHz: every cell here, 1.1 kHz at 1440 rpm to 4.1 kHz at 144 rpm), and on the second machine. "
              "The magnitudes differ (%s), measured: (1) both ripples go as V_dc / (sigma L_s): doubling both leakages "
              "halves them and leaves the DTC's frequency, the second machine (V_dc / sigma L_s x %.2f) scales them by "
              "%.2f / %.2f; the paper's rig (machine and link unprinted) would need about x %.2f of ours for its DFOC "
              "at 720 rpm but x %.2f for its DTC, so no one machine explains both columns; (2) the DTC/DFOC ratio: "
              "the zero-band DTC's frequency is set by its period and by the link against the back-EMF, not by the "
              "leakage (x 1.5 link: %.0f Hz, 20 us: %.0f Hz, against %.0f Hz); at 40 us it stays below the DFOC's "
              "4.17 kHz at 720 rpm (the paper notes it below 4.1 kHz in the high-speed range only); with 20 us and its band tuned to 4.1 kHz (the "
              "criterion met from the DTC's side) its ripple at 720 rpm halves%s; (3) the paper's DFOC at 720 rpm rises "
              "from 0.63 A at rated torque to 0.94 / 0.93 A at half / no load, ours stays flat: %s" % (
                  span, vl, r(causes[4][1]) / r(base[1]), r(causes[4][2]) / r(base[2]), 0.63 / r(base[2]),
                  1.57 / r(base[1]), fs(causes[2][1]), fs(causes[3][1]), fs(base[1]),
                  "" if ctx.short else " (ratios above)", load_reason)) if p.returncode == 0 else (
        "tools/plot/casadei_table5.py: " + p.stdout.strip()[-600:])
    return [_entry("Table 5", "deviates", meas,
                   "three-phase rms current ripple, DFOC 0.34..0.94 A, DTC 1.09..1.57 A, DFOC lower in every cell, "
                   "equal mean switching frequency (4.1 kHz)", reason, None, "Casadei Table 5")]
