#!/usr/bin/python3
"""Casadei et al. 2006 on the SIL: run the IM drive's figure tests and write a markdown report.

    /usr/bin/python3 tools/plot/casadei_report.py [--build build/host] [--out out/casadei]

Runs build/host/bin/sil_im_casadei (tests/sil/test_im_casadei.cpp: each of Casadei's figures
under its conditions on the default IM through the scenario API, the disabled findings included)
and dtc-sil on tools/scenarios/im_dtc_speed.toml, then writes OUT/casadei.md: per figure, the
paper's statement beside the SIL's measured figures (the tests' MEASURE lines) and the test's
verdict (passed / failed / a finding kept as a disabled test, run here all the same). Exit status 1
if a test that is not disabled failed or a run did not complete.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys

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
    ("FaultsTripTheImDriveAndBadConfigurationIsRefused", "Faults",
     "(not in the paper) over-current and DC-link trips, bad IM configuration refused naming the key."),
]


# Why a test is kept disabled, in a sentence (the test's comment has the measurements).
FINDINGS = {}


def run_tests(build):
    exe = os.path.join(build, "bin", "sil_im_casadei")
    p = subprocess.run([exe, "--gtest_also_run_disabled_tests"], capture_output=True, text=True)
    out = p.stdout + p.stderr
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
    return verdict, measures, out


def run_scenario(build, out_dir):
    exe = os.path.join(build, "bin", "dtc-sil")
    dst = os.path.join(out_dir, "im_dtc_speed")
    p = subprocess.run([exe, "run", os.path.join(ROOT, "tools", "scenarios", "im_dtc_speed.toml"), "--out", dst,
                        "--no-trace", "--quiet"], capture_output=True, text=True)
    if p.returncode != 0:
        return None, p.stderr.strip()
    with open(os.path.join(dst, "metrics.json")) as f:
        return json.load(f), ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "host"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "casadei"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    verdict, measures, raw = run_tests(a.build)
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
