/*
 * pm_itc_cfg.h - the PM indirect torque control's part of the configuration (dtc_config_t.u.pm_itc,
 * law DTC_LAW_PM_ITC; the law: itc.h): the machine model, the rotor-frame current regulator, the
 * FSTP mid-point regulation and the observer's low-pass correction. Per-unit Q formats
 * (dtc_base.h, IQ = Q8.24 unless named otherwise); written by tools/config (law_pm_itc_si.c, which
 * derives every value from the configured machine and board) and checked by itc_check (itc_check.c).
 */
#ifndef PM_ITC_CFG_H
#define PM_ITC_CFG_H

#include <stdint.h>

#include "dtc_config_common.h"
#include "pm_dtc_cfg.h" /* dtc_pm_machine_cfg_t: the same machine model as the PM DTC law's */

/* Rotor-frame current regulator (dqpi.h), one PI per axis on the decoupling and back-EMF
 * feed-forward. */
typedef struct {
    iq_t kp_iq;       /* K_p = l_s w_c, pu voltage per pu current; > 0 (range (0, 128)) */
    iq_t ki_ts_iq;    /* K_i Ts = r_s w_c Ts, pu voltage per pu current per control period; > 0
                       * (the tools derive w_c = pi / (9 Ts)) */
    iq_t iq_per_t_iq; /* 1 / psi_m, pu current per pu torque (i_q* = T* / psi_m, Hoang eq. 10 on
                       * i_d = 0); > 0 */
} dtc_itc_cc_cfg_t;

/* FSTP mid-point regulation (itc.h): a DC phase-A current i_a* = g y, y the mid-point deviation
 * low-passed, y += k_f (d - y). Needs the FSTP with the mid-point measured. */
typedef struct {
    iq_t g_iq;        /* g = 2 C w_m, pu current per pu voltage; >= 0, 0 = off */
    iq_t kf_iq;       /* k_f = w_f Ts (w_f = 4 w_m), per control period; in (0, 1) when g > 0 */
} dtc_itc_mid_cfg_t;

/* The observer's low-pass correction (lpfcorr.h), as the PM DTC law's (pm_dtc_cfg.h). */
typedef struct {
    uint16_t lpf_comp;  /* 1 = gain/phase correction of the voltage model's low-pass with the
                         * measured speed, 0 = the low-pass output as it is */
    iq_t wc_pu_iq;      /* the low-pass cut-off w_c / w_base, pu; > 0 when lpf_comp */
    iq_t lpf_wmin_iq;   /* the correction's speed floor (2 w_c), pu; > 0 when lpf_comp */
} dtc_itc_est_cfg_t;

/* The part; the members the step reads every period first. */
typedef struct {
    uint16_t part;                /* DTC_PART_PM_ITC */
    dtc_itc_cc_cfg_t cc;
    dtc_itc_mid_cfg_t mid;
    dtc_itc_est_cfg_t est;
    dtc_pm_machine_cfg_t machine; /* l_s (l_d), psi_m, 1/l_s, l_q (> 0 each) */
} dtc_pm_itc_cfg_t;

/* The PM ITC part's parameters, once (dtc_param.h). */
#define DTC_PARAMS_PM_ITC(X)                                                                                  \
    X(300, u.pm_itc.part, U16, NONE, DTC_PART_PM_ITC, DTC_PART_PM_ITC, DTC_ERR_PART, DTC_PARAM_RO,            \
      "tag of the PM ITC part (DTC_PART_PM_ITC)")                                                             \
    X(301, u.pm_itc.cc.kp_iq, IQ, Z, 1, DTC_I32_MAX, DTC_ERR_SVM, 0U,                                         \
      "current PI proportional gain K_p = L_s w_c")                                                           \
    X(302, u.pm_itc.cc.ki_ts_iq, IQ, Z, 1, DTC_I32_MAX, DTC_ERR_SVM, 0U,                                      \
      "current PI integral gain times T_s, R_s w_c T_s")                                                      \
    X(303, u.pm_itc.cc.iq_per_t_iq, IQ, PU, 1, DTC_I32_MAX, DTC_ERR_SVM, DTC_PARAM_RO,                        \
      "q-axis current per unit torque, 1 / psi_m")                                                            \
    X(304, u.pm_itc.mid.g_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_DCSUPP, DTC_PARAM_RO,                           \
      "FSTP mid-point regulation gain 2 C w_m; 0 = off")                                                      \
    X(305, u.pm_itc.mid.kf_iq, IQ, RATIO, 0, 16777215L, DTC_ERR_DCSUPP, DTC_PARAM_RO,                         \
      "mid-point regulation's filter gain per period, in (0, 1) with it on")                                  \
    X(306, u.pm_itc.est.lpf_comp, U16, NONE, 0, 1, DTC_ERR_LPFCOMP, 0U,                                       \
      "observer voltage model: 1 = gain and phase correction of the low-pass")                                \
    X(307, u.pm_itc.est.wc_pu_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_LPFCOMP, DTC_PARAM_RO,                       \
      "the low-pass cut-off w_c (> 0 with lpf_comp)")                                                         \
    X(308, u.pm_itc.est.lpf_wmin_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_LPFCOMP, 0U,                              \
      "the low-pass correction's speed floor (> 0 with lpf_comp)")                                            \
    X(310, u.pm_itc.machine.ls_iq, IQ, L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO,                      \
      "synchronous inductance L_s (1/L_s is derived with it)")                                                \
    X(311, u.pm_itc.machine.psi_m_iq, IQ, PSI, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO,                 \
      "magnet flux linkage psi_m (1/psi_m is derived with it)")                                               \
    X(312, u.pm_itc.machine.inv_ls_iq, IQ, INV_L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO, "1 / L_s")    \
    X(313, u.pm_itc.machine.lq_iq, IQ, L, 131072L, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO,                \
      "quadrature-axis inductance L_q, = L_s on a surface PM; 1/L_q is formed at init")

#endif /* PM_ITC_CFG_H */
