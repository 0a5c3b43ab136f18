/* law_pm_dtc_si.c - the PM DTC law's part of the SI -> per-unit converter (dtc_config_si.h,
 * dtc_config_si_conv.h): its defaults' derivations (hand-over speed, current limit, mid-point
 * reconstruction), its range checks and its conversion into dtc_config_t.u.pm_dtc; the PM
 * machine's protection levels the ITC shares (dtc_si_pm_prot_convert). Host code. */
#include "dtc_config_si.h"
#include "dtc_config_si_conv.h"

#include <math.h>

double dtc_handover_residual_v(const dtc_config_si_t *si, double i_a)
{
    const double dev = fmax(si->v_ce_v, si->v_d_v);
    const double off_f = fmax(fabs(si->v_ce_v - si->v_f_v), fabs(si->v_d_v - si->v_f_v));
    double v;
    switch (si->compensation) {
    case DTC_COMP_NONE: v = dev + si->r_on_ohm * i_a; break;
    case DTC_COMP_SSTP: v = off_f; break;                           /* V_f and R_on (Hoang eqs. 24-25) */
    case DTC_COMP_FSTP_SIMPLE: v = off_f + si->r_on_ohm * i_a; break; /* Hoang Table V: V_f only */
    default: v = 0.0; break; /* Hoang Table VI with eqs. 37-38 (FSTP), Table III per leg with eqs. 24-25 (SSTP) */
    }
    if (si->deadtime_comp == 0) {
        v += si->dead_time_s / si->ts_s * si->vdc_v;
    }
    return v;
}

double dtc_vmid_beta_k(const dtc_config_si_t *si)
{
    const int on = si->vmid_cal != 0 && si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0 &&
                   si->estimator == DTC_EST_VOLTAGE && si->law == DTC_LAW_PM_DTC;
    if (!on) {
        return 0.0;
    }
    return 3.0 / 8.0 * si->c_dc_f * si->ls_h; /* beta / (3 C w^2) <= l_s / 8 */
}

double dtc_vmid_gain_tol(const dtc_config_si_t *si)
{
    return 0.02 + 1.0 / si->vdc_v;
}

double dtc_handover_default_rpm(const dtc_config_si_t *si)
{
    double drop = (si->v_ce_v > si->v_d_v ? si->v_ce_v : si->v_d_v) + si->r_on_ohm * si->rated_current_a;
    double w_emf = 3.0 * drop / si->psi_m_wb;
    double w_lpf = 10.0 * si->lpf_cutoff_rad_s;
    double w = w_emf > w_lpf ? w_emf : w_lpf;
    /* current budget of the uncompensated residual (dtc_config_si.h) */
    const double i_lim = si->current_limit_auto != 0 ? dtc_ilim_default_a(si)
                         : si->current_limit_a > 0.0 ? si->current_limit_a
                                                     : si->i_trip_a;
    const double i_r = si->rated_torque_nm / (1.5 * (double)si->pole_pairs * si->psi_m_wb);
    const double head = sqrt(fmax(i_lim * i_lim - i_r * i_r, 0.01 * i_lim * i_lim));
    const double k_topo = si->topology == DTC_TOPO_FSTP ? 2.0 / 3.0 : 1.0;
    const double w_cur = 4.0 / M_PI * k_topo * dtc_handover_residual_v(si, i_lim) / (si->ls_h * head);
    w = w_cur > w ? w_cur : w;
    {
        const double k = dtc_vmid_beta_k(si);
        /* the voltage model runs down to (1 - hyst) w_h, the hand-back speed: beta must cover the
         * tolerance there */
        const double back = 1.0 - si->handover_hyst_frac;
        const double w_beta = k > 0.0 && back > 0.0 ? sqrt(dtc_vmid_gain_tol(si) / k) / back : 0.0;
        w = w_beta > w ? w_beta : w;
    }
    return w * 30.0 / M_PI / (double)si->pole_pairs;
}

double dtc_pm_lq_h(const dtc_config_si_t *si)
{
    return si->lq_h > 0.0 ? si->lq_h : si->ls_h;
}

double dtc_ilim_step_a(const dtc_config_si_t *si)
{
    double v_max = si->topology == DTC_TOPO_SSTP ? 2.0 * si->vdc_v / 3.0 : si->vdc_v / sqrt(3.0);
    double w_max = si->speed_limit_rpm * M_PI / 30.0 * (double)si->pole_pairs;
    double l = fmin(si->ls_h, dtc_pm_lq_h(si)), psi = si->psi_m_wb;
    double e_max;
    if (dtc_law_is_im((uint16_t)si->law) != 0U) {
        dtc_im_transient_si(si, &l, &psi);
        if (si->law == DTC_LAW_IM_SFVC || si->law == DTC_LAW_IM_DFOC || si->law == DTC_LAW_IM_DSVM) {
            /* modulated laws: the period's mean voltage is made against the back-EMF (the SVM
             * laws' feed-forward, DSVM's speed ranges, Casadei eq. 15); the current changes by
             * what the applied voltage's difference from the back-EMF, at most V_max, drives
             * over one period */
            return si->ts_s * (v_max + si->rs_ohm * si->i_trip_a) / l;
        }
    }
    e_max = fmin(w_max * psi, v_max);
    return si->ts_s * (v_max + e_max + si->rs_ohm * si->i_trip_a) / l;
}

double dtc_ilim_default_a(const dtc_config_si_t *si)
{
    double di = dtc_ilim_step_a(si);
    double lim = si->i_trip_a - (si->delay_comp != 0 ? 1.0 : 2.0) * di;
    return lim > 0.0 ? lim : 0.0;
}

int dtc_config_post_fault_si(const dtc_config_si_t *si, dtc_config_si_t *post)
{
    if ((si->law != DTC_LAW_PM_DTC && si->law != DTC_LAW_IM_DTC) || si->topology != DTC_TOPO_SSTP ||
        si->reconfig_relay != 1) {
        return DTC_SI_ERR_VARIANT;
    }
    *post = *si;
    post->topology = DTC_TOPO_FSTP;
    if (si->law == DTC_LAW_IM_DTC) {
        const double k = dtc_im_fstp_flux_scale(post);
        post->flux_ref_wb *= k;
        post->psir_ref_wb *= k;
    }
    post->compensation = si->compensation == DTC_COMP_SSTP            ? DTC_COMP_FSTP_SIMPLE
                         : si->compensation == DTC_COMP_SSTP_PROPOSED ? DTC_COMP_FSTP_PROPOSED
                                                                      : si->compensation;
    post->vmid_cal = 0;
    post->cal_hold = 0;
    return DTC_SI_OK;
}

int dtc_si_pm_dtc_check(dtc_si_conv_t *c, const dtc_config_si_t *si)
{
    /* the induction machine's fields are not this law's (its machine: ls_h, psi_m_wb) */
    if (si->rr_ohm != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "rr_ohm", "rr_ohm = %g: an induction machine's field, not one of the PM law's (ls_h, psi_m_wb); must be 0", si->rr_ohm);
    if (si->lls_h != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "lls_h", "lls_h = %g: an induction machine's field, not one of the PM law's (ls_h, psi_m_wb); must be 0", si->lls_h);
    if (si->llr_h != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "llr_h", "llr_h = %g: an induction machine's field, not one of the PM law's (ls_h, psi_m_wb); must be 0", si->llr_h);
    if (si->lm_h != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "lm_h", "lm_h = %g: an induction machine's field, not one of the PM law's (ls_h, psi_m_wb); must be 0", si->lm_h);
    if (si->estimator != DTC_EST_VOLTAGE && si->estimator != DTC_EST_CURRENT)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "estimator", "estimator = %d: the PM law has DTC_EST_VOLTAGE or DTC_EST_CURRENT (DTC_EST_IMPROVED, Casadei eqs. 20-22, is the induction machine's)", si->estimator);
    if (si->sstp_table < DTC_ST_BASIC || si->sstp_table > DTC_ST_D)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "sstp_table", "sstp_table = %d: must be DTC_ST_BASIC..DTC_ST_D (DTC_ST_SPEED, Casadei sec. 8, is an induction-machine table)", si->sstp_table);
    if (si->speed_sensor != DTC_SPEED_ENCODER)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "speed_sensor", "speed_sensor = %d: DTC_SPEED_ENCODER, or DTC_SPEED_NONE with the IM law", si->speed_sensor);
    return DTC_SI_OK;
}

void dtc_si_pm_dtc_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    cfg->u.pm_dtc.part = DTC_PART_PM_DTC;
    cfg->u.pm_dtc.machine.ls_iq = dtc_si_to_iq(c, "ls_h", si->ls_h, si->ls_h / b->l_base_h);
    cfg->u.pm_dtc.machine.psi_m_iq = dtc_si_to_iq(c, "psi_m_wb", si->psi_m_wb, si->psi_m_wb / b->psi_base_wb);
    cfg->u.pm_dtc.machine.inv_ls_iq = dtc_si_to_iq(c, "ls_h (1/l_s)", si->ls_h, b->l_base_h / si->ls_h);
    cfg->u.pm_dtc.machine.lq_iq = dtc_si_to_iq(c, "lq_h", dtc_pm_lq_h(si), dtc_pm_lq_h(si) / b->l_base_h);
    {
        double h_rpm = si->handover_auto != 0 ? dtc_handover_default_rpm(si) : si->handover_speed_rpm;
        double h_pu = h_rpm * M_PI / 30.0 * si->pole_pairs / b->w_base_rad_s;
        cfg->u.pm_dtc.est.handover_speed_iq = dtc_si_to_iq(c, "handover_speed_rpm", h_rpm, h_pu);
        cfg->u.pm_dtc.est.handover_hyst_iq = dtc_si_to_iq(c, "handover_hyst_frac", si->handover_hyst_frac * h_rpm,
                                      si->handover_hyst_frac * h_pu);
        if (cfg->u.pm_dtc.est.handover_hyst_iq > cfg->u.pm_dtc.est.handover_speed_iq) {
            cfg->u.pm_dtc.est.handover_hyst_iq = cfg->u.pm_dtc.est.handover_speed_iq;
        }
    }

    cfg->u.pm_dtc.est.delay_comp = (uint16_t)si->delay_comp;
    {
        /* current limit and rotor hold (dtc_si_pm_prot_convert), ripple-robust polarity,
         * low-pass correction, DC-current suppression and mid-point regulation (dtc.c) */
        dtc_si_pm_prot_convert(c, si, b, cfg);
        cfg->u.pm_dtc.est.polarity_mid = (uint16_t)si->polarity_mid;
        cfg->u.pm_dtc.est.lpf_comp = (uint16_t)si->lpf_comp;
        cfg->u.pm_dtc.est.dc_supp = (uint16_t)si->dc_supp;
        /* Ts l_s / 20 in pu (the firmware multiplies by |w|: w_d = |w| / 20, dtc.c dtc_dcsupp) */
        cfg->u.pm_dtc.est.dcs_k_iq = dtc_si_to_iq(c, "dc_supp (Ts l_s / 20)", si->ls_h,
                                  si->ts_s * b->w_base_rad_s * si->ls_h / b->l_base_h / 20.0);
        cfg->u.pm_dtc.est.wc_pu_iq = dtc_si_to_iq(c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, si->lpf_cutoff_rad_s / b->w_base_rad_s);
        cfg->u.pm_dtc.est.lpf_wmin_iq = dtc_si_to_iq(c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, 2.0 * si->lpf_cutoff_rad_s / b->w_base_rad_s);
        {
            const int reg = si->dc_supp != 0 && si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0;
            const double g = 2.0 * si->c_dc_f * 0.5 * si->lpf_cutoff_rad_s; /* A/V, w_m = w_c / 2 */
            cfg->u.pm_dtc.est.vmid_g_iq = reg ? dtc_si_to_iq(c, "c_dc_f", si->c_dc_f, g * b->z_base_ohm) : 0;
        }
        /* restoring mid-point reconstruction: beta = min(1/16, (s w)^2), s = sqrt(k) w_base */
        cfg->u.pm_dtc.est.vmid_beta_s_iq = dtc_si_to_iq(c, "c_dc_f", si->c_dc_f, sqrt(dtc_vmid_beta_k(si)) * b->w_base_rad_s);
    }
}

double dtc_si_ilim_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    /* the current limit in use, A (0 = off) */
    const double ilim = si->current_limit_auto != 0 ? dtc_ilim_default_a(si) : si->current_limit_a;
    cfg->prot.i_lim_iq = ilim > 0.0 ? dtc_si_to_iq(c, "current_limit_a", ilim, ilim / b->i_base_a) : 0;
    if (cfg->prot.i_lim_iq >= cfg->prot.i_trip_iq) {
        cfg->prot.i_lim_iq = cfg->prot.i_trip_iq - 1; /* below the trip after rounding */
    }
    return ilim;
}

void dtc_si_pm_prot_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    const double ilim = dtc_si_ilim_convert(c, si, b, cfg);
    /* Rotor hold during the FSTP mid-point calibration (app_hold.c), PM laws: the hold may command the
     * current that gives the torque limit on the magnet axis, T = 3/2 p psi_m i_q (Hoang eq. 10),
     * and never more than the current limit, which leaves a period's current rise below the trip
     * (dtc_ilim_default_a; the hold's rise, Ts (V_dc/2 + R_s i)/L_s, is smaller). */
    cfg->prot.i_hold_iq = 0;
    if (cfg->board.vmid_cal != 0U && si->cal_hold != 0 && c->code == DTC_SI_OK) {
        const double i_t = si->torque_limit_nm / (1.5 * (double)si->pole_pairs * si->psi_m_wb);
        const double i_l = ilim > 0.0 ? ilim : dtc_ilim_default_a(si);
        const double ih = fmin(i_t, i_l);
        if (!(ih > 0.0)) {
            dtc_si_fail(c, DTC_SI_ERR_ILIM, "cal_hold", "cal_hold: no rotor-hold current fits below i_trip_a = %g A "
                        "(a period's current rise reaches the trip); set cal_hold to 0", si->i_trip_a);
            return;
        }
        cfg->prot.i_hold_iq = dtc_si_to_iq(c, "cal_hold (hold current)", ih, ih / b->i_base_a);
    }
}
