/* law_pm_itc_si.c - the PM indirect torque control's part of the SI -> per-unit converter
 * (dtc_config_si.h, dtc_config_si_conv.h): the current regulator's gains and the FSTP mid-point
 * regulation derived from the machine and the board, its range checks and its conversion into
 * dtc_config_t.u.pm_itc (firmware/dtc/pm_itc_cfg.h, itc.h). Host code.
 *
 * Current regulator (dqpi.h). The rotor-frame voltage equation with the decoupling and back-EMF
 * fed forward leaves L_s di/dt = v - R_s i per axis; a PI with K_i / K_p = R_s / L_s puts its zero
 * on that pole and the open loop becomes (w_c / s) e^{-s 1.5 Ts}: the computation period (the
 * command of step k acts from k+1, hal.h) plus half a PWM period (the zero-order hold of the
 * centred pulse) of delay. Its phase margin is 90 deg - 1.5 w_c Ts; 60 deg gives
 * w_c = (pi/6) / (1.5 Ts) = pi / (9 Ts) (a gain margin of 3, 9.5 dB, where the delay reaches
 * -180 deg): K_p = L_s w_c, K_i = R_s w_c. The torque of the surface PM machine on i_d = 0 is
 * T = (3/2) p psi_m i_q (Hoang eq. 10 with psi = L_s i + psi_m e^{j theta}): in pu
 * i_q* = T* / psi_m.
 *
 * FSTP mid-point regulation (the mid-point measured). Phase A's current is the split capacitors'
 * only DC path, dd/dt = -i_a / (2 C) for the deviation d = v_lo - V_dc/2, and an acceleration from
 * standstill leaves d at 15 V or more (the low-frequency phase-A current, SIL), which the balancing
 * resistors return only with R_bal C (15 s) while it takes min(v_lo, V_dc - v_lo)/sqrt3 of voltage
 * away. The ITC commands a DC phase-A current i_a* = g y, y the deviation low-passed at w_f (it
 * removes the swing at the fundamental, I / (2 C w)), g = 2 C w_m: the loop
 * d'' + w_f d' + w_f w_m d = 0, critically damped with w_f = 4 w_m. The current the swing feeds
 * back at the fundamental w is (w_m w_f / w^2) I; w_m = w_h / 20 with w_h the electrical speed at
 * half the rated speed keeps it at 1 % there (4 (w_h/20)^2 / w_h^2). */
#include "dtc_config_si.h"
#include "dtc_config_si_conv.h"

double dtc_itc_wc_rad_s(const dtc_config_si_t *si)
{
    return M_PI / (9.0 * si->ts_s);
}

double dtc_itc_vmid_wm_rad_s(const dtc_config_si_t *si)
{
    return 0.5 * si->rated_speed_rpm * M_PI / 30.0 * si->pole_pairs / 20.0;
}

int dtc_si_pm_itc_check(dtc_si_conv_t *c, const dtc_config_si_t *si)
{
    /* the same machine model, estimators and speed sensor as the PM DTC law (the switching table
     * is not read by this law) */
    return dtc_si_pm_dtc_check(c, si);
}

void dtc_si_pm_itc_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    dtc_pm_itc_cfg_t *p = &cfg->u.pm_itc;
    const double wc = dtc_itc_wc_rad_s(si);
    p->part = DTC_PART_PM_ITC;
    p->machine.ls_iq = dtc_si_to_iq(c, "ls_h", si->ls_h, si->ls_h / b->l_base_h);
    p->machine.psi_m_iq = dtc_si_to_iq(c, "psi_m_wb", si->psi_m_wb, si->psi_m_wb / b->psi_base_wb);
    p->machine.inv_ls_iq = dtc_si_to_iq(c, "ls_h (1/l_s)", si->ls_h, b->l_base_h / si->ls_h);
    p->machine.lq_iq = dtc_si_to_iq(c, "lq_h", dtc_pm_lq_h(si), dtc_pm_lq_h(si) / b->l_base_h);
    p->cc.kp_iq = dtc_si_to_iq(c, "ls_h (ITC K_p = L_s w_c)", si->ls_h, si->ls_h / b->l_base_h * wc / b->w_base_rad_s);
    p->cc.ki_ts_iq = dtc_si_to_iq(c, "rs_ohm (ITC K_i Ts = R_s w_c Ts)", si->rs_ohm, si->rs_ohm / b->z_base_ohm * wc * si->ts_s);
    p->cc.iq_per_t_iq = dtc_si_to_iq(c, "psi_m_wb (ITC 1/psi_m)", si->psi_m_wb, b->psi_base_wb / si->psi_m_wb);
    p->est.lpf_comp = (uint16_t)si->lpf_comp;
    p->est.wc_pu_iq = dtc_si_to_iq(c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, si->lpf_cutoff_rad_s / b->w_base_rad_s);
    p->est.lpf_wmin_iq = dtc_si_to_iq(c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, 2.0 * si->lpf_cutoff_rad_s / b->w_base_rad_s);
    if (si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0) {
        const double w_m = dtc_itc_vmid_wm_rad_s(si);
        p->mid.g_iq = dtc_si_to_iq(c, "c_dc_f (ITC mid-point gain 2 C w_m)", si->c_dc_f, 2.0 * si->c_dc_f * w_m * b->z_base_ohm);
        p->mid.kf_iq = dtc_si_to_iq(c, "rated_speed_rpm (ITC mid-point filter w_f Ts)", si->rated_speed_rpm, 4.0 * w_m * si->ts_s);
    }
    dtc_si_pm_prot_convert(c, si, b, cfg);
}
