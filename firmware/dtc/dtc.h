/*
 * dtc.h - the DTC controller: one dtc_step() per 50 us control period (Hoang Fig. 4, Casadei
 * Fig. 4), the speed loop every speed_div-th call.
 *
 *   Clarke (clarke.h) -> voltage reconstruction (vrec.h) + drop compensation (vcomp.h)
 *   -> stator-flux estimator (flux_est.h) -> torque, |psi|, sector (torque.h, sector.h)
 *   -> hysteresis comparators (hyst.h) -> switching table (swtab.h) -> leg states
 *   speed measurement (speed_meas.h) + speed PI (speed_pi.h) every speed_div-th call
 *
 * Timing contract (hal.h): the command returned by step k takes effect at the start of period
 * k+1. The voltage-model estimator at step k therefore integrates the period [k-1, k] with the
 * leg states returned by step k-2 (two-deep history kept here), the measured V_dc and the
 * currents sampled at k.
 *
 * Ownership: the caller owns dtc_t (no static state anywhere); the configuration passed to
 * dtc_init() must outlive the controller (it is typically const data in flash).
 *
 * Shadow set: the background loop changes references and speed-PI gains with
 * law_shadow_write() into the shadow set `sh`; dtc_step() adopts a complete set atomically at its top (dtc_refs.h: the
 * sequence lock every law shares).
 */
#ifndef DTC_H
#define DTC_H

#include <stdint.h>

#include "clarke.h"
#include "dtc_config.h"
#include "vrec.h"
#include "dtc_refs.h"
#include "fixmath.h"
#include "flux_est.h"
#include "hyst.h"
#include "ilim.h"
#include "law_io.h"
#include "speed_meas.h"
#include "speed_pi.h"
#include "swtab.h"
#include "torque.h"
#include "vcomp.h"

typedef struct {
    const dtc_config_t *cfg;
    /* parameters derived at init */
    flux_est_params_t fe_p;
    vcomp_params_t vc_p;
    speed_meas_params_t sm_p;
    speed_pi_params_t pi_p;
    /* block states */
    flux_est_t fe;
    speed_meas_t sm;
    speed_pi_t pi;
    hyst2_t h_flux;
    hyst2_t h_torque2;
    hyst3_t h_torque3;
    /* references in force and the shadow set */
    dtc_refs_t act;
    dtc_shadow_t sh;
    /* timing */
    uint16_t div_cnt;
    uint16_t speed_primed;
    swtab_legs_t legs_1; /* returned by the previous step: applied during this period */
    swtab_legs_t legs_2; /* returned two steps ago: applied during the period just ended */
    swtab_legs_t legs_3; /* returned three steps ago: applied before legs_2 (dead time) */
    uint16_t vec_1;      /* vector returned by the previous step */
    iq_t te_ref_iq;
    iq_t te_trim_iq;     /* torque mode: mean-torque trim added to the reference */
    iq_t speed_iq;
    uint16_t on_cm;      /* voltage model with hand-over: 1 while the current model drives */
    uint16_t cm_hold;    /* periods the current model still drives after a reconfiguration
                          * (dtc_reconfigure), whatever the speed */
    /* delay compensation (dtc_predict): voltage of legs_1, its drop and dead-time terms */
    iq_t v1_alpha_iq, v1_beta_iq, v1f_alpha_iq, v1f_beta_iq, v1d_alpha_iq, v1d_beta_iq;
    /* current limit (ilim.h): the current predicted for k+1 by dtc_predict */
    clarke_out_t i1;
    /* ripple-robust polarity (polarity_mid): the previous sample and the period's mean current */
    clarke_out_t i_prev, i_mid;
    uint16_t i_limited;  /* 1: the current limit replaced the table's vector in the last step */
    /* low-pass correction (lpfcorr.h): y ~ 1/max(|w|, w_min), r = sign(w) w_c y */
    iq_t lpf_y_iq, lpf_r_iq;
    /* DC-current suppression (dtc_dcsupp): the flux correction, alpha/beta, Q32 pu */
    iq_t dcs_alpha_iq, dcs_beta_iq;
    iq_t dcs_kw_iq;      /* its gain Ts l_s |w| / 20, updated at the speed-loop rate */
    iq_t vmid_beta_iq;   /* restoring mid-point reconstruction (dtc_vmid_dev): beta at the
                          * measured speed, updated at the speed-loop rate */
    iq_t vmid_dev_iq;    /* FSTP voltage model: (1 - beta)(vmid - V_dc/2) of this step */
    /* shared blocks' parameters derived at init (last: the members above keep their offsets) */
    deadtime_params_t dt_p;
    ilim_params_t il_p;
    iq_t wts_iq;         /* delay compensation (dtc_predict): w Ts of the measured speed, IQ pu,
                          * updated with the speed at the speed-loop rate */
    iq_t ri_alpha_iq, ri_beta_iq; /* r_s i of this step, IQ pu (dtc_step: the voltage model and
                                   * dtc_predict take the same product) */
    uint16_t dt_code;    /* dead-time compensation: the deadtime_code (vrec.h) dtc_predict formed for
                          * legs_2 -> legs_1 on the current sample, which the next step's estimator
                          * takes for legs_3 -> legs_2 on i_prev; DEADTIME_CODE_NONE when none
                          * (reset, no prediction) */
    uint16_t gains_due;  /* 1: the speed-dependent gains of the speed measured last are still to be
                          * formed (dtc_speed_gains, at the start of the next step) */
    /* dtc_step's working values of one step (the currents at k, the estimator's input), kept here
     * and not in its frame: dtc_step heads the deepest call chains of the Cortex-M0 stack budget */
    clarke_out_t i_k;
    flux_est_in_t fin;
    /* drop compensation (dtc_vcomp_est): the forward drops dtc_predict formed for legs_1 on the
     * current sample (vcomp_fwd_lin), which the next step's estimator takes for legs_2 over i_prev
     * -> i when no phase current changed sign; fwd_ok 0 when none (reset, no prediction) */
    iq_t fwd_alpha_iq, fwd_beta_iq;
    uint16_t fwd_ok;
    /* the flux comparator's squared bounds (hyst.h hyst2_sq_bounds) of act.flux_ref_iq and h_flux,
     * formed where either changes (dtc_flux_bounds: reference adopted, reset, reconfiguration) */
    hyst2_sq_t flux_sq;
    vcomp_pt_t vc_pt;    /* vc_p's forward drops at a sample as a table (FSTP modes; dtc_predict's) */
    uint64_t ilim2_q48;  /* the current limit's square I_lim^2, Q48 (iq_sumsq_q48 of i_lim_iq; ilim.h),
                          * formed with il_p (dtc_block_params) */
} dtc_t;

/* The law's configuration check (dtc_check.c): the common part, then the law DTC_LAW_PM_DTC and
 * its part u.pm_dtc. Returns DTC_OK or the first enum dtc_err code; *field (if not null) names
 * the field ("u.pm_dtc.machine.ls_iq"), "" on DTC_OK. Pure, init only. */
int16_t dtc_check(const dtc_config_t *cfg, const char **field);

/* Checks cfg (dtc_check) and initialises c. Returns DTC_OK or an enum dtc_err code; on error c is
 * left unusable (c->cfg = 0) and must not be stepped. */
int16_t dtc_init(dtc_t *c, const dtc_config_t *cfg);

/* Back to the initial state (speed unknown, integrator at zero, references kept). The first
 * dtc_step() after it takes the encoder position as the speed reference and, for the voltage
 * model, seeds the flux with the current model (flux_est_seed). */
void dtc_reset(dtc_t *c);

/* One control period. */
void dtc_step(dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* Live reconfiguration of an SSTP drive whose leg `phase` (0 = A, 1 = B, 2 = C) failed into the
 * FSTP of post (Hoang sec. I and ref. [9]: the phase goes onto the capacitor mid-point, the other
 * two legs switch). The FSTP law then runs in the frame whose phase A' is the failed phase,
 * (a', b', c') = (x, x+1, x+2) cyclically: the caller permutes the currents in and the legs out
 * (app_core.c). post must be the FSTP configuration of the same PM drive (the app checks it,
 * app_core_set_reconfig). Returns DTC_OK, or DTC_ERR_RECONFIG for a phase above 2 or a post
 * that is not an FSTP PM configuration (nothing changed then). */
int16_t dtc_reconfigure(dtc_t *c, const dtc_config_t *post, uint16_t phase);

/* |psi| of a step's estimate (Hoang eq. 11), IQ pu, rounded to nearest, saturating at 128 pu
 * (torque.h). For the background and telemetry: dtc_step() itself compares |psi|^2 and takes no
 * square root (hyst2_sq_step). */
static inline iq_t dtc_out_flux_mag(const dtc_out_t *o)
{
    return torque_flux_mag(o->psi_alpha_iq, o->psi_beta_iq);
}

#endif /* DTC_H */
