/*
 * pm_dtc_cfg.h - the PM DTC law's part of the configuration (dtc_config_t.u.pm_dtc, law
 * DTC_LAW_PM_DTC; the law: dtc.h): the machine model, the voltage model's start-up hand-over and
 * corrections the PM law adds, the switching table and comparators. Per-unit Q formats
 * (dtc_base.h); checked by dtc_check (dtc_check.c).
 */
#ifndef PM_DTC_CFG_H
#define PM_DTC_CFG_H

#include <stdint.h>

#include "dtc_config_common.h"

/* PM machine (Hoang Table VIII), pu. A salient PM has the rotor-frame inductances L_d (ls_iq) and
 * L_q (lq_iq); a surface PM L_q = L_d (Hoang eqs. 8-9), which the laws take as their unchanged
 * surface-PM path (flux_est.h, dtc.c dtc_predict). */
typedef struct {
    iq_t ls_iq;     /* synchronous inductance l_s; of a salient PM its d-axis inductance l_d */
    iq_t psi_m_iq;  /* magnet flux linkage psi_m */
    iq_t inv_ls_iq; /* 1 / l_s (> 0; precomputed: no division in the ISR) */
    iq_t lq_iq;     /* quadrature-axis inductance l_q (= ls_iq on a surface PM; >= 1/128 pu: 1/l_q,
                     * formed at init, flux_est_params_t, within IQ) */
} dtc_pm_machine_cfg_t;

/* The PM law's estimator settings beside the common ones (dtc_est_cfg_t); the flags first (the
 * step reads them every period: small offsets). */
typedef struct {
    /* Actuation-delay compensation (dtc.c dtc_predict): the vector chosen at step k acts in
     * period k+1, so the comparators and the sector work on the flux and torque predicted for
     * the start of period k+1 from the vector already committed for period k. */
    uint16_t delay_comp;      /* 1: on (default), 0: comparators on the estimate at k */
    uint16_t polarity_mid;    /* 1: the drop compensation of period [k-1, k] takes each leg's
                               * forward drop averaged over the current's line from i(k-1) to i(k)
                               * (vcomp_step_lin), its R_on terms at the period's mean current
                               * (i(k-1) + i(k))/2, and the dead-time compensation from the current
                               * at the switching instant i(k-1); 0: all from the sample i(k) */
    uint16_t lpf_comp;        /* voltage model: 1 = gain/phase correction of the low-pass with the
                               * measured speed (lpfcorr.h), 0 = the low-pass output as it is */
    uint16_t dc_supp;         /* voltage model: 1 = DC-current suppression (dtc.c dtc_dcsupp) */

    /* Start-up and hand-over (voltage model only; dtc.c step 3). Below handover_speed_iq the
     * drive runs on the current model (Hoang eqs. 8-9, encoder) and the voltage model's low-pass
     * state is overwritten with that flux every period; once |measured speed| exceeds
     * handover_speed_iq the voltage model integrates on from that state (bumpless: the estimate
     * is continuous at the hand-over); it falls back to the current model when |speed| drops
     * below handover_speed_iq - handover_hyst_iq. Electrical speed, pu; handover_speed_iq = 0:
     * no hand-over, the voltage model runs from standstill (seeded once after a reset). */
    iq_t handover_speed_iq;   /* >= 0 */
    iq_t handover_hyst_iq;    /* 0 <= hyst <= handover_speed_iq */

    iq_t wc_pu_iq;            /* the low-pass cut-off w_c / w_base (> 0 when lpf_comp) */
    iq_t lpf_wmin_iq;         /* the correction's speed floor, pu (> 0 when lpf_comp; 2 w_c) */
    iq_t dcs_k_iq;            /* its gain per period over |w|, Ts l_s / 20 in pu (> 0 when dc_supp):
                               * w_d = |w| / 20 */
    iq_t vmid_g_iq;           /* FSTP mid-point regulation (dtc_dcsupp): phase-A DC current demanded
                               * per volt of mid-point deviation, 2 C w_m in pu (>= 0; 0 = off) */
    iq_t vmid_beta_s_iq;      /* FSTP restoring mid-point reconstruction (dtc.c dtc_vmid_beta):
                               * beta = min(2^-DTC_VMID_BETA_MAX_LOG2, (s w)^2), w the measured
                               * electrical speed in pu; s = sqrt(k) in pu (>= 0; 0 = off) */
} dtc_pm_est_cfg_t;

/* The part; the members the step reads every period first (small offsets from the configuration's
 * start on the 16-bit-offset loads of the proxies and the C28x). */
typedef struct {
    uint16_t part;            /* DTC_PART_PM_DTC */
    dtc_table_cfg_t sw;       /* sstp_table up to DTC_ST_D */
    dtc_pm_est_cfg_t est;
    dtc_pm_machine_cfg_t machine;
} dtc_pm_dtc_cfg_t;

/* The PM DTC part's parameters, once (dtc_param.h). */
#define DTC_PARAMS_PM_DTC(X)                                                                                  \
    X(100, u.pm_dtc.part, U16, NONE, DTC_PART_PM_DTC, DTC_PART_PM_DTC, DTC_ERR_PART, DTC_PARAM_RO,            \
      "tag of the PM DTC part (DTC_PART_PM_DTC)")                                                             \
    X(101, u.pm_dtc.sw.sstp_table, U16, NONE, 0, DTC_ST_D, DTC_ERR_VARIANT, 0U,                               \
      "SSTP switching table: 0 Casadei Table 1, 1..4 ST-A..ST-D")                                             \
    X(102, u.pm_dtc.sw.flux_band_iq, IQ, PSI, 0, DTC_I32_MAX, DTC_ERR_BAND, DTC_PARAM_LIVE,                   \
      "flux hysteresis band, full width (Hoang eq. 13)")                                                      \
    X(103, u.pm_dtc.sw.torque_band_iq, IQ, T, 0, DTC_I32_MAX, DTC_ERR_BAND, DTC_PARAM_LIVE,                   \
      "torque hysteresis band, full width (Hoang eq. 14)")                                                    \
    X(104, u.pm_dtc.est.delay_comp, U16, NONE, 0, 1, DTC_ERR_DELAY, 0U,                                       \
      "1: the comparators act on the estimate predicted for k+1")                                             \
    X(105, u.pm_dtc.est.polarity_mid, U16, NONE, 0, 1, DTC_ERR_POLARITY, 0U,                                  \
      "1: the drops averaged over the period's current, 0: from the sample")                                  \
    X(106, u.pm_dtc.est.lpf_comp, U16, NONE, 0, 1, DTC_ERR_LPFCOMP, 0U,                                       \
      "voltage model: 1 = gain and phase correction of the low-pass")                                        \
    X(107, u.pm_dtc.est.dc_supp, U16, NONE, 0, 1, DTC_ERR_DCSUPP, 0U,                                         \
      "voltage model: 1 = DC-current suppression")                                                            \
    X(108, u.pm_dtc.est.handover_speed_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_HANDOVER, 0U,                       \
      "voltage model: current model below this electrical speed; 0 = none")                                   \
    X(109, u.pm_dtc.est.handover_hyst_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_HANDOVER, 0U,                        \
      "hysteresis of the hand-over, at most the hand-over speed")                                             \
    X(110, u.pm_dtc.est.wc_pu_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_LPFCOMP, DTC_PARAM_RO,                       \
      "the low-pass cut-off w_c (> 0 with lpf_comp)")                                                         \
    X(111, u.pm_dtc.est.lpf_wmin_iq, IQ, W, 0, DTC_I32_MAX, DTC_ERR_LPFCOMP, 0U,                              \
      "the low-pass correction's speed floor (> 0 with lpf_comp)")                                            \
    X(112, u.pm_dtc.est.dcs_k_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_DCSUPP, DTC_PARAM_RO,                       \
      "DC-current suppression gain per period over |w| (> 0 with dc_supp)")                                   \
    X(113, u.pm_dtc.est.vmid_g_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_DCSUPP, DTC_PARAM_RO,                      \
      "FSTP mid-point regulation gain; 0 = off")                                                              \
    X(114, u.pm_dtc.est.vmid_beta_s_iq, IQ, PU, 0, DTC_I32_MAX, DTC_ERR_DCSUPP, DTC_PARAM_RO,                 \
      "FSTP restoring mid-point reconstruction gain; 0 = off")                                                \
    X(115, u.pm_dtc.machine.ls_iq, IQ, L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED,                     \
      "synchronous inductance L_s, of a salient PM L_d (1/L_s is derived with it)")                           \
    X(116, u.pm_dtc.machine.psi_m_iq, IQ, PSI, 1, DTC_I32_MAX, DTC_ERR_MACHINE, 0U, "magnet flux linkage psi_m") \
    X(117, u.pm_dtc.machine.inv_ls_iq, IQ, INV_L, 1, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, \
      "1 / L_s")                                                                                              \
    X(118, u.pm_dtc.machine.lq_iq, IQ, L, 131072L, DTC_I32_MAX, DTC_ERR_MACHINE, DTC_PARAM_RO | DTC_PARAM_STORED, \
      "quadrature-axis inductance L_q, = L_s on a surface PM; 1/L_q is formed at init")

#endif /* PM_DTC_CFG_H */
