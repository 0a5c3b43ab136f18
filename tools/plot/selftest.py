#!/usr/bin/python3
"""Self-test of plot_run.py and report.py on synthetic data (no simulator needed).

    /usr/bin/python3 tools/plot/selftest.py [WORK_DIR]

1. Writes a synthetic FSTP run folder (trace.csv + metrics.json with dtc-sil's columns and keys):
   25 Hz currents with switching ripple and an imbalance, torque with ripple, an estimated flux
   with an alpha/beta imbalance like Hoang Fig. 5(b); runs plot_run and checks every PNG.
2. Runs report.py with a stand-in for dtc-sil (this script, --fake-sil) that writes such folders,
   and checks the markdown table carries the paper's (Hoang) Table IX/X values next to the simulated ones.
Exit status 0 = pass. Registered with ctest as sil.plot_selftest.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import plot_run  # noqa: E402

COLUMNS = ("t_s,i_a_a,i_b_a,i_c_a,i_alpha_a,i_beta_a,torque_nm,torque_est_nm,psi_alpha_wb,psi_beta_wb,"
           "psi_alpha_est_wb,psi_beta_est_wb,speed_rpm,sa,sb,sc,vdc_v,en,theta_e_rad,vc_lo_v,v_alpha_v,"
           "v_beta_v,tload_nm")


def synthetic_run(out_dir, scenario="synthetic_fstp", amp=(2.97, 2.37, 3.00), te_est_bias=0.035, seed=1):
    os.makedirs(out_dir, exist_ok=True)
    rng = np.random.default_rng(seed)
    ts, n = 50e-6, 8000
    t = np.arange(n) * ts
    th = 2 * math.pi * 25.0 * t
    i = [amp[p] * np.cos(th - 2 * math.pi * p / 3) + 0.08 * rng.standard_normal(n) for p in range(3)]
    ial = (2 * i[0] - i[1] - i[2]) / 3
    ibe = (i[1] - i[2]) / math.sqrt(3)
    psa = 3.19e-3 * ial + 0.0928 * np.cos(th)
    psb = 3.19e-3 * ibe + 0.0928 * np.sin(th)
    te = 1.5 * (psa * ibe - psb * ial)
    sb = (rng.random(n) < 0.5).astype(int)
    sc = (rng.random(n) < 0.5).astype(int)
    cols = [t, i[0], i[1], i[2], ial, ibe, te, te + te_est_bias, psa, psb, 0.95 * psa, 1.05 * psb,
            np.full(n, 1500.0), np.zeros(n, int), sb, sc, np.full(n, 70.0), np.ones(n, int),
            np.mod(th, 2 * math.pi), np.full(n, 35.0), np.zeros(n), np.zeros(n), np.full(n, 0.3)]
    np.savetxt(os.path.join(out_dir, "trace.csv"), np.column_stack(cols), delimiter=",", header=COLUMNS,
               comments="", fmt="%.9g")
    m = {
        "scenario": scenario, "sim_time_s": n * ts, "wall_time_s": 0.01, "isr_count": n,
        "fundamental_a": list(amp), "imbalance_pct": 100 * (max(amp) / min(amp) - 1),
        "thd_pct": [7.1, 7.3, 7.2], "thd_total_pct": 7.2, "thd40_total_pct": 6.54, "trf_filtered_pct": 61.5, "torque_mean_nm": 0.3,
        "torque_est_mean_nm": 0.3 + te_est_bias, "trf_pct": 88.0, "trf_est_pct": 90.0,
        "speed_mean_rpm": 1500.0, "switching_freq_hz": 5000.0, "flux_est_error_rms_pct": 5.0, "fault": "none",
        "metrics_window": {"t_start_s": 0.2, "t_end_s": 0.39995, "electrical_periods": 5, "f_e_hz": 25.0},
        "config": {"mode": "speed", "topology": "fstp", "estimator": "voltage", "compensation": "none",
                   "load": "generator", "speed_ref_rpm": 1500.0},
    }
    with open(os.path.join(out_dir, "metrics.json"), "w", encoding="utf-8") as f:
        json.dump(m, f, indent=2)


def check_png(path):
    import matplotlib.image as mpimg
    assert os.path.getsize(path) > 10000, f"{path}: suspiciously small"
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    img = mpimg.imread(path)
    assert img.shape[0] >= 400 and img.shape[1] >= 400, f"{path}: {img.shape}"
    # Not a blank canvas: a plotted figure has many distinct colours.
    assert len(np.unique(img.reshape(-1, img.shape[2]), axis=0)) > 20, f"{path}: blank"


def fake_sil(argv):
    """Stand-in for `dtc-sil run SCENARIO --out DIR [...]`: writes a synthetic run folder; for
    `dtc-sil sweep ... --keep-runs --zip K=V1,..` one synthetic run per case in DIR/runs/I and the
    rows in DIR/summary.json; for `dtc-sil keys` the defaults of the keys a scenario file may omit."""
    if argv[0] == "keys":
        print("| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|")
        for k, d in (("inverter.finite_dc_link", "true"), ("initial_speed_rpm", "0"), ("load.torque_nm", "0"),
                     ("load.speed_rpm", "1500")):
            print(f"| `{k}` | x |  | {d} | x | x |")
        return 0
    if argv[0] == "sweep":
        out = argv[argv.index("--out") + 1]
        zipped = argv[argv.index("--zip") + 1].split("=", 1)[1]
        n = zipped.count(",") + 1 - zipped.count("[") * 2  # cases (values hold no arrays here)
        rows = []
        for i in range(n):
            synthetic_run(os.path.join(out, "runs", str(i)), scenario=f"case{i}", amp=(2.2, 2.2, 2.3),
                          te_est_bias=0.0, seed=i + 1)
            rows.append({"run": i, "status": "ok", "fault": "none", "error": None, "values": {}, "metrics": {}})
        with open(os.path.join(out, "summary.json"), "w", encoding="utf-8") as f:
            json.dump({"rows": rows}, f)
        print(f"fake dtc-sil sweep: {n} runs")
        return 0
    scen = argv[argv.index("run") + 1]
    out = argv[argv.index("--out") + 1]
    stem = os.path.splitext(os.path.basename(scen))[0]
    synthetic_run(out, scenario=stem, amp=(2.2, 2.2, 2.3), te_est_bias=0.0, seed=len(stem))
    print(f"fake dtc-sil: {stem}")
    return 0


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--fake-sil":
        return fake_sil(sys.argv[2:])
    work = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="dtc_plot_selftest_")
    shutil.rmtree(work, ignore_errors=True)
    run = os.path.join(work, "run")
    synthetic_run(run)
    outs = plot_run.plot_run(run)
    assert [os.path.basename(p) for p in outs] == ["currents.png", "torque.png", "flux_locus.png",
                                                   "flux_components.png"], outs
    for p in outs:
        check_png(p)
    # Null metrics (a diverged or tripped run) and a trip: every figure is drawn, the trip marked.
    tripped = os.path.join(work, "tripped")
    synthetic_run(tripped)
    tr = plot_run.load_trace(os.path.join(tripped, "trace.csv"))
    with open(os.path.join(tripped, "metrics.json"), encoding="utf-8") as f:
        m = json.load(f)
    for k in ("fundamental_a", "imbalance_pct", "thd_total_pct", "torque_est_mean_nm", "trf_est_pct",
              "flux_est_error_rms_pct", "switching_freq_hz", "torque_mean_nm", "trf_pct", "speed_mean_rpm"):
        m[k] = None
    m["thd_pct"] = [None, 7.0, None]
    m["fault"] = "overcurrent"
    m["fault_detail"] = "synthetic trip"
    m["fault_time_s"] = None
    with open(os.path.join(tripped, "metrics.json"), "w", encoding="utf-8") as f:
        json.dump(m, f)
    # Gates off from t = 0.3 s on: the trip time comes from the trace's en column.
    data = np.loadtxt(os.path.join(tripped, "trace.csv"), delimiter=",", skiprows=1)
    data[data[:, 0] >= 0.3, 17] = 0
    data[data[:, 0] >= 0.3, 1:4] = 0
    np.savetxt(os.path.join(tripped, "trace.csv"), data, delimiter=",", header=COLUMNS, comments="", fmt="%.9g")
    tr = plot_run.load_trace(os.path.join(tripped, "trace.csv"))
    trip = plot_run.trip_of(tr, m)
    assert trip is not None and abs(trip[0] - 0.3) < 1e-9 and "TRIPPED: overcurrent" in trip[1], trip
    sel = plot_run.span(tr, m, None, None)
    assert abs(tr["t_s"][sel][0] - 0.2) < 1e-6 and abs(tr["t_s"][sel][-1] - 0.32) < 1e-6  # around the trip
    for p in plot_run.plot_run(tripped):
        check_png(p)
    fault_free = dict(m, fault="none")
    assert plot_run.trip_of(tr, fault_free) is None

    # A malformed trace is refused with the file named.
    bad = os.path.join(work, "bad")
    os.makedirs(bad)
    with open(os.path.join(bad, "trace.csv"), "w", encoding="ascii") as f:
        f.write("t_s,i_a_a\n0,1\n")
    try:
        plot_run.plot_run(bad)
        raise AssertionError("a trace without the required columns was accepted")
    except ValueError as e:
        assert "trace.csv: missing columns" in str(e), e

    # report.py with the stand-in simulator.
    fake = os.path.join(work, "fake-dtc-sil")
    with open(fake, "w", encoding="ascii") as f:
        f.write(f"#!/bin/sh\nexec /usr/bin/python3 '{os.path.abspath(__file__)}' --fake-sil \"$@\"\n")
    os.chmod(fake, 0o755)
    rep = os.path.join(work, "report")
    r = subprocess.run(["/usr/bin/python3", os.path.join(HERE, "report.py"), "--exe", fake, "--out", rep],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    with open(os.path.join(rep, "report.md"), encoding="utf-8") as f:
        md = f.read()
    # Paper values (Hoang Table IX FSTP voltage model without compensation; Table X proposed).
    for s in ("2.97 / 2.37 / 3.00", "0.3345", "7.16", "86.27", "fstp_voltage_proposed_full", "2.20 / 2.20 / 2.30",
              "| 6.54 |", "| 61.50 |", "1000 Hz sensor", "IEC 61000-4-7"):
        assert s in md, f"report.md lacks {s!r}"
    for stem in ("sstp_current_full", "fstp_voltage_simple_full"):
        for png in ("currents.png", "torque.png", "flux_locus.png", "flux_components.png"):
            check_png(os.path.join(rep, stem, png))
    for fig in ("fig12.png", "fig15.png", "fig16.png", "fig17.png"):
        check_png(os.path.join(rep, fig))
        assert f"]({fig})" in md, f"report.md does not show {fig}"
    print(f"selftest: ok ({work})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
