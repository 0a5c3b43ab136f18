/* dtc_config_si.c - SI -> per-unit Q-format configuration (see dtc_config_si.h). Host code. */
#include "dtc_config_si.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void dtc_config_si_defaults(dtc_config_si_t *si)
{
    memset(si, 0, sizeof *si);
    /* Hoang Table VIII */
    si->rs_ohm = 0.466;
    si->ls_h = 3.19e-3;
    si->psi_m_wb = 0.0928;
    si->pole_pairs = 1;
    si->rated_speed_rpm = 3000.0;
    si->rated_torque_nm = 0.3;
    si->rated_current_a = 2.2;
    si->inertia_kgm2 = 2.0e-4; /* not given in the paper: small BLAC machine + DC generator, assumed */
    /* Table IV devices, 70 V link; V_f = 0.9 V as in the paper's simple scheme (Fig. 6) */
    si->topology = DTC_TOPO_FSTP;
    si->vdc_v = 70.0;
    si->v_ce_v = 0.9;
    si->v_d_v = 1.25;
    si->v_f_v = 0.9;
    si->r_on_ohm = 0.075;
    si->fstp_vmid_measured = 0;
    /* Section IV: 50 us, speed loop 10x slower, 2000-line encoder (Fig. 9) */
    si->ts_s = 50e-6;
    si->speed_div = 10;
    si->enc_lines = 2000;
    si->enc_offset_rad = 0.0;
    si->speed_min_counts = 100; /* <= 1 % quantisation wherever a window holds 100 counts */
    /* Section IV: zero bands, LPF 5 rad/s, |psi*| = psi_m */
    si->flux_band_wb = 0.0;
    si->torque_band_nm = 0.0;
    si->lpf_cutoff_rad_s = 5.0;
    si->handover_auto = 1;
    si->handover_speed_rpm = 0.0;
    si->handover_hyst_frac = 0.2; /* back below 80 %: well clear of the speed ripple */
    si->delay_comp = 1;
    si->deadtime_comp = 1;
    si->dead_time_s = 1e-6; /* IRAMY20UP60B module, as the plant (docs/plant.md) */
    si->pi_from_bandwidth = 1;
    si->speed_bw_rad_s = 60.0;
    si->torque_limit_nm = 0.45; /* 1.5 x rated */
    si->torque_trim_tau_s = 0.02; /* 400 control periods: slow against the torque ripple */
    si->stall_time_s = 0.0;       /* derived: max(0.1 s, 20 speed periods), long against the speed
                                   * measurement's window, short against a locked rotor's heating */
    si->speed_limit_rpm = 3000.0;
    si->flux_ref_wb = 0.0928;
    si->speed_ref_rpm = 1500.0; /* the paper's test speed */
    si->torque_ref_nm = 0.0;
    si->estimator = DTC_EST_VOLTAGE;
    si->compensation = DTC_COMP_FSTP_PROPOSED;
    si->sstp_table = DTC_ST_BASIC;
    si->mode = DTC_MODE_SPEED;
    /* ADC: +-10 A current sensors on 12 bits (mid-scale offset), 0..100 V dividers */
    si->adc_i_a_per_count = 20.0 / 4096.0;
    si->adc_i_offset[0] = 2048;
    si->adc_i_offset[1] = 2048;
    si->adc_i_offset[2] = 2048;
    si->adc_vdc_v_per_count = 100.0 / 4096.0;
    si->adc_vdc_offset = 0;
    si->adc_vmid_v_per_count = 100.0 / 4096.0;
    si->adc_vmid_offset = 0;
    si->i_trip_a = 6.0;
    si->vdc_max_v = 90.0;
    si->vdc_min_v = 40.0;
    si->current_limit_auto = 1;
    si->current_limit_a = 0.0;
    si->polarity_mid = 1;
    si->vmid_cal = 1;
    si->lpf_comp = 1;
    si->dc_supp = 1;
    si->c_dc_f = 4.7e-3;
    /* bases: V_dc, rated peak current, rated electrical speed */
    si->v_base_v = 70.0;
    si->i_base_a = 2.2;
    si->w_base_rad_s = 2.0 * M_PI * 3000.0 / 60.0;
}

double dtc_handover_default_rpm(const dtc_config_si_t *si)
{
    double drop = (si->v_ce_v > si->v_d_v ? si->v_ce_v : si->v_d_v) + si->r_on_ohm * si->rated_current_a;
    double w_emf = 3.0 * drop / si->psi_m_wb;
    double w_lpf = 10.0 * si->lpf_cutoff_rad_s;
    double w = w_emf > w_lpf ? w_emf : w_lpf;
    return w * 30.0 / M_PI / (double)si->pole_pairs;
}

double dtc_ilim_default_a(const dtc_config_si_t *si)
{
    double v_max = si->topology == DTC_TOPO_SSTP ? 2.0 * si->vdc_v / 3.0 : si->vdc_v / sqrt(3.0);
    double w_max = si->speed_limit_rpm * M_PI / 30.0 * (double)si->pole_pairs;
    double e_max = fmin(w_max * si->psi_m_wb, v_max);
    double di = si->ts_s * (v_max + e_max + si->rs_ohm * si->i_trip_a) / si->ls_h;
    double lim = si->i_trip_a - (si->delay_comp != 0 ? 1.0 : 2.0) * di;
    return lim > 0.0 ? lim : 0.0;
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

typedef struct {
    char *msg;
    size_t len;
    int code;
} conv_t;

static int fail(conv_t *c, int code, const char *fmt, ...)
{
    if (c->code == DTC_SI_OK) {
        c->code = code;
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
static iq_t to_iq(conv_t *c, const char *field, double si_value, double pu)
{
    double r = nearbyint(pu * 16777216.0);
    if (!(r <= 2147483647.0 && r >= -2147483648.0) || !isfinite(pu)) {
        fail(c, DTC_SI_ERR_RANGE, "%s = %g: %g pu overflows the IQ24 range (+-128 pu)", field,
             si_value, pu);
        return 0;
    }
    if (r == 0.0 && pu != 0.0) {
        fail(c, DTC_SI_ERR_RANGE, "%s = %g: %g pu is below one IQ24 LSB (rounds to zero)", field,
             si_value, pu);
    }
    return (iq_t)r;
}

static q31_t to_q31(conv_t *c, const char *field, double v)
{
    double r = nearbyint(v * 2147483648.0);
    if (!(r <= 2147483647.0 && r >= 1.0) || !isfinite(v)) {
        fail(c, DTC_SI_ERR_RANGE, "%s = %g: not representable in Q31 as a gain in (0, 1)", field,
             v);
        return 0;
    }
    return (q31_t)r;
}

static uint32_t to_u32_milli(double v) { return (uint32_t)nearbyint(v * 1000.0); }

/* ---- conversion ---------------------------------------------------------------------------- */

int dtc_config_from_si(const dtc_config_si_t *si, dtc_config_t *cfg, char *msg, size_t msg_len)
{
    conv_t c = {msg, msg_len, DTC_SI_OK};
    dtc_bases_t b;
    double tsp, kp, ki, enc_counts, a, wc_pu;
    int fw;

    if (msg != NULL && msg_len > 0U) {
        msg[0] = '\0';
    }
    if (si == NULL || cfg == NULL) {
        return fail(&c, DTC_SI_ERR_NULL, "null argument");
    }
    memset(cfg, 0, sizeof *cfg);

    /* Plain range checks, field by field (first failure wins). */
    if (!(si->v_base_v > 0.0)) return fail(&c, DTC_SI_ERR_BASE, "v_base_v = %g: must be > 0", si->v_base_v);
    if (!(si->i_base_a > 0.0)) return fail(&c, DTC_SI_ERR_BASE, "i_base_a = %g: must be > 0", si->i_base_a);
    if (!(si->w_base_rad_s > 0.0)) return fail(&c, DTC_SI_ERR_BASE, "w_base_rad_s = %g: must be > 0", si->w_base_rad_s);
    if (!(si->rs_ohm >= 0.0)) return fail(&c, DTC_SI_ERR_MACHINE, "rs_ohm = %g: resistance must be >= 0", si->rs_ohm);
    if (!(si->ls_h > 0.0)) return fail(&c, DTC_SI_ERR_MACHINE, "ls_h = %g: inductance must be > 0", si->ls_h);
    if (!(si->psi_m_wb > 0.0)) return fail(&c, DTC_SI_ERR_MACHINE, "psi_m_wb = %g: magnet flux must be > 0", si->psi_m_wb);
    if (si->pole_pairs < 1 || si->pole_pairs > 16) return fail(&c, DTC_SI_ERR_MACHINE, "pole_pairs = %d: must be 1..16", si->pole_pairs);
    if (!(si->rated_speed_rpm > 0.0) || !(si->rated_torque_nm > 0.0) || !(si->rated_current_a > 0.0))
        return fail(&c, DTC_SI_ERR_MACHINE, "rated_speed_rpm/rated_torque_nm/rated_current_a: must be > 0");
    if (si->topology != DTC_TOPO_SSTP && si->topology != DTC_TOPO_FSTP)
        return fail(&c, DTC_SI_ERR_VARIANT, "topology = %d: must be DTC_TOPO_SSTP or DTC_TOPO_FSTP", si->topology);
    if (!(si->vdc_v > 0.0)) return fail(&c, DTC_SI_ERR_INVERTER, "vdc_v = %g: must be > 0", si->vdc_v);
    if (!(si->v_ce_v >= 0.0)) return fail(&c, DTC_SI_ERR_INVERTER, "v_ce_v = %g: must be >= 0", si->v_ce_v);
    if (!(si->v_d_v >= 0.0)) return fail(&c, DTC_SI_ERR_INVERTER, "v_d_v = %g: must be >= 0", si->v_d_v);
    if (!(si->v_f_v >= 0.0)) return fail(&c, DTC_SI_ERR_INVERTER, "v_f_v = %g: must be >= 0", si->v_f_v);
    if (!(si->r_on_ohm >= 0.0)) return fail(&c, DTC_SI_ERR_INVERTER, "r_on_ohm = %g: must be >= 0", si->r_on_ohm);
    if (si->fstp_vmid_measured != 0 && si->fstp_vmid_measured != 1)
        return fail(&c, DTC_SI_ERR_VARIANT, "fstp_vmid_measured = %d: must be 0 or 1", si->fstp_vmid_measured);
    if (!(si->ts_s > 0.0)) return fail(&c, DTC_SI_ERR_TIMING, "ts_s = %g: must be > 0", si->ts_s);
    if (si->speed_div < 1 || si->speed_div > 1000) return fail(&c, DTC_SI_ERR_TIMING, "speed_div = %d: must be 1..1000", si->speed_div);
    if (!(si->ts_s * si->w_base_rad_s < 1.0))
        return fail(&c, DTC_SI_ERR_BASE, "ts_s = %g: ts * w_base_rad_s = %g must be < 1 (one sample shorter than the time base)", si->ts_s, si->ts_s * si->w_base_rad_s);
    if (si->enc_lines < 1 || si->enc_lines > 16383) return fail(&c, DTC_SI_ERR_ENCODER, "enc_lines = %d: 4*lines must fit 16 bits (1..16383)", si->enc_lines);
    if (si->speed_min_counts < 1 || si->speed_min_counts > 16000) return fail(&c, DTC_SI_ERR_ENCODER, "speed_min_counts = %d: must be 1..16000", si->speed_min_counts);
    if (!isfinite(si->enc_offset_rad)) return fail(&c, DTC_SI_ERR_ENCODER, "enc_offset_rad: not finite");
    if (!(si->flux_band_wb >= 0.0)) return fail(&c, DTC_SI_ERR_BAND, "flux_band_wb = %g: must be >= 0", si->flux_band_wb);
    if (!(si->torque_band_nm >= 0.0)) return fail(&c, DTC_SI_ERR_BAND, "torque_band_nm = %g: must be >= 0", si->torque_band_nm);
    if (!(si->lpf_cutoff_rad_s > 0.0)) return fail(&c, DTC_SI_ERR_CUTOFF, "lpf_cutoff_rad_s = %g: must be > 0 (a pure integrator drifts)", si->lpf_cutoff_rad_s);
    if (!(si->lpf_cutoff_rad_s * si->ts_s < M_PI))
        return fail(&c, DTC_SI_ERR_CUTOFF, "lpf_cutoff_rad_s = %g: at or above the Nyquist rate pi/ts_s = %g rad/s", si->lpf_cutoff_rad_s, M_PI / si->ts_s);
    if (!(si->handover_auto != 0 || si->handover_speed_rpm >= 0.0))
        return fail(&c, DTC_SI_ERR_HANDOVER, "handover_speed_rpm = %g: must be >= 0 (0 = voltage model from standstill)", si->handover_speed_rpm);
    if (si->delay_comp != 0 && si->delay_comp != 1)
        return fail(&c, DTC_SI_ERR_DELAY, "delay_comp = %d: must be 0 or 1", si->delay_comp);
    if (si->deadtime_comp != 0 && si->deadtime_comp != 1)
        return fail(&c, DTC_SI_ERR_DEADTIME, "deadtime_comp = %d: must be 0 or 1", si->deadtime_comp);
    if (!(si->dead_time_s >= 0.0 && si->dead_time_s < 0.5 * si->ts_s))
        return fail(&c, DTC_SI_ERR_DEADTIME, "dead_time_s = %g: must be in [0, ts_s/2)", si->dead_time_s);
    if (!(si->handover_hyst_frac >= 0.0 && si->handover_hyst_frac <= 1.0))
        return fail(&c, DTC_SI_ERR_HANDOVER, "handover_hyst_frac = %g: must be in [0, 1]", si->handover_hyst_frac);
    if (si->estimator != DTC_EST_VOLTAGE && si->estimator != DTC_EST_CURRENT)
        return fail(&c, DTC_SI_ERR_VARIANT, "estimator = %d: must be DTC_EST_VOLTAGE or DTC_EST_CURRENT", si->estimator);
    if (si->compensation < DTC_COMP_NONE || si->compensation > DTC_COMP_FSTP_PROPOSED ||
        (si->topology == DTC_TOPO_SSTP && si->compensation >= DTC_COMP_FSTP_SIMPLE) ||
        (si->topology == DTC_TOPO_FSTP && si->compensation == DTC_COMP_SSTP))
        return fail(&c, DTC_SI_ERR_VARIANT, "compensation = %d: not available for topology %d", si->compensation, si->topology);
    if (si->sstp_table < DTC_ST_BASIC || si->sstp_table > DTC_ST_D)
        return fail(&c, DTC_SI_ERR_VARIANT, "sstp_table = %d: must be DTC_ST_BASIC..DTC_ST_D", si->sstp_table);
    if (si->mode != DTC_MODE_SPEED && si->mode != DTC_MODE_TORQUE)
        return fail(&c, DTC_SI_ERR_VARIANT, "mode = %d: must be DTC_MODE_SPEED or DTC_MODE_TORQUE", si->mode);
    if (!(si->torque_limit_nm > 0.0)) return fail(&c, DTC_SI_ERR_LIMIT, "torque_limit_nm = %g: must be > 0", si->torque_limit_nm);
    if (!(si->stall_time_s == 0.0 ||
          (si->stall_time_s >= 20.0 * si->ts_s * si->speed_div && si->stall_time_s / (si->ts_s * si->speed_div) <= 65535.0)))
        return fail(&c, DTC_SI_ERR_GAIN, "stall_time_s = %g: must be 0 (derived) or span 20 .. 65535 speed periods of %g s", si->stall_time_s, si->ts_s * si->speed_div);
    if (!(si->torque_trim_tau_s == 0.0 || si->torque_trim_tau_s > si->ts_s))
        return fail(&c, DTC_SI_ERR_GAIN, "torque_trim_tau_s = %g: must be 0 (off) or longer than ts_s = %g", si->torque_trim_tau_s, si->ts_s);
    if (!(si->speed_limit_rpm > 0.0)) return fail(&c, DTC_SI_ERR_LIMIT, "speed_limit_rpm = %g: must be > 0", si->speed_limit_rpm);
    if (!(si->i_trip_a > 0.0)) return fail(&c, DTC_SI_ERR_LIMIT, "i_trip_a = %g: must be > 0", si->i_trip_a);
    if (!(si->c_dc_f > 0.0))
        return fail(&c, DTC_SI_ERR_INVERTER, "c_dc_f = %g: must be > 0", si->c_dc_f);
    if (si->dc_supp != 0 && si->dc_supp != 1)
        return fail(&c, DTC_SI_ERR_CUTOFF, "dc_supp = %d: must be 0 or 1", si->dc_supp);
    if (si->lpf_comp != 0 && si->lpf_comp != 1)
        return fail(&c, DTC_SI_ERR_CUTOFF, "lpf_comp = %d: must be 0 or 1", si->lpf_comp);
    if (si->vmid_cal != 0 && si->vmid_cal != 1)
        return fail(&c, DTC_SI_ERR_ILIM, "vmid_cal = %d: must be 0 or 1", si->vmid_cal);
    if (si->polarity_mid != 0 && si->polarity_mid != 1)
        return fail(&c, DTC_SI_ERR_ILIM, "polarity_mid = %d: must be 0 or 1", si->polarity_mid);
    if (si->current_limit_auto == 0 &&
        !(si->current_limit_a >= 0.0 && (si->current_limit_a == 0.0 || si->current_limit_a < si->i_trip_a)))
        return fail(&c, DTC_SI_ERR_ILIM, "current_limit_a = %g: must be 0 (off) or in (0, i_trip_a = %g)", si->current_limit_a, si->i_trip_a);
    if (!(si->vdc_min_v >= 0.0 && si->vdc_max_v > si->vdc_min_v))
        return fail(&c, DTC_SI_ERR_LIMIT, "vdc_min_v = %g, vdc_max_v = %g: need 0 <= min < max", si->vdc_min_v, si->vdc_max_v);
    if (!(si->flux_ref_wb > 0.0)) return fail(&c, DTC_SI_ERR_REFERENCE, "flux_ref_wb = %g: must be > 0", si->flux_ref_wb);
    if (!(fabs(si->speed_ref_rpm) <= si->speed_limit_rpm)) return fail(&c, DTC_SI_ERR_REFERENCE, "speed_ref_rpm = %g: beyond speed_limit_rpm = %g", si->speed_ref_rpm, si->speed_limit_rpm);
    if (!(fabs(si->torque_ref_nm) <= si->torque_limit_nm)) return fail(&c, DTC_SI_ERR_REFERENCE, "torque_ref_nm = %g: beyond torque_limit_nm = %g", si->torque_ref_nm, si->torque_limit_nm);
    if (!(si->adc_i_a_per_count > 0.0)) return fail(&c, DTC_SI_ERR_ADC, "adc_i_a_per_count = %g: must be > 0", si->adc_i_a_per_count);
    if (!(si->adc_vdc_v_per_count > 0.0)) return fail(&c, DTC_SI_ERR_ADC, "adc_vdc_v_per_count = %g: must be > 0", si->adc_vdc_v_per_count);
    if (!(si->adc_vmid_v_per_count > 0.0)) return fail(&c, DTC_SI_ERR_ADC, "adc_vmid_v_per_count = %g: must be > 0", si->adc_vmid_v_per_count);
    for (int k = 0; k < 3; k++) {
        if (si->adc_i_offset[k] < 0 || si->adc_i_offset[k] > 4095)
            return fail(&c, DTC_SI_ERR_ADC, "adc_i_offset[%d] = %d: must be 0..4095", k, si->adc_i_offset[k]);
    }
    if (si->adc_vdc_offset < 0 || si->adc_vdc_offset > 4095) return fail(&c, DTC_SI_ERR_ADC, "adc_vdc_offset = %d: must be 0..4095", si->adc_vdc_offset);
    if (si->adc_vmid_offset < 0 || si->adc_vmid_offset > 4095) return fail(&c, DTC_SI_ERR_ADC, "adc_vmid_offset = %d: must be 0..4095", si->adc_vmid_offset);

    /* Speed PI, SI. */
    if (si->pi_from_bandwidth) {
        if (!(si->speed_bw_rad_s > 0.0)) return fail(&c, DTC_SI_ERR_GAIN, "speed_bw_rad_s = %g: must be > 0", si->speed_bw_rad_s);
        if (!(si->inertia_kgm2 > 0.0)) return fail(&c, DTC_SI_ERR_GAIN, "inertia_kgm2 = %g: must be > 0", si->inertia_kgm2);
        if (!(si->speed_bw_rad_s * si->ts_s * si->speed_div < 0.2))
            return fail(&c, DTC_SI_ERR_GAIN, "speed_bw_rad_s = %g: too fast for the speed period %g s (bw * T < 0.2)", si->speed_bw_rad_s, si->ts_s * si->speed_div);
        /* Crossover at bw with the plant 1/(J s): kp = J bw; PI zero a quarter below: ki = kp bw/4. */
        kp = si->inertia_kgm2 * si->speed_bw_rad_s;
        ki = kp * si->speed_bw_rad_s / 4.0;
    } else {
        kp = si->kp_nm_s_rad;
        ki = si->ki_nm_rad;
        if (!(kp >= 0.0)) return fail(&c, DTC_SI_ERR_GAIN, "kp_nm_s_rad = %g: must be >= 0", kp);
        if (!(ki >= 0.0)) return fail(&c, DTC_SI_ERR_GAIN, "ki_nm_rad = %g: must be >= 0", ki);
    }

    /* Conversion. */
    dtc_bases_from_si(si, &b);
    tsp = si->ts_s * si->speed_div;
    enc_counts = 4.0 * si->enc_lines;

    cfg->version = DTC_CONFIG_VERSION;
    cfg->topology = (uint16_t)si->topology;
    cfg->estimator = (uint16_t)si->estimator;
    cfg->compensation = (uint16_t)si->compensation;
    cfg->sstp_table = (uint16_t)si->sstp_table;
    cfg->mode = (uint16_t)si->mode;
    cfg->fstp_vmid_measured = (uint16_t)si->fstp_vmid_measured;
    cfg->v_base_mv = to_u32_milli(b.v_base_v);
    cfg->i_base_ma = to_u32_milli(b.i_base_a);
    cfg->w_base_mrad_s = to_u32_milli(b.w_base_rad_s);
    cfg->pole_pairs = (uint16_t)si->pole_pairs;

    cfg->rs_iq = to_iq(&c, "rs_ohm", si->rs_ohm, si->rs_ohm / b.z_base_ohm);
    cfg->ls_iq = to_iq(&c, "ls_h", si->ls_h, si->ls_h / b.l_base_h);
    cfg->psi_m_iq = to_iq(&c, "psi_m_wb", si->psi_m_wb, si->psi_m_wb / b.psi_base_wb);

    /* Exact ZOH discretisation of 1/(s + w_c) in pu time. */
    a = exp(-si->lpf_cutoff_rad_s * si->ts_s);
    wc_pu = si->lpf_cutoff_rad_s / b.w_base_rad_s;
    cfg->k_leak_q31 = to_q31(&c, "lpf_cutoff_rad_s (k_leak)", 1.0 - a);
    cfg->k_in_q31 = to_q31(&c, "ts_s (k_in)", (1.0 - a) / wc_pu);

    {
        double h_rpm = si->handover_auto != 0 ? dtc_handover_default_rpm(si) : si->handover_speed_rpm;
        double h_pu = h_rpm * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s;
        cfg->handover_speed_iq = to_iq(&c, "handover_speed_rpm", h_rpm, h_pu);
        cfg->handover_hyst_iq = to_iq(&c, "handover_hyst_frac", si->handover_hyst_frac * h_rpm,
                                      si->handover_hyst_frac * h_pu);
        if (cfg->handover_hyst_iq > cfg->handover_speed_iq) {
            cfg->handover_hyst_iq = cfg->handover_speed_iq;
        }
    }

    cfg->delay_comp = (uint16_t)si->delay_comp;
    cfg->deadtime_comp = (uint16_t)si->deadtime_comp;
    cfg->td_ts_q15 = (q15_t)lround(32768.0 * si->dead_time_s / si->ts_s);
    cfg->ts_pu_iq = to_iq(&c, "ts_s", si->ts_s, si->ts_s * b.w_base_rad_s);
    cfg->inv_ls_iq = to_iq(&c, "ls_h (1/l_s)", si->ls_h, b.l_base_h / si->ls_h);

    if (!(65536.0 * 65536.0 * si->pole_pairs / enc_counts <= 2147483648.0))
        return fail(&c, DTC_SI_ERR_ENCODER, "enc_lines = %d: fewer than two counts per electrical turn with %d pole pairs", si->enc_lines, si->pole_pairs);
    cfg->enc_counts = (uint16_t)enc_counts;
    cfg->enc_gain_q16 = (uint32_t)nearbyint(65536.0 * 65536.0 * si->pole_pairs / enc_counts);
    {
        double turns = si->enc_offset_rad / (2.0 * M_PI);
        turns -= floor(turns);
        cfg->enc_offset = (angle_t)((uint32_t)nearbyint(turns * 65536.0) & 0xFFFFu);
    }

    cfg->v_f_iq = to_iq(&c, "v_f_v", si->v_f_v, si->v_f_v / b.v_base_v);
    cfg->v_ce_iq = to_iq(&c, "v_ce_v", si->v_ce_v, si->v_ce_v / b.v_base_v);
    cfg->v_d_iq = to_iq(&c, "v_d_v", si->v_d_v, si->v_d_v / b.v_base_v);
    cfg->r_on_iq = to_iq(&c, "r_on_ohm", si->r_on_ohm, si->r_on_ohm / b.z_base_ohm);

    cfg->flux_band_iq = to_iq(&c, "flux_band_wb", si->flux_band_wb, si->flux_band_wb / b.psi_base_wb);
    cfg->torque_band_iq = to_iq(&c, "torque_band_nm", si->torque_band_nm, si->torque_band_nm / b.t_base_nm);

    cfg->speed_div = (uint16_t)si->speed_div;
    cfg->speed_k_iq = to_iq(&c, "enc_lines (speed gain)", enc_counts,
                            2.0 * M_PI * si->pole_pairs / (enc_counts * tsp * b.w_base_rad_s));
    cfg->speed_min_counts = (uint16_t)si->speed_min_counts;
    {
        const double t_speed = si->ts_s * si->speed_div;
        const double t_stall = si->stall_time_s != 0.0 ? si->stall_time_s : fmax(0.1, 20.0 * t_speed);
        cfg->stall_speed_periods = (uint16_t)fmin(65535.0, (double)lround(t_stall / t_speed));
    }
    /* kp: N.m per mech rad/s -> pu torque per pu speed: w_mech = w_pu w_base / p. */
    cfg->kp_iq = to_iq(&c, "kp_nm_s_rad", kp, kp * b.w_base_rad_s / (si->pole_pairs * b.t_base_nm));
    cfg->ki_ts_iq = to_iq(&c, "ki_nm_rad", ki, ki * tsp * b.w_base_rad_s / (si->pole_pairs * b.t_base_nm));
    cfg->torque_limit_iq = to_iq(&c, "torque_limit_nm", si->torque_limit_nm, si->torque_limit_nm / b.t_base_nm);
    cfg->torque_trim_k_q15 = si->torque_trim_tau_s == 0.0 ? 0
                             : (q15_t)lround(32768.0 * si->ts_s / si->torque_trim_tau_s);
    cfg->speed_limit_iq = to_iq(&c, "speed_limit_rpm", si->speed_limit_rpm,
                                si->speed_limit_rpm * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s);

    cfg->flux_ref_iq = to_iq(&c, "flux_ref_wb", si->flux_ref_wb, si->flux_ref_wb / b.psi_base_wb);
    cfg->speed_ref_iq = to_iq(&c, "speed_ref_rpm", si->speed_ref_rpm,
                              si->speed_ref_rpm * M_PI / 30.0 * si->pole_pairs / b.w_base_rad_s);
    cfg->torque_ref_iq = to_iq(&c, "torque_ref_nm", si->torque_ref_nm, si->torque_ref_nm / b.t_base_nm);

    cfg->adc_i_gain_iq = to_iq(&c, "adc_i_a_per_count", si->adc_i_a_per_count, si->adc_i_a_per_count / b.i_base_a);
    for (int k = 0; k < 3; k++) {
        cfg->adc_i_offset[k] = (uint16_t)si->adc_i_offset[k];
    }
    cfg->adc_vdc_gain_iq = to_iq(&c, "adc_vdc_v_per_count", si->adc_vdc_v_per_count, si->adc_vdc_v_per_count / b.v_base_v);
    cfg->adc_vdc_offset = (uint16_t)si->adc_vdc_offset;
    cfg->adc_vmid_gain_iq = to_iq(&c, "adc_vmid_v_per_count", si->adc_vmid_v_per_count, si->adc_vmid_v_per_count / b.v_base_v);
    cfg->adc_vmid_offset = (uint16_t)si->adc_vmid_offset;
    cfg->i_trip_iq = to_iq(&c, "i_trip_a", si->i_trip_a, si->i_trip_a / b.i_base_a);
    cfg->vdc_max_iq = to_iq(&c, "vdc_max_v", si->vdc_max_v, si->vdc_max_v / b.v_base_v);
    cfg->vdc_min_iq = to_iq(&c, "vdc_min_v", si->vdc_min_v, si->vdc_min_v / b.v_base_v);
    {
        double ilim = si->current_limit_auto != 0 ? dtc_ilim_default_a(si) : si->current_limit_a;
        cfg->i_lim_iq = ilim > 0.0 ? to_iq(&c, "current_limit_a", ilim, ilim / b.i_base_a) : 0;
        if (cfg->i_lim_iq >= cfg->i_trip_iq) {
            cfg->i_lim_iq = cfg->i_trip_iq - 1; /* below the trip after rounding */
        }
    }
    cfg->polarity_mid = (uint16_t)si->polarity_mid;
    /* the mid-point calibration only where a mid-point is measured (FSTP) */
    cfg->lpf_comp = (uint16_t)si->lpf_comp;
    cfg->dc_supp = (uint16_t)si->dc_supp;
    /* Ts l_s / 20 in pu (the firmware multiplies by |w|: w_d = |w| / 20, dtc.c dtc_dcsupp) */
    cfg->dcs_k_iq = to_iq(&c, "dc_supp (Ts l_s / 20)", si->ls_h,
                          si->ts_s * b.w_base_rad_s * si->ls_h / b.l_base_h / 20.0);
    cfg->wc_pu_iq = to_iq(&c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, si->lpf_cutoff_rad_s / b.w_base_rad_s);
    cfg->lpf_wmin_iq = to_iq(&c, "lpf_cutoff_rad_s", si->lpf_cutoff_rad_s, 2.0 * si->lpf_cutoff_rad_s / b.w_base_rad_s);
    {
        const int reg = si->dc_supp != 0 && si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0;
        const double g = 2.0 * si->c_dc_f * 0.5 * si->lpf_cutoff_rad_s; /* A/V, w_m = w_c / 2 */
        cfg->vmid_g_iq = reg ? to_iq(&c, "c_dc_f", si->c_dc_f, g * b.z_base_ohm) : 0;
    }
    cfg->vmid_cal = (uint16_t)(si->vmid_cal != 0 && si->topology == DTC_TOPO_FSTP && si->fstp_vmid_measured != 0 ? 1 : 0);

    if (c.code != DTC_SI_OK) {
        return c.code;
    }
    fw = dtc_config_validate(cfg);
    if (fw != DTC_OK) {
        return fail(&c, DTC_SI_ERR_FIRMWARE, "firmware validation refused the converted configuration (dtc_err %d)", fw);
    }
    return DTC_SI_OK;
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

int dtc_config_emit_c(const dtc_config_t *cfg, const char *symbol, FILE *f)
{
    char b[32];
    const double iq = 16777216.0, q31 = 2147483648.0;
    int r = 0;

    if (cfg == NULL || symbol == NULL || f == NULL) {
        return -1;
    }
#define EMIT(...) do { if (fprintf(f, __VA_ARGS__) < 0) r = -1; } while (0)
#define EIQ(name) EMIT("    .%s = %s, /* %.9g pu */\n", #name, i32(b, sizeof b, cfg->name), (double)cfg->name / iq)
#define EQ31(name) EMIT("    .%s = %s, /* %.12g */\n", #name, i32(b, sizeof b, cfg->name), (double)cfg->name / q31)
#define EU(name) EMIT("    .%s = %luU,\n", #name, (unsigned long)cfg->name)
    EMIT("/* Generated by dtc_config_emit_c (tools/config): DTC firmware configuration, per-unit\n"
         " * Q formats (firmware/dtc/dtc_config.h, bases in firmware/dtc/dtc_base.h).\n"
         " * Bases: V_base %.3f V, I_base %.3f A, w_base %.3f rad/s. Do not edit by hand. */\n",
         cfg->v_base_mv / 1000.0, cfg->i_base_ma / 1000.0, cfg->w_base_mrad_s / 1000.0);
    EMIT("#include \"dtc_config.h\"\n\n");
    EMIT("const dtc_config_t %s = {\n", symbol);
    EU(version); EU(topology); EU(estimator); EU(compensation); EU(sstp_table); EU(mode);
    EU(fstp_vmid_measured); EU(v_base_mv); EU(i_base_ma); EU(w_base_mrad_s); EU(pole_pairs);
    EIQ(rs_iq); EIQ(ls_iq); EIQ(psi_m_iq);
    EQ31(k_in_q31); EQ31(k_leak_q31);
    EIQ(handover_speed_iq); EIQ(handover_hyst_iq);
    EU(delay_comp); EIQ(ts_pu_iq); EIQ(inv_ls_iq);
    EU(deadtime_comp);
    EMIT("    .td_ts_q15 = %d, /* T_d / T_s, Q15 */\n", (int)cfg->td_ts_q15);
    EU(enc_counts); EU(enc_gain_q16); EU(enc_offset);
    EIQ(v_f_iq); EIQ(v_ce_iq); EIQ(v_d_iq); EIQ(r_on_iq);
    EIQ(flux_band_iq); EIQ(torque_band_iq);
    EU(speed_div); EIQ(speed_k_iq); EU(speed_min_counts); EU(stall_speed_periods);
    EIQ(kp_iq); EIQ(ki_ts_iq); EIQ(torque_limit_iq); EIQ(speed_limit_iq);
    EMIT("    .torque_trim_k_q15 = %d, /* Ts / tau of the torque-mode trim, Q15 */\n", (int)cfg->torque_trim_k_q15);
    EIQ(flux_ref_iq); EIQ(speed_ref_iq); EIQ(torque_ref_iq);
    EIQ(adc_i_gain_iq);
    EMIT("    .adc_i_offset = {%uU, %uU, %uU},\n", (unsigned)cfg->adc_i_offset[0],
         (unsigned)cfg->adc_i_offset[1], (unsigned)cfg->adc_i_offset[2]);
    EIQ(adc_vdc_gain_iq); EU(adc_vdc_offset); EIQ(adc_vmid_gain_iq); EU(adc_vmid_offset);
    EIQ(i_trip_iq); EIQ(vdc_max_iq); EIQ(vdc_min_iq);
    EIQ(i_lim_iq); EU(polarity_mid); EU(vmid_cal);
    EU(lpf_comp); EIQ(wc_pu_iq); EIQ(lpf_wmin_iq); EU(dc_supp); EIQ(dcs_k_iq); EIQ(vmid_g_iq);
    EMIT("};\n");
#undef EMIT
#undef EIQ
#undef EQ31
#undef EU
    return r;
}
