/*
 * dtc_config.h - the firmware's configuration: every parameter of every block, in per-unit Q
 * formats (dtc_base.h), plus the validation that dtc_init() runs before accepting it.
 *
 * The struct is produced on the host from SI values by tools/config (dtc_config_from_si(), which
 * also precomputes every reciprocal so the firmware never divides) and may be emitted as a C
 * source file for a target build (dtc_config_emit_c()). dtc_config_validate() re-checks it on the
 * target: a corrupted or hand-edited struct is refused with a code from enum dtc_err.
 */
#ifndef DTC_CONFIG_H
#define DTC_CONFIG_H

#include <stdint.h>

#include "dtc_base.h"
#include "fixmath.h"

/* Layout version: bump when a field is added, removed or changes meaning. */
#define DTC_CONFIG_VERSION 4U

enum dtc_topology {
    DTC_TOPO_SSTP = 0, /* six-switch three-phase inverter (Hoang Fig. 1a, Casadei) */
    DTC_TOPO_FSTP = 1  /* four-switch three-phase: phase A on the capacitor mid-point (Fig. 1b) */
};

enum dtc_estimator {
    DTC_EST_VOLTAGE = 0, /* Hoang eqs. 15-16 (with 37-38 when compensated), low-pass instead of an integrator */
    DTC_EST_CURRENT = 1  /* Hoang eqs. 8-9 from the encoder angle */
};

enum dtc_compensation {
    DTC_COMP_NONE = 0,          /* ideal switches (Hoang eqs. 15-16) */
    DTC_COMP_SSTP = 1,          /* SSTP, equal device and diode drops (Hoang ref. [29], eqs. 24-25) */
    DTC_COMP_FSTP_SIMPLE = 2,   /* FSTP, Hoang Table V (eqs. 35-36), V_f */
    DTC_COMP_FSTP_PROPOSED = 3  /* FSTP, Hoang Table VI with V_CE, V_d, plus the R_on terms (37-38) */
};

enum dtc_sstp_table {
    DTC_ST_BASIC = 0, /* Casadei Table 1, three-level torque comparator */
    DTC_ST_A = 1,     /* Casadei Table 3, two-level torque comparator */
    DTC_ST_B = 2,
    DTC_ST_C = 3,
    DTC_ST_D = 4
};

enum dtc_mode {
    DTC_MODE_SPEED = 0, /* speed PI (every speed_div-th step) produces the torque reference */
    DTC_MODE_TORQUE = 1 /* the torque reference comes straight from the shadow set */
};

/* Error codes of dtc_config_validate() / dtc_init() (0 = accepted). Stable numbers: the app
 * reports them as its fault reason. */
enum dtc_err {
    DTC_OK = 0,
    DTC_ERR_NULL = -1,         /* null controller or configuration pointer */
    DTC_ERR_VERSION = -2,      /* version field is not DTC_CONFIG_VERSION */
    DTC_ERR_VARIANT = -3,      /* topology, estimator, table or mode out of range */
    DTC_ERR_COMPENSATION = -4, /* compensation out of range or not meant for the topology */
    DTC_ERR_MACHINE = -5,      /* r_s < 0, l_s <= 0, psi_m <= 0 */
    DTC_ERR_FLUX_EST = -6,     /* integration gain or low-pass leak outside (0, 1) */
    DTC_ERR_ENCODER = -7,      /* encoder counts/angle gain not representable */
    DTC_ERR_BAND = -8,         /* negative hysteresis band */
    DTC_ERR_SPEED = -9,        /* speed divider or speed-measurement parameters out of range */
    DTC_ERR_PI = -10,          /* negative gain (speed PI, torque trim) or torque limit <= 0 */
    DTC_ERR_REFERENCE = -11,   /* flux reference <= 0, references outside their limits */
    DTC_ERR_DROP = -12,        /* negative device drop or on-resistance */
    DTC_ERR_ADC = -13,         /* zero or negative ADC gain, offset outside 12 bits */
    DTC_ERR_BASE = -14,        /* a base value of zero */
    DTC_ERR_LIMIT = -15,       /* trip/limit levels not positive or not ordered */
    DTC_ERR_HANDOVER = -16,    /* hand-over speed < 0, or its hysteresis < 0 or above it */
    DTC_ERR_DELAY = -17,       /* delay compensation flag not 0/1, ts_pu or 1/l_s not > 0 */
    DTC_ERR_DEADTIME = -18,    /* dead-time compensation flag not 0/1, T_d/T_s outside [0, 1/2) */
    DTC_ERR_ILIM = -19,        /* current limit < 0 or not below the trip level */
    DTC_ERR_POLARITY = -20,    /* polarity_mid or vmid_cal flag not 0/1 */
    DTC_ERR_LPFCOMP = -21,     /* lpf_comp not 0/1, or w_c / w_min not > 0 with it on */
    DTC_ERR_DCSUPP = -22       /* dc_supp not 0/1, its gain not > 0 with it on, mid-point gain < 0 */
};

/* Speed measurement: ring of encoder positions at the speed-loop rate (see speed_meas.h). */
#define DTC_SPEED_RING 32U     /* positions kept; a power of two */
#define DTC_SPEED_WIN_LOG2_MAX 4U /* longest window 2^4 = 16 speed ticks (8 ms at 2 kHz) */

struct dtc_config {
    uint16_t version; /* DTC_CONFIG_VERSION */

    /* Variant selection (enum values above). */
    uint16_t topology;
    uint16_t estimator;
    uint16_t compensation;
    uint16_t sstp_table;
    uint16_t mode;               /* initial mode; the shadow set may change it */
    uint16_t fstp_vmid_measured; /* 1: the FSTP mid-point voltage is measured (dtc_meas_t.vmid_iq) */

    /* Per-unit bases, informational (for logs and the app): milli-units, integers. */
    uint32_t v_base_mv;
    uint32_t i_base_ma;
    uint32_t w_base_mrad_s;
    uint16_t pole_pairs;

    /* Machine (Hoang Table VIII), pu. */
    iq_t rs_iq;     /* stator resistance r_s */
    iq_t ls_iq;     /* synchronous inductance l_s (surface PM: L_d = L_q) */
    iq_t psi_m_iq;  /* magnet flux linkage psi_m */

    /* Voltage-model flux estimator (flux_est.h): psi += k_in*(v - r_s*i + v_f) - k_leak*psi,
     * the exact (zero-order-hold) discretisation of the low-pass 1/(s + w_c) that replaces the
     * integrator of Hoang eqs. 15-16: k_leak = 1 - exp(-w_c*Ts), k_in = k_leak / (w_c/w_base). */
    q31_t k_in_q31;
    q31_t k_leak_q31;

    /* Start-up and hand-over (voltage model only; dtc.c step 3). Below handover_speed_iq the
     * drive runs on the current model (Hoang eqs. 8-9, encoder) and the voltage model's low-pass
     * state is overwritten with that flux every period; once |measured speed| exceeds
     * handover_speed_iq the voltage model integrates on from that state (bumpless: the estimate
     * is continuous at the hand-over); it falls back to the current model when |speed| drops
     * below handover_speed_iq - handover_hyst_iq. Electrical speed, pu; handover_speed_iq = 0:
     * no hand-over, the voltage model runs from standstill (seeded once after a reset). */
    iq_t handover_speed_iq;   /* >= 0 */
    iq_t handover_hyst_iq;    /* 0 <= hyst <= handover_speed_iq */

    /* Actuation-delay compensation (dtc.c dtc_predict): the vector chosen at step k acts in
     * period k+1, so the comparators and the sector work on the flux and torque predicted for
     * the start of period k+1 from the vector already committed for period k. */
    uint16_t delay_comp;      /* 1: on (default), 0: comparators on the estimate at k */
    iq_t ts_pu_iq;            /* Ts * w_base (> 0) */
    iq_t inv_ls_iq;           /* 1 / l_s, pu (> 0; precomputed: no division in the ISR) */

    /* Dead-time compensation of the reconstructed voltage (dtc.c dtc_deadtime_i; Casadei sec.
     * 10.5: its drive compensated the dead time). */
    uint16_t deadtime_comp;   /* 1: on, 0: off */
    q15_t td_ts_q15;          /* dead time over the control period, T_d / T_s, [0, 0.5) */

    /* Current-model estimator (Hoang eqs. 8-9): theta_e = count * enc_gain + enc_offset. */
    uint16_t enc_counts;       /* 4 * lines (quadrature), counts per mechanical turn */
    uint32_t enc_gain_q16;     /* electrical angle LSB per count, unsigned Q16: 65536*p/enc_counts */
    angle_t enc_offset;        /* electrical angle at count 0 (encoder-to-magnet alignment) */

    /* Inverter voltage-drop compensation (Hoang Tables III-VI, eqs. 20, 24-25, 37-38), pu. */
    iq_t v_f_iq;   /* equal device/diode drop V_f (SSTP [29] and Table V) */
    iq_t v_ce_iq;  /* switching-device forward drop V_CE (Table VI) */
    iq_t v_d_iq;   /* free-wheeling diode forward drop V_d (Table VI) */
    iq_t r_on_iq;  /* on-state resistance R_on (eqs. 20, 24-25, 37-38) */

    /* Hysteresis bands (full widths, Hoang eqs. 13-14: the thresholds are +-band/2), pu; >= 0. */
    iq_t flux_band_iq;
    iq_t torque_band_iq;

    /* Speed loop (every speed_div-th step). */
    uint16_t speed_div;           /* control periods per speed period (10) */
    iq_t speed_k_iq;              /* pu speed per encoder count over ONE speed period */
    uint16_t speed_min_counts;    /* shortest window with at least this many counts is used */
    iq_t kp_iq;                   /* speed PI proportional gain, pu torque per pu speed */
    iq_t ki_ts_iq;                /* integral gain times the speed period, pu torque per pu speed */
    iq_t torque_limit_iq;         /* |T_ref| limit, pu (> 0) */
    q15_t torque_trim_k_q15;      /* torque mode: mean-torque trim gain per control period,
                                   * Ts / tau (0 = off, < 1); see dtc.c step 5 */
    iq_t speed_limit_iq;          /* |speed_ref| limit, pu (> 0) */
    uint16_t stall_speed_periods; /* app stall window in speed periods (> 0): the host converts
                                   * the stall time (0.1 s by default) with Ts and speed_div */

    /* Initial references (the shadow set replaces them at run time), pu. */
    iq_t flux_ref_iq;
    iq_t speed_ref_iq;
    iq_t torque_ref_iq;

    /* ADC scaling for the app: pu = (count - offset) * gain. Offsets are nominal; the app
     * calibrates the current offsets with the gates off. */
    iq_t adc_i_gain_iq;       /* pu current per count */
    uint16_t adc_i_offset[3]; /* counts at zero current, phases A, B, C */
    iq_t adc_vdc_gain_iq;     /* pu voltage per count, DC link */
    uint16_t adc_vdc_offset;
    iq_t adc_vmid_gain_iq;    /* pu voltage per count, FSTP mid-point to negative rail */
    uint16_t adc_vmid_offset;

    /* Protection levels for the app, pu. */
    iq_t i_trip_iq;   /* phase-current trip */
    iq_t vdc_max_iq;  /* DC-link over-voltage */
    iq_t vdc_min_iq;  /* DC-link under-voltage */

    /* ---- Current limit and ripple-robust polarity (issue 10; ilim.h, dtc.c) ---- */
    iq_t i_lim_iq;          /* current-limit override on |i| (ilim.h), pu; 0 = off, else
                             * 0 < i_lim < i_trip (derived on the host from the trip level) */
    uint16_t polarity_mid;  /* 1: the drop compensation of period [k-1, k] takes the current
                             * polarity from the period's mean current (i(k-1) + i(k))/2 and the
                             * dead-time compensation from the current at the switching instant
                             * i(k-1); 0: both from the sample i(k) */
    uint16_t vmid_cal;      /* FSTP with the mid-point measured: 1 = the app calibrates the
                             * mid-point sensor against V_dc/2 with the gates off (app_core.c
                             * calibrate_step), 0 = the mid-point as measured */
    uint16_t lpf_comp;      /* voltage model: 1 = gain/phase correction of the low-pass with the
                             * measured speed (lpfcorr.h), 0 = the low-pass output as it is */
    iq_t wc_pu_iq;          /* the low-pass cut-off w_c / w_base (> 0 when lpf_comp) */
    iq_t lpf_wmin_iq;       /* the correction's speed floor, pu (> 0 when lpf_comp; 2 w_c) */
    uint16_t dc_supp;       /* voltage model: 1 = DC-current suppression (dtc.c dtc_dcsupp) */
    iq_t dcs_k_iq;          /* its gain per period over |w|, Ts l_s / 20 in pu (> 0 when dc_supp):
                             * w_d = |w| / 20 */
    iq_t vmid_g_iq;         /* FSTP mid-point regulation (dtc_dcsupp): phase-A DC current demanded
                             * per volt of mid-point deviation, 2 C w_m in pu (>= 0; 0 = off) */
};

typedef struct dtc_config dtc_config_t;

/* Checks every field of a configuration. Returns DTC_OK or the first enum dtc_err code found
 * (in the order of the enum). Pure; used by dtc_init() and by the host converter. */
int16_t dtc_config_validate(const dtc_config_t *cfg);

#endif /* DTC_CONFIG_H */
