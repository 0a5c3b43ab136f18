/*
 * im_cfg.h - the induction-machine laws' part of the configuration (dtc_config_t.u.im, laws
 * DTC_LAW_IM_DTC, _DSC, _SFVC, _DFOC, _DSVM; the law: im_dtc.h): the machine model, the improved
 * estimator, the switching table and comparators, the flux weakening, the rotor-flux reference
 * and start-up, and each scheme's own settings in its sub-struct. Per-unit Q formats
 * (dtc_base.h); checked by im_dtc_check (im_dtc_check.c).
 */
#ifndef IM_CFG_H
#define IM_CFG_H

#include <stdint.h>

#include "dtc_config_common.h"

/* Induction machine (Casadei appendix, T model), pu. Every ratio the law needs is precomputed by
 * the host (no division in the ISR). */
typedef struct {
    iq_t rr_iq;          /* rotor resistance r_r (Casadei eq. 16) */
    iq_t sigma_ls_iq;    /* sigma l_s (Casadei eq. 21) */
    iq_t sigma_lr_iq;    /* sigma l_r (Casadei eq. 19) */
    iq_t kr_iq;          /* l_r / m (Casadei eq. 21), > 0 */
    iq_t ks_iq;          /* l_s / m (Casadei eq. 19), > 0 */
    iq_t inv_ks_iq;      /* m / l_s: rotor flux of a stator flux at no load (start-up) */
    iq_t m_iq;           /* magnetising inductance m, pu (start-up rotor-flux model), > 0 */
} dtc_im_machine_cfg_t;

/* Improved estimator (Casadei eq. 20, section 10.2): Ts/tau = k_lo below |w| = w_lo, k_hi above
 * w_hi, linear in between with the host's slope (im_est.h). */
typedef struct {
    q31_t k_lo_q31;
    q31_t k_hi_q31;
    iq_t w_lo_iq;
    iq_t w_hi_iq;
    q31_t k_slope_q31;
} dtc_im_est_cfg_t;

/* Flux weakening (Casadei section 12, im_fw.h). */
typedef struct {
    uint16_t on;             /* 1: on */
    uint16_t window;         /* N control periods per decision, >= 20 (section 12.3) */
    iq_t step_down_iq;
    iq_t step_up_iq;
    iq_t psi_min_iq;
    iq_t inv_psi_rated_iq;   /* 1 / (the stator-flux reference), pu */
    iq_t kt_iq;              /* k_T of Casadei eq. 34, pu torque per pu flux squared */
} dtc_im_fw_cfg_t;

/* Rotor-flux reference, sensorless speed and start-up. */
typedef struct {
    /* Constant rotor flux (Casadei eq. 19). psir_ref_iq > 0: the stator-flux reference follows
     * the torque reference by Casadei eq. 19 for this rotor flux; 0: speed.flux_ref_iq is used. The
     * rotor-flux reference of the improved estimator (Casadei eq. 20) is psir_ref_iq, or
     * m/l_s flux_ref_iq when it is 0. */
    iq_t psir_ref_iq;
    iq_t inv_psir_ref_iq;    /* 1 / psir_ref (Casadei eq. 19), 0 when psir_ref is 0 */
    iq_t inv_psir_sq_iq;     /* 1 / (rotor-flux reference)^2 (Casadei eq. 16 slip), > 0 */
    /* Sensorless speed (im_ref.h). */
    iq_t gain_w_iq;          /* 2 pi / (65536 T_speed w_base): pu speed of one angle_t LSB per
                              * speed period T_speed = speed_div Ts (im_ref.h) */
    q31_t speed_filt_q31;    /* 1 - exp(-T_speed / T_filter) */
    /* Start-up (Casadei Fig. 17b): the torque reference is held at zero for this many control
     * periods after a reset while the machine is magnetised (im_dtc.h). > 0. */
    uint16_t magn_periods;
    /* Start-up: stator-flux reference increment per control period of the magnetising ramp
     * (im_dtc.h), IQ pu, > 0. */
    iq_t magn_ramp_iq;
    /* Start-up: Ts / tau_r, tau_r = l_r / r_r (the rotor-flux model of the start-up), Q31. */
    q31_t magn_k_q31;
    /* Encoder plausibility (speed.sensor = DTC_SPEED_ENCODER, im_dtc.h): the largest credible
     * difference, pu electrical speed, between the sensorless speed (the rotor-flux angular speed
     * minus the slip of Casadei eq. 16) and the encoder's speed through the same filter; the host
     * derives it from the slip at the torque limit and the speed period's delay at the largest
     * acceleration. 0 = off; >= 0. */
    iq_t enc_plaus_iq;
    /* The rotor resistance tracked on line (im_sup.h, encoder and encoder plausibility): 1 = the
     * slip of Casadei eq. 16 uses the tracked r_r and the estimator's r_s follows it by the same
     * ratio; 0 = tracked and reported only. 0 or 1. */
    uint16_t rr_track;
    /* Casadei eq. 20's reference at low speed from the rotor-flux current model (im_sup.h; the
     * encoder and the improved estimator, not DSVM): 1 = on, 0 = the paper's reference at every
     * speed. 0 or 1. */
    uint16_t cm_ref;
} dtc_im_ref_cfg_t;

/* Stator-flux vector control (DTC_LAW_IM_SFVC, Casadei sections 10.3-10.5). The SVM carrier
 * period is the control period Ts (one centred pulse per leg per period, hal.h), so the carrier
 * frequency is 1/Ts. */
typedef struct {
    iq_t kp_iq;              /* flux-regulator gain K_p of Casadei eq. 24 over w_base (pu voltage
                              * per pu flux), in (0, 1/ts_pu]: K_p Ts = 1 removes a flux error in
                              * one period (deadbeat) */
} dtc_im_sfvc_cfg_t;

/* Direct rotor-flux-oriented control (DTC_LAW_IM_DFOC, Casadei section 13, im_dfoc.c). */
typedef struct {
    iq_t kp_iq;              /* current PI proportional gain, pu voltage per pu current (> 0) */
    iq_t ki_ts_iq;           /* its integral gain times Ts, pu voltage per pu current (>= 0) */
    iq_t id_ref_iq;          /* d-axis current reference phi_r* / m, pu (> 0) */
    iq_t iq_per_t_iq;        /* q-axis current per pu torque, l_r / (m phi_r*) (> 0) */
} dtc_im_dfoc_cfg_t;

/* DTC with DSVM (DTC_LAW_IM_DSVM, Casadei section 11, dsvm.h). */
typedef struct {
    iq_t torque_band2_iq;    /* the five-level torque comparator's outer band (full width, pu,
                              * >= sw.torque_band_iq; hyst5_t): beyond +-band2/2 the tables'
                              * levels +-2, between +-torque_band/2 and +-band2/2 the levels +-1 */
} dtc_im_dsvm_cfg_t;

/* What the host converter designed rows from (tools/config law_im_si.c), held so that the
 * identification's apply designs those rows again on the identified machine (app_ident_apply.c
 * derive_im_design); written by the converter only, each 0 where it designed nothing. */
typedef struct {
    iq_t vdc_iq;             /* the nominal DC link (inverter.vdc_v) the current step dI and the
                              * DSVM band are designed on, pu; 0 = neither designed here */
    iq_t torque_limit_iq;    /* the configured torque limit (torque_limit_nm) before the current
                              * limit's clamp (speed.torque_limit_iq is the smaller of the two), pu
                              * of the torque base of machine.pole_pairs; 0 = not held */
    iq_t magn_wait_iq;       /* ln(1 / (1 - magn_frac)): the start-up's wait after the flux ramp,
                              * in rotor time constants; 0 = not held */
    uint16_t derived;        /* bits 0-1: n of the current limit derived as i_trip - n dI
                              * (dtc_ilim_default_a: 1 with delay_comp, else 2; 0 = the limit
                              * given or off); bit 2: the DSVM outer band derived (Casadei eqs.
                              * 12, 15), not given */
} dtc_im_design_cfg_t;

/* u.im.design.derived's bits */
#define DTC_IM_DESIGN_ILIM_N 3U
#define DTC_IM_DESIGN_BAND2 4U

typedef struct {
    uint16_t part;               /* DTC_PART_IM */
    dtc_im_machine_cfg_t machine;
    dtc_im_est_cfg_t est;        /* with est.estimator = DTC_EST_IMPROVED */
    dtc_table_cfg_t sw;          /* sstp_table up to DTC_ST_SPEED */
    iq_t table_speed_iq;         /* DTC_ST_SPEED: |speed| at which ST-D hands over to ST-A, pu */
    dtc_im_fw_cfg_t fw;
    dtc_im_ref_cfg_t ref;
    uint16_t svm_mode;           /* SFVC, DFOC: enum svm_mode (svm.h), 0 symmetric, 1 two-phase */
    dtc_im_sfvc_cfg_t sfvc;
    dtc_im_dfoc_cfg_t dfoc;
    dtc_im_dsvm_cfg_t dsvm;
    dtc_im_design_cfg_t design;
} dtc_im_cfg_t;

/* The IM part's parameters, once (dtc_param.h). The machine's values are derived together from
 * R_r, the leakages and M (tools/config law_im_si.c): read-only here; those an identification
 * writes (app_ident_apply.c) are stored with the parameters (DTC_PARAM_STORED). */
#define DTC_PARAMS_IM(X)                                                                                      \
    X(200, u.im.part, U16, NONE, DTC_PART_IM, DTC_PART_IM, DTC_ERR_PART, DTC_PARAM_RO,                        \
      "tag of the IM part (DTC_PART_IM)")                                                                     \
    X(201, u.im.machine.rr_iq, IQ, Z, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, "rotor resistance R_r (Casadei eq. 16)") \
    X(202, u.im.machine.sigma_ls_iq, IQ, L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED,                    \
      "stator transient inductance sigma L_s (Casadei eq. 21)")                                               \
    X(203, u.im.machine.sigma_lr_iq, IQ, L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED,                    \
      "rotor transient inductance sigma L_r (Casadei eq. 19)")                                                \
    X(204, u.im.machine.kr_iq, IQ, RATIO, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, "L_r / M (Casadei eq. 21)") \
    X(205, u.im.machine.ks_iq, IQ, RATIO, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, "L_s / M (Casadei eq. 19)") \
    X(206, u.im.machine.inv_ks_iq, IQ, RATIO, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, "M / L_s")       \
    X(207, u.im.machine.m_iq, IQ, L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, "magnetising inductance M") \
    X(210, u.im.est.k_lo_q31, Q31, RATIO, 0, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,                     \
      "improved estimator's correction gain T_s / tau at low speed (> 0 with it)")                            \
    X(211, u.im.est.k_hi_q31, Q31, RATIO, 0, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,                     \
      "its gain at high speed (> 0 with it)")                                                                 \
    X(212, u.im.est.w_lo_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,                           \
      "speed up to which the low-speed gain applies")                                                         \
    X(213, u.im.est.w_hi_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,                           \
      "speed from which the high-speed gain applies (>= w_lo)")                                               \
    X(214, u.im.est.k_slope_q31, Q31, RATIO, DTC_I32_MIN, DTC_I32_MAX, DTC_ERR_FLUX_EST, DTC_PARAM_RO,         \
      "the gain's slope between the two speeds")                                                              \
    X(220, u.im.sw.sstp_table, U16, NONE, 0, DTC_ST_SPEED, DTC_ERR_VARIANT, 0U,                               \
      "switching table: 0 Casadei Table 1, 1..4 ST-A..ST-D, 5 speed-dependent (sec. 8)")                      \
    X(221, u.im.sw.flux_band_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_BAND, DTC_PARAM_LIVE,                       \
      "flux hysteresis band, full width")                                                                     \
    X(222, u.im.sw.torque_band_iq, IQ, T, 0, DTC_I32_MAX, DTC_ERR_BAND, DTC_PARAM_LIVE,                       \
      "torque hysteresis band, full width")                                                                   \
    X(223, u.im.table_speed_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_VARIANT, 0U,                                   \
      "speed-dependent table: speed at which ST-D hands over to ST-A")                                        \
    X(230, u.im.fw.on, U16, NONE, 0, 1, DTC_ERR_WEAKENING, 0U, "1: flux weakening (Casadei sec. 12)")         \
    X(231, u.im.fw.window, U16, NONE, 0, 65535, DTC_ERR_WEAKENING, 0U,                                        \
      "control periods per flux-reference decision (>= 20 with it on)")                                       \
    X(232, u.im.fw.step_down_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_WEAKENING, 0U, "flux-reference step down")  \
    X(233, u.im.fw.step_up_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_WEAKENING, 0U, "flux-reference step up")      \
    X(234, u.im.fw.psi_min_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_WEAKENING, 0U, "lowest flux reference")       \
    X(235, u.im.fw.inv_psi_rated_iq, IQ, INV_PSI, 0, DTC_I32_MAX, DTC_ERR_WEAKENING, DTC_PARAM_RO,            \
      "1 / the rated stator-flux reference")                                                                  \
    X(236, u.im.fw.kt_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_WEAKENING, DTC_PARAM_RO | DTC_PARAM_STORED,                            \
      "k_T of Casadei eq. 34, torque per flux squared")                                                       \
    X(240, u.im.ref.psir_ref_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_REFERENCE, DTC_PARAM_RO,                    \
      "rotor-flux reference (Casadei eq. 19); 0 = the stator-flux reference")                                 \
    X(241, u.im.ref.inv_psir_ref_iq, IQ, INV_PSI, 0, DTC_I32_MAX, DTC_ERR_REFERENCE, DTC_PARAM_RO,             \
      "1 / the rotor-flux reference")                                                                         \
    X(242, u.im.ref.inv_psir_sq_iq, IQ, PU, 1, DTC_I32_MAX, DTC_ERR_REFERENCE, DTC_PARAM_RO | DTC_PARAM_STORED,                  \
      "1 / the rotor-flux reference squared (Casadei eq. 16 slip)")                                           \
    X(243, u.im.ref.gain_w_iq, IQ, PU, 1, DTC_I32_MAX, DTC_ERR_SPEED, DTC_PARAM_RO,                           \
      "pu speed of one angle LSB per speed period")                                                           \
    X(244, u.im.ref.speed_filt_q31, Q31, RATIO, 1, DTC_I32_MAX, DTC_ERR_SPEED, DTC_PARAM_RO,                  \
      "sensorless speed filter gain per speed period")                                                        \
    X(245, u.im.ref.magn_periods, U16, NONE, 1, 65535, DTC_ERR_STARTUP, DTC_PARAM_RO | DTC_PARAM_STORED,                         \
      "start-up: control periods of the magnetisation")                                                       \
    X(246, u.im.ref.magn_ramp_iq, IQ, PSI, 1, DTC_I32_MAX, DTC_ERR_STARTUP, DTC_PARAM_RO | DTC_PARAM_STORED,                     \
      "start-up: flux-reference ramp per period")                                                             \
    X(247, u.im.ref.magn_k_q31, Q31, RATIO, 1, DTC_I32_MAX, DTC_ERR_STARTUP, DTC_PARAM_RO | DTC_PARAM_STORED,                    \
      "start-up rotor-flux model's gain per period, T_s / tau_r")                                             \
    X(248, u.im.ref.enc_plaus_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_SPEED, DTC_PARAM_RO | DTC_PARAM_STORED,                        \
      "encoder plausibility: largest credible sensorless - encoder speed difference (Casadei eqs. 16, 22); 0 = off") \
    X(249, u.im.ref.rr_track, U16, NONE, 0, 1, DTC_ERR_SPEED, DTC_PARAM_RO,                                  \
      "1: the slip uses the rotor resistance tracked on line and r_s follows it (im_sup.h)")                 \
    X(259, u.im.ref.cm_ref, U16, NONE, 0, 1, DTC_ERR_SPEED, DTC_PARAM_RO,                                    \
      "1: Casadei eq. 20's reference from the rotor-flux current model at low speed (im_sup.h)")             \
    X(250, u.im.svm_mode, U16, NONE, 0, 1, DTC_ERR_SVM, 0U, "SFVC, DFOC: 0 symmetric SVM, 1 two-phase")      \
    X(251, u.im.sfvc.kp_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_SVM, 0U,                                          \
      "SFVC flux-regulator gain K_p of Casadei eq. 24 over w_b, in (0, 1/T_s]")                               \
    X(255, u.im.dfoc.kp_iq, IQ, Z, 0, DTC_I32_MAX, DTC_ERR_SVM, 0U, "DFOC current PI proportional gain")      \
    X(256, u.im.dfoc.ki_ts_iq, IQ, Z, 0, DTC_I32_MAX, DTC_ERR_SVM, 0U, "DFOC current PI integral gain times T_s") \
    X(257, u.im.dfoc.id_ref_iq, IQ, A, 0, DTC_I32_MAX, DTC_ERR_SVM, DTC_PARAM_RO | DTC_PARAM_STORED,                             \
      "DFOC d-axis current reference psi_r* / M")                                                             \
    X(258, u.im.dfoc.iq_per_t_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_SVM, DTC_PARAM_RO | DTC_PARAM_STORED,                          \
      "DFOC q-axis current per unit torque, L_r / (M psi_r*)")                                                \
    X(260, u.im.dsvm.torque_band2_iq, IQ, T, 0, DTC_I32_MAX, DTC_ERR_BAND, DTC_PARAM_LIVE,                    \
      "DSVM five-level torque comparator's outer band, full width (>= the torque band)")           \
    X(261, u.im.design.vdc_iq, IQ, V, 0, DTC_I32_MAX, DTC_ERR_ILIM, DTC_PARAM_RO,                              \
      "the nominal DC link the current step and the DSVM band are designed on; 0 = not designed")            \
    X(262, u.im.design.torque_limit_iq, IQ, T, 0, DTC_I32_MAX, DTC_ERR_PI, DTC_PARAM_RO,                       \
      "the configured torque limit before the current limit's clamp; 0 = not held")                          \
    X(263, u.im.design.magn_wait_iq, IQ, RATIO, 0, DTC_I32_MAX, DTC_ERR_STARTUP, DTC_PARAM_RO,                 \
      "start-up: the wait after the flux ramp in rotor time constants, ln(1 / (1 - magn_frac))")             \
    X(264, u.im.design.derived, U16, NONE, 0, 6, DTC_ERR_ILIM, DTC_PARAM_RO,                                   \
      "bits 0-1: n of the current limit derived as the trip less n current steps (0 = given); bit 2: the DSVM outer band derived")

#endif /* IM_CFG_H */
