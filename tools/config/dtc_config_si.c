/* dtc_config_si.c - SI -> per-unit Q-format configuration (see dtc_config_si.h). Host code. */
#include "dtc_config_si.h"
#include "dtc_config_si_conv.h"

#include "app_core.h"
#include "law.h"
#include "dtc_params.h"
#include "dtc_si_params.h"
#include "plant_defaults.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <string.h>

void dtc_config_si_defaults(dtc_config_si_t *si)
{
    /* Values of the rig and sources: plant_defaults.h. */
    memset(si, 0, sizeof *si);
    si->law = DTC_LAW_PM_DTC;
    si->rs_ohm = PLANT_DEF_PM_RS_OHM;
    si->ls_h = PLANT_DEF_PM_LS_H;
    si->psi_m_wb = PLANT_DEF_PM_PSI_M_WB;
    si->pole_pairs = PLANT_DEF_PM_POLE_PAIRS;
    si->rated_speed_rpm = PLANT_DEF_PM_RATED_SPEED_RPM;
    si->rated_torque_nm = PLANT_DEF_PM_RATED_TORQUE_NM;
    si->rated_current_a = PLANT_DEF_PM_RATED_CURRENT_A;
    si->inertia_kgm2 = PLANT_DEF_PM_J_KGM2;
    /* The F2812 image's variant: Hoang's headline configuration (FSTP, voltage model, Table VI). */
    si->topology = DTC_TOPO_FSTP;
    si->vdc_v = PLANT_DEF_VDC_V;
    si->v_ce_v = PLANT_DEF_V_CE_V;
    si->v_d_v = PLANT_DEF_V_D_V;
    si->v_f_v = PLANT_DEF_V_F_V;
    si->r_on_ohm = PLANT_DEF_R_ON_OHM;
    si->fstp_vmid_measured = 0;
    si->ts_s = PLANT_DEF_TS_S;
    si->speed_div = PLANT_DEF_SPEED_LOOP_DIVIDER;
    si->enc_lines = PLANT_DEF_ENCODER_LINES;
    si->enc_offset_rad = 0.0;
    si->enc_reversed = 0;
    si->speed_min_counts = 100; /* <= 1 % quantisation wherever a window holds 100 counts */
    /* Hoang sec. IV: zero bands */
    si->flux_band_wb = 0.0;
    si->torque_band_nm = 0.0;
    si->lpf_cutoff_rad_s = PLANT_DEF_LPF_CUTOFF_RAD_S;
    si->handover_auto = 1;
    si->handover_speed_rpm = 0.0;
    si->handover_hyst_frac = 0.2; /* back below 80 %: well clear of the speed ripple */
    si->delay_comp = 1;
    si->deadtime_comp = 1;
    si->dead_time_s = PLANT_DEF_DEAD_TIME_S;
    si->pi_from_bandwidth = 1;
    si->speed_bw_rad_s = 2.0 * M_PI * PLANT_DEF_SPEED_BW_HZ;
    si->torque_limit_nm = PLANT_DEF_TORQUE_LIMIT_NM;
    si->torque_trim_tau_s = 0.02; /* 400 control periods: slow against the torque ripple */
    si->stall_time_s = 0.0;       /* derived: max(0.1 s, 20 speed periods), long against the speed
                                   * measurement's window, short against a locked rotor's heating */
    si->speed_limit_rpm = PLANT_DEF_PM_RATED_SPEED_RPM;
    si->flux_ref_wb = PLANT_DEF_FLUX_REF_WB;
    si->speed_ref_rpm = PLANT_DEF_SPEED_REF_RPM;
    si->torque_ref_nm = 0.0;
    /* Induction-machine law: unused by the PM law, set to the IM defaults' values so that a
     * switch of law alone keeps them sane. */
    si->psir_ref_wb = 0.0;
    si->tau_lo_s = PLANT_DEF_IM_OBSERVER_TAU_S;
    si->tau_hi_s = PLANT_DEF_IM_OBSERVER_TAU_S;
    si->tau_w_lo_rpm = 0.0;
    si->tau_w_hi_rpm = 0.0;
    si->speed_sensor = DTC_SPEED_ENCODER;
    si->table_speed_rpm = 0.0;
    si->speed_filter_s = 0.005;
    si->magn_frac = PLANT_DEF_IM_MAGN_FRAC;
    si->rr_track = 0;
    si->cm_ref = 1;         /* on: with the encoder, the torque target at low speed needs it (im_sup.h);
                             * the firmware ignores it without the encoder, with DSVM or another estimator */
    si->flux_weakening = 0;
    si->fw_window = 20;
    si->fw_step_frac = 0.005;
    si->fw_psi_min_frac = 0.1;
    si->carrier_hz = 0.0;
    si->svm_mode = 0;
    si->sfvc_kp_per_s = 0.0;
    si->dfoc_bw_hz = 0.0;
    si->dfoc_zeta = 0.0;
    si->dsvm_torque_band2_nm = 0.0;
    si->estimator = DTC_EST_VOLTAGE;
    si->compensation = DTC_COMP_FSTP_PROPOSED;
    si->sstp_table = DTC_ST_BASIC;
    si->mode = DTC_MODE_SPEED;
    /* ADC: 12 bits, 0..3 V = codes 0..4095. Currents: -range..+range onto 0..3 V (zero at
     * mid-scale, 2047.5 rounded to 2048); voltages: 0..range onto 0..3 V. */
    si->adc_i_a_per_count = 2.0 * PLANT_DEF_CURRENT_RANGE_A / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->adc_i_offset[0] = 2048;
    si->adc_i_offset[1] = 2048;
    si->adc_i_offset[2] = 2048;
    si->adc_vdc_v_per_count = PLANT_DEF_VOLTAGE_RANGE_V / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->adc_vdc_offset = 0;
    si->adc_vmid_v_per_count = PLANT_DEF_VOLTAGE_RANGE_V / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si->adc_vmid_offset = 0;
    si->i_trip_a = PLANT_DEF_OVERCURRENT_A;
    si->vdc_max_v = PLANT_DEF_VDC_MAX_V;
    si->vdc_min_v = PLANT_DEF_VDC_MIN_V;
    si->current_limit_auto = 1;
    si->current_limit_a = 0.0;
    si->polarity_mid = 1;
    si->vmid_cal = 1;
    si->cal_hold = 1;
    si->i_sensors3 = 0;
    si->fault_detect = 1;
    si->reconfig_relay = 0;
    si->relay_delay_s = 0.0;
    si->lpf_comp = 1;
    si->dc_supp = 1;
    si->c_dc_f = PLANT_DEF_C_DC_F;
    /* bases: V_dc, rated peak current, rated electrical speed */
    si->v_base_v = PLANT_DEF_VDC_V;
    si->i_base_a = PLANT_DEF_PM_RATED_CURRENT_A;
    si->w_base_rad_s = 2.0 * M_PI * PLANT_DEF_PM_RATED_SPEED_RPM / 60.0 * PLANT_DEF_PM_POLE_PAIRS;
}

double dtc_overspeed_default_rpm(const dtc_config_si_t *si)
{
    return 1.1 * fmax(si->rated_speed_rpm, si->speed_limit_rpm);
}

void dtc_bases_from_si(const dtc_config_si_t *si, dtc_bases_t *b)
{
    b->v_base_v = si->v_base_v;
    b->i_base_a = si->i_base_a;
    b->w_base_rad_s = si->w_base_rad_s;
    b->psi_base_wb = si->v_base_v / si->w_base_rad_s;
    b->z_base_ohm = si->v_base_v / si->i_base_a;
    b->l_base_h = b->z_base_ohm / si->w_base_rad_s;
    b->t_base_nm = 1.5 * (double)si->pole_pairs * b->psi_base_wb * si->i_base_a;
    b->t_base_s = 1.0 / si->w_base_rad_s;
}

/* ---- error reporting ---------------------------------------------------------------------- */

int dtc_si_fail(dtc_si_conv_t *c, int code, const char *field, const char *fmt, ...)
{
    if (c->code == DTC_SI_OK) {
        const dtc_si_param_t *p = dtc_si_param_of_label(field);
        c->code = code;
        c->field = p != NULL ? p->name : "";
        if (c->msg != NULL && c->len > 0U) {
            va_list ap;
            va_start(ap, fmt);
            vsnprintf(c->msg, c->len, fmt, ap);
            va_end(ap);
        }
    }
    return code;
}

/* value (in pu) -> IQ, refusing overflow and a non-zero value that rounds to zero. */
iq_t dtc_si_to_iq(dtc_si_conv_t *c, const char *field, double si_value, double pu)
{
    double r = nearbyint(pu * 16777216.0);
    if (!(r <= 2147483647.0 && r >= -2147483648.0) || !isfinite(pu)) {
        dtc_si_fail(c, DTC_SI_ERR_RANGE, field, "%s = %g: %g pu overflows the IQ24 range (+-128 pu)", field,
             si_value, pu);
        return 0;
    }
    if (r == 0.0 && pu != 0.0) {
        dtc_si_fail(c, DTC_SI_ERR_RANGE, field, "%s = %g: %g pu is below one IQ24 LSB (rounds to zero)", field,
             si_value, pu);
    }
    return (iq_t)r;
}

q31_t dtc_si_to_q31(dtc_si_conv_t *c, const char *field, double v)
{
    double r = nearbyint(v * 2147483648.0);
    if (!(r <= 2147483647.0 && r >= 1.0) || !isfinite(v)) {
        dtc_si_fail(c, DTC_SI_ERR_RANGE, field, "%s = %g: not representable in Q31 as a gain in (0, 1)", field,
             v);
        return 0;
    }
    return (q31_t)r;
}

static uint32_t to_u32_milli(double v) { return (uint32_t)nearbyint(v * 1000.0); }

/* ---- conversion ---------------------------------------------------------------------------- */

/* Fault-detection levels (firmware app_core.c), from the configured machine, board and
 * drive:
 *  - current sum (three sensors): a quarter of the rated current. A healthy sum is the sensors'
 *    gain and offset errors times the current plus noise (2 % gain errors at the 6 A trip level:
 *    0.24 A, below 0.55 A for Hoang Table VIII); a sensor stuck at its zero makes the sum its phase's
 *    current, which passes the level for most of each half-wave at a quarter of rated current;
 *  - open phase: the least |i| an eighth of the rated current, and at least 32 ADC counts so that
 *    the zero band (a quarter of it, firmware app_core.c) is at least 8 counts, above the sensors'
 *    noise (at lighter load a failed leg is found when the load comes). An eighth, not more: a
 *    phase of Hoang Table VIII's machine opened at 1500 rpm, full load, leaves the other two carrying
 *    0.2-0.6 A for up to 14 ms at some angles, and a quarter (0.55 A) let the detection take
 *    20.6 ms (SIL, 36 fault instants);
 *  - lost encoder: the electrical speed above which a count cannot stand still for N =
 *    APP_ENC_FREEZE_PERIODS periods: the rotor then turns at least 8 counts in N Ts (2 pi 8 /
 *    (counts N Ts)), and at least 4 times the speed the drive's largest deceleration, a = 2
 *    T_lim / J (the torque limit plus as much load), takes away in N Ts; 0 (off) without an
 *    encoder speed or without an inertia;
 *  - relay: 1.5 times its closing time (coil tolerance and bounce) plus one period. */
static void dtc_fault_levels(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg)
{
    const double n_ts = (double)APP_ENC_FREEZE_PERIODS * si->ts_s;
    cfg->prot.i_sum_max_iq = 0;
    cfg->prot.leg_i_min_iq = 0;
    cfg->prot.enc_freeze_speed_iq = 0;
    cfg->prot.relay_periods = 0U;
    cfg->prot.i_plaus = 0U;
    if (si->fault_detect == 0) {
        return;
    }
    cfg->prot.i_plaus = 1U;
    if (si->i_sensors3 != 0) {
        cfg->prot.i_sum_max_iq = dtc_si_to_iq(c, "rated_current_a (current-sum level)", si->rated_current_a,
                                       0.25 * si->rated_current_a / b->i_base_a);
    }
    {
        /* the zero band (leg_i_min / 4, firmware) at least 8 ADC counts: above the sensors' noise */
        const double i_min = fmax(si->rated_current_a / 8.0, 32.0 * si->adc_i_a_per_count);
        cfg->prot.leg_i_min_iq = dtc_si_to_iq(c, "rated_current_a (open-phase level)", i_min, i_min / b->i_base_a);
    }
    if (si->speed_sensor == DTC_SPEED_ENCODER && si->inertia_kgm2 > 0.0) {
        const double w_counts = 2.0 * M_PI * 8.0 / (4.0 * si->enc_lines * n_ts);
        const double w_decel = 4.0 * (2.0 * si->torque_limit_nm / si->inertia_kgm2) * n_ts;
        const double w_e = fmax(w_counts, w_decel) * si->pole_pairs;
        cfg->prot.enc_freeze_speed_iq = dtc_si_to_iq(c, "enc_lines (lost-encoder speed)", w_e, w_e / b->w_base_rad_s);
    }
    if (si->reconfig_relay == 1) {
        cfg->prot.relay_periods = (uint16_t)fmin(65535.0, ceil(1.5 * si->relay_delay_s / si->ts_s) + 1.0);
    }
}


/* The conversion (dtc_config_from_si_err), its error state in *c. */
static int convert(const dtc_config_si_t *si, dtc_config_t *cfg, dtc_si_conv_t *c)
{
    dtc_bases_t b;
    double tsp, kp, ki, enc_counts, a, wc_pu;
    int fw;
    const char *fw_field = "";

    if (si == NULL || cfg == NULL) {
        return dtc_si_fail(c, DTC_SI_ERR_NULL, "", "null argument");
    }
    memset(cfg, 0, sizeof *cfg);

    /* Plain range checks, one per row of dtc_si_params.h (first failure wins), then the law's own
     * checks and the relations between fields. */
    if (dtc_si_params_check(c, si) != DTC_SI_OK)
        return c->code;
    if ((dtc_law_is_im((uint16_t)si->law) != 0U ? dtc_si_im_check(c, si)
         : si->law == DTC_LAW_PM_ITC           ? dtc_si_pm_itc_check(c, si)
                                               : dtc_si_pm_dtc_check(c, si)) != DTC_SI_OK)
        return c->code;
    if (!(si->ts_s * si->w_base_rad_s < 1.0))
        return dtc_si_fail(c, DTC_SI_ERR_BASE, "ts_s", "ts_s = %g: ts * w_base_rad_s = %g must be < 1 (one sample shorter than the time base)", si->ts_s, si->ts_s * si->w_base_rad_s);
    if (!(si->lpf_cutoff_rad_s * si->ts_s < M_PI))
        return dtc_si_fail(c, DTC_SI_ERR_CUTOFF, "lpf_cutoff_rad_s", "lpf_cutoff_rad_s = %g: at or above the Nyquist rate pi/ts_s = %g rad/s", si->lpf_cutoff_rad_s, M_PI / si->ts_s);
    if (!(si->dead_time_s < 0.5 * si->ts_s))
        return dtc_si_fail(c, DTC_SI_ERR_DEADTIME, "dead_time_s", "dead_time_s = %g: must be in [0, ts_s/2)", si->dead_time_s);
    if ((si->topology == DTC_TOPO_SSTP && (si->compensation == DTC_COMP_FSTP_SIMPLE || si->compensation == DTC_COMP_FSTP_PROPOSED)) ||
        (si->topology == DTC_TOPO_FSTP && (si->compensation == DTC_COMP_SSTP || si->compensation == DTC_COMP_SSTP_PROPOSED)))
        return dtc_si_fail(c, DTC_SI_ERR_VARIANT, "compensation", "compensation = %d: not available for topology %d (the SSTP takes DTC_COMP_NONE or the SSTP ones, the FSTP DTC_COMP_NONE or the FSTP ones, Hoang Tables III, V-VI)", si->compensation, si->topology);
    if (!(si->stall_time_s == 0.0 ||
          (si->stall_time_s >= 20.0 * si->ts_s * si->speed_div && si->stall_time_s / (si->ts_s * si->speed_div) <= 65535.0)))
        return dtc_si_fail(c, DTC_SI_ERR_GAIN, "stall_time_s", "stall_time_s = %g: must be 0 (derived) or span 20 .. 65535 speed periods of %g s", si->stall_time_s, si->ts_s * si->speed_div);
    if (!(si->torque_trim_tau_s == 0.0 || si->torque_trim_tau_s > si->ts_s))
        return dtc_si_fail(c, DTC_SI_ERR_GAIN, "torque_trim_tau_s", "torque_trim_tau_s = %g: must be 0 (off) or longer than ts_s = %g", si->torque_trim_tau_s, si->ts_s);
    if (!(si->overspeed_rpm <= 0.0 || si->overspeed_rpm > si->speed_limit_rpm))
        return dtc_si_fail(c, DTC_SI_ERR_LIMIT, "overspeed_rpm", "overspeed_rpm = %g: must be above speed_limit_rpm = %g (0 = derived, < 0 = off)",
                           si->overspeed_rpm, si->speed_limit_rpm);
    if (si->current_limit_auto == 0 && !(si->current_limit_a == 0.0 || si->current_limit_a < si->i_trip_a))
        return dtc_si_fail(c, DTC_SI_ERR_ILIM, "current_limit_a", "current_limit_a = %g: must be 0 (off) or in (0, i_trip_a = %g)", si->current_limit_a, si->i_trip_a);
    if (!(si->vdc_max_v > si->vdc_min_v))
        return dtc_si_fail(c, DTC_SI_ERR_LIMIT, "vdc_min_v", "vdc_min_v = %g: must be below vdc_max_v = %g", si->vdc_min_v, si->vdc_max_v);
    if (!(fabs(si->speed_ref_rpm) <= si->speed_limit_rpm)) return dtc_si_fail(c, DTC_SI_ERR_REFERENCE, "speed_ref_rpm", "speed_ref_rpm = %g: beyond speed_limit_rpm = %g", si->speed_ref_rpm, si->speed_limit_rpm);
    if (!(fabs(si->torque_ref_nm) <= si->torque_limit_nm)) return dtc_si_fail(c, DTC_SI_ERR_REFERENCE, "torque_ref_nm", "torque_ref_nm = %g: beyond torque_limit_nm = %g", si->torque_ref_nm, si->torque_limit_nm);

    /* Speed PI, SI. */
    if (si->pi_from_bandwidth) {
        if (!(si->speed_bw_rad_s * si->ts_s * si->speed_div < 0.2))
            return dtc_si_fail(c, DTC_SI_ERR_GAIN, "speed_bw_rad_s", "speed_bw_rad_s = %g: too fast for the speed period %g s (bw * T < 0.2)", si->speed_bw_rad_s, si->ts_s * si->speed_div);
        /* Crossover at bw with the plant 1/(J s): kp = J bw; PI zero a quarter below: ki = kp bw/4. */
        kp = si->inertia_kgm2 * si->speed_bw_rad_s;
        ki = kp * si->speed_bw_rad_s / 4.0;
    } else {
        kp = si->kp_nm_s_rad;
        ki = si->ki_nm_rad;
    }

    /* Conversion. */
    dtc_bases_from_si(si, &b);
    tsp = si->ts_s * si->speed_div;
    enc_counts = 4.0 * si->enc_lines;

    cfg->version = DTC_CONFIG_VERSION;
    cfg->law = (uint16_t)si->law;
    cfg->board.topology = (uint16_t)si->topology;
    cfg->est.estimator = (uint16_t)si->estimator;
    cfg->est.compensation = (uint16_t)si->compensation;
    cfg->speed.mode = (uint16_t)si->mode;
    cfg->board.fstp_vmid_measured = (uint16_t)si->fstp_vmid_measured;
    cfg->board.v_base_mv = to_u32_milli(b.v_base_v);
    cfg->board.i_base_ma = to_u32_milli(b.i_base_a);
    cfg->board.w_base_mrad_s = to_u32_milli(b.w_base_rad_s);
    cfg->machine.pole_pairs = (uint16_t)si->pole_pairs;

    cfg->machine.rs_iq = dtc_si_to_iq(c, "rs_ohm", si->rs_ohm, si->rs_ohm / b.z_base_ohm);

    /* Exact ZOH discretisation of 1/(s + w_c) in pu time. */
    a = exp(-si->lpf_cutoff_rad_s * si->ts_s);
    wc_pu = si->lpf_cutoff_rad_s / b.w_base_rad_s;
    cfg->est.k_leak_q31 = dtc_si_to_q31(c, "lpf_cutoff_rad_s (k_leak)", 1.0 - a);
    cfg->est.k_in_q31 = dtc_si_to_q31(c, "ts_s (k_in)", (1.0 - a) / wc_pu);

    cfg->est.deadtime_comp = (uint16_t)si->deadtime_comp;
    cfg->board.td_ts_q15 = (q15_t)lround(32768.0 * si->dead_time_s / si->ts_s);
    cfg->board.ts_pu_iq = dtc_si_to_iq(c, "ts_s", si->ts_s, si->ts_s * b.w_base_rad_s);

    if (!(65536.0 * 65536.0 * si->pole_pairs / enc_counts < 2147483647.5)) /* board.enc_gain_q16's range */
        return dtc_si_fail(c, DTC_SI_ERR_ENCODER, "enc_lines", "enc_lines = %d: two or fewer counts per electrical turn with %d pole pairs (the electrical angle aliases)", si->enc_lines, si->pole_pairs);
    cfg->board.enc_counts = (uint16_t)enc_counts;
    cfg->board.enc_gain_q16 = (uint32_t)nearbyint(65536.0 * 65536.0 * si->pole_pairs / enc_counts);
    cfg->board.enc_reversed = (uint16_t)si->enc_reversed;
    {
        /* reversed: the firmware reads N - 1 - count, whose angle at raw count 0 is the offset less one
         * count's angle; the board's offset is one count ahead to keep enc_offset_rad's meaning */
        double turns = si->enc_offset_rad / (2.0 * M_PI) + (si->enc_reversed != 0 ? si->pole_pairs / enc_counts : 0.0);
        turns -= floor(turns);
        cfg->board.enc_offset = (angle_t)((uint32_t)nearbyint(turns * 65536.0) & 0xFFFFu);
    }

    cfg->board.v_f_iq = dtc_si_to_iq(c, "v_f_v", si->v_f_v, si->v_f_v / b.v_base_v);
    cfg->board.v_ce_iq = dtc_si_to_iq(c, "v_ce_v", si->v_ce_v, si->v_ce_v / b.v_base_v);
    cfg->board.v_d_iq = dtc_si_to_iq(c, "v_d_v", si->v_d_v, si->v_d_v / b.v_base_v);
    cfg->board.r_on_iq = dtc_si_to_iq(c, "r_on_ohm", si->r_on_ohm, si->r_on_ohm / b.z_base_ohm);

    if (si->law != DTC_LAW_PM_ITC) {
        /* the switching table and comparators of the table-driven laws (all but the ITC) */
        dtc_table_cfg_t *tab = dtc_law_is_im((uint16_t)si->law) != 0U ? &cfg->u.im.sw : &cfg->u.pm_dtc.sw;
        tab->sstp_table = (uint16_t)si->sstp_table;
        tab->flux_band_iq = dtc_si_to_iq(c, "flux_band_wb", si->flux_band_wb, si->flux_band_wb / b.psi_base_wb);
        tab->torque_band_iq = dtc_si_to_iq(c, "torque_band_nm", si->torque_band_nm, si->torque_band_nm / b.t_base_nm);
    }

    cfg->speed.speed_div = (uint16_t)si->speed_div;
    cfg->speed.speed_k_iq = dtc_si_to_iq(c, "enc_lines (speed gain)", enc_counts,
                            2.0 * M_PI * si->pole_pairs / (enc_counts * tsp * b.w_base_rad_s));
    cfg->speed.speed_min_counts = (uint16_t)si->speed_min_counts;
    {
        const double t_speed = si->ts_s * si->speed_div;
        const double t_stall = si->stall_time_s != 0.0 ? si->stall_time_s : fmax(0.1, 20.0 * t_speed);
        cfg->prot.stall_speed_periods = (uint16_t)fmin(65535.0, (double)lround(t_stall / t_speed));
    }
    {
        const double n_os = si->overspeed_rpm == 0.0 ? dtc_overspeed_default_rpm(si) : si->overspeed_rpm;
        cfg->prot.overspeed_iq = n_os < 0.0 ? 0
                                 : dtc_si_to_iq(c, "overspeed_rpm", n_os, n_os * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s);
    }
    /* kp: N.m per mech rad/s -> pu torque per pu speed: w_mech = w_pu w_base / p. */
    cfg->speed.kp_iq = dtc_si_to_iq(c, "kp_nm_s_rad", kp, kp * b.w_base_rad_s / (si->pole_pairs * b.t_base_nm));
    cfg->speed.ki_ts_iq = dtc_si_to_iq(c, "ki_nm_rad", ki, ki * tsp * b.w_base_rad_s / (si->pole_pairs * b.t_base_nm));
    cfg->speed.speed_bw_iq = si->pi_from_bandwidth ? dtc_si_to_iq(c, "speed_bw_rad_s", si->speed_bw_rad_s, si->speed_bw_rad_s / b.w_base_rad_s) : 0;
    cfg->speed.torque_limit_iq = dtc_si_to_iq(c, "torque_limit_nm", si->torque_limit_nm, si->torque_limit_nm / b.t_base_nm);
    cfg->speed.torque_trim_k_q15 = si->torque_trim_tau_s == 0.0 ? 0
                             : (q15_t)lround(32768.0 * si->ts_s / si->torque_trim_tau_s);
    cfg->speed.speed_limit_iq = dtc_si_to_iq(c, "speed_limit_rpm", si->speed_limit_rpm,
                                si->speed_limit_rpm * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s);

    cfg->speed.flux_ref_iq = dtc_si_to_iq(c, "flux_ref_wb", si->flux_ref_wb, si->flux_ref_wb / b.psi_base_wb);
    cfg->speed.speed_ref_iq = dtc_si_to_iq(c, "speed_ref_rpm", si->speed_ref_rpm,
                              si->speed_ref_rpm * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s);
    cfg->speed.torque_ref_iq = dtc_si_to_iq(c, "torque_ref_nm", si->torque_ref_nm, si->torque_ref_nm / b.t_base_nm);

    cfg->board.adc_i_gain_iq = dtc_si_to_iq(c, "adc_i_a_per_count", si->adc_i_a_per_count, si->adc_i_a_per_count / b.i_base_a);
    for (int k = 0; k < 3; k++) {
        cfg->board.adc_i_offset[k] = (uint16_t)si->adc_i_offset[k];
    }
    cfg->board.adc_vdc_gain_iq = dtc_si_to_iq(c, "adc_vdc_v_per_count", si->adc_vdc_v_per_count, si->adc_vdc_v_per_count / b.v_base_v);
    cfg->board.adc_vdc_offset = (uint16_t)si->adc_vdc_offset;
    cfg->board.adc_vmid_gain_iq = dtc_si_to_iq(c, "adc_vmid_v_per_count", si->adc_vmid_v_per_count, si->adc_vmid_v_per_count / b.v_base_v);
    cfg->board.adc_vmid_offset = (uint16_t)si->adc_vmid_offset;
    cfg->prot.i_trip_iq = dtc_si_to_iq(c, "i_trip_a", si->i_trip_a, si->i_trip_a / b.i_base_a);
    cfg->prot.vdc_max_iq = dtc_si_to_iq(c, "vdc_max_v", si->vdc_max_v, si->vdc_max_v / b.v_base_v);
    cfg->prot.vdc_min_iq = dtc_si_to_iq(c, "vdc_min_v", si->vdc_min_v, si->vdc_min_v / b.v_base_v);
    /* the mid-point calibration only where a mid-point is measured (FSTP) and used: by the
     * voltage model's reconstruction and its mid-point regulation. The current model uses
     * neither, and the calibration's 51 ms with the gates off let an active load (a hoist, a
     * constant torque) turn the rotor backwards before the drive starts (0.3 N*m on 5e-4 kg m^2:
     * -244 rpm at the end of it, SIL) */
    cfg->board.vmid_cal = (uint16_t)(si->vmid_cal != 0 && si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0 &&
                                             si->estimator == DTC_EST_VOLTAGE
                                         ? 1
                                         : 0);
    if (si->law == DTC_LAW_PM_DTC && c->code == DTC_SI_OK) {
        dtc_si_pm_dtc_convert(c, si, &b, cfg);
    }
    if (si->law == DTC_LAW_PM_ITC && c->code == DTC_SI_OK) {
        dtc_si_pm_itc_convert(c, si, &b, cfg);
    }
    if (c->code != DTC_SI_OK) {
        return c->code;
    }

    cfg->board.i_sensors3 = (uint16_t)si->i_sensors3;
    dtc_fault_levels(c, si, &b, cfg);

    if (dtc_law_is_im((uint16_t)si->law) != 0U && c->code == DTC_SI_OK) {
        dtc_si_im_convert(c, si, &b, cfg);
    }
    if (c->code != DTC_SI_OK) {
        return c->code;
    }
    fw = law_check(cfg, &fw_field);
    if (fw != DTC_OK) {
        return dtc_si_fail(c, DTC_SI_ERR_FIRMWARE, "", "firmware validation refused the converted configuration (dtc_err %d, field %s)", fw, fw_field);
    }
    return DTC_SI_OK;
}

int dtc_config_from_si(const dtc_config_si_t *si, dtc_config_t *cfg, char *msg, size_t msg_len)
{
    dtc_si_conv_t c = {msg, msg_len, DTC_SI_OK, ""}; /* no message formatted without msg */
    if (msg != NULL && msg_len > 0U) {
        msg[0] = '\0';
    }
    return convert(si, cfg, &c);
}

int dtc_config_from_si_err(const dtc_config_si_t *si, dtc_config_t *cfg, dtc_si_error_t *err)
{
    dtc_si_conv_t c = {err->msg, sizeof err->msg, DTC_SI_OK, ""};
    err->msg[0] = '\0';
    err->code = convert(si, cfg, &c);
    err->field = c.field;
    return err->code;
}

/* ---- C emitter ----------------------------------------------------------------------------- */

static const char *i32(char *buf, size_t n, int32_t v)
{
    if (v == INT32_MIN) {
        snprintf(buf, n, "(-2147483647 - 1)");
    } else {
        snprintf(buf, n, "%ld", (long)v);
    }
    return buf;
}

double dtc_param_value(const dtc_config_t *cfg, const dtc_param_t *p)
{
    const double raw = (double)dtc_param_raw(cfg, p);
    switch (p->fmt) {
    case DTC_PF_Q15: return raw / 32768.0;
    case DTC_PF_IQ: return raw / 16777216.0;
    case DTC_PF_Q31: return raw / 2147483648.0;
    default: return raw;
    }
}

double dtc_param_si_scale(const dtc_config_t *cfg, uint16_t qty)
{
    const double vb = cfg->board.v_base_mv / 1000.0, ib = cfg->board.i_base_ma / 1000.0,
                 wb = cfg->board.w_base_mrad_s / 1000.0;
    const double psib = vb / wb, zb = vb / ib, lb = zb / wb, tb = 1.5 * cfg->machine.pole_pairs * psib * ib;
    switch (qty) {
    case DTC_PQ_V: case DTC_PQ_V_COUNT: return vb;
    case DTC_PQ_A: case DTC_PQ_A_COUNT: return ib;
    case DTC_PQ_W: return wb;
    case DTC_PQ_PSI: return psib;
    case DTC_PQ_T: return tb;
    case DTC_PQ_Z: return zb;
    case DTC_PQ_L: return lb;
    case DTC_PQ_INV_L: return 1.0 / lb;
    case DTC_PQ_INV_PSI: return 1.0 / psib;
    case DTC_PQ_TIME: return 1.0 / wb;
    case DTC_PQ_ANGLE: return 2.0 * M_PI / 65536.0;
    case DTC_PQ_T_W: return tb / wb;
    default: return 1.0;
    }
}

/* One row as a designated initialiser, with the value in pu and SI where it has them. */
static int emit_row(FILE *f, const dtc_config_t *cfg, const dtc_param_t *p)
{
    char b[32];
    const int64_t raw = dtc_param_raw(cfg, p);
    const double v = dtc_param_value(cfg, p), si = v * dtc_param_si_scale(cfg, p->qty);
    const char *unit = dtc_param_unit(p->qty);
    int r;
    if (p->fmt == DTC_PF_U16 || p->fmt == DTC_PF_U32 || p->fmt == DTC_PF_ANGLE) {
        r = fprintf(f, "    .%s = %lluU, /* #%u", p->name, (unsigned long long)raw, (unsigned)p->id);
    } else {
        r = fprintf(f, "    .%s = %s, /* #%u %.9g", p->name, i32(b, sizeof b, (int32_t)raw), (unsigned)p->id, v);
    }
    if (r >= 0 && unit[0] != '\0') {
        r = fprintf(f, " = %.6g %s", si, unit);
    }
    if (r >= 0) {
        r = fprintf(f, " */\n");
    }
    return r < 0 ? -1 : 0;
}

int dtc_config_emit_c(const dtc_config_t *cfg, const char *symbol, FILE *f)
{
    const dtc_param_list_t *law;
    uint16_t k;
    int r = 0;

    if (cfg == NULL || symbol == NULL || f == NULL) {
        return -1;
    }
    law = dtc_param_law_list(cfg->law);
    if (law == NULL) {
        return -1;
    }
    if (fprintf(f, "/* Generated by dtc_config_emit_c (tools/config): DTC firmware configuration, per-unit\n"
                   " * Q formats (firmware/dtc/dtc_config.h, bases in firmware/dtc/dtc_base.h), one line per\n"
                   " * parameter (#id: firmware/dtc/dtc_param.h).\n"
                   " * Bases: V_base %.3f V, I_base %.3f A, w_base %.3f rad/s. Do not edit by hand. */\n"
                   "#include \"dtc_config.h\"\n\nconst dtc_config_t %s = {\n",
                cfg->board.v_base_mv / 1000.0, cfg->board.i_base_ma / 1000.0, cfg->board.w_base_mrad_s / 1000.0,
                symbol) < 0) {
        return -1;
    }
    /* the common part, then the law's part only: designated initialisers of its union member */
    for (k = 0U; k < dtc_params_common.n && r == 0; k++) {
        r = emit_row(f, cfg, &dtc_params_common.rows[k]);
    }
    for (k = 0U; k < law->n && r == 0; k++) {
        r = emit_row(f, cfg, &law->rows[k]);
    }
    if (r == 0 && fprintf(f, "};\n") < 0) {
        r = -1;
    }
    return r;
}
