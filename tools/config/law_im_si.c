/* law_im_si.c - the induction-machine laws' part of the SI -> per-unit converter
 * (dtc_config_si.h, dtc_config_si_conv.h): the IM rig's defaults, the derived table speed, the
 * range checks of the IM fields and the conversion into dtc_config_t.u.im. Host code. */
#include "dtc_config_si.h"
#include "dtc_config_si_conv.h"
#include "plant_defaults.h"

#include <math.h>
#include <stdio.h>

void dtc_config_si_im_defaults(dtc_config_si_t *si)
{
    dtc_config_si_defaults(si);
    si->law = DTC_LAW_IM_DTC;
    /* The default IM of plant_defaults.h: 4 kW, 4 poles, 50 Hz, 220 V */
    si->rs_ohm = PLANT_DEF_IM_RS_OHM;
    si->rr_ohm = PLANT_DEF_IM_RR_OHM;
    si->lls_h = PLANT_DEF_IM_LLS_H;
    si->llr_h = PLANT_DEF_IM_LLR_H;
    si->lm_h = PLANT_DEF_IM_LM_H;
    si->ls_h = 0.0;
    si->psi_m_wb = 0.0;
    si->pole_pairs = PLANT_DEF_IM_POLE_PAIRS;
    si->rated_speed_rpm = 1500.0;  /* synchronous speed at 50 Hz: the speed base */
    si->rated_torque_nm = PLANT_DEF_IM_RATED_TORQUE_NM;
    si->rated_current_a = PLANT_DEF_IM_RATED_CURRENT_A;
    si->inertia_kgm2 = PLANT_DEF_IM_J_KGM2;
    /* SSTP on sqrt(2) * 220 V; the plant's devices */
    si->topology = DTC_TOPO_SSTP;
    si->vdc_v = PLANT_DEF_IM_VDC_V;
    si->compensation = DTC_COMP_SSTP;
    si->ts_s = PLANT_DEF_IM_TS_S;   /* Casadei section 10.5 */
    si->handover_auto = 0;         /* PM start-up only */
    si->handover_speed_rpm = 0.0;
    si->delay_comp = 0;            /* PM law only */
    si->flux_ref_wb = PLANT_DEF_IM_FLUX_REF_WB;
    si->flux_band_wb = 0.0;
    si->torque_band_nm = 0.0;
    si->torque_limit_nm = PLANT_DEF_IM_TORQUE_LIMIT_NM;
    si->speed_limit_rpm = 6000.0;     /* Casadei Fig. 32: 400 % of base speed */
    si->speed_ref_rpm = 0.0;
    si->speed_bw_rad_s = 30.0;
    si->estimator = DTC_EST_IMPROVED;
    si->sstp_table = DTC_ST_BASIC;
    /* The IM rig's sensors and protection (plant_defaults.h): currents -range..+range over the
     * 12-bit code range, voltages 0..range. */
    si->adc_i_a_per_count = 2.0 * PLANT_DEF_IM_CURRENT_RANGE_A / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->adc_vdc_v_per_count = PLANT_DEF_IM_VOLTAGE_RANGE_V / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->adc_vmid_v_per_count = PLANT_DEF_IM_VOLTAGE_RANGE_V / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->i_trip_a = PLANT_DEF_IM_OVERCURRENT_A;
    si->vdc_max_v = PLANT_DEF_IM_VDC_MAX_V;
    si->vdc_min_v = PLANT_DEF_IM_VDC_MIN_V;
    si->v_base_v = PLANT_DEF_IM_VDC_V;
    si->i_base_a = PLANT_DEF_IM_RATED_CURRENT_A;
    si->w_base_rad_s = 2.0 * M_PI * 50.0;
}

double dtc_table_speed_default_rpm(const dtc_config_si_t *si)
{
    const double w_el = 0.5 * si->vdc_v / sqrt(3.0) / si->flux_ref_wb;
    return w_el * 30.0 / M_PI / (double)si->pole_pairs;
}

void dtc_im_transient_si(const dtc_config_si_t *si, double *l_h, double *psi_wb)
{
    const double ls = si->lls_h + si->lm_h, lr = si->llr_h + si->lm_h, m = si->lm_h;
    const double psir = si->psir_ref_wb > 0.0 ? si->psir_ref_wb : si->flux_ref_wb * m / ls;
    *l_h = (1.0 - m * m / (ls * lr)) * ls;
    *psi_wb = m / lr * psir;
}

double dtc_im_torque_at_current_nm(const dtc_config_si_t *si, double i_a)
{
    const double ls = si->lls_h + si->lm_h, lr = si->llr_h + si->lm_h, m = si->lm_h;
    const double sigma = 1.0 - m * m / (ls * lr);
    double id2;
    if (si->psir_ref_wb > 0.0) {
        id2 = (si->psir_ref_wb / m) * (si->psir_ref_wb / m);
    } else {
        const double phi = si->flux_ref_wb, sli = sigma * ls * i_a;
        if (phi <= sli) {
            return HUGE_VAL;
        }
        id2 = (phi * phi - sli * sli) / (ls * ls * (1.0 - sigma * sigma));
    }
    if (!(i_a * i_a > id2)) {
        return 0.0;
    }
    return 1.5 * (double)si->pole_pairs * m * m / lr * sqrt(id2) * sqrt(i_a * i_a - id2);
}

double dtc_im_hold_margin_a(const dtc_config_si_t *si)
{
    if (si->law == DTC_LAW_IM_SFVC || (si->law == DTC_LAW_IM_DFOC && !(si->dfoc_zeta > 0.0))) {
        /* V_max T_s / (4 sigma L_s): the SVM laws' dI without its r_s I_trip term, a quarter. The
         * SFVC's deadbeat flux regulator (Casadei eq. 24) and the DFOC's first-order current loops
         * (the PI's zero on the stator transient pole, dfoc_zeta = 0, with the conditional-integration
         * anti-windup, firmware im_dfoc.c) put no overshoot on a step of the reference to the limit
         * (measured, docs/sil.md), so what lies above the held current is the modulator's ripple */
        dtc_config_si_t z = *si;
        z.i_trip_a = 0.0;
        return 0.25 * dtc_ilim_step_a(&z);
    }
    /* a whole period's dI: the switching-table laws and DSVM (one vector over the period), and the
     * DFOC with dfoc_zeta > 0 (both poles at w_c: the PI's zero near w_c, the step overshoots) */
    return dtc_ilim_step_a(si);
}

int dtc_im_torque_room_check(const dtc_config_si_t *si, char *msg, size_t msg_size)
{
    double ilim, di, h, t_i, lo = 0.0, hi, i_need, k, ts_max;
    int n;
    if (dtc_law_is_im((uint16_t)si->law) == 0U || !(si->rated_torque_nm > 0.0) || !(si->ts_s > 0.0)) {
        return 0;
    }
    ilim = si->current_limit_auto != 0 ? dtc_ilim_default_a(si) : si->current_limit_a;
    if (!(ilim > 0.0)) {
        return 0;
    }
    di = dtc_ilim_step_a(si);
    h = dtc_im_hold_margin_a(si);
    t_i = dtc_im_torque_at_current_nm(si, ilim - h);
    if (!(t_i < si->rated_torque_nm) || !(di > 0.0) || !(h > 0.0)) {
        return 0;
    }
    /* the current the rated torque needs: the torque rises with the current (bisection) */
    hi = si->i_trip_a > 0.0 ? si->i_trip_a : 1.0;
    for (n = 0; n < 40 && dtc_im_torque_at_current_nm(si, hi) < si->rated_torque_nm; n++) {
        hi *= 2.0;
    }
    for (n = 0; n < 60; n++) {
        const double mid = 0.5 * (lo + hi);
        if (dtc_im_torque_at_current_nm(si, mid) < si->rated_torque_nm) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    i_need = hi;
    if (si->current_limit_auto != 0) {
        /* the margin between the trip and the current held: k periods' dI (dtc_ilim_default_a) and
         * the law's excursion h, both proportional to ts_s and of the form a + b i_trip (dI's
         * r_s i_trip term) */
        dtc_config_si_t z = *si;
        double tot, tot0, b, trip_min;
        k = (si->i_trip_a - ilim) / di;
        tot = si->i_trip_a - ilim + h;
        ts_max = si->i_trip_a > i_need ? si->ts_s * (si->i_trip_a - i_need) / tot : 0.0;
        z.i_trip_a = 0.0;
        tot0 = k * dtc_ilim_step_a(&z) + dtc_im_hold_margin_a(&z);
        b = si->i_trip_a > 0.0 ? (tot - tot0) / si->i_trip_a : 0.0;
        trip_min = 1.0 - b > 0.0 ? (i_need + tot0) / (1.0 - b) : HUGE_VAL;
        snprintf(msg, msg_size,
                 "the torque the current allows, %.1f N*m, is below rated_torque_nm %.1f N*m: the rated torque "
                 "needs %.2f A, the limit holds %.2f A (i_trip_a %.1f A less %.2f periods' largest change dI = %.2f A "
                 "at ts_s = %.4g s and the law's excursion above the held current, %.2f A); ts_s <= %.4g s or "
                 "i_trip_a >= %.2f A gives it",
                 t_i, si->rated_torque_nm, i_need, ilim - h, si->i_trip_a, k, di, si->ts_s, h, ts_max, trip_min);
    } else {
        ts_max = ilim > i_need ? si->ts_s * (ilim - i_need) / h : 0.0;
        snprintf(msg, msg_size,
                 "the torque the current allows, %.1f N*m, is below rated_torque_nm %.1f N*m: the rated torque "
                 "needs %.2f A, the limit holds %.2f A (current_limit_a %.1f A less the law's excursion above the "
                 "held current, %.2f A at ts_s = %.4g s); ts_s <= %.4g s or current_limit_a >= %.2f A (below "
                 "i_trip_a) gives it",
                 t_i, si->rated_torque_nm, i_need, ilim - h, ilim, h, si->ts_s, ts_max, i_need + h);
    }
    return 1;
}

double dtc_im_fstp_flux_scale(const dtc_config_si_t *si)
{
    /* Hoang Table I's four vectors span a rhombus with the vertices V_dc/3 (alpha) and V_dc/sqrt3
     * (beta); the largest circle inside it has the radius V_dc / (2 sqrt3), half the SSTP's
     * V_dc / sqrt3 (less the mid-point's swing, below). The flux follows a circle at w_e while the
     * voltage left after R_s I_n, V = r - R_s I_n, covers w_e |phi_s| (Casadei eq. 1 in steady state), at the
     * drive's speed plus the rated slip at the rated flux (Casadei eq. 16 in SI:
     * w_slip = R_r T_n / (3/2 p phi_r^2), phi_r the configured rotor flux). Along the alpha axis the
     * rhombus reaches V_dc/3, 15 % beyond the circle: the torque-producing part of the stator flux
     * (Casadei eq. 19's second term) that a rotor-flux reference scaled by the same factor leaves
     * under load is within that. */
    const double ls = si->lls_h + si->lm_h, m = si->lm_h;
    const double psir = si->psir_ref_wb > 0.0 ? si->psir_ref_wb : si->flux_ref_wb * m / ls;
    const double rpm = si->mode == DTC_MODE_SPEED && si->speed_ref_rpm != 0.0 ? fabs(si->speed_ref_rpm)
                                                                             : si->rated_speed_rpm;
    const double w_slip = si->rr_ohm * si->rated_torque_nm / (1.5 * si->pole_pairs * psir * psir);
    const double w_e = rpm * M_PI / 30.0 * si->pole_pairs + w_slip;
    /* The split link's mid-point swings with phase A's current, which returns through the two
     * capacitors: d v_lo / dt = -i_a / (2 C) (docs/plant.md "DC link"), so a phase current of
     * amplitude I_n at w_e moves the mid-point by I_n / (2 C w_e) either way, and the alpha
     * vectors V_1, V_3 (2/3 of the mid-point's distance from either rail, Hoang Table I with
     * v_a0 = V_mid) each shrink by 2/3 of that in their half-period: the rhombus's alpha vertex is
     * a = V_dc/3 - I_n / (3 C w_e), its beta vertex b = V_dc/sqrt3, and the circle inside it has
     * the radius a b / sqrt(a^2 + b^2) (V_dc / (2 sqrt3) for a stiff mid-point). */
    const double a = si->vdc_v / 3.0 - (w_e > 0.0 && si->c_dc_f > 0.0 ? si->rated_current_a / (3.0 * si->c_dc_f * w_e) : 0.0);
    const double b = si->vdc_v / sqrt(3.0);
    const double v = (a > 0.0 ? a * b / sqrt(a * a + b * b) : 0.0) - si->rs_ohm * si->rated_current_a;
    const double psi_max = w_e > 0.0 && v > 0.0 ? v / w_e : si->flux_ref_wb;
    return psi_max < si->flux_ref_wb ? psi_max / si->flux_ref_wb : 1.0;
}

int dtc_si_im_check(dtc_si_conv_t *c, const dtc_config_si_t *si)
{
    /* the PM law's machine fields are not this law's (its machine: rr_ohm, lls_h, llr_h, lm_h) */
    if (si->ls_h != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "ls_h", "ls_h = %g: a PM machine's field, not one of the IM law's (rr_ohm, lls_h, llr_h, lm_h); must be 0", si->ls_h);
    if (si->lq_h != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "lq_h", "lq_h = %g: a PM machine's field, not one of the IM law's (rr_ohm, lls_h, llr_h, lm_h); must be 0", si->lq_h);
    if (si->psi_m_wb != 0.0) return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "psi_m_wb", "psi_m_wb = %g: a PM machine's field, not one of the IM law's (rr_ohm, lls_h, llr_h, lm_h); must be 0", si->psi_m_wb);
    if (si->estimator != DTC_EST_VOLTAGE && si->estimator != DTC_EST_IMPROVED)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "estimator", "estimator = %d: the IM law has DTC_EST_VOLTAGE or DTC_EST_IMPROVED (DTC_EST_CURRENT, Hoang eqs. 8-9, needs a magnet)", si->estimator);
    if (si->topology != DTC_TOPO_SSTP && !(si->topology == DTC_TOPO_FSTP && si->law == DTC_LAW_IM_DTC))
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "topology", "topology = %d: the four-switch inverter (DTC_TOPO_FSTP) runs the IM switching-table DTC only (law DTC_LAW_IM_DTC, Hoang Table II); DSC, DSVM, SFVC and DFOC need the six-switch inverter (DTC_TOPO_SSTP)", si->topology);
    if (si->topology == DTC_TOPO_FSTP && si->flux_weakening != 0)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "flux_weakening", "flux_weakening = %d: Casadei section 12's flux weakening is not written for the four-switch inverter (DTC_TOPO_FSTP)", si->flux_weakening);
    if (si->sstp_table < DTC_ST_BASIC || si->sstp_table > DTC_ST_SPEED)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "sstp_table", "sstp_table = %d: must be DTC_ST_BASIC..DTC_ST_SPEED", si->sstp_table);
    if (si->speed_sensor != DTC_SPEED_ENCODER && si->speed_sensor != DTC_SPEED_NONE)
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "speed_sensor", "speed_sensor = %d: DTC_SPEED_ENCODER, or DTC_SPEED_NONE with the IM law", si->speed_sensor);
    return DTC_SI_OK;
}

/* The induction-machine laws' part u.im (Casadei 2006), after the common part (the speed PI,
 * limits and references are converted by dtc_config_from_si). T model: L_s = L_ls + M, L_r = L_lr + M,
 * sigma = 1 - M^2 / (L_s L_r). */
void dtc_si_im_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    const double ls = si->lls_h + si->lm_h, lr = si->llr_h + si->lm_h, m = si->lm_h;
    const double sigma = 1.0 - m * m / (ls * lr);
    const double tsp = si->ts_s * b->w_base_rad_s;
    const double rpm_pu = M_PI / 30.0 * si->pole_pairs / b->w_base_rad_s;
    /* Rotor-flux reference: the constant one of Casadei eq. 19, or the no-load rotor flux of the stator-
     * flux reference (phi_r = (M/L_s) phi_s at zero torque). */
    const double psir = si->psir_ref_wb > 0.0 ? si->psir_ref_wb : si->flux_ref_wb * m / ls;
    dtc_im_machine_cfg_t *im = &cfg->u.im.machine;

    cfg->u.im.part = DTC_PART_IM;
    /* what the derived rows below are designed from, held for the identification's apply
     * (firmware app_ident_apply.c designs them again on the identified machine) */
    cfg->u.im.design.vdc_iq = dtc_si_to_iq(c, "vdc_v", si->vdc_v, si->vdc_v / b->v_base_v);
    cfg->u.im.design.torque_limit_iq = dtc_si_to_iq(c, "torque_limit_nm", si->torque_limit_nm, si->torque_limit_nm / b->t_base_nm);
    cfg->u.im.design.derived = (uint16_t)((si->current_limit_auto == 0 ? 0U : si->delay_comp != 0 ? 1U : 2U) |
                                          (si->law == DTC_LAW_IM_DSVM && si->dsvm_torque_band2_nm == 0.0 ? DTC_IM_DESIGN_BAND2 : 0U));
    cfg->u.im.design.magn_wait_iq = si->magn_frac > 0.0 && si->magn_frac < 1.0
        ? dtc_si_to_iq(c, "magn_frac", si->magn_frac, log(1.0 / (1.0 - si->magn_frac))) : 0;
    {
        /* The current limit (the switching-table laws' vector override, firmware/dtc/ilim.h) and
         * the torque the current allows: the steady-state torque at I_lim less the law's excursion
         * above the held current (dtc_im_hold_margin_a: one period's change dI, or the SFVC's SVM
         * ripple), so that the excursion stays below the limit. The torque limit in force
         * (references, speed PI) is the smaller of torque_limit_nm and that torque. */
        const double ilim = dtc_si_ilim_convert(c, si, b, cfg);
        if (ilim > 0.0) {
            const double t_i = dtc_im_torque_at_current_nm(si, ilim - dtc_im_hold_margin_a(si));
            if (!(t_i > 0.0)) {
                /* the trip level leaves no room for the limit with a period this long: no limit,
                 * the trip is the only protection, as dtc_ilim_default_a does for the PM law */
                cfg->prot.i_lim_iq = 0;
            } else if (t_i < si->torque_limit_nm) {
                /* a larger request is held at the limit, as the firmware clamps a reference set */
                cfg->speed.torque_limit_iq = dtc_si_to_iq(c, "torque_limit_nm (the current limit's torque)", t_i, t_i / b->t_base_nm);
                cfg->speed.torque_ref_iq = fix_clamp32(cfg->speed.torque_ref_iq, -cfg->speed.torque_limit_iq,
                                                       cfg->speed.torque_limit_iq);
            }
        }
    }
    if (!(si->tau_lo_s > si->ts_s)) { dtc_si_fail(c, DTC_SI_ERR_IM, "tau_lo_s", "tau_lo_s = %g: must be longer than the control period ts_s = %g s", si->tau_lo_s, si->ts_s); return; }
    if (!(si->tau_hi_s > si->ts_s)) { dtc_si_fail(c, DTC_SI_ERR_IM, "tau_hi_s", "tau_hi_s = %g: must be longer than the control period ts_s = %g s", si->tau_hi_s, si->ts_s); return; }
    if (!(si->tau_w_hi_rpm >= si->tau_w_lo_rpm)) { dtc_si_fail(c, DTC_SI_ERR_IM, "tau_w_hi_rpm", "tau_w_hi_rpm = %g: must not be below tau_w_lo_rpm = %g", si->tau_w_hi_rpm, si->tau_w_lo_rpm); return; }
    if (!(si->speed_filter_s > si->ts_s * si->speed_div)) { dtc_si_fail(c, DTC_SI_ERR_IM, "speed_filter_s", "speed_filter_s = %g: must be longer than the speed period ts_s * speed_div", si->speed_filter_s); return; }

    im->rr_iq = dtc_si_to_iq(c, "rr_ohm", si->rr_ohm, si->rr_ohm / b->z_base_ohm);
    im->sigma_ls_iq = dtc_si_to_iq(c, "lls_h (sigma L_s)", si->lls_h, sigma * ls / b->l_base_h);
    im->sigma_lr_iq = dtc_si_to_iq(c, "llr_h (sigma L_r)", si->llr_h, sigma * lr / b->l_base_h);
    im->kr_iq = dtc_si_to_iq(c, "llr_h (L_r/M)", si->llr_h, lr / m);
    im->ks_iq = dtc_si_to_iq(c, "lls_h (L_s/M)", si->lls_h, ls / m);
    im->inv_ks_iq = dtc_si_to_iq(c, "lls_h (M/L_s)", si->lls_h, m / ls);
    im->m_iq = dtc_si_to_iq(c, "lm_h", si->lm_h, m / b->l_base_h);

    /* Improved estimator: Ts/tau in Q31, speed-dependent between the two speeds. */
    cfg->u.im.est.k_lo_q31 = dtc_si_to_q31(c, "tau_lo_s (Ts/tau)", si->ts_s / si->tau_lo_s);
    cfg->u.im.est.k_hi_q31 = dtc_si_to_q31(c, "tau_hi_s (Ts/tau)", si->ts_s / si->tau_hi_s);
    cfg->u.im.est.w_lo_iq = dtc_si_to_iq(c, "tau_w_lo_rpm", si->tau_w_lo_rpm, si->tau_w_lo_rpm * rpm_pu);
    cfg->u.im.est.w_hi_iq = dtc_si_to_iq(c, "tau_w_hi_rpm", si->tau_w_hi_rpm, si->tau_w_hi_rpm * rpm_pu);
    if (cfg->u.im.est.w_hi_iq > cfg->u.im.est.w_lo_iq) {
        const double slope = (si->ts_s / si->tau_hi_s - si->ts_s / si->tau_lo_s) /
                             ((si->tau_w_hi_rpm - si->tau_w_lo_rpm) * rpm_pu);
        const double r = nearbyint(slope * 2147483648.0);
        if (!(fabs(r) <= 2147483647.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "tau_w_hi_rpm", "tau_w_hi_rpm = %g: the Ts/tau slope overflows Q31", si->tau_w_hi_rpm); return; }
        cfg->u.im.est.k_slope_q31 = (q31_t)r;
    }

    if (si->law == DTC_LAW_IM_SFVC || si->law == DTC_LAW_IM_DFOC) {
        /* SVM schemes (im_sfvc.c, im_dfoc.c): one SVM carrier period per control period */
        if (!(si->carrier_hz == 0.0 || fabs(si->carrier_hz * si->ts_s - 1.0) < 1e-9)) { dtc_si_fail(c, DTC_SI_ERR_IM, "carrier_hz", "carrier_hz = %g: the SVM carrier period must equal the control period ts_s = %g s (one PWM period per control period; 0 = 1/ts_s)", si->carrier_hz, si->ts_s); return; }
        if (!(si->psir_ref_wb > 0.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "psir_ref_wb", "psir_ref_wb = %g: the stator-flux vector control (Casadei eq. 18) and the rotor-flux-oriented control take the rotor-flux command: must be > 0", si->psir_ref_wb); return; }
        if (si->flux_weakening != 0) { dtc_si_fail(c, DTC_SI_ERR_IM, "flux_weakening", "flux_weakening = %d: section 12's flux weakening watches the DTC torque comparator; not with SFVC or DFOC", si->flux_weakening); return; }
        cfg->u.im.svm_mode = (uint16_t)si->svm_mode;
    }
    if (si->law == DTC_LAW_IM_SFVC) {
        /* the flux regulator's K_p (Casadei eq. 24) in pu voltage per pu flux = K_p / w_base */
        const double kp = si->sfvc_kp_per_s > 0.0 ? si->sfvc_kp_per_s : 0.5 / si->ts_s;
        if (!(si->sfvc_kp_per_s * si->ts_s <= 1.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "sfvc_kp_per_s", "sfvc_kp_per_s = %g: must be at most 1/ts_s = %g 1/s, the deadbeat gain (0 = derived)", si->sfvc_kp_per_s, 1.0 / si->ts_s); return; }
        cfg->u.im.sfvc.kp_iq = dtc_si_to_iq(c, "sfvc_kp_per_s", kp, kp / b->w_base_rad_s);
    }
    if (si->law == DTC_LAW_IM_DFOC) {
        /* Current PI regulators in the rotor-flux frame (Casadei sec. 13, im_dfoc.c). With the
         * back-EMF j w_s phi_s fed forward, the current sees sigma L_s di/dt = v - R_s i (the
         * transient inductance): a PI with its zero at R_s / (sigma L_s) and the crossover w_c
         * makes the loop w_c / (s + w_c): K_p = sigma L_s w_c, K_i = R_s w_c. The loop's delay of
         * about 1.5 Ts (the computation period and the PWM's half period) costs 1.5 w_c Ts of
         * phase at w_c: derived w_c = 0.2 / Ts, 0.3 rad (17 deg), a first-order response without
         * overshoot; dfoc_bw_hz sets w_c / (2 pi) instead, below 1 / (6 Ts) where the delay takes
         * the whole 90 deg (a faster loop overshoots: the modulus optimum w_c = 1 / (3 Ts), 4 %).
         * dfoc_zeta > 0 places the PI instead as textbooks of field-oriented control do, both poles
         * of sigma L_s s^2 + (R_s + K_p) s + K_i at w_c with damping zeta: K_p = 2 zeta w_c sigma L_s
         * - R_s, K_i = sigma L_s w_c^2; its zero K_i / K_p, near w_c, makes the step overshoot.
         * References (T model, rotor-flux frame): i_d = phi_r* / M, T = (3/2) p (M/L_r) phi_r i_q,
         * in pu i_q = (l_r/m) T / phi_r*. */
        const double wc = si->dfoc_bw_hz > 0.0 ? 2.0 * M_PI * si->dfoc_bw_hz : 0.2 / si->ts_s;
        const double sls = sigma * ls;
        const double kp_ohm = si->dfoc_zeta > 0.0 ? 2.0 * si->dfoc_zeta * wc * sls - si->rs_ohm : sls * wc;
        const double ki_ohm_per_s = sls * wc * wc;
        if (!(si->dfoc_bw_hz >= 0.0 && si->dfoc_bw_hz * 6.0 * si->ts_s < 1.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "dfoc_bw_hz", "dfoc_bw_hz = %g: must be 0 (derived) or below 1/(6 ts_s) = %g Hz, where the loop's 1.5 ts_s delay leaves no phase margin", si->dfoc_bw_hz, 1.0 / (6.0 * si->ts_s)); return; }
        if (!(si->dfoc_zeta >= 0.0 && si->dfoc_zeta <= 10.0 && kp_ohm > 0.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "dfoc_zeta", "dfoc_zeta = %g: must be 0 (the zero on the stator pole) or in (0, 10] with K_p = 2 zeta w_c sigma L_s - R_s > 0 (here %g ohm)", si->dfoc_zeta, kp_ohm); return; }
        if (si->dfoc_zeta > 0.0) {
            cfg->u.im.dfoc.kp_iq = dtc_si_to_iq(c, "lls_h (DFOC K_p = 2 zeta w_c sigma L_s - R_s)", si->lls_h, kp_ohm / b->z_base_ohm);
            cfg->u.im.dfoc.ki_ts_iq = dtc_si_to_iq(c, "lls_h (DFOC K_i Ts = sigma L_s w_c^2 Ts)", si->lls_h, ki_ohm_per_s / b->z_base_ohm * si->ts_s);
        } else {
            const double zpu = si->rs_ohm / b->z_base_ohm;
            cfg->u.im.dfoc.kp_iq = dtc_si_to_iq(c, "lls_h (DFOC K_p = sigma L_s w_c)", si->lls_h, sigma * ls / b->l_base_h * wc / b->w_base_rad_s);
            cfg->u.im.dfoc.ki_ts_iq = zpu > 0.0 ? dtc_si_to_iq(c, "rs_ohm (DFOC K_i Ts = R_s w_c Ts)", si->rs_ohm, zpu * wc * si->ts_s) : 0;
        }
        cfg->u.im.dfoc.id_ref_iq = dtc_si_to_iq(c, "psir_ref_wb (DFOC i_d* = phi_r* / M)", si->psir_ref_wb, si->psir_ref_wb / m / b->i_base_a);
        cfg->u.im.dfoc.iq_per_t_iq = dtc_si_to_iq(c, "psir_ref_wb (DFOC l_r/(m phi_r*))", si->psir_ref_wb, lr / m / (si->psir_ref_wb / b->psi_base_wb));
    }
    if (si->law == DTC_LAW_IM_DSVM) {
        /* The five-level torque comparator (hyst.h hyst5_t): the outer band. Derived (0): the
         * levels +-2 (a whole active vector) only when the torque error exceeds what a whole
         * vector changes in one period, Casadei eqs. 12, 15 at standstill with the vector
         * across the flux: dT = (3/2) p M / (sigma L_s L_r) |V_k| |phi_r| Ts, |V_k| = 2/3 V_dc;
         * so band2 / 2 = dT (and at least the inner band). */
        const double dt_full = 1.5 * si->pole_pairs * m / (sigma * ls * lr) * (2.0 / 3.0 * si->vdc_v) * psir * si->ts_s;
        const double b2 = si->dsvm_torque_band2_nm > 0.0 ? si->dsvm_torque_band2_nm
                                                         : fmax(2.0 * dt_full, si->torque_band_nm);
        if (!(si->dsvm_torque_band2_nm == 0.0 || si->dsvm_torque_band2_nm >= si->torque_band_nm)) { dtc_si_fail(c, DTC_SI_ERR_BAND, "dsvm_torque_band2_nm", "dsvm_torque_band2_nm = %g: must be 0 (derived) or >= torque_band_nm = %g", si->dsvm_torque_band2_nm, si->torque_band_nm); return; }
        if (si->flux_weakening != 0) { dtc_si_fail(c, DTC_SI_ERR_IM, "flux_weakening", "flux_weakening = %d: section 12's flux weakening watches the three-level torque comparator; not with DSVM", si->flux_weakening); return; }
        cfg->u.im.dsvm.torque_band2_iq = dtc_si_to_iq(c, "dsvm_torque_band2_nm", b2, b2 / b->t_base_nm);
    }
    {
        const double rpm = si->table_speed_rpm > 0.0 ? si->table_speed_rpm : dtc_table_speed_default_rpm(si);
        cfg->u.im.table_speed_iq = dtc_si_to_iq(c, "table_speed_rpm", rpm, rpm * rpm_pu);
    }
    cfg->u.im.fw.on = (uint16_t)si->flux_weakening;
    cfg->u.im.fw.window = (uint16_t)si->fw_window;
    {
        /* Casadei eq. 31: pull-out torque at stator flux phi_s (R_s neglected):
         * T_max = (3/2) p (1 - sigma) / (2 sigma L_s) phi_s^2, so k_T = T_max / phi_s^2. In pu
         * (T_base = 3/2 p psi_base I_base): k_T = (1 - sigma) / (2 sigma l_s). */
        const double kt_pu = (1.0 - sigma) / (2.0 * sigma * ls / b->l_base_h);
        const double psi_pu = si->flux_ref_wb / b->psi_base_wb;
        cfg->u.im.fw.step_down_iq = dtc_si_to_iq(c, "fw_step_frac", si->fw_step_frac, si->fw_step_frac * psi_pu);
        cfg->u.im.fw.step_up_iq = cfg->u.im.fw.step_down_iq;
        cfg->u.im.fw.psi_min_iq = dtc_si_to_iq(c, "fw_psi_min_frac", si->fw_psi_min_frac, si->fw_psi_min_frac * psi_pu);
        cfg->u.im.fw.inv_psi_rated_iq = dtc_si_to_iq(c, "flux_ref_wb (1/phi_s,rated)", si->flux_ref_wb, 1.0 / psi_pu);
        cfg->u.im.fw.kt_iq = dtc_si_to_iq(c, "lls_h (k_T of eq. 34)", si->lls_h, kt_pu);
    }

    cfg->speed.sensor = (uint16_t)si->speed_sensor;
    cfg->u.im.ref.psir_ref_iq = dtc_si_to_iq(c, "psir_ref_wb", si->psir_ref_wb, si->psir_ref_wb / b->psi_base_wb);
    cfg->u.im.ref.inv_psir_ref_iq = si->psir_ref_wb > 0.0
        ? dtc_si_to_iq(c, "psir_ref_wb (1/phi_r*)", si->psir_ref_wb, b->psi_base_wb / si->psir_ref_wb) : 0;
    cfg->u.im.ref.inv_psir_sq_iq = dtc_si_to_iq(c, "psir_ref_wb (1/phi_r*^2)", psir,
                                      (b->psi_base_wb / psir) * (b->psi_base_wb / psir));
    /* sensorless speed once per speed period T_speed = speed_div Ts (im_ref.h) */
    cfg->u.im.ref.gain_w_iq = dtc_si_to_iq(c, "ts_s (angle-to-speed gain)", si->ts_s,
                                    2.0 * M_PI / (65536.0 * tsp * si->speed_div));
    cfg->u.im.ref.speed_filt_q31 = dtc_si_to_q31(c, "speed_filter_s",
                                          1.0 - exp(-si->ts_s * si->speed_div / si->speed_filter_s));
    cfg->u.im.ref.enc_plaus_iq = 0;
    cfg->u.im.ref.rr_track = (uint16_t)si->rr_track;
    cfg->u.im.ref.cm_ref = (uint16_t)si->cm_ref;
    if (si->fault_detect == 1 && si->speed_sensor == DTC_SPEED_ENCODER && si->inertia_kgm2 > 0.0) {
        /* Encoder plausibility (im_dtc.h, app_enc.h app_enc_flux_check): the sensorless speed
         * (Casadei eq. 22's angular speed less eq. 16's slip r_r T / phi_r*^2) and the encoder's
         * speed through the same filter differ, on a sound encoder, by the error of the slip
         * term and by the delay of one speed period at the largest acceleration. The slip error is
         * at most the true slip, w_slip = R_r T / (3/2 p phi_r^2) (eq. 16 in SI): at the torque
         * limit with phi_r*; with the flux weakening (section 12) phi_r falls to (M/L_s)
         * fw_psi_min_frac phi_s,rated while the torque stays below the pull-out torque k_T
         * phi_s^2 (eq. 31), so the slip at min(T_lim, k_T phi_s^2) over that range. A factor 1.5
         * covers a warm rotor (copper R_r +40 % at 120 C) and the flux 10 % short at the end of
         * the magnetisation (magn_frac 0.9: the slip 23 % above eq. 16's at phi_r*). Largest
         * acceleration p T_lim / J (electrical), delay the speed period ts_s * speed_div. */
        double slip = si->rr_ohm * si->torque_limit_nm / (1.5 * si->pole_pairs * psir * psir);
        if (si->flux_weakening != 0) {
            const double kt = 1.5 * si->pole_pairs * (1.0 - sigma) / (2.0 * sigma * ls);
            const double psir_min = m / ls * si->fw_psi_min_frac * si->flux_ref_wb;
            slip = fmax(slip, si->rr_ohm * fmin(si->torque_limit_nm, kt * (psir_min * ls / m) * (psir_min * ls / m)) /
                                  (1.5 * si->pole_pairs * psir_min * psir_min));
        }
        {
            const double acc = si->pole_pairs * si->torque_limit_nm / si->inertia_kgm2;
            const double tol = 1.5 * slip + acc * si->ts_s * si->speed_div;
            cfg->u.im.ref.enc_plaus_iq = dtc_si_to_iq(c, "rr_ohm (encoder plausibility tolerance)", si->rr_ohm,
                                                      tol / b->w_base_rad_s);
        }
    }
    {
        /* Start-up (im_dtc.h). Magnetising ramp: at DC (T model, Casadei eqs. A7-A9 at w = 0)
         * phi_s = sigma L_s i + (M/L_r) phi_r and d phi_r/dt = (M i - phi_r)/tau_r. With phi_s
         * ramped at rho the current settles (after sigma tau_r) to
         *     i = phi_r/M + tau_r rho / L_s,   phi_r lagging (M/L_s) phi_s by sigma tau_r,
         * so it stays below the rated current I_n when rho = (I_n - I_m) L_s / tau_r, I_m =
         * phi_r* / M the final magnetising current. (A stator-flux step instead drives the current
         * towards phi_s* / (sigma L_s).) Then the stator flux is held: the improved estimator's
         * error at DC decays as 1 - exp(-t/tau_r) (Casadei eq. 20 at DC: d phi_r/dt = -(R_r/L_r)(phi_r -
         * phi_r*)), so the torque waits tau_r ln(1/(1 - magn_frac)) more. */
        const double tau_r = lr / si->rr_ohm;
        const double psis_final = si->psir_ref_wb > 0.0 ? si->psir_ref_wb * ls / m : si->flux_ref_wb;
        const double i_m = psir / m;
        const double rho = (si->rated_current_a - i_m) * ls / tau_r;
        double n_ramp, n;
        if (!(si->rated_current_a > i_m)) { dtc_si_fail(c, DTC_SI_ERR_IM, "rated_current_a", "rated_current_a = %g: must exceed the magnetising current phi_r*/M = %g A", si->rated_current_a, i_m); return; }
        n_ramp = ceil(psis_final / (rho * si->ts_s));
        n = n_ramp + ceil(tau_r * log(1.0 / (1.0 - si->magn_frac)) / si->ts_s);
        if (!(n >= 1.0 && n <= 65535.0)) { dtc_si_fail(c, DTC_SI_ERR_IM, "magn_frac", "magn_frac = %g: the magnetisation time %g s is not 1..65535 periods of ts_s", si->magn_frac, n * si->ts_s); return; }
        cfg->u.im.ref.magn_periods = (uint16_t)n;
        cfg->u.im.ref.magn_ramp_iq = dtc_si_to_iq(c, "rated_current_a (magnetising ramp)", si->rated_current_a,
                                           rho * si->ts_s / b->psi_base_wb);
        cfg->u.im.ref.magn_k_q31 = dtc_si_to_q31(c, "rr_ohm (Ts/tau_r)", si->ts_s / tau_r);
    }
}
