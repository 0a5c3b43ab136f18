#!/usr/bin/python3
"""Casadei sec. 10.6-10.7: the linearised sensorless stator-flux vector control with the improved
estimator (Casadei eqs. 26-28), its eigenvalues, the Fig. 21 stability map and the check of a tau schedule.

The machine comes from a scenario file (motor.* keys, the default IM of model/include/plant_defaults.h
for the keys left unset) or from explicit values; nothing of Casadei's unprinted machine is assumed.

Derivation (states in the estimated rotor-flux frame, rotating at the estimated stator frequency
w_s = w0 + w_sl; the flux regulator holds the estimated stator flux at Casadei eq. 18's reference): with
e = phi_s - phi_s^ the estimator error, eq. 21 gives phi_r^ = phi_r - (L_r/M) e, and eq. 20 with
exact R_s and currents gives de/dt = -(phi_r* - |phi_r^|) e^{j theta} / tau. The rotor equation
(A7-A9) and the frame's speed (the angle of phi_r^, eq. 22) then linearise to eq. 27:

    [A] = [ -1/tau_r   w_s - w0   -k          ]     k = M^2 / (sigma L_s L_r tau_r)
          [ -w_s       0           w_s        ]
          [ -1/tau_r   -w0        -k - g/tau  ]     g = L_r / M

Casadei eq. 27 prints 1/tau for g/tau (equal when L_r = M; 3 % apart on the default IM). The C twin is
tools/config/im_tau_check.c; tests/unit/test_im_linear.py holds the two together.

    /usr/bin/python3 tools/report/im_linear.py [--scenario FILE] [--slip 5] [--out fig21.png]
"""
import argparse
import math
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))


def plant_defaults():
    """The PLANT_DEF_IM_* constants of model/include/plant_defaults.h, evaluated."""
    path = os.path.join(ROOT, "model", "include", "plant_defaults.h")
    env = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"#define\s+(PLANT_DEF_\w+)\s+(.+?)\s*(/\*.*)?$", line)
            if not m:
                continue
            expr = m.group(2)
            try:
                env[m.group(1)] = eval(expr, {"__builtins__": {}}, env)  # numbers and the names above
            except Exception:
                pass
    return env


class Machine:
    """T-model induction machine, stator-referred (the plant's names: docs/sil.md motor.*)."""

    def __init__(self, rr_ohm, lls_h, llr_h, lm_h, pole_pairs=2, rs_ohm=None):
        self.rr, self.lls, self.llr, self.m, self.p, self.rs = rr_ohm, lls_h, llr_h, lm_h, pole_pairs, rs_ohm
        self.ls, self.lr = lls_h + lm_h, llr_h + lm_h
        self.sigma = 1.0 - lm_h * lm_h / (self.ls * self.lr)
        self.tau_r = self.lr / rr_ohm
        self.k = lm_h * lm_h / (self.sigma * self.ls * self.lr * self.tau_r)
        self.g = self.lr / lm_h

    @classmethod
    def default_im(cls):
        d = plant_defaults()
        return cls(d["PLANT_DEF_IM_RR_OHM"], d["PLANT_DEF_IM_LLS_H"], d["PLANT_DEF_IM_LLR_H"], d["PLANT_DEF_IM_LM_H"],
                   d["PLANT_DEF_IM_POLE_PAIRS"], d["PLANT_DEF_IM_RS_OHM"])

    @classmethod
    def from_scenario(cls, path, sets=None):
        """motor.* of a scenario TOML (the firmware's firmware.* values where given, as
        controller_firmware.cpp does), the default IM's for the keys left unset."""
        import tomllib
        with open(path, "rb") as f:
            sc = tomllib.load(f)
        flat = {}
        for sect, v in sc.items():
            if isinstance(v, dict):
                for k, x in v.items():
                    flat["%s.%s" % (sect, k)] = x
        for s in sets or []:
            k, v = s.split("=", 1)
            flat[k] = float(v) if re.match(r"^[-+0-9.eE]+$", v) else v
        d = cls.default_im()

        def get(key, dflt):
            return float(flat.get("firmware." + key, flat.get("motor." + key, dflt)))

        return cls(get("rr_ohm", d.rr), get("lls_h", d.lls), get("llr_h", d.llr), get("lm_h", d.m),
                   int(flat.get("motor.pole_pairs", d.p)), get("rs_ohm", d.rs))

    def A(self, w0, w_sl, tau):
        """Casadei eq. 27 at rotor speed w0 and slip w_sl (electrical rad/s), estimator tau (s)."""
        ws = w0 + w_sl
        return np.array([[-1.0 / self.tau_r, w_sl, -self.k],
                         [-ws, 0.0, ws],
                         [-1.0 / self.tau_r, -w0, -self.k - self.g / tau]])

    def dominant_re(self, w0, w_sl, tau):
        return float(np.max(np.linalg.eigvals(self.A(w0, w_sl, tau)).real))

    def slip_for_torque(self, torque_nm, psir_wb):
        """Casadei eq. 16 at constant rotor flux (amplitude-invariant): T = 3/2 p phi_r^2 w_sl / R_r."""
        return torque_nm * self.rr / (1.5 * self.p * psir_wb * psir_wb)


def _reduced(mach, x, u, w0, torque, psir, tau, law, r_off=0.0):
    """The drive of Casadei sec. 10.6 reduced to its slow states, in the frame of the estimated rotor
    flux (the angle of eq. 21's phi_r^): x = (phi_rd, phi_rq, e_d) with phi_r the machine's rotor
    flux and e = phi_s - phi_s^ the estimator's error; u = (dR_s, di_d, di_q), eq. 25's mismatch
    (the current error di in this frame). Returns (dx/dt, w_f) with w_f the frame's speed.

    The regulator holds the estimated stator flux at its reference exactly: law "sfvc" the vector of
    Casadei eq. 18 at constant rotor flux; law "dtc" its magnitude, eq. 19, and the estimated torque
    (3/2) p phi_s^ x i^ = T*. Eq. 21 with i^ = i + di gives phi_r^ = phi_r - g e - g sigma L_s di,
    whose q part is zero in this frame: it fixes e_q. The machine: Casadei eqs. A7-A9 (rotor flux
    from the stator current, speed w0). The estimator error from eq. 20: de/dt = dR_s i + R_s di -
    (phi_r* - |phi_r^|)/tau - j w_f e. The frame's speed w_f keeps phi_r^ on its axis, the offset
    turning backwards at w_f in it. r_off: a resistance the current error meets in the estimator's EMF
    beside R_s (0 in eq. 26; fig24_offset_resistance gives the drive's)."""
    g, sls = mach.g, mach.sigma * mach.ls
    xd, xq, ed = x
    dr, dd, dq = u
    eq = (xq - g * sls * dq) / g
    pr = xd - g * ed - g * sls * dd
    if law == "sfvc":
        ps = complex(mach.ls / mach.m * psir, mach.ls / mach.m * mach.sigma * mach.lr * 2.0 / 3.0 * torque /
                     (mach.p * psir))
    else:
        mag = mach.ls / mach.m * math.hypot(psir, 2.0 / 3.0 * mach.sigma * mach.lr / mach.p * torque / psir)
        ps = mag * np.exp(1j * math.asin(torque * g * sls / (1.5 * mach.p * pr * mag)))
    e = complex(ed, eq)
    i = (ps + e - complex(xd, xq) / g) / sls
    tr = mach.tau_r
    wf = (mach.m / tr * i.imag - xq / tr + w0 * xd - g * dr * i.imag - g * (mach.rs + r_off) * dq) / pr
    dxd = mach.m / tr * i.real - xd / tr + (wf - w0) * xq
    dxq = mach.m / tr * i.imag - xq / tr - (wf - w0) * xd
    ded = wf * eq + dr * i.real + (mach.rs + r_off) * dd - (psir - pr) / tau
    return np.array([dxd, dxq, ded]), wf


def linearised(mach, w0, torque, psir, tau, law="sfvc", r_off=0.0):
    """Casadei eq. 26 by numerical linearisation of _reduced at its operating point without mismatch:
    (A, B, w_s, x0); A's eigenvalues are eq. 27's (tests/unit/test_im_linear.py), B is eq. 28's
    in this model's states."""
    x = np.array([psir, 0.0, 0.0])
    u0 = np.zeros(3)
    for _ in range(50):  # Newton on the equilibrium (the DTC's stator-flux angle depends on the state)
        f0, _ = _reduced(mach, x, u0, w0, torque, psir, tau, law)
        J = np.empty((3, 3))
        for k in range(3):
            d = np.zeros(3)
            d[k] = 1e-7
            J[:, k] = (_reduced(mach, x + d, u0, w0, torque, psir, tau, law)[0] - f0) / 1e-7
        step = np.linalg.solve(J, -f0)
        x = x + step
        if np.max(np.abs(step)) < 1e-13:
            break
    h = 1e-7
    A, B = np.empty((3, 3)), np.empty((3, 3))
    f0, ws = _reduced(mach, x, u0, w0, torque, psir, tau, law)
    for k in range(3):
        d = np.zeros(3)
        d[k] = h
        A[:, k] = (_reduced(mach, x + d, u0, w0, torque, psir, tau, law)[0] -
                   _reduced(mach, x - d, u0, w0, torque, psir, tau, law)[0]) / (2 * h)
        B[:, k] = (_reduced(mach, x, d, w0, torque, psir, tau, law, r_off)[0] -
                   _reduced(mach, x, -d, w0, torque, psir, tau, law, r_off)[0]) / (2 * h)
    return A, B, ws, x


def offset_oscillation(mach, w0, torque, psir, tau, di_ab, law="sfvc", r_off=0.0):
    """Casadei eq. 26's answer to a constant current-sensor offset di_ab (complex, A, stationary frame):
    in the rotor-flux frame it turns at -w_s, so the rotor-flux magnitude oscillates at w_s with
    amplitude |(j w_s - A)^-1 B (0, 1, j)| |di_ab| (first row). Returns (relative amplitude of
    |phi_r| / phi_r*, w_s rad/s). r_off: as _reduced."""
    A, B, ws, _ = linearised(mach, w0, torque, psir, tau, law, r_off)
    x = np.linalg.solve(1j * ws * np.eye(3) - A, B @ np.array([0.0, 1.0, 1j]) * abs(di_ab))
    return abs(x[0]) / psir, ws


def fig24_offset_resistance(v_sign_v, i_peak_a):
    """The resistance a current-sensor offset meets in addition to R_s when the drive takes a
    sign-dependent voltage (the dead time's V_dc T_d f_sw per leg, a device's forward drop) from the
    measured current's sign: around each zero crossing of a phase whose measurement is offset by di
    the sign is wrong for di / i_peak rad of the turn, where the voltage the estimator assumes is off
    by 2 v_sign from the plant's; two crossings per turn give a mean 2 v_sign di / (pi i_peak) along
    the offset (for a two-sensor Clarke, phase A's offset also moves the reconstructed C the other way:
    the leg errors add up along the offset's alpha-beta vector). Ohm."""
    return 2.0 * v_sign_v / (math.pi * i_peak_a)


def offset_oscillation_simulated(mach, w0, torque, psir, tau, di_ab, h=2e-4, t_run=8.0, t_from=5.0):
    """The same answer from the drive's reduced model written in the stationary frame and simulated
    (RK4, step h) without linearising, SFVC (eq. 18's stator flux on the estimated rotor flux's
    angle): states phi_r and e = phi_s - phi_s^. The rotor-flux magnitude's line at w_s over
    [t_from, t_run] of the run with the offset less the run without. Relative amplitude."""
    g, sls = mach.g, mach.sigma * mach.ls
    ps_f = complex(mach.ls / mach.m * psir, mach.ls / mach.m * mach.sigma * mach.lr * 2.0 / 3.0 * torque / (mach.p * psir))

    def f(y, d):
        pr, e = y
        prh = pr - g * e - g * sls * d  # Casadei eq. 21 with the measured current
        th = prh / abs(prh)
        i = (ps_f * th + e - pr / g) / sls
        return np.array([mach.m / mach.tau_r * i - pr / mach.tau_r + 1j * w0 * pr,
                         mach.rs * d - (psir * th - prh) / tau])  # eqs. A7-A9; eq. 20's error

    def run(d, y, n):
        out = np.empty(n)
        for k in range(n):
            k1 = f(y, d)
            k2 = f(y + 0.5 * h * k1, d)
            k3 = f(y + 0.5 * h * k2, d)
            k4 = f(y + h * k3, d)
            y = y + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            out[k] = abs(y[0]) / psir
        return out
    _, _, ws, x0 = linearised(mach, w0, torque, psir, tau, "sfvc")
    y0 = np.array([complex(x0[0], x0[1]), complex(x0[2], (x0[1]) / g)])
    n = int(round(t_run / h))
    diff = run(di_ab, y0, n) - run(0.0, y0, n)
    tail = diff[int(round(t_from / h)):]
    per = int(round(2 * math.pi / ws / h))
    m = len(tail) // per * per
    return 2.0 * abs(np.sum(tail[:m] * np.exp(-1j * ws * h * np.arange(m)))) / m


def fig21_map(mach, w_sl=5.0, ws=None, taus=None):
    """Real part of the dominant pole over (w_s, tau) at a fixed slip (Casadei Fig. 21): (ws, taus, re[tau, ws])."""
    ws = np.linspace(-40.0, 40.0, 321) if ws is None else ws
    taus = np.logspace(-3.5, 0, 120) if taus is None else taus
    re = np.array([[mach.dominant_re(w - w_sl, w_sl, t) for w in ws] for t in taus])
    return ws, taus, re


def tau_at(tau_lo, tau_hi, w_lo_rpm, w_hi_rpm, ts, w_rad_s, p):
    """The firmware's tau at electrical speed w (firmware/dtc/im_est.c im_est_gain: Ts/tau linear)."""
    rpm = abs(w_rad_s) * 30.0 / math.pi / p
    if rpm <= w_lo_rpm:
        return tau_lo
    if rpm >= w_hi_rpm:
        return tau_hi
    k_lo, k_hi = ts / tau_lo, ts / tau_hi
    return ts / (k_lo + (k_hi - k_lo) * (rpm - w_lo_rpm) / (w_hi_rpm - w_lo_rpm))


def tau_check(mach, psir, torque_limit, speed_limit_rpm, tau_lo, tau_hi, w_lo_rpm=0.0, w_hi_rpm=0.0, ts=40e-6,
              n_torque=24, n_speed=800):
    """The scan of tools/config/im_tau_check.c (same grid): dict of the worst point and the unstable range."""
    p = mach.p
    w_max = speed_limit_rpm * math.pi / 30.0 * p
    out = dict(unstable=False, worst_re=-math.inf, worst_rpm=0.0, worst_torque_nm=0.0, rpm_lo=math.inf,
               rpm_hi=-math.inf, torque_min_nm=math.inf, points=0)
    for j in range(1, n_torque + 1):
        t = torque_limit * j / n_torque
        w_sl = mach.slip_for_torque(t, psir)
        for i in range(-n_speed, n_speed + 1):
            x = i / n_speed
            ws = w_max * x * x * x
            w0 = ws - w_sl
            if abs(w0) > w_max:
                continue
            tau = tau_at(tau_lo, tau_hi, w_lo_rpm, w_hi_rpm, ts, w0, p)
            re = mach.dominant_re(w0, w_sl, tau)
            out["points"] += 1
            rpm = w0 * 30.0 / math.pi / p
            if re > out["worst_re"]:
                out.update(worst_re=re, worst_rpm=rpm, worst_torque_nm=t)
            if re > 1e-9 * (1.0 / tau + w_max):
                out["unstable"] = True
                out["rpm_lo"] = min(out["rpm_lo"], rpm)
                out["rpm_hi"] = max(out["rpm_hi"], rpm)
                out["torque_min_nm"] = min(out["torque_min_nm"], t)
    return out


def plot_fig21(mach, path, w_sl=5.0, points=None, title=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ws, taus, re = fig21_map(mach, w_sl)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    cs = ax.contour(ws, taus, re, levels=[-20, -10, -5, -2, -1, -0.5, -0.2, 0.0, 0.5, 1, 2, 5, 10], colors="k",
                    linewidths=0.6)
    ax.clabel(cs, fontsize=6, fmt="%g")
    ax.contourf(ws, taus, re, levels=[0.0, max(1e-9, float(re.max()))], hatches=["//"], colors="none")
    ax.contour(ws, taus, re, levels=[0.0], colors="r", linewidths=1.2)
    for w, t, stable_sil, label in points or []:
        ax.plot([w], [t], "o" if stable_sil else "x", color="b" if stable_sil else "r", ms=7, mew=2)
    ax.set_yscale("log")
    ax.set_xlabel("estimated stator angular frequency w_s, rad/s (electrical)")
    ax.set_ylabel("estimator time constant tau, s")
    ax.set_title(title or "Re of the dominant pole, slip %g rad/s (hatched: unstable)" % w_sl, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", help="scenario TOML (motor.*); default: the default IM")
    ap.add_argument("--slip", type=float, default=5.0, help="slip angular frequency, rad/s (Fig. 21: 5)")
    ap.add_argument("--out", default="fig21.png")
    a = ap.parse_args()
    mach = Machine.from_scenario(a.scenario) if a.scenario else Machine.default_im()
    plot_fig21(mach, a.out, a.slip)
    print("wrote %s (sigma %.4f, tau_r %.4f s)" % (a.out, mach.sigma, mach.tau_r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
