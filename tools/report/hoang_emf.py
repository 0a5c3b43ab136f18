"""The phase currents that an ideal voltage-model DTC draws from a PM machine with unbalanced back-EMF
(Hoang Table VII), from the control law alone: no inverter, no sampling, no bands.

The voltage model (Hoang eqs. 15-16) estimates the machine's true stator flux
psi_s = L_s i + psi_PM(theta) (Hoang eqs. 8-9 with the machine's own, unbalanced PM flux), and the
DTC (Hoang eqs. 13-14, zero bands) holds |psi_s| = psi* and the torque of Hoang eq. 10,
T = 3/2 p (psi_alpha i_beta - psi_beta i_alpha) = 3/2 p (psi_PM x i), at T*. With psi_PM known at each
angle these two conditions fix the current vector: along psi_PM's direction u and across it,

    i = a u + b u_perp,  b = T* / (3/2 p |psi_PM|),  (L_s a + |psi_PM|)^2 + (L_s b)^2 = psi*^2.

An unbalanced psi_PM has a negative-sequence part; its fundamental phase currents are then unbalanced
by a negative-sequence current of nearly fixed size, so the imbalance grows as the load falls.

ideal_currents() gives the three fundamental amplitudes, the imbalance 100 (max/min - 1) (Hoang
Table IX's measure) and the positive- and negative-sequence amplitudes. signature() reduces three
fundamental amplitudes to the negative-sequence part they imply (size relative to the mean, angle),
so that a measured row of Hoang Table IX can be compared with this law's pattern.
"""
import numpy as np


def pm_flux_abc(theta, gains, harm, psi_m):
    """Per-phase PM flux (Wb) at electrical angles theta as the plant has it (model/src/machine_pm.h):
    psi_m g_x sum_n h_xn / n cos(n (theta - x 2 pi / 3)), n = 1, 3, 5, 7, h_x1 = 1."""
    out = np.zeros((3, len(theta)))
    for x in range(3):
        for n, h in zip((1, 3, 5, 7), [1.0] + list(harm[x])):
            out[x] += psi_m * gains[x] * h / n * np.cos(n * (theta - x * 2.0 * np.pi / 3.0))
    return out


def ideal_currents(gains, harm, ls_h, psi_m_wb, psi_ref_wb, torque_nm, pole_pairs, n=3600):
    """{"fundamental_a": [A, B, C] peak, "imbalance_pct", "i_pos_a", "i_neg_a"} of the law above over
    one electrical period. Raises ValueError when psi* cannot carry the torque (no real a)."""
    th = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    ph = pm_flux_abc(th, gains, harm, psi_m_wb)
    ph -= ph.mean(axis=0)  # a star-connected winding carries no zero sequence
    pa = (2.0 / 3.0) * (ph[0] - 0.5 * ph[1] - 0.5 * ph[2])
    pb = (1.0 / np.sqrt(3.0)) * (ph[1] - ph[2])
    mag = np.hypot(pa, pb)
    ua, ub = pa / mag, pb / mag
    b = torque_nm / (1.5 * pole_pairs * mag)
    disc = psi_ref_wb ** 2 - (ls_h * b) ** 2
    if np.any(disc < 0.0):
        raise ValueError("psi* = %g Wb cannot carry %g N*m" % (psi_ref_wb, torque_nm))
    a = (np.sqrt(disc) - mag) / ls_h
    ia, ib = a * ua - b * ub, a * ub + b * ua
    abc = (ia, -0.5 * ia + 0.5 * np.sqrt(3.0) * ib, -0.5 * ia - 0.5 * np.sqrt(3.0) * ib)
    f = [float(2.0 * abs(np.mean(i * np.exp(-1j * th)))) for i in abc]
    iv = ia + 1j * ib
    return {"fundamental_a": f, "imbalance_pct": 100.0 * (max(f) / min(f) - 1.0),
            "i_pos_a": float(abs(np.mean(iv * np.exp(-1j * th)))), "i_neg_a": float(abs(np.mean(iv * np.exp(1j * th))))}


def signature(f):
    """(size % of the mean, angle deg in [0, 360)) of the negative-sequence part that three fundamental
    amplitudes imply: phase x's amplitude is |I_p + I_n e^(j(phi + 4 pi x / 3))| ~ I_p + I_n cos(phi +
    4 pi x / 3), so (2/3) sum_x A_x e^(-j 4 pi x / 3) ~ I_n e^(j phi) to first order in I_n / I_p."""
    f = np.asarray(f, float)
    c = (2.0 / 3.0) * np.sum(f * np.exp(-1j * np.arange(3) * 4.0 * np.pi / 3.0))
    return float(100.0 * abs(c) / f.mean()), float(np.degrees(np.angle(c)) % 360.0)


def signature_diff(f, g):
    """Size (% of f's mean) of the difference between two rows' signatures: the part of row f's
    imbalance that row g (same rig, another estimator) does not have."""
    s1, a1 = signature(f)
    s2, a2 = signature(g)
    return float(abs(s1 * np.exp(1j * np.radians(a1)) - s2 * np.exp(1j * np.radians(a2))))
