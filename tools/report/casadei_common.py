#!/usr/bin/python3
"""The shared part of the Casadei items of the report (casadei_items.py, casadei_table5_items.py): the
scenarios, the status.json entry, dtc-sil runs and sweeps, and the machine's steady state."""
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
    """Torque mode from standstill; the dynamometer takes the rotor to rpm after the magnetisation.
    The figures' condition is Casadei's estimator (eq. 20 with the reference flux), so the product's
    low-speed current-model reference (control.current_model_ref, on by default) is off."""
    s = {"control.mode": "torque", "control.torque_ref_nm": "%.6g" % torque, "load.type": "speed",
         "control.current_model_ref": "false",
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



def _vdc(scn):
    return _toml(scn).get("inverter", {}).get("vdc_v", im_linear.plant_defaults()["PLANT_DEF_IM_VDC_V"])


def machine_steady_state(mach, psir, rpm, torque):
    """(v, i, w_s) in the rotor-flux frame at constant rotor flux (Casadei eqs. 16, 19, A6)."""
    i_d = psir / mach.m
    i_q = torque * mach.lr / (1.5 * mach.p * mach.m * psir)
    w_s = mach.p * rpm * math.pi / 30.0 + mach.m / mach.tau_r * i_q / psir
    i = complex(i_d, i_q)
    phis = complex(mach.sigma * mach.ls * i_d + mach.m / mach.lr * psir, mach.sigma * mach.ls * i_q)
    return mach.rs * i + 1j * w_s * phis, i, w_s
