/*
 * dtc_config_common.h - the configuration's common part: what every control law uses (board,
 * protection, the machine's pole pairs and stator resistance, the flux estimator's low-pass and
 * compensations, the speed loop, limits and references), the enums the configuration selects
 * with, and the error codes of the checks. Each law's own part (dtc_config.h, u) is declared by
 * the law's module (pm_dtc_cfg.h, im_cfg.h), which includes this header.
 */
#ifndef DTC_CONFIG_COMMON_H
#define DTC_CONFIG_COMMON_H

#include <stdint.h>

#include "dtc_base.h"
#include "fixmath.h"

/* Layout version: bump when a field is added, removed or changes meaning. */
#define DTC_CONFIG_VERSION 13U

/* Largest accepted |calibrated - nominal| current offset, ADC counts (5 % of full scale): the
 * app's gates-off calibration (app_core.c) trips beyond it, and the trip level must stay visible
 * with the offset anywhere inside it (dtc_config.c dtc_range_check). */
#define DTC_ADC_OFFSET_TOL_COUNTS 205

/* The control law the application runs: the one choice of machine, law and scheme (app/law.c
 * dispatches on it). Each value's configuration part is a member of dtc_config_t.u. */
enum dtc_law {
    DTC_LAW_PM_DTC = 0,  /* PM brushless AC machine, DTC of Hoang et al. 2011 (dtc.h; u.pm_dtc) */
    DTC_LAW_IM_DTC = 1,  /* induction machine, Casadei et al. 2006: switching-table DTC
                          * (sections 4-8; im_dtc.h; u.im) */
    DTC_LAW_IM_DSC = 2,  /* IM: Direct Self Control (Casadei section 9, dsc.h; u.im) */
    DTC_LAW_IM_SFVC = 3, /* IM: stator-flux vector control with SVM at a constant switching
                          * frequency (Casadei sections 10.3-10.5, Fig. 18; im_sfvc.c; u.im) */
    DTC_LAW_IM_DFOC = 4, /* IM: direct rotor-flux-oriented control, PI current regulators in the
                          * rotor-flux frame, SVM (Casadei section 13; im_dfoc.c; u.im) */
    DTC_LAW_IM_DSVM = 5, /* IM: DTC with Discrete Space Vector Modulation, three equal
                          * sub-intervals per period (Casadei section 11; dsvm.h, im_dsvm.c; u.im) */
    DTC_LAW_PM_ITC = 6,  /* PM machine: indirect torque control, the current-controlled drive Hoang
                          * et al. set beside DTC (Figs. 5-8 (a)); itc.h; u.pm_itc */
    DTC_LAW_COUNT = 7
};

/* The tag each law's part of the configuration (dtc_config_t.u) starts with: the law's check
 * refuses a part whose tag is not its own (DTC_ERR_PART), so a configuration whose part was
 * written for another law (or not at all) never reaches the law. Arbitrary constants, none 0. */
#define DTC_PART_PM_DTC 0x5044U /* "PD": dtc_pm_dtc_cfg_t */
#define DTC_PART_IM 0x494DU     /* "IM": dtc_im_cfg_t */
#define DTC_PART_PM_ITC 0x5049U /* "PI": dtc_pm_itc_cfg_t */

/* The case labels of the induction-machine laws, the ones dtc_law_is_im accepts: one module
 * (im_dtc.h) runs them all on one configuration part (u.im), so a dispatch on the law that does
 * the same for all five writes `DTC_LAW_IM_CASES: ...;`. */
#define DTC_LAW_IM_CASES                                                                           \
    case DTC_LAW_IM_DTC:                                                                           \
    case DTC_LAW_IM_DSC:                                                                           \
    case DTC_LAW_IM_SFVC:                                                                          \
    case DTC_LAW_IM_DFOC:                                                                          \
    case DTC_LAW_IM_DSVM

/* 1 for the induction-machine laws (their part is u.im). */
static inline uint16_t dtc_law_is_im(uint16_t law)
{
    return (uint16_t)(law >= (uint16_t)DTC_LAW_IM_DTC && law <= (uint16_t)DTC_LAW_IM_DSVM ? 1U : 0U);
}

enum dtc_topology {
    DTC_TOPO_SSTP = 0, /* six-switch three-phase inverter (Hoang Fig. 1a, Casadei) */
    DTC_TOPO_FSTP = 1  /* four-switch three-phase: phase A on the capacitor mid-point (Hoang Fig. 1b) */
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
    DTC_COMP_FSTP_PROPOSED = 3, /* FSTP, Hoang Table VI with V_CE, V_d, plus the R_on terms (37-38) */
    DTC_COMP_SSTP_PROPOSED = 4  /* SSTP, Hoang Table III per leg with V_CE and V_d (the device that
                                 * conducts: the transistor of the leg's on switch or the diode of
                                 * the other), plus the R_on terms of eqs. 24-25 */
};

enum dtc_sstp_table {
    DTC_ST_BASIC = 0, /* Casadei Table 1, three-level torque comparator */
    DTC_ST_A = 1,     /* Casadei Table 3, two-level torque comparator */
    DTC_ST_B = 2,
    DTC_ST_C = 3,
    DTC_ST_D = 4,
    DTC_ST_SPEED = 5  /* IM only: Casadei section 8, ST-D below im_table_speed_iq, ST-A above */
};

enum dtc_speed_sensor {
    DTC_SPEED_ENCODER = 0, /* speed from the encoder counts (speed_meas.h) */
    DTC_SPEED_NONE = 1     /* IM only: rotor-flux angular speed minus the slip of Casadei eq. 16 */
};

enum dtc_mode {
    DTC_MODE_SPEED = 0, /* speed PI (every speed_div-th step) produces the torque reference */
    DTC_MODE_TORQUE = 1 /* the torque reference comes straight from the shadow set */
};

/* Error codes of the configuration checks and the laws' init (0 = accepted). Stable numbers: the
 * app reports them as its fault reason; the checks also name the field. */
enum dtc_err {
    DTC_OK = 0,
    DTC_ERR_NULL = -1,         /* null controller or configuration pointer */
    DTC_ERR_VERSION = -2,      /* version field is not DTC_CONFIG_VERSION */
    DTC_ERR_VARIANT = -3,      /* law, topology, estimator, table, sensor or mode out of range or
                                * not meant for the law, or a law not linked into the image */
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
    DTC_ERR_DCSUPP = -24,      /* dc_supp not 0/1, its gain not > 0 with it on, mid-point gains < 0
                                * (ITC: the mid-point filter gain not in (0, 1) with its gain on) */
    DTC_ERR_SVM = -25,         /* SFVC / DFOC: modulation out of range, flux-regulator gain K_p
                                * not in (0, 1/Ts], DFOC current-loop gains or references not > 0;
                                * ITC: current-regulator gains or 1/psi_m not > 0 */
    DTC_ERR_FAULTDET = -26,    /* fault detection: a level < 0, the current-sum check without
                                * three current sensors */
    DTC_ERR_RECONFIG = -27,    /* post-fault configuration (app_core_set_reconfig) not the FSTP
                                * of the same PM drive, or the drive cannot be reconfigured */
    DTC_ERR_PART = -28,        /* the law's part of the configuration (dtc_config_t.u) is not that
                                * law's: its tag (part) is another law's or none; a parameter row
                                * (dtc_params.h) of a part the configuration's law has not */
    DTC_ERR_READONLY = -29     /* a parameter derived from others or fixed by the board
                                * (DTC_PARAM_RO): written only by the host converter */
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
    iq_t v_f_iq;   /* equal device/diode drop V_f (SSTP [29] and Hoang Table V) */
    iq_t v_ce_iq;  /* switching-device forward drop V_CE (Hoang Table VI) */
    iq_t v_d_iq;   /* free-wheeling diode forward drop V_d (Hoang Table VI) */
    iq_t r_on_iq;  /* on-state resistance R_on (Hoang eqs. 20, 24-25, 37-38) */

    /* Encoder: theta_e = count * enc_gain + enc_offset. */
    uint16_t enc_counts;       /* 4 * lines (quadrature), counts per mechanical turn */
    uint32_t enc_gain_q16;     /* electrical angle LSB per count, unsigned Q16: 65536*p/enc_counts */
    angle_t enc_offset;        /* electrical angle at count 0 (encoder-to-magnet alignment) */
    uint16_t enc_reversed;     /* 1: the encoder counts down when the inverter's field turns forward (a
                                * reversed encoder or two motor leads exchanged): the app reads
                                * enc_counts - 1 - count (app_enc_reverse) before anything uses it */

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
    /* Fault detection (app_core.c check_faults), each 0 = off. */
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


/* Machine, the part every law uses; the rest of the machine's model is the law's (u). */
typedef struct {
    uint16_t pole_pairs;
    iq_t rs_iq;                 /* stator resistance r_s, pu */
} dtc_machine_cfg_t;

/* Flux estimator: the voltage model's low-pass and the corrections of the voltage it integrates,
 * as every law's voltage model uses them. */
typedef struct {
    uint16_t estimator;     /* enum dtc_estimator (which values a law takes: its check) */
    uint16_t compensation;  /* enum dtc_compensation */

    /* Voltage model (flux_est.h): psi += k_in*(v - r_s*i + v_f) - k_leak*psi,
     * the exact (zero-order-hold) discretisation of the low-pass 1/(s + w_c) that replaces the
     * integrator of Hoang eqs. 15-16 / Casadei eq. 1: k_leak = 1 - exp(-w_c*Ts),
     * k_in = k_leak / (w_c/w_base). */
    q31_t k_in_q31;
    q31_t k_leak_q31;

    /* Dead-time compensation of the reconstructed voltage (vrec.h deadtime_error; Casadei sec. 10.5: its
     * drive compensated the dead time). */
    uint16_t deadtime_comp;   /* 1: on, 0: off */
} dtc_est_cfg_t;

/* Switching table and hysteresis comparators of the table-driven laws (PM DTC, the IM laws): a
 * block's parameters, a member of each such law's part. */
typedef struct {
    uint16_t sstp_table;    /* enum dtc_sstp_table (SSTP; the FSTP has Hoang Table II only) */
    /* Hysteresis bands (full widths, Hoang eqs. 13-14: the thresholds are +-band/2), pu; >= 0. */
    iq_t flux_band_iq;
    iq_t torque_band_iq;
} dtc_table_cfg_t;

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
                                   * Ts / tau (0 = off, < 1); see dtc.c dtc_torque_trim */
    iq_t speed_limit_iq;          /* |speed_ref| limit, pu (> 0) */
    iq_t flux_ref_iq;             /* stator-flux reference */
    iq_t speed_ref_iq;
    iq_t torque_ref_iq;
    iq_t speed_bw_iq;             /* the speed loop's crossover the host designed kp, ki for, pu of
                                   * w_base (kp = J bw, ki = kp bw / 4: tools/config); 0 = the gains
                                   * were given, not designed. Read by the identification's apply,
                                   * which designs them again on the identified J (app_ident_apply.c) */
} dtc_speed_cfg_t;

/* The common part's parameters, once (dtc_param.h: X(id, path, fmt, qty, lo, hi, err, flags,
 * text)). The ranges are what each field can ever be; the relations between fields and the
 * conditions on a law are checked in code (dtc_config.c and the laws' checks). */
#define DTC_I32_MAX 2147483647L
#define DTC_I32_MIN (-2147483647L - 1L)
#define DTC_PARAMS_COMMON(X)                                                                       \
    X(1, version, U16, NONE, DTC_CONFIG_VERSION, DTC_CONFIG_VERSION, DTC_ERR_VERSION, DTC_PARAM_RO,\
      "layout version of the configuration (DTC_CONFIG_VERSION)")                                  \
    X(2, law, U16, NONE, 0, DTC_LAW_COUNT - 1, DTC_ERR_VARIANT, DTC_PARAM_RO,                      \
      "control law (enum dtc_law): 0 PM DTC, 1 IM DTC, 2 IM DSC, 3 IM SFVC, 4 IM DFOC, 5 IM DSVM, 6 PM ITC")\
    X(3, board.v_base_mv, U32, NONE, 1, DTC_I32_MAX, DTC_ERR_BASE, DTC_PARAM_RO, "voltage base V_b, mV")\
    X(4, board.i_base_ma, U32, NONE, 1, DTC_I32_MAX, DTC_ERR_BASE, DTC_PARAM_RO, "current base I_b, mA")\
    X(5, board.w_base_mrad_s, U32, NONE, 1, DTC_I32_MAX, DTC_ERR_BASE, DTC_PARAM_RO,               \
      "electrical speed base w_b, mrad/s")                                                         \
    X(6, board.topology, U16, NONE, 0, DTC_TOPO_FSTP, DTC_ERR_VARIANT, DTC_PARAM_RO,               \
      "inverter: 0 six-switch (SSTP), 1 four-switch (FSTP)")                                       \
    X(7, board.fstp_vmid_measured, U16, NONE, 0, 1, DTC_ERR_VARIANT, DTC_PARAM_RO,                 \
      "1: the FSTP's capacitor mid-point voltage is measured")                                     \
    X(8, board.ts_pu_iq, IQ, TIME, 1, DTC_I32_MAX, DTC_ERR_DELAY, DTC_PARAM_RO, "control period T_s")\
    X(9, board.td_ts_q15, Q15, RATIO, 0, 16383, DTC_ERR_DEADTIME, 0U,                              \
      "inverter dead time over the control period, T_d / T_s, below 1/2")                          \
    X(10, board.v_f_iq, IQ, V, 0, DTC_I32_MAX, DTC_ERR_DROP, 0U,                                   \
      "equal device and diode drop V_f (SSTP ref. [29], Hoang Table V)")                           \
    X(11, board.v_ce_iq, IQ, V, 0, DTC_I32_MAX, DTC_ERR_DROP, 0U, "switching-device forward drop V_CE (Hoang Table VI)")\
    X(12, board.v_d_iq, IQ, V, 0, DTC_I32_MAX, DTC_ERR_DROP, 0U, "diode forward drop V_d (Hoang Table VI)")\
    X(13, board.r_on_iq, IQ, Z, 0, DTC_I32_MAX, DTC_ERR_DROP, 0U, "device on-state resistance R_on (Hoang eqs. 37-38)")\
    X(14, board.enc_counts, U16, NONE, 4, 65535, DTC_ERR_ENCODER, DTC_PARAM_RO,                    \
      "encoder counts per mechanical turn (4 x lines)")                                            \
    X(15, board.enc_gain_q16, U32, NONE, 1, DTC_I32_MAX, DTC_ERR_ENCODER, DTC_PARAM_RO | DTC_PARAM_STORED,\
      "electrical angle per count, Q16 angle LSB: 65536 p / counts (at least 3 counts per electrical turn)")\
    X(16, board.enc_offset, ANGLE, ANGLE, 0, 65535, DTC_ERR_ENCODER, 0U,                           \
      "electrical angle at encoder count 0 (encoder-to-magnet offset)")                            \
    X(27, board.enc_reversed, U16, NONE, 0, 1, DTC_ERR_ENCODER, DTC_PARAM_RO | DTC_PARAM_STORED,\
      "1: the count runs down for forward rotation of the field; the app reads counts - 1 - count")\
    X(17, board.adc_i_gain_iq, IQ, A_COUNT, 1, DTC_I32_MAX, DTC_ERR_ADC, DTC_PARAM_RO, "phase current per ADC count")\
    X(18, board.adc_i_offset[0], U16, NONE, 0, 4095, DTC_ERR_ADC, 0U, "phase A current ADC count at zero current")\
    X(19, board.adc_i_offset[1], U16, NONE, 0, 4095, DTC_ERR_ADC, 0U, "phase B current ADC count at zero current")\
    X(20, board.adc_i_offset[2], U16, NONE, 0, 4095, DTC_ERR_ADC, 0U, "phase C current ADC count at zero current")\
    X(21, board.adc_vdc_gain_iq, IQ, V_COUNT, 1, DTC_I32_MAX, DTC_ERR_ADC, DTC_PARAM_RO, "DC-link voltage per ADC count")\
    X(22, board.adc_vdc_offset, U16, NONE, 0, 4095, DTC_ERR_ADC, 0U, "DC-link ADC count at zero voltage")\
    X(23, board.adc_vmid_gain_iq, IQ, V_COUNT, 1, DTC_I32_MAX, DTC_ERR_ADC, DTC_PARAM_RO,          \
      "mid-point voltage per ADC count")                                                           \
    X(24, board.adc_vmid_offset, U16, NONE, 0, 4095, DTC_ERR_ADC, 0U, "mid-point ADC count at zero voltage")\
    X(25, board.vmid_cal, U16, NONE, 0, 1, DTC_ERR_POLARITY, 0U,                                   \
      "1: the mid-point sensor is calibrated against V_dc / 2 before the drive starts")            \
    X(26, board.i_sensors3, U16, NONE, 0, 1, DTC_ERR_FAULTDET, DTC_PARAM_RO,                       \
      "1: all three phase currents are measured, 0: two")                                          \
    X(30, prot.i_trip_iq, IQ, A, 1, DTC_I32_MAX, DTC_ERR_LIMIT, 0U, "phase-current trip level")    \
    X(31, prot.vdc_max_iq, IQ, V, 1, DTC_I32_MAX, DTC_ERR_LIMIT, 0U, "DC-link over-voltage trip level")\
    X(32, prot.vdc_min_iq, IQ, V, 0, DTC_I32_MAX, DTC_ERR_LIMIT, 0U,                               \
      "DC-link under-voltage trip level, below the over-voltage one")                              \
    X(33, prot.i_lim_iq, IQ, A, 0, DTC_I32_MAX, DTC_ERR_ILIM, 0U,                                  \
      "current limit of the vector override, below the trip; 0 = off")                             \
    X(34, prot.stall_speed_periods, U16, NONE, 1, 65535, DTC_ERR_SPEED, 0U,                        \
      "stall: speed periods at the torque limit with no shrinking speed error")                    \
    X(35, prot.i_hold_iq, IQ, A, 0, DTC_I32_MAX, DTC_ERR_ILIM, 0U,                                 \
      "largest rotor-hold current during the mid-point calibration, below the trip; 0 = gates off")\
    X(36, prot.i_sum_max_iq, IQ, A, 0, DTC_I32_MAX, DTC_ERR_FAULTDET, 0U,                          \
      "three sensors: largest |i_a + i_b + i_c| before a sensor fault; 0 = off")                   \
    X(37, prot.leg_i_min_iq, IQ, A, 0, DTC_I32_MAX, DTC_ERR_FAULTDET, 0U,                          \
      "open phase: least |i| at which a phase that stays near zero is an open leg; 0 = off")       \
    X(38, prot.enc_freeze_speed_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_FAULTDET, 0U,                   \
      "lost encoder: speed above which a count that does not move is a fault; 0 = off")            \
    X(39, prot.relay_periods, U16, NONE, 0, 65535, DTC_ERR_RECONFIG, 0U,                           \
      "control periods from the relay command until the phase is on the mid-point")                \
    X(40, prot.i_plaus, U16, NONE, 0, 1, DTC_ERR_FAULTDET, 0U,                                     \
      "1: measured currents checked against the law's prediction (stuck sensor)")                  \
    X(41, prot.overspeed_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_LIMIT, 0U,                             \
      "overspeed trip, electrical speed above the speed limit; 0 = off")                           \
    X(45, machine.pole_pairs, U16, NONE, 1, 65535, DTC_ERR_ENCODER, DTC_PARAM_RO | DTC_PARAM_STORED, "pole pairs p")\
    X(46, machine.rs_iq, IQ, Z, 0, DTC_I32_MAX, DTC_ERR_MACHINE, 0U, "stator resistance R_s")      \
    X(50, est.estimator, U16, NONE, 0, DTC_EST_IMPROVED, DTC_ERR_VARIANT, 0U,                      \
      "flux estimator: 0 voltage model, 1 current model (PM), 2 improved (IM, Casadei eqs. 20-22)")\
    X(51, est.compensation, U16, NONE, 0, DTC_COMP_SSTP_PROPOSED, DTC_ERR_COMPENSATION, 0U,        \
      "voltage-drop compensation: 0 none, 1 SSTP ref. [29], 2 FSTP Hoang Table V, 3 FSTP Hoang Table VI, 4 SSTP Hoang Table III")\
    X(52, est.k_in_q31, Q31, RATIO, 1, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,                \
      "voltage model's low-pass input gain per period")                                            \
    X(53, est.k_leak_q31, Q31, RATIO, 1, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,              \
      "voltage model's low-pass leak per period, 1 - exp(-w_c T_s)")                               \
    X(54, est.deadtime_comp, U16, NONE, 0, 1, DTC_ERR_DEADTIME, 0U,                                \
      "1: the reconstructed voltage is corrected for the dead time")                               \
    X(60, speed.mode, U16, NONE, 0, DTC_MODE_TORQUE, DTC_ERR_VARIANT, DTC_PARAM_LIVE,              \
      "initial mode: 0 speed (PI), 1 torque")                                                      \
    X(61, speed.sensor, U16, NONE, 0, DTC_SPEED_NONE, DTC_ERR_VARIANT, 0U,                         \
      "speed: 0 encoder, 1 none (IM, from the flux)")                                              \
    X(62, speed.speed_div, U16, NONE, 1, 65535, DTC_ERR_SPEED, DTC_PARAM_RO, "control periods per speed period")\
    X(63, speed.speed_k_iq, IQ, PU, 1, DTC_I32_MAX, DTC_ERR_SPEED, DTC_PARAM_RO,                   \
      "pu speed of one encoder count per speed period")                                            \
    X(64, speed.speed_min_counts, U16, NONE, 1, 65535, DTC_ERR_SPEED, 0U,                          \
      "speed window: the shortest with at least this many counts")                                 \
    X(65, speed.kp_iq, IQ, T_W, 0, DTC_I32_MAX, DTC_ERR_PI, DTC_PARAM_LIVE, "speed PI proportional gain")\
    X(66, speed.ki_ts_iq, IQ, T_W, 0, DTC_I32_MAX, DTC_ERR_PI, DTC_PARAM_LIVE,                     \
      "speed PI integral gain times the speed period")                                             \
    X(67, speed.torque_limit_iq, IQ, T, 1, DTC_I32_MAX, DTC_ERR_PI, 0U, "torque reference limit")  \
    X(68, speed.torque_trim_k_q15, Q15, RATIO, 0, 32767, DTC_ERR_PI, 0U,                           \
      "torque mode: mean-torque trim gain per period, T_s / tau; 0 = off")                         \
    X(69, speed.speed_limit_iq, IQ, W, 1, DTC_I32_MAX, DTC_ERR_REFERENCE, 0U, "speed reference limit (electrical)")\
    X(70, speed.flux_ref_iq, IQ, PSI, 1, DTC_I32_MAX, DTC_ERR_REFERENCE, 0U, "stator-flux reference")\
    X(71, speed.speed_ref_iq, IQ, W, DTC_I32_MIN, DTC_I32_MAX, DTC_ERR_REFERENCE, DTC_PARAM_LIVE,  \
      "speed reference (electrical), within the speed limit")                                      \
    X(72, speed.torque_ref_iq, IQ, T, DTC_I32_MIN, DTC_I32_MAX, DTC_ERR_REFERENCE, DTC_PARAM_LIVE, \
      "torque reference, within the torque limit")                                                 \
    X(73, speed.speed_bw_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_PI, DTC_PARAM_RO,                      \
      "speed PI's design crossover (kp = J bw, ki = kp bw / 4); 0 = the gains given")

/* A check's refusal: the code, and *f pointed at the field's name ("part.field", a string
 * constant). For the checks of dtc_config.c and of the laws (their *_check functions), each of
 * which has `const char **f` in scope and returns int16_t. */
#define DTC_REFUSE(cond, code, name) \
    do {                             \
        if (cond) {                  \
            *f = (name);             \
            return (code);           \
        }                            \
    } while (0)

#endif /* DTC_CONFIG_COMMON_H */
