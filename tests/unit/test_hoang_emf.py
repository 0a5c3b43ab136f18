#!/usr/bin/python3
"""tools/report/hoang_emf.py (the ideal voltage-model DTC law on an unbalanced PM machine) against a
closed form and against the physics it must show.

    /usr/bin/python3 tests/unit/test_hoang_emf.py

At zero torque with psi* = psi_m the law leaves i = -(|psi_PM| - psi_m) / L_s along psi_PM; an
unbalanced psi_PM has |psi_PM| = psi_m + psi_n cos(2 theta + phi) to first order, with psi_n the
negative-sequence PM flux psi_m (1/3) |sum_x g_x e^(j 4 pi x / 3)|, so the current's negative sequence
is psi_n / (2 L_s). Balanced back-EMF gives balanced currents at every load; an unbalanced one a
negative sequence of nearly fixed size, so the imbalance falls as the load rises.
"""
import os
import sys

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
import hoang_emf  # noqa: E402

# Hoang Table VIII's machine; Table VII's per-phase fundamentals normalised to their mean.
LS, PSI_M, P = 3.19e-3, 0.0928, 1
GAINS = [0.98739, 1.00149, 1.01112]
NO_HARM = [[0.0, 0.0, 0.0]] * 3
fails = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fails.append(what)


def main():
    psi_n = PSI_M * abs(sum(g * np.exp(1j * 4.0 * np.pi * x / 3.0) for x, g in enumerate(GAINS))) / 3.0
    z = hoang_emf.ideal_currents(GAINS, NO_HARM, LS, PSI_M, PSI_M, 1e-6, P)
    check(abs(z["i_neg_a"] / (psi_n / (2.0 * LS)) - 1.0) < 0.02,
          "zero torque: negative sequence %.4f A = psi_n / (2 L_s) %.4f A within 2 %%" % (z["i_neg_a"], psi_n / (2 * LS)))
    imbs, negs = [], []
    for t in (0.075, 0.15, 0.3):
        b = hoang_emf.ideal_currents([1.0, 1.0, 1.0], NO_HARM, LS, PSI_M, PSI_M, t, P)
        check(b["imbalance_pct"] < 0.01 and b["i_neg_a"] < 1e-6, "balanced back-EMF at %.3f N*m: %.4f %%" % (t, b["imbalance_pct"]))
        # Hoang eq. 10 with psi_s = L i + psi_PM: T = 3/2 p psi_m i_q for a balanced machine
        check(abs(1.5 * P * PSI_M * b["i_pos_a"] * np.cos(np.arcsin(LS * b["i_pos_a"] / PSI_M / 2.0)) / t - 1.0) < 0.02,
              "balanced: positive sequence %.3f A carries %.3f N*m" % (b["i_pos_a"], t))
        u = hoang_emf.ideal_currents(GAINS, NO_HARM, LS, PSI_M, PSI_M, t, P)
        imbs.append(u["imbalance_pct"])
        negs.append(u["i_neg_a"])
    check(imbs[0] > imbs[1] > imbs[2] > 0.0, "Table VII: imbalance falls as the load rises %s" % np.round(imbs, 1))
    check(max(negs) / min(negs) < 1.05, "Table VII: negative sequence nearly fixed %s A" % np.round(negs, 4))
    # signature(): a pure negative sequence added to a balanced set is recovered to first order
    th = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    ip, inn, phi = 1.0, 0.05, 1.0
    iv = ip * np.exp(1j * th) + inn * np.exp(-1j * (th + phi))
    f = [2.0 * abs(np.mean(np.real(iv * np.exp(-1j * 2 * np.pi * x / 3)) * np.exp(-1j * th))) for x in range(3)]
    size, _ = hoang_emf.signature(f)
    check(abs(size / (100.0 * inn / ip) - 1.0) < 0.05, "signature of a 5 %% negative sequence: %.2f %%" % size)
    check(hoang_emf.signature_diff(f, f) < 1e-9, "signature_diff of a row with itself is 0")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
