#!/usr/bin/python3
"""Casadei et al. 2006 on the SIL: run the IM drive's figure tests and write a markdown report.

    /usr/bin/python3 tools/plot/casadei_report.py [--build build/host] [--out out/casadei]

Runs build/host/bin/sil_im_casadei (tests/sil/test_im_casadei.cpp: each of Casadei's figures
under its conditions on the default IM through the scenario API, disabled findings included) with
DTC_FIGURE_DIR=OUT/data, so that the tests write their waveforms there, and dtc-sil on
tools/scenarios/im_dtc_speed.toml. Writes OUT/casadei.md: per figure, the paper's statement, the
SIL's figure drawn from those waveforms (OUT/*.png), the measured figures (the tests' MEASURE
lines) and the test's verdict. Exit status 1 if a test that is not disabled failed, a waveform is
missing or a run did not complete.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

# (test name without DISABLED_, Casadei's figure, the paper's statement)
FIGURES = [
    ("Fig17ImprovedEstimatorMagnetisesAtZeroTorqueAndTheTorqueFollowsInMilliseconds", "Fig. 17",
     "With a pure integrator it is not possible to magnetise the machine at zero torque; the torque then "
     "rises slowly. With the improved estimator (tau = 0.01 s) the phase current at zero torque is the "
     "magnetising current and the torque reaches its reference in a few ms."),
    ("Fig14And15TorqueStepTo300PercentAtConstantRotorFlux", "Figs. 14-15",
     "Torque step 50 % -> 300 % rated at constant rotor flux: fast torque response, circular rotor-flux "
     "locus, stator flux rising as eq. 19."),
    ("Fig5StASluggishAtLowSpeedStDQuickBothQuickAtHighSpeed", "Fig. 5",
     "Pulse +18 -> -18 N*m for 8.8 ms, speed held: ST-A sluggish at 20 rad/s (null vectors for the decrease), "
     "ST-D quick; at 100 rad/s both quick and almost identical."),
    ("Sec6StACannotHoldTheFluxAtZeroTorqueAtStandstill", "Section 6 (ST-A at zero torque)",
     "ST-A (as ST-B, ST-C) is suitable for two-quadrant operation, ST-D for four-quadrant operation."),
    ("Sec8SpeedDependentTableAgainstStAAndStD", "Section 8",
     "A speed-dependent table (ST-D at low speed, ST-A at high) gives a better torque response over the "
     "whole range and a reduction in the torque ripple."),
    ("Fig13DtcWithWideFluxBandTracesAHexagonLikeLocus", "Fig. 13",
     "DTC with a flux band of 0.14 phi_s* reproduces the DSC behaviour (hexagon-like locus)."),
    ("Sec9DscHexagonWithFewerCommutationsThanDtc", "Section 9 (DSC)",
     "DSC: hexagonal flux locus, lower switching frequency than DTC."),
    ("Figs22To24ImprovedEstimatorErrorBoundedBasicGrows", "Figs. 22-24",
     "omega = 1 rad/s, tau = 0.01 s, rated torque: with R_s 10 % low / high or a 0.01 A offset the improved "
     "estimator's rotor-flux error settles near the theoretical value; the basic estimator's does not."),
    ("Fig25SensorlessSpeedEstimateFollowsTheSpeed", "Fig. 25",
     "Sensorless drive, speed steps with regenerative braking down to 0: the drive follows the speed."),
    ("Fig32FluxWeakeningTorqueReferenceWithinEq34", "Fig. 32 (references)",
     "Flux weakening: T* = T_command phi_s*/phi_s,rated (eq. 33), at most k_T phi_s*^2 (eq. 34)."),
    ("Fig32FluxWeakeningReaches400PercentWithNearlyConstantCurrent", "Fig. 32 (speed, current)",
     "Start-up from standstill to about 400 % of base speed with a nearly constant current in the "
     "constant-power range."),
    ("Sec10SfvcTorqueFollowsTheReferenceAtRatedAndLowSpeed", "Secs. 10.3-10.5 (SFVC)",
     "Stator-flux vector control with SVM: the torque follows its reference at a constant switching frequency."),
    ("Sec10SfvcSwitchesAtTheCarrierWithLowerThdThanDtc", "Sec. 10.3 (SFVC against DTC)",
     "Constant switching frequency: the current's switching content at the carrier; lower distortion than "
     "DTC at the same switching frequency."),
    ("Sec13DfocTorqueFollowsWithTwoPhaseModulation", "Sec. 13 (DFOC)",
     "Direct rotor-flux-oriented control, PI current regulators, two-phase modulation, 160 us cycle: mean "
     "switching frequency 2/3 of the carrier."),
    ("Figs33And34DfocSpectrumAtTheCarrierDtcSpread", "Figs. 33-34",
     "Rated speed and torque: the DFOC current spectrum shows only the component of the modulation cycle; "
     "the DTC spectrum has lower lines spread over the whole frequency range."),
    ("Figs35And36TorqueStepAt100RpmDtcRisesFasterThanDfoc", "Figs. 35-36",
     "Torque step at 100 rpm: DTC gives a better response in settling time and maximum overshoot; the PI "
     "regulators of DFOC delay the torque response."),
    ("FaultsTripTheImDriveAndBadConfigurationIsRefused", "Faults",
     "(not in the paper) over-current and DC-link trips, bad IM configuration refused naming the key."),
]


# Why a test is kept disabled, in a sentence (the test's comment has the measurements).
FINDINGS = {}


def run_tests(build, data_dir):
    exe = os.path.join(build, "bin", "sil_im_casadei")
    env = dict(os.environ, DTC_FIGURE_DIR=data_dir)
    p = subprocess.run([exe, "--gtest_also_run_disabled_tests"], capture_output=True, text=True, env=env)
    out = p.stdout + p.stderr
    verdict, measures = parse_output(out)
    return verdict, measures, out


def parse_output(out):
    """{test: (passed|failed, disabled)} and {test: [MEASURE lines]} of sil_im_casadei's output
    (OUT/sil_im_casadei.log)."""
    verdict = {}
    for m in re.finditer(r"\[\s+(OK|FAILED)\s+\] ImCasadei\.(DISABLED_)?(\w+) \(", out):
        verdict[m.group(3)] = ("passed" if m.group(1) == "OK" else "failed", m.group(2) is not None)
    # MEASURE lines by the test that printed them (between its RUN line and the next).
    measures = {}
    current = None
    for line in out.splitlines():
        m = re.match(r"\[ RUN\s+\] ImCasadei\.(?:DISABLED_)?(\w+)", line)
        if m:
            current = m.group(1)
        elif line.startswith("MEASURE ") and current:
            measures.setdefault(current, []).append(line[len("MEASURE "):])
    return verdict, measures


def load(data_dir, name):
    return np.genfromtxt(os.path.join(data_dir, name + ".csv"), delimiter=",", names=True)


def rel_ms(w, t0=None):
    return 1e3 * (w["t_s"] - (w["t_s"][0] if t0 is None else t0))


def fig5(d, ax_list):
    for ax, w in zip(ax_list, (20, 100)):
        for table, style in (("st-a", "-"), ("st-d", "--")):
            x = load(d, "fig5_%s_%d" % (table, w))
            t = rel_ms(x, x["t_s"][0] + 0.02)  # the pulse starts 20 ms into the recording
            ax.plot(t, x["te_nm"], style, lw=0.8, label=table.upper())
        ax.plot(t, x["te_ref_nm"], ":", lw=0.8, color="k", label="T* (after the trim)")
        ax.set_title("%d rad/s" % w)
        ax.set_xlabel("ms from the -18 N*m command")
        ax.set_ylabel("plant torque, N*m")
        ax.set_xlim(-3, 12)
        ax.legend(fontsize=7)


def fig14(d, ax_list):
    x = load(d, "fig14_500rpm")
    t = rel_ms(x, x["t_s"][0] + 0.02)
    ax_list[0].plot(t, x["te_nm"], lw=0.7, label="plant torque")
    ax_list[0].plot(t, x["te_ref_nm"], lw=0.7, label="T*")
    ax_list[0].set_xlabel("ms from the step")
    ax_list[0].set_ylabel("N*m")
    ax_list[0].legend(fontsize=7)
    ax_list[1].plot(t, np.hypot(x["psi_alpha_wb"], x["psi_beta_wb"]), lw=0.7, label="|phi_s|")
    ax_list[1].plot(t, np.hypot(x["psi_r_alpha_wb"], x["psi_r_beta_wb"]), lw=0.7, label="|phi_r|")
    ax_list[1].set_xlabel("ms from the step")
    ax_list[1].set_ylabel("Wb")
    ax_list[1].legend(fontsize=7)
    ax_list[2].plot(x["psi_r_alpha_wb"], x["psi_r_beta_wb"], lw=0.5)
    ax_list[2].set_aspect("equal")
    ax_list[2].set_title("rotor-flux locus (500 rpm)")


def fig17(d, ax_list):
    for ax, est in zip(ax_list, ("voltage", "improved")):
        x = load(d, "fig17_" + est)
        t = rel_ms(x)
        ax.plot(t, x["i_a_a"], lw=0.6, label="i_a, A")
        ax.plot(t, x["te_nm"], lw=0.6, label="torque, N*m")
        ax.set_title("%s estimator" % est)
        ax.set_xlabel("ms from the start")
        ax.legend(fontsize=7)


def locus(d, ax_list):
    for ax, (name, title) in zip(ax_list, (("fig13_dtc_band0", "DTC, flux band 0"),
                                           ("fig13_dtc_band014", "DTC, flux band 0.14 phi_s*"),
                                           ("sec9_dsc", "DSC"))):
        x = load(d, name)
        ax.plot(x["psi_alpha_wb"], x["psi_beta_wb"], lw=0.4)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("phi_s alpha, Wb")


def fig22(d, ax_list):
    with open(os.path.join(ROOT, "tools", "scenarios", "im_dtc_speed.toml"), "rb") as f:
        ref = tomllib.load(f)["control"]["rotor_flux_ref_wb"]
    for ax, est in zip(ax_list, ("improved", "voltage")):
        for case in ("none", "rs_low", "rs_high", "offset"):
            x = load(d, "fig22_%s_%s" % (case, est))
            err = 100.0 * (np.hypot(x["psi_r_alpha_wb"], x["psi_r_beta_wb"]) / ref - 1.0)
            ax.plot(x["t_s"] - x["t_s"][0], err, lw=0.6, label=case)
        ax.set_title("%s estimator" % est)
        ax.set_xlabel("s at 1 rad/s, rated torque")
        ax.set_ylabel("plant |phi_r| vs phi_r*, %")
        ax.legend(fontsize=7)


def fig25(d, ax_list):
    x = load(d, "fig25")
    ax = ax_list[0]
    ax.plot(x["t_s"], x["speed_rpm"], lw=0.7, label="true speed")
    ax.plot(x["t_s"], x["speed_est_rpm"], lw=0.7, label="estimated (no sensor)")
    ax.set_xlabel("s")
    ax.set_ylabel("rpm")
    ax.legend(fontsize=7)
    ax_list[1].plot(x["t_s"], x["te_nm"], lw=0.5)
    ax_list[1].set_xlabel("s")
    ax_list[1].set_ylabel("plant torque, N*m")


def fig32(d, ax_list):
    x = load(d, "fig32")
    ax_list[0].plot(x["t_s"], x["speed_rpm"], lw=0.8)
    ax_list[0].set_ylabel("speed, rpm")
    ax_list[1].plot(x["t_s"], x["i_mag_a"], lw=0.5)
    ax_list[1].set_ylabel("|i_s|, A")
    ax_list[2].plot(x["t_s"], x["psi_ref_wb"], lw=0.8, label="phi_s*, Wb")
    ax_list[2].plot(x["t_s"], x["te_ref_nm"] / 50.0, lw=0.8, label="T* / 50 N*m")
    ax_list[2].legend(fontsize=7)
    for ax in ax_list:
        ax.set_xlabel("s")


def sec6(d, ax_list):
    ax = ax_list[0]
    for table in ("st-a", "st-d"):
        x = load(d, "sec6_" + table)
        t = rel_ms(x)
        ax.plot(t, np.hypot(x["psi_alpha_wb"], x["psi_beta_wb"]), lw=0.8, label="%s plant" % table.upper())
        ax.plot(t, x["psi_est_wb"], "--", lw=0.8, label="%s estimate" % table.upper())
    ax.set_xlabel("ms at T* = 0, standstill")
    ax.set_ylabel("|phi_s|, Wb")
    ax.legend(fontsize=7)


def spectra(d, ax_list):
    for ax, (name, title) in zip(ax_list, (("fig33_dfoc_1440", "DFOC (Fig. 33)"), ("fig34_dtc_1440", "DTC (Fig. 34)"))):
        x = np.genfromtxt(os.path.join(d, name + ".csv"), delimiter=",", names=True)
        dt = x["dt_s"][0]
        i = x["i_a_a"] - np.mean(x["i_a_a"])
        amp = 2.0 * np.abs(np.fft.rfft(i)) / len(i)
        f = np.fft.rfftfreq(len(i), dt)
        ax.semilogy(f / 1e3, np.maximum(amp, 1e-5), lw=0.5)
        ax.set_xlim(0, 25)
        ax.set_ylim(1e-4, 50)
        ax.set_title("%s, 1440 rpm, 26.5 N*m" % title, fontsize=9)
        ax.set_xlabel("kHz")
        ax.set_ylabel("i_a line amplitude, A")


def steps(d, ax_list):
    ax = ax_list[0]
    for name, label in (("fig36_dtc", "DTC (Fig. 36)"), ("fig35_dfoc", "DFOC (Fig. 35)")):
        x = load(d, name)
        t = rel_ms(x, x["t_s"][0] + 0.005)  # the step 5 ms into the recording
        ax.plot(t, x["te_nm"], lw=0.7, label=label)
    ax.set_xlabel("ms from the 0 -> 26.5 N*m step, 100 rpm")
    ax.set_ylabel("plant torque, N*m")
    ax.set_xlim(-2, 25)
    ax.legend(fontsize=7)


# test name -> (drawing function, number of panels)
PLOTS = {
    "Fig5StASluggishAtLowSpeedStDQuickBothQuickAtHighSpeed": (fig5, 2),
    "Fig14And15TorqueStepTo300PercentAtConstantRotorFlux": (fig14, 3),
    "Fig17ImprovedEstimatorMagnetisesAtZeroTorqueAndTheTorqueFollowsInMilliseconds": (fig17, 2),
    "Fig13DtcWithWideFluxBandTracesAHexagonLikeLocus": (locus, 3),
    "Figs22To24ImprovedEstimatorErrorBoundedBasicGrows": (fig22, 2),
    "Fig25SensorlessSpeedEstimateFollowsTheSpeed": (fig25, 2),
    "Fig32FluxWeakeningReaches400PercentWithNearlyConstantCurrent": (fig32, 3),
    "Sec6StACannotHoldTheFluxAtZeroTorqueAtStandstill": (sec6, 1),
    "Figs33And34DfocSpectrumAtTheCarrierDtcSpread": (spectra, 2),
    "Figs35And36TorqueStepAt100RpmDtcRisesFasterThanDfoc": (steps, 1),
}


def draw(name, data_dir, out_dir):
    """Draws the test's figure into OUT/NAME.png; returns the file name or an error text."""
    fn, n = PLOTS[name]
    fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.4), squeeze=False)
    try:
        fn(data_dir, list(axes[0]))
    except OSError as e:
        plt.close(fig)
        return None, str(e)
    fig.tight_layout()
    png = name + ".png"
    fig.savefig(os.path.join(out_dir, png), dpi=110)
    plt.close(fig)
    return png, ""


def run_scenario(build, out_dir):
    exe = os.path.join(build, "bin", "dtc-sil")
    dst = os.path.join(out_dir, "im_dtc_speed")
    p = subprocess.run([exe, "run", os.path.join(ROOT, "tools", "scenarios", "im_dtc_speed.toml"), "--out", dst,
                        "--no-trace", "--quiet"], capture_output=True, text=True)
    if p.returncode != 0:
        return None, p.stderr.strip()
    with open(os.path.join(dst, "metrics.json")) as f:
        return json.load(f), ""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "host"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "casadei"))
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    data_dir = os.path.join(a.out, "data")
    os.makedirs(data_dir, exist_ok=True)
    verdict, measures, raw = run_tests(a.build, data_dir)
    with open(os.path.join(a.out, "sil_im_casadei.log"), "w") as f:
        f.write(raw)
    metrics, err = run_scenario(a.build, a.out)

    bad = False
    md = ["# Casadei et al. 2006 on the SIL", "",
          "Generated %s by `tools/plot/casadei_report.py` from `sil_im_casadei --gtest_also_run_disabled_tests` "
          "(tests/sil/test_im_casadei.cpp: the default IM, 4 kW, 220 V, 4 poles, on SSTP 311 V with the plant's "
          "devices, 40 us, from standstill) and `dtc-sil run tools/scenarios/im_dtc_speed.toml`. A *finding* is "
          "a test kept disabled because the drive does not yet do what the paper shows; it is run here anyway "
          "and its measurements say why." % datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
          ""]
    for name, fig, paper in FIGURES:
        v = verdict.get(name)
        if v is None:
            status = "not run"
            bad = True
        else:
            result, disabled = v
            status = ("finding (disabled test, %s here)" % result) if disabled else result
            bad = bad or (not disabled and result != "passed")
        md += ["## %s" % fig, "", "- Paper: %s" % paper, "- Test: `sil.ImCasadei.%s%s`: **%s**" %
               ("DISABLED_" if v and v[1] else "", name, status)]
        if name in FINDINGS:
            md.append("- Finding: %s" % FINDINGS[name])
        if name in PLOTS:
            png, err = draw(name, data_dir, a.out)
            if png:
                md.append("- SIL figure: ![%s](%s)" % (fig, png))
            else:
                md.append("- SIL figure missing: %s" % err)
                bad = True
        for line in measures.get(name, []):
            md.append("- SIL: %s" % line)
        md.append("")
    md += ["## Speed mode from standstill (`im_dtc_speed.toml`)", "",
           "- On the IM rig's own sensors and trips: the start-up ramps the stator-flux reference so that the "
           "magnetising current stays below the rated current (firmware/dtc/im_dtc.h)."]
    if metrics is None:
        md.append("- run failed: %s" % err)
        bad = True
    else:
        md.append("- fault %s; speed %.1f rpm (reference 1000); torque mean %.2f N*m (rated load 26.5), TRF %.1f %%; "
                  "current fundamental %.2f A, THD %.2f %%; switching %.0f Hz per device" %
                  (metrics["fault"], metrics["speed_mean_rpm"], metrics["torque_mean_nm"], metrics["trf_pct"],
                   sum(metrics["fundamental_a"]) / 3.0, metrics["thd_total_pct"] or float("nan"),
                   metrics["switching_freq_hz"]))
    md.append("")
    with open(os.path.join(a.out, "casadei.md"), "w") as f:
        f.write("\n".join(md))
    print("wrote %s" % os.path.join(a.out, "casadei.md"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
