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
#define DTC_CONFIG_VERSION 11U

/* Largest accepted |calibrated - nominal| current offset, ADC counts (5 % of full scale): the
 * app's gates-off calibration (app_core.c) trips beyond it, and the trip level must stay visible
 * with the offset anywhere inside it (dtc_config.c dtc_range_check). */
#define DTC_ADC_OFFSET_TOL_COUNTS 205

/* The control law the application runs (dtc_law.h dispatches on it). */
enum dtc_law {
    DTC_LAW_PM_DTC = 0, /* PM brushless AC machine, Hoang et al. 2011 (dtc.h) */
    DTC_LAW_IM_DTC = 1  /* induction machine, Casadei et al. 2006 DTC / DSC (im_dtc.h) */
};

enum dtc_topology {
    DTC_TOPO_SSTP = 0, /* six-switch three-phase inverter (Hoang Fig. 1a, Casadei) */
    DTC_TOPO_FSTP = 1  /* four-switch three-phase: phase A on the capacitor mid-point (Fig. 1b) */
};

enum dtc_estimator {
    DTC_EST_VOLTAGE = 0,  /* PM: Hoang eqs. 15-16 (with 37-38 when compensated); IM: Casadei eq. 1;
                           * both with a low-pass instead of an integrator */
    DTC_EST_CURRENT = 1,  /* PM only: Hoang eqs. 8-9 from the encoder angle */
    DTC_EST_IMPROVED = 2  /* IM only: Casadei eqs. 20-22 (im_est.h) */
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
    DTC_ST_D = 4,
    DTC_ST_SPEED = 5  /* IM only: Casadei section 8, ST-D below im_table_speed_iq, ST-A above */
};

enum dtc_scheme {
    DTC_SCHEME_DTC = 0, /* switching table (Casadei sections 4-8) */
    DTC_SCHEME_DSC = 1, /* IM only: Direct Self Control (Casadei section 9, dsc.h) */
    DTC_SCHEME_SFVC = 2, /* IM only: stator-flux vector control with SVM at a constant switching
                          * frequency (Casadei sections 10.3-10.5, Fig. 18; im_sfvc.c, svm.h) */
    DTC_SCHEME_DFOC = 3, /* IM only: direct rotor-flux-oriented control, PI current regulators in
                          * the rotor-flux frame, SVM (Casadei section 13; im_dfoc.c) */
    DTC_SCHEME_DSVM = 4  /* IM only: DTC with Discrete Space Vector Modulation, three equal
                          * sub-intervals per period (Casadei section 11; dsvm.h, im_dsvm.c) */
};

enum dtc_speed_sensor {
    DTC_SPEED_ENCODER = 0, /* speed from the encoder counts (speed_meas.h) */
    DTC_SPEED_NONE = 1     /* IM only: rotor-flux angular speed minus the slip of Casadei eq. 16 */
};

enum dtc_mode {
    DTC_MODE_SPEED = 0, /* speed PI (every speed_div-th step) produces the torque reference */
    DTC_MODE_TORQUE = 1 /* the torque reference comes straight from the shadow set */
};

/* Error codes of dtc_config_validate() / dtc_init() (0 = accepted). Stable numbers: the app
 * reports them as its fault reason; dtc_config_check() also names the field. */
enum dtc_err {
    DTC_OK = 0,
    DTC_ERR_NULL = -1,         /* null controller or configuration pointer */
    DTC_ERR_VERSION = -2,      /* version field is not DTC_CONFIG_VERSION */
    DTC_ERR_VARIANT = -3,      /* law, topology, estimator, table, scheme, sensor or mode out of
                                * range or not meant for the law */
    DTC_ERR_COMPENSATION = -4, /* compensation out of range or not meant for the topology */
    DTC_ERR_MACHINE = -5,      /* PM: r_s < 0, l_s <= 0, psi_m <= 0; IM: see dtc_im_machine_cfg_t */
    DTC_ERR_FLUX_EST = -6,     /* integration gain or low-pass leak outside (0, 1), IM observer */
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
    DTC_ERR_WEAKENING = -19,   /* IM flux-weakening parameters (im_fw.h) inconsistent */
    DTC_ERR_STARTUP = -20,     /* IM magnetisation threshold out of range */
    DTC_ERR_ILIM = -21,        /* current limit or rotor-hold current < 0 or not below the trip level */
    DTC_ERR_POLARITY = -22,    /* polarity_mid or vmid_cal flag not 0/1 */
    DTC_ERR_LPFCOMP = -23,     /* lpf_comp not 0/1, or w_c / w_min not > 0 with it on */
    DTC_ERR_DCSUPP = -24,      /* dc_supp not 0/1, its gain not > 0 with it on, mid-point gains < 0 */
    DTC_ERR_SVM = -25,         /* SFVC / DFOC: modulation out of range, flux-regulator gain K_p
                                * not in (0, 1/Ts], DFOC current-loop gains or references not > 0 */
    DTC_ERR_FAULTDET = -26,    /* fault detection: a level < 0, the current-sum check without
                                * three current sensors */
    DTC_ERR_RECONFIG = -27     /* post-fault configuration (app_core_set_reconfig) not the FSTP
                                * of the same PM drive, or the drive cannot be reconfigured */
};

/* Speed measurement: ring of encoder positions at the speed-loop rate (see speed_meas.h). */
#define DTC_SPEED_RING 32U     /* positions kept; a power of two */
#define DTC_SPEED_WIN_LOG2_MAX 4U /* longest window 2^4 = 16 speed ticks (8 ms at 2 kHz) */

/* Board: per-unit bases, inverter, sampling, sensors (everything that is the same whatever the
 * machine and the control law). */
typedef struct {
    /* Per-unit bases, informational (for logs and the app): milli-units, integers. */
    uint32_t v_base_mv;
    uint32_t i_base_ma;
    uint32_t w_base_mrad_s;

    uint16_t topology;           /* enum dtc_topology */
    uint16_t fstp_vmid_measured; /* 1: the FSTP mid-point voltage is measured (dtc_meas_t.vmid_iq) */
    iq_t ts_pu_iq;               /* control period Ts * w_base (> 0) */
    q15_t td_ts_q15;             /* dead time over the control period, T_d / T_s, [0, 0.5) */

    /* Inverter voltage drops (Hoang Tables III-VI, eqs. 20, 24-25, 37-38), pu. */
    iq_t v_f_iq;   /* equal device/diode drop V_f (SSTP [29] and Table V) */
    iq_t v_ce_iq;  /* switching-device forward drop V_CE (Table VI) */
    iq_t v_d_iq;   /* free-wheeling diode forward drop V_d (Table VI) */
    iq_t r_on_iq;  /* on-state resistance R_on (eqs. 20, 24-25, 37-38) */

    /* Encoder: theta_e = count * enc_gain + enc_offset. */
    uint16_t enc_counts;       /* 4 * lines (quadrature), counts per mechanical turn */
    uint32_t enc_gain_q16;     /* electrical angle LSB per count, unsigned Q16: 65536*p/enc_counts */
    angle_t enc_offset;        /* electrical angle at count 0 (encoder-to-magnet alignment) */

    /* ADC scaling for the app: pu = (count - offset) * gain. Offsets are nominal; the app
     * calibrates the current offsets with the gates off. */
    iq_t adc_i_gain_iq;       /* pu current per count */
    uint16_t adc_i_offset[3]; /* counts at zero current, phases A, B, C */
    iq_t adc_vdc_gain_iq;     /* pu voltage per count, DC link */
    uint16_t adc_vdc_offset;
    iq_t adc_vmid_gain_iq;    /* pu voltage per count, FSTP mid-point to negative rail */
    uint16_t adc_vmid_offset;
    uint16_t vmid_cal;        /* FSTP with the mid-point measured: 1 = the app calibrates the
                               * mid-point sensor against V_dc/2 with the gates off (app_core.c
                               * calibrate_step), 0 = the mid-point as measured */
    uint16_t i_sensors3;      /* 1: all three phase currents are measured (the app calibrates the
                               * three offsets and checks their sum, prot.i_sum_max_iq); 0: two
                               * (the SSTP's A and B, the FSTP's B and C), the third derived */
} dtc_board_cfg_t;

/* Protection levels for the app, pu. */
typedef struct {
    iq_t i_trip_iq;   /* phase-current trip */
    iq_t vdc_max_iq;  /* DC-link over-voltage */
    iq_t vdc_min_iq;  /* DC-link under-voltage */
    iq_t i_lim_iq;    /* current-limit override on |i| (ilim.h), pu; 0 = off, else
                       * 0 < i_lim < i_trip (derived on the host from the trip level) */
    uint16_t stall_speed_periods; /* app stall window in speed periods (> 0): the host converts
                                   * the stall time (0.1 s by default) with Ts and speed_div */
    iq_t i_hold_iq;   /* rotor hold while the FSTP mid-point is calibrated (board.vmid_cal; app_core.c
                       * hold_step), pu: the largest phase-B current the hold may command; 0 = the
                       * gates stay off for the whole calibration. 0 <= i_hold < i_trip (the host
                       * derives it from the torque limit and the current limit) */
    /* Fault detection (app_core.c check_faults; issue 16), each 0 = off. */
    iq_t i_sum_max_iq;  /* three sensors: |i_a + i_b + i_c| above it for APP_ISUM_PERIODS periods
                         * is a failed current sensor (the star point is isolated), pu; > 0 needs
                         * board.i_sensors3 */
    iq_t leg_i_min_iq;  /* open phase: the least |i| (Clarke magnitude) at which a phase that
                         * stays below |i|/4 over APP_LEG_ANGLE of electrical angle is taken for
                         * an open leg, phase or device, pu */
    iq_t enc_freeze_speed_iq; /* lost encoder signal: a count that does not move for
                               * APP_ENC_FREEZE_PERIODS while the measured speed is above this
                               * electrical speed, pu (the host derives it from the encoder
                               * resolution and the drive's largest deceleration) */
    uint16_t relay_periods;   /* reconfiguration: control periods from the relay command until
                               * the phase is on the mid-point (the relay's closing time with a
                               * margin); the open-phase check waits that long */
    uint16_t i_plaus;         /* 1: the measured currents are checked against the law's prediction
                               * (app_plaus.h; needs leg_i_min_iq > 0 for its zero band), 0: off */
    iq_t overspeed_iq;        /* overspeed trip: |measured electrical speed| above it, pu (> the
                               * speed limit; 0 = off; the host derives it from the rated speed) */
} dtc_protect_cfg_t;

/* PM machine (Hoang Table VIII), pu; used by the PM law. */
typedef struct {
    iq_t ls_iq;     /* synchronous inductance l_s (surface PM: L_d = L_q) */
    iq_t psi_m_iq;  /* magnet flux linkage psi_m */
    iq_t inv_ls_iq; /* 1 / l_s (> 0; precomputed: no division in the ISR) */
} dtc_pm_machine_cfg_t;

/* Induction machine (Casadei appendix, T model), pu; used by the IM law. Every ratio the law
 * needs is precomputed by the host (no division in the ISR). */
typedef struct {
    iq_t rr_iq;          /* rotor resistance r_r (eq. 16) */
    iq_t sigma_ls_iq;    /* sigma l_s (eq. 21) */
    iq_t sigma_lr_iq;    /* sigma l_r (eq. 19) */
    iq_t kr_iq;          /* l_r / m (eq. 21), > 0 */
    iq_t ks_iq;          /* l_s / m (eq. 19), > 0 */
    iq_t inv_ks_iq;      /* m / l_s: rotor flux of a stator flux at no load (start-up) */
    iq_t m_iq;           /* magnetising inductance m, pu (start-up rotor-flux model), > 0 */
} dtc_im_machine_cfg_t;

typedef struct {
    uint16_t pole_pairs;
    iq_t rs_iq;                 /* stator resistance r_s, pu */
    dtc_pm_machine_cfg_t pm;    /* law DTC_LAW_PM_DTC */
    dtc_im_machine_cfg_t im;    /* law DTC_LAW_IM_DTC */
} dtc_machine_cfg_t;

/* Flux estimator and the corrections of the voltage it integrates. */
typedef struct {
    uint16_t estimator;     /* enum dtc_estimator */
    uint16_t compensation;  /* enum dtc_compensation */

    /* Voltage model (flux_est.h): psi += k_in*(v - r_s*i + v_f) - k_leak*psi,
     * the exact (zero-order-hold) discretisation of the low-pass 1/(s + w_c) that replaces the
     * integrator of Hoang eqs. 15-16 / Casadei eq. 1: k_leak = 1 - exp(-w_c*Ts),
     * k_in = k_leak / (w_c/w_base). */
    q31_t k_in_q31;
    q31_t k_leak_q31;

    /* PM start-up and hand-over (voltage model only; dtc.c step 3). Below handover_speed_iq the
     * drive runs on the current model (Hoang eqs. 8-9, encoder) and the voltage model's low-pass
     * state is overwritten with that flux every period; once |measured speed| exceeds
     * handover_speed_iq the voltage model integrates on from that state (bumpless: the estimate
     * is continuous at the hand-over); it falls back to the current model when |speed| drops
     * below handover_speed_iq - handover_hyst_iq. Electrical speed, pu; handover_speed_iq = 0:
     * no hand-over, the voltage model runs from standstill (seeded once after a reset). */
    iq_t handover_speed_iq;   /* >= 0 */
    iq_t handover_hyst_iq;    /* 0 <= hyst <= handover_speed_iq */

    /* Actuation-delay compensation (PM law, dtc.c dtc_predict): the vector chosen at step k acts
     * in period k+1, so the comparators and the sector work on the flux and torque predicted for
     * the start of period k+1 from the vector already committed for period k. */
    uint16_t delay_comp;      /* 1: on (default), 0: comparators on the estimate at k */
    /* Dead-time compensation of the reconstructed voltage (dtc_deadtime; Casadei sec. 10.5: its
     * drive compensated the dead time). */
    uint16_t deadtime_comp;   /* 1: on, 0: off */
    uint16_t polarity_mid;    /* 1: the drop compensation of period [k-1, k] takes the current
                               * polarity from the period's mean current (i(k-1) + i(k))/2 and the
                               * dead-time compensation from the current at the switching instant
                               * i(k-1); 0: both from the sample i(k) */
    uint16_t lpf_comp;        /* voltage model: 1 = gain/phase correction of the low-pass with the
                               * measured speed (lpfcorr.h), 0 = the low-pass output as it is */
    iq_t wc_pu_iq;            /* the low-pass cut-off w_c / w_base (> 0 when lpf_comp) */
    iq_t lpf_wmin_iq;         /* the correction's speed floor, pu (> 0 when lpf_comp; 2 w_c) */
    uint16_t dc_supp;         /* voltage model: 1 = DC-current suppression (dtc.c dtc_dcsupp) */
    iq_t dcs_k_iq;            /* its gain per period over |w|, Ts l_s / 20 in pu (> 0 when dc_supp):
                               * w_d = |w| / 20 */
    iq_t vmid_g_iq;           /* FSTP mid-point regulation (dtc_dcsupp): phase-A DC current demanded
                               * per volt of mid-point deviation, 2 C w_m in pu (>= 0; 0 = off) */
    iq_t vmid_beta_s_iq;      /* FSTP restoring mid-point reconstruction (dtc.c dtc_vmid_beta):
                               * beta = min(2^-DTC_VMID_BETA_MAX_LOG2, (s w)^2), w the measured
                               * electrical speed in pu; s = sqrt(k) in pu (>= 0; 0 = off) */

    /* IM improved estimator (Casadei eq. 20, section 10.2): Ts/tau = k_lo below |w| = w_lo,
     * k_hi above w_hi, linear in between with the host's slope (im_est.h). */
    q31_t im_k_lo_q31;
    q31_t im_k_hi_q31;
    iq_t im_w_lo_iq;
    iq_t im_w_hi_iq;
    q31_t im_k_slope_q31;
} dtc_est_cfg_t;

/* Switching: tables, comparators, scheme, and the IM flux weakening (which acts on the flux
 * reference from the table's output). */
typedef struct {
    uint16_t sstp_table;    /* enum dtc_sstp_table (SSTP; the FSTP has Hoang Table II only) */
    uint16_t scheme;        /* enum dtc_scheme */
    /* Hysteresis bands (full widths, Hoang eqs. 13-14: the thresholds are +-band/2), pu; >= 0. */
    iq_t flux_band_iq;
    iq_t torque_band_iq;
    iq_t im_table_speed_iq; /* DTC_ST_SPEED: |speed| at which ST-D hands over to ST-A, pu */
    /* IM flux weakening (Casadei section 12, im_fw.h). */
    uint16_t im_fw_on;         /* 1: on */
    uint16_t im_fw_window;     /* N control periods per decision, >= 20 (section 12.3) */
    iq_t im_fw_step_down_iq;
    iq_t im_fw_step_up_iq;
    iq_t im_fw_psi_min_iq;
    iq_t im_fw_inv_psi_rated_iq; /* 1 / (the stator-flux reference), pu */
    iq_t im_fw_kt_iq;          /* k_T of eq. 34, pu torque per pu flux squared */
    /* IM stator-flux vector control (scheme DTC_SCHEME_SFVC, Casadei sections 10.3-10.5). The
     * SVM carrier period is the control period Ts (one centred pulse per leg per period,
     * hal.h), so the carrier frequency is 1/Ts. */
    uint16_t svm_mode;         /* enum svm_mode (svm.h): 0 symmetric, 1 two-phase */
    iq_t sfvc_kp_iq;           /* flux-regulator gain K_p of eq. 24 over w_base (pu voltage per
                                * pu flux), in (0, 1/ts_pu]: K_p Ts = 1 removes a flux error in
                                * one period (deadbeat) */
    /* IM direct rotor-flux-oriented control (scheme DTC_SCHEME_DFOC, Casadei section 13,
     * im_dfoc.c); svm_mode as above. */
    iq_t dfoc_kp_iq;           /* current PI proportional gain, pu voltage per pu current (> 0) */
    iq_t dfoc_ki_ts_iq;        /* its integral gain times Ts, pu voltage per pu current (>= 0) */
    iq_t dfoc_id_ref_iq;       /* d-axis current reference phi_r* / m, pu (> 0) */
    iq_t dfoc_iq_per_t_iq;     /* q-axis current per pu torque, l_r / (m phi_r*) (> 0) */
    /* IM DTC with DSVM (scheme DTC_SCHEME_DSVM, Casadei section 11, dsvm.h): the five-level
     * torque comparator's outer band (full width, pu, >= torque_band_iq; hyst5_t): beyond
     * +-band2/2 the tables' levels +-2, between +-torque_band/2 and +-band2/2 the levels +-1. */
    iq_t dsvm_torque_band2_iq;
} dtc_switch_cfg_t;

/* Speed loop, limits and the initial references (the shadow set replaces the references at run
 * time), pu. */
typedef struct {
    uint16_t mode;                /* initial mode (enum dtc_mode); the shadow set may change it */
    uint16_t sensor;              /* enum dtc_speed_sensor */
    uint16_t speed_div;           /* control periods per speed period (10) */
    iq_t speed_k_iq;              /* pu speed per encoder count over ONE speed period */
    uint16_t speed_min_counts;    /* shortest window with at least this many counts is used */
    iq_t kp_iq;                   /* speed PI proportional gain, pu torque per pu speed */
    iq_t ki_ts_iq;                /* integral gain times the speed period, pu torque per pu speed */
    iq_t torque_limit_iq;         /* |T_ref| limit, pu (> 0) */
    q15_t torque_trim_k_q15;      /* torque mode: mean-torque trim gain per control period,
                                   * Ts / tau (0 = off, < 1); see dtc.c step 5 */
    iq_t speed_limit_iq;          /* |speed_ref| limit, pu (> 0) */
    iq_t flux_ref_iq;             /* stator-flux reference */
    iq_t speed_ref_iq;
    iq_t torque_ref_iq;
    /* IM: constant rotor flux (Casadei eq. 19). psir_ref_iq > 0: the stator-flux reference
     * follows the torque reference by eq. 19 for this rotor flux; 0: flux_ref_iq is used. The
     * rotor-flux reference of the improved estimator (eq. 20) is psir_ref_iq, or
     * m/l_s flux_ref_iq when it is 0. */
    iq_t psir_ref_iq;
    iq_t inv_psir_ref_iq;         /* 1 / psir_ref (eq. 19), 0 when psir_ref is 0 */
    iq_t inv_psir_sq_iq;          /* 1 / (rotor-flux reference)^2 (eq. 16 slip), > 0 for the IM */
    /* IM sensorless speed (im_ref.h). */
    iq_t im_gain_w_iq;            /* 2 pi / (65536 T_speed w_base): pu speed of one angle_t LSB
                                   * per speed period T_speed = speed_div Ts (im_ref.h) */
    q31_t im_speed_filt_q31;      /* 1 - exp(-T_speed / T_filter) */
    /* IM start-up (Casadei Fig. 17b): the torque reference is held at zero for this many control
     * periods after a reset while the machine is magnetised (im_dtc.h). > 0. */
    uint16_t im_magn_periods;
    /* IM start-up: stator-flux reference increment per control period of the magnetising ramp
     * (im_dtc.h), IQ pu, > 0. */
    iq_t im_magn_ramp_iq;
    /* IM start-up: Ts / tau_r, tau_r = l_r / r_r (the rotor-flux model of the start-up), Q31. */
    q31_t im_magn_k_q31;
} dtc_speed_cfg_t;

struct dtc_config {
    uint16_t version;          /* DTC_CONFIG_VERSION */
    uint16_t law;              /* enum dtc_law */
    dtc_board_cfg_t board;
    dtc_protect_cfg_t prot;
    dtc_machine_cfg_t machine;
    dtc_est_cfg_t est;
    dtc_switch_cfg_t sw;
    dtc_speed_cfg_t speed;
};

typedef struct dtc_config dtc_config_t;

/* Checks every field of a configuration, part by part (board, protection, machine for the law,
 * estimator, switching, speed). Returns DTC_OK or the first enum dtc_err code found; *field (if
 * field is not null) then names the offending field as "part.field" (e.g. "machine.im.kr_iq"),
 * a string constant; on DTC_OK it is set to "". Pure; used by dtc_init() and the host converter. */
int16_t dtc_config_check(const dtc_config_t *cfg, const char **field);
/* dtc_config_check without the field name. */
int16_t dtc_config_validate(const dtc_config_t *cfg);
/* A law's init: dtc_config_validate, then DTC_ERR_VARIANT when cfg configures another law (law.h
 * dispatches). DTC_ERR_NULL for a null cfg. */
int16_t dtc_config_validate_for(const dtc_config_t *cfg, uint16_t law);

#endif /* DTC_CONFIG_H */
