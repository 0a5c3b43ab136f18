#!/usr/bin/python3
"""Casadei eqs. 26-28 twice: tools/report/im_linear.py (numpy eigenvalues) against
tools/config/im_tau_check.c (closed-form cubic) through im_tau_dump, on the default IM and on a
second machine (gym-electric-motor's squirrel-cage default, /work/shared/reference/im-facts.md),
and the physics both must show (Casadei sec. 10.7, Fig. 21).

    /usr/bin/python3 tests/unit/test_im_linear.py build/host/bin/im_tau_dump
"""
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
import im_linear  # noqa: E402

fails = []


def check(cond, what):
    if not cond:
        fails.append(what)
        print("FAIL:", what)


def main():
    exe = sys.argv[1]
    machines = [im_linear.Machine.default_im(),
                im_linear.Machine(1.355, 5.87e-3, 5.87e-3, 143.75e-3, 2, 2.9338)]
    rng = np.random.default_rng(7)
    req, expect = [], []
    for m in machines:
        for _ in range(400):
            w0 = rng.uniform(-400, 400) if rng.random() < 0.5 else rng.uniform(-30, 30)
            wsl = rng.uniform(-40, 40)
            tau = 10 ** rng.uniform(-3.5, 0.5)
            req.append("re %.17g %.17g %.17g %.17g %.17g %.17g %.17g" % (m.rr, m.lls, m.llr, m.m, w0, wsl, tau))
            expect.append(m.dominant_re(w0, wsl, tau))
    checks = [(machines[0], 0.53, 79.5, 6000.0, 0.01, 0.01, 0.0, 0.0),
              (machines[0], 0.53, 26.5, 1440.0, 0.001, 0.1, 100.0, 300.0),
              (machines[1], 0.8, 20.0, 3000.0, 0.03, 0.03, 0.0, 0.0)]
    for m, psir, tlim, nmax, tlo, thi, wlo, whi in checks:
        req.append("check %.17g %.17g %.17g %.17g %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g 4e-05" %
                   (m.rr, m.lls, m.llr, m.m, m.p, psir, tlim, nmax, tlo, thi, wlo, whi))
    p = subprocess.run([exe], input="\n".join(req) + "\n", capture_output=True, text=True)
    check(p.returncode == 0, "im_tau_dump exit %d: %s" % (p.returncode, p.stderr))
    lines = p.stdout.split("\n")
    worst = 0.0
    for i, e in enumerate(expect):
        c = float(lines[i])
        err = abs(c - e) / (1.0 + abs(e))
        worst = max(worst, err)
    check(worst < 1e-7, "dominant real part: C and numpy differ by %.3g (relative)" % worst)
    print("eigenvalues: %d points, largest relative difference %.2e" % (len(expect), worst))
    for k, (m, psir, tlim, nmax, tlo, thi, wlo, whi) in enumerate(checks):
        f = lines[len(expect) + k].split()
        py = im_linear.tau_check(m, psir, tlim, nmax, tlo, thi, wlo, whi, 4e-5)
        c_unst, c_worst, c_lo, c_hi, c_pts = int(f[0]), float(f[1]), float(f[4]), float(f[5]), int(f[7])
        print("check %d: C unstable %d worst %+.4f 1/s range %.1f..%.1f rpm (%d points); python %d %+.4f %.1f..%.1f (%d)"
              % (k, c_unst, c_worst, c_lo, c_hi, c_pts, py["unstable"], py["worst_re"], py["rpm_lo"], py["rpm_hi"],
                 py["points"]))
        check(c_unst == int(py["unstable"]) and c_pts == py["points"], "check %d: verdict or grid differs" % k)
        check(abs(c_worst - py["worst_re"]) < 1e-6 * (1 + abs(c_worst)), "check %d: worst pole differs" % k)
        if c_unst:
            check(abs(c_lo - py["rpm_lo"]) < 1e-6 and abs(c_hi - py["rpm_hi"]) < 1e-6, "check %d: range differs" % k)
    # Physics (Casadei sec. 10.7, Fig. 21 at 5 rad/s slip), on both machines: stable for every
    # positive w_s; an unstable region at small negative w_s for a short tau, which a long enough
    # tau removes; the pole at w_s = 0 is at the origin for every tau (Casadei eq. 27's second row).
    for m in machines:
        ws, taus, re = im_linear.fig21_map(m, 5.0, np.linspace(-40, 40, 81), np.logspace(-3, 0, 13))
        check(np.all(re[:, ws > 0.1] < 0.0), "a positive w_s is unstable")
        check(re[0, (ws < -1) & (ws > -5)].max() > 0.0, "tau = 1 ms: no unstable region at small negative w_s")
        check(np.all(re[-1, :] <= 1e-9), "tau = 1 s: an unstable point")
        check(abs(m.dominant_re(-5.0, 5.0, 0.01)) < 1e-9, "w_s = 0: the dominant pole is not at the origin")
    # Casadei eq. 26 built a second way: im_linear.linearised differentiates the reduced drive
    # numerically (its own states); its eigenvalues under the SFVC must be eq. 27's, and a current
    # offset must be answered at the stator frequency w_s with an amplitude proportional to it.
    worst = 0.0
    for m in machines:
        for _ in range(40):
            w0, wsl, tau = rng.uniform(-60, 60), rng.uniform(1, 15), 10 ** rng.uniform(-3, -0.5)
            psir = 0.53 if m is machines[0] else 0.9
            torque = 1.5 * m.p * psir * psir * wsl / m.rr
            a, _, ws, _ = im_linear.linearised(m, w0, torque, psir, tau)
            ev = np.sort_complex(np.linalg.eigvals(a))
            ref = np.sort_complex(np.linalg.eigvals(m.A(w0, wsl, tau)))
            worst = max(worst, float(np.max(np.abs(ev - ref) / (1.0 + np.abs(ref)))))
            check(abs(ws - (w0 + wsl)) < 1e-6, "linearised: w_s %g, not w0 + slip %g" % (ws, w0 + wsl))
    check(worst < 1e-5, "linearised: eigenvalues differ from eq. 27's by %.3g (relative)" % worst)
    print("linearised eq. 26 against eq. 27: largest relative eigenvalue difference %.2e" % worst)
    a1, _ = im_linear.offset_oscillation(machines[0], 1.0, 26.5, 0.53, 0.01, 0.1)
    a2, ws = im_linear.offset_oscillation(machines[0], 1.0, 26.5, 0.53, 0.01, 0.2j)
    check(abs(a2 / a1 - 2.0) < 1e-6, "offset response not linear in the offset: %g" % (a2 / a1))
    # ... and the same amplitude from the drive simulated in the stationary frame without linearising
    di = 0.25 * complex(1.0, 3 ** -0.5)
    lin, _ = im_linear.offset_oscillation(machines[0], 1.0, 26.5, 0.53, 0.01, di)
    sim = im_linear.offset_oscillation_simulated(machines[0], 1.0, 26.5, 0.53, 0.01, di)
    print("offset 0.25 A on phase A, 1 rad/s, rated torque: eq. 26 %.3f %%, simulated %.3f %%" % (100 * lin, 100 * sim))
    check(abs(sim / lin - 1.0) < 0.02, "simulated offset oscillation %.4f against eq. 26's %.4f" % (sim, lin))
    print("FAILED" if fails else "OK")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
