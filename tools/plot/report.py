#!/usr/bin/python3
"""Run Hoang 2011's Table IX/X matrix with dtc-sil and write a side-by-side markdown report.

    /usr/bin/python3 tools/plot/report.py [--exe build/host/bin/dtc-sil] [--out out/report]
                                          [--jobs 2] [--set key=value ...]

For each of the seven operating points of Hoang Tables IX and X (1500 rpm, full load 0.3 N*m) it runs
tools/scenarios/<name>.toml into OUT/<name>/, draws that run's figures (plot_run.py), and writes
OUT/report.md: paper vs simulation for the per-phase fundamental currents and their imbalance
(Hoang Table IX), the DC component of the predicted (estimated) torque, the total current THD (eq. 39)
and the TRF (eq. 40) (Table X). Unless --table-only, it also runs the FSTP inertial and half-load
points and draws OUT/fig12.png, fig15.png, fig16.png, fig17.png: phase currents at inertial, half
and full load, as Hoang Figs. 12 and 15-17, and adds two tables: the FSTP matrix on a
stiff split DC link for comparison (runs in OUT/<name>_stiff/; the scenarios themselves run on
the finite split link with balancing resistors and ESR) and the low-speed points at 700 / 300 / 200 rpm,
25 % load (OUT/<name>_low<rpm>/). Exit status 1 if any run failed (its row says why).

The runs go through `dtc-sil sweep` (docs/sweep.md): the scenario files of a series are one sweep
whose --zip axes are the keys in which the files differ, so the files stay the one source of the
operating points, and the runs use every core (--jobs) like any other sweep.
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tomllib

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


# Hoang's load series at 1500 rpm (FSTP): (a) inertial, (b) half, (c) full load.
FIGURES = [
    ("fig12", "Fig. 12: current-model DTC, FSTP", "fstp_current"),
    ("fig15", "Fig. 15: voltage-model DTC, FSTP, no compensation", "fstp_voltage_none"),
    ("fig16", "Fig. 16: voltage-model DTC, FSTP, simple compensation (Table V)", "fstp_voltage_simple"),
    ("fig17", "Fig. 17: voltage-model DTC, FSTP, proposed compensation (Table VI)", "fstp_voltage_proposed"),
]
LOADS = [("inertial", "(a) inertial load"), ("half", "(b) half load"), ("full", "(c) full load (0.3 N·m)")]

# The scenarios run on the finite split link (2 x 4.7 mF, 3.3 kohm balancing resistors,
# 25 mohm ESR; docs/plant.md); the FSTP matrix again on a stiff link for comparison, and the
# low-speed points of Hoang Figs. 18-20 at 25 % load (0.075 N*m
# constant, the voltage model from 100 rpm on), each with the schemes the paper runs there.
FINITE = ["fstp_current_full", "fstp_voltage_none_full", "fstp_voltage_simple_full", "fstp_voltage_proposed_full"]
STIFF_SETS = ["inverter.finite_dc_link=false"]
LOW_SPEED = [(700, ["fstp_voltage_none_full", "fstp_voltage_simple_full", "fstp_voltage_proposed_full"]),
             (300, ["fstp_voltage_simple_full", "fstp_voltage_proposed_full"]),
             (200, ["fstp_voltage_simple_full", "fstp_voltage_proposed_full"])]
LOW_SETS = ["load.type=torque", "load.torque_nm=0.075", "control.handover_rpm=100", "duration_s=2.5",
            "metrics_window_s=0.6"]


def load_figure(out_root, name, title, base):
    """Three stacked current plots (inertial, half, full load), as Hoang's Figs. 12 and 15-17."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 1, figsize=(8, 9), sharex=False)
    for ax, (load, label) in zip(axes, LOADS):
        run = os.path.join(out_root, f"{base}_{load}")
        try:
            tr = plot_run.load_trace(os.path.join(run, "trace.csv"))
            m = plot_run.load_metrics(run)
            sel = plot_run.span(tr, m, None, None)
        except (OSError, ValueError) as e:
            ax.text(0.5, 0.5, f"{label}: no run ({e})", transform=ax.transAxes, ha="center", fontsize=8)
            continue
        t_ms = 1e3 * tr["t_s"][sel]
        t_ms = t_ms - t_ms[0]
        for col, lab, color in (("i_a_a", "$i_a$", "tab:blue"), ("i_b_a", "$i_b$", "tab:red"), ("i_c_a", "$i_c$", "tab:green")):
            ax.plot(t_ms, tr[col][sel], label=lab, color=color, linewidth=0.8)
        fund = m.get("fundamental_a")
        txt = label
        if fund:
            txt += ":  fundamental " + " / ".join(f"{x:.2f}" for x in fund) + " A"
        if m.get("fault", "none") != "none":
            txt += f"  FAULT: {m['fault']}"
        ax.set_title(txt, fontsize=8, loc="left")
        ax.set_ylabel("current (A)")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", ncol=3, fontsize=7)
    axes[-1].set_xlabel("time (ms)")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path = os.path.join(out_root, name + ".png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def imbalance(a):
    return 100.0 * (max(a) / min(a) - 1.0)


def flat_toml(d, prefix=""):
    """{dotted key: value} of a parsed scenario file."""
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(flat_toml(v, prefix + k + "."))
        else:
            out[prefix + k] = v
    return out


def toml_value(v):
    """A value as --set takes it (TOML)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return repr(v)


def key_defaults(exe):
    """Schema defaults (dtc-sil keys) as TOML text, for keys a scenario file leaves out."""
    r = subprocess.run([exe, "keys"], capture_output=True, text=True, check=True)
    out = {}
    for line in r.stdout.splitlines():
        cells = [c.strip() for c in line.split("|")]
        if len(cells) > 5 and cells[1].startswith("`"):
            out[cells[1].strip("`")] = cells[4]
    return out


def sweep_series(exe, scen_dir, out_root, name, stems, sets, jobs, suffix=""):
    """Runs the scenario files `stems` as one dtc-sil sweep and moves run i to OUT/<stems[i]><suffix>/.
    Returns {stem: (metrics or None, error or None)} and the command."""
    flats = []
    for stem in stems:
        with open(os.path.join(scen_dir, stem + ".toml"), "rb") as f:
            flats.append(flat_toml(tomllib.load(f)))
    keys = sorted(set().union(*flats))
    differ = [k for k in keys if len({json.dumps(f.get(k), sort_keys=True) for f in flats}) > 1]
    defaults = key_defaults(exe) if any(k not in f for f in flats for k in differ) else {}
    cmd = [exe, "sweep", os.path.join(scen_dir, stems[0] + ".toml"), "--out", os.path.join(out_root, name),
           "--keep-runs", "--jobs", str(jobs), "-q"]
    for k in differ:
        vals = []
        for f in flats:
            if k in f:
                vals.append(toml_value(f[k]))
            elif defaults.get(k, "").strip() not in ("", "(none)", "derived"):
                vals.append(defaults[k])
            else:
                raise SystemExit(f"report: {k} is set in some of {stems} and has no literal default")
        cmd += ["--zip", k + "=" + ",".join(vals)]
    for s_ in sets:
        cmd += ["--set", s_]
    subprocess.run(["rm", "-rf", os.path.join(out_root, name)], check=True)
    r = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if r.returncode not in (0, 3):
        msg = (r.stderr.strip().splitlines() or ["exit status %d" % r.returncode])[-1]
        return {stem: (None, msg) for stem in stems}, cmd
    with open(os.path.join(out_root, name, "summary.json"), encoding="utf-8") as f:
        rows = {row["run"]: row for row in json.load(f)["rows"]}
    results = {}
    for i, stem in enumerate(stems):
        row = rows.get(i)
        run_dir = os.path.join(out_root, name, "runs", str(i))
        if row is None or not os.path.exists(os.path.join(run_dir, "metrics.json")):
            results[stem] = (None, (row or {}).get("error") or (row or {}).get("status") or "no row")
            continue
        dest = os.path.join(out_root, stem + suffix)
        subprocess.run(["rm", "-rf", dest], check=True)
        os.replace(run_dir, dest)
        with open(os.path.join(dest, "metrics.json"), encoding="utf-8") as f:
            results[stem] = (json.load(f), None)
    return results, cmd


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
    hz = next((float(x.split("=", 1)[1]) for x in reversed(sets) if x.startswith("metrics.torque_sensor_hz=")), 0.0)
    flt = f"sim TRF % (true, {hz:g} Hz sensor)" if hz > 0 else "sim TRF % (true, unfiltered)"
    lines += ["", "## Table X: predicted torque, current THD (eq. 39), TRF (eq. 40)", "",
              "Two definitions each: THD over every line of the spectrum (full band, switching ripple "
              "included) and THD 2..40 (harmonic subgroups 2..40 only, IEC 61000-4-7 style); TRF of the "
              "instantaneous plant torque sampled every period, and TRF of the plant torque after a "
              "first-order torque sensor (`metrics.torque_sensor_hz`).", "",
              "| scheme | paper predicted torque N·m | sim estimated torque N·m | sim true torque N·m "
              "| paper THD % | sim THD % (full band) | sim THD % (2..40) | paper TRF % | sim TRF % (true) "
              f"| {flt} | sim TRF % (estimate) |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for stem, label, _, x in PAPER:
        m, err = results[stem]
        if m is None:
            lines.append(f"| {label} | {x[0]:.4f} | run failed | | {x[1]:.2f} | | | {x[2]:.2f} | | | |")
            continue
        lines.append(f"| {label} | {x[0]:.4f} | {num(m.get('torque_est_mean_nm'))} | {num(m.get('torque_mean_nm'))} "
                     f"| {x[1]:.2f} | {num(m.get('thd_total_pct'), '{:.2f}')} "
                     f"| {num(m.get('thd40_total_pct'), '{:.2f}')} | {x[2]:.2f} "
                     f"| {num(m.get('trf_pct'), '{:.2f}')} | {num(m.get('trf_filtered_pct'), '{:.2f}')} "
                     f"| {num(m.get('trf_est_pct'), '{:.2f}')} |")
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
              "100 (max/min - 1); THD (full band) = eq. 39 total over all non-fundamental lines; THD (2..40) = "
              "eq. 39 over the harmonic subgroups h = 2..40 (the line at h f1 and its two neighbours at the "
              "window's resolution, IEC 61000-4-7), so switching ripple above 40 f1 does not count; TRF = "
              "eq. 40, peak-to-peak over the window / rated torque, sampled once per control period; the "
              "filtered TRF applies 1 / (1 + s / (2 pi f_s)) first (f_s = `metrics.torque_sensor_hz`, "
              "0 = unfiltered). The paper's torque transducer bandwidth is not stated: the unfiltered TRF is "
              "an upper bound, the filtered one what a sensor of that bandwidth would show.", ""]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines))


def issue10_tables(finite, low):
    """Markdown: the FSTP matrix on a stiff link (comparison) and the low-speed table."""
    lines = ["", "## FSTP on a stiff split DC link, for comparison", "",
             "The tables above run on the scenarios' finite split link (2 x 4.7 mF, 3.3 kOhm balancing "
             "resistors, 25 mOhm ESR). Here the Table IX/X operating points with `--set "
             + " --set ".join(STIFF_SETS) + "` (capacitor voltages held at V_dc/2), from "
             "standstill (DC-current suppression with mid-point regulation, `control.dc_supp`, on).", "",
             "| scheme | fault | speed rpm | sim A / B / C | imbalance % | THD % (2..40) | estimated / true torque N·m |",
             "|---|---|---|---|---|---|---|"]
    for stem in FINITE:
        m, err = finite.get(stem, (None, "not run"))
        if m is None:
            lines.append(f"| `{stem}` | run failed: {err} | | | | | |")
            continue
        lines.append(f"| `{stem}` | {m.get('fault')} | {num(m.get('speed_mean_rpm'), '{:.1f}')} "
                     f"| {fmt3(m.get('fundamental_a'))} | {num(m.get('imbalance_pct'), '{:.1f}')} "
                     f"| {num(m.get('thd40_total_pct'), '{:.1f}')} "
                     f"| {num(m.get('torque_est_mean_nm'))} / {num(m.get('torque_mean_nm'))} |")
    lines += ["", "## Low speed, 25 % load (Hoang Figs. 18-20)", "",
              "0.075 N·m constant load, `--set " + " --set ".join(LOW_SETS) + "`; the paper shows "
              "sinusoidal currents at 700 rpm (all schemes), 300 rpm (simple, proposed) and 200 rpm "
              "(proposed).", "",
              "| speed rpm | scheme | fault | mean speed rpm | sim A / B / C | imbalance % | THD % (2..40) "
              "| estimated / true torque N·m |", "|---|---|---|---|---|---|---|---|"]
    for rpm, stems in LOW_SPEED:
        for stem in stems:
            m, err = low.get((rpm, stem), (None, "not run"))
            if m is None:
                lines.append(f"| {rpm} | `{stem}` | run failed: {err} | | | | | |")
                continue
            lines.append(f"| {rpm} | `{stem}` | {m.get('fault')} | {num(m.get('speed_mean_rpm'), '{:.1f}')} "
                         f"| {fmt3(m.get('fundamental_a'))} | {num(m.get('imbalance_pct'), '{:.1f}')} "
                         f"| {num(m.get('thd40_total_pct'), '{:.1f}')} "
                         f"| {num(m.get('torque_est_mean_nm'))} / {num(m.get('torque_mean_nm'))} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "host", "bin", "dtc-sil"))
    ap.add_argument("--scenarios", default=os.path.join(ROOT, "tools", "scenarios"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "report"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--set", action="append", default=[], help="override passed to every run")
    ap.add_argument("--torque-sensor-hz", type=float, default=1000.0,
                    help="bandwidth of the torque sensor for the filtered TRF column (default 1000 Hz, a typical "
                         "in-line transducer; not stated in the paper; 0 = unfiltered)")
    ap.add_argument("--table-only", action="store_true",
                    help="only the seven Table IX/X runs, not the inertial/half-load runs of Figs. 12, 15-17")
    a = ap.parse_args(argv)
    if not os.path.exists(a.exe):
        print(f"report: {a.exe} not found (build it: cmake --build build/host --target dtc-sil)", file=sys.stderr)
        return 1
    os.makedirs(a.out, exist_ok=True)
    a.set = [f"metrics.torque_sensor_hz={a.torque_sensor_hz:g}"] + a.set
    extra = [] if a.table_only else [f"{base}_{load}" for _, _, base in FIGURES for load in ("inertial", "half")]
    results, cmd = sweep_series(a.exe, a.scenarios, a.out, "sweep_table", [p[0] for p in PAPER], a.set, a.jobs)
    extra_results = {}
    if extra:
        extra_results, _ = sweep_series(a.exe, a.scenarios, a.out, "sweep_loads", extra, a.set, a.jobs)
    finite, low = {}, {}
    if not a.table_only:
        finite, _ = sweep_series(a.exe, a.scenarios, a.out, "sweep_stiff", FINITE, a.set + STIFF_SETS, a.jobs,
                                 suffix="_stiff")
        for rpm, stems in LOW_SPEED:
            r, _ = sweep_series(a.exe, a.scenarios, a.out, f"sweep_low{rpm}", stems,
                                a.set + LOW_SETS + [f"control.speed_ref_rpm={rpm}"], a.jobs, suffix=f"_low{rpm}")
            low.update({(rpm, k): v for k, v in r.items()})
        extra_results.update({k + "_stiff": v for k, v in finite.items()})
        extra_results.update({f"{k[1]}_low{k[0]}": v for k, v in low.items()})
    for stem, (m, err) in list(results.items()) + list(extra_results.items()):
        print(f"{'FAILED' if err else 'ok    '} {stem}" + (f": {err}" if err else ""))
    print("sweep: " + " ".join(cmd))
    # Figures in this thread only: matplotlib's text layout is not thread-safe.
    for stem, *_ in PAPER:
        m, err = results[stem]
        if m is not None:
            try:
                plot_run.plot_run(os.path.join(a.out, stem))
            except (OSError, ValueError) as e:
                results[stem] = (m, f"plots failed: {e}")
    figs = [] if a.table_only else [(title, load_figure(a.out, name, title, base)) for name, title, base in FIGURES]
    path = os.path.join(a.out, "report.md")
    write_report(path, results, a.exe, a.set)
    if not a.table_only:
        with open(path, "a", encoding="utf-8") as f:
            f.write(issue10_tables(finite, low))
    if figs:
        with open(path, "a", encoding="utf-8") as f:
            f.write("\n## Load series (Hoang Figs. 12, 15-17)\n\n")
            for title, p in figs:
                f.write(f"![{title}]({os.path.basename(p)})\n\n")
    print(path)
    failed = [k for k, (_, err) in list(results.items()) + list(extra_results.items()) if err]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
