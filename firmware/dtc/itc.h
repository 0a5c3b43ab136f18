/*
 * itc.h - indirect torque control (ITC) of the PM brushless AC machine: the current-controlled
 * drive Hoang et al. set beside DTC (Hoang sec. I, refs. [2]-[18]; Figs. 5-8 (a)), one
 * itc_step() per control period = one PWM carrier period (50 us), the speed loop every
 * speed_div-th call as in the DTC law (dtc.h).
 *
 *   Clarke (clarke.h, Hoang eqs. 4-5) -> rotor frame from the encoder angle (park.h; the d axis on
 *   the magnet, Hoang eqs. 8-9's psi_m e^{j theta_e})
 *   -> references: i_d* = 0 (surface PM, L_d = L_q: the torque is psi_m i_q alone, Hoang eq. 10
 *      with psi = l_s i + psi_m e^{j theta_e}: T = psi_m i_q in pu) and i_q* = T* / psi_m,
 *      T* from the shared speed loop (speed_pi.h) or the torque reference (dtc_refs.h)
 *   -> PI current regulators (dqpi.h) on the decoupling and back-EMF feed-forward of the rotor
 *      frame's voltage equation (Hoang eqs. 6-7 with psi = l_s i + psi_m e^{j theta_e}):
 *        v_d = r_s i_d + l_s di_d/dt - w l_s i_q,   v_q = r_s i_q + l_s di_q/dt + w (l_s i_d + psi_m)
 *      f_d = -w l_s i_q,  f_q = w (l_s i_d + psi_m); gains K_p = l_s w_c, K_i = r_s w_c from the
 *      machine (tools/config: w_c from the control period and the actuation delay); voltage limit
 *      the largest circle the inverter makes in every direction: V_dc / sqrt3 (SSTP),
 *      min(v_lo, V_dc - v_lo) / sqrt3 (FSTP with the measured lower capacitor v_lo)
 *   -> stator frame at the angle the rotor reaches in the middle of the period the voltage acts in
 *      (theta_e + 1.5 w Ts: the command of step k is applied over [k+1, k+2], hal.h), the advance
 *      as the rotation (1 + j 1.5 w Ts)
 *   -> SVM: six-switch svm.h (seven-segment, dead-time compensation as configured), four-switch
 *      svm4.h (its four active vectors with the measured mid-point, the same dead-time
 *      compensation); the command in the duty form (law_io.h LAW_OUT_DUTY, dtc_out_t duty_iq).
 * Observer (not in the control path): the configured stator-flux estimator (flux_est.h, voltage
 * model with its compensation, Hoang eqs. 15-16, 31-38, Tables V-VI, or the current model eqs. 8-9)
 * runs on the voltage the duties applied over the period just ended, with the low-pass correction
 * when configured, and gives psi_alpha/beta and the torque (Hoang eq. 10) in dtc_out_t, so that the flux
 * the estimator sees under ITC can be set beside the one under DTC (Hoang Figs. 5-8). The drop
 * compensation of a PWM period is the duty-weighted mean of the tables' per-state values
 * (itc_vcomp).
 *
 * FSTP mid-point regulation (the mid-point measured, u.pm_itc.mid.g_iq > 0): phase A's current is the
 * split capacitors' only DC path (dd/dt = -i_a / (2 C), d = v_lo - V_dc/2), so a DC phase-A current
 * i_a* = g y, y the deviation d low-passed (y += k_f (d - y), k_f = w_f Ts), is added to the
 * references (its Park transform, a component rotating at -w in the rotor frame); tools/config
 * derives g = 2 C w_m and w_f = 4 w_m (critically damped, and the fundamental's swing kept out).
 * |i_a*| is bounded by half the room the torque limit's current T_lim / psi_m leaves below the
 * trip level (an acceleration from standstill leaves the mid-point 15 V off, which g would turn
 * into 2 A on top of the torque current of a two-pole-pair machine: a trip, SIL).
 *
 * Configuration (dtc_config_t, law DTC_LAW_PM_ITC): the common part (board, protection, r_s, the
 * voltage model's low-pass and compensation, speed loop and references) and the law's own part
 * u.pm_itc (pm_itc_cfg.h): the machine (l_s, psi_m), the current regulator cc (K_p, K_i Ts,
 * 1 / psi_m), the mid-point regulation mid (g, k_f) and the observer's low-pass correction est;
 * tools/config (law_pm_itc_si.c) derives them from the machine and the board.
 *
 * Ownership and shadow set as dtc.h: the caller owns itc_t; the configuration must outlive it;
 * references and speed-PI gains change through the shadow set `sh` (dtc_refs.h, law_shadow_write).
 *
 * Formats: IQ pu (dtc_base.h); angles angle_t.
 * Scaling and overflow: see the blocks (clarke.h, park.h, dqpi.h, svm.h, svm4.h, flux_est.h);
 * the feed-forwards and the advance are rounded IQ products with saturating sums.
 */
#ifndef ITC_H
#define ITC_H

#include <stdint.h>

#include "clarke.h"
#include "dqpi.h"
#include "dtc_config.h"
#include "dtc_refs.h"
#include "flux_est.h"
#include "law_io.h"
#include "park.h"
#include "speed_meas.h"
#include "speed_pi.h"
#include "svm.h"
#include "svm4.h"
#include "vcomp.h"

/* The configuration's variant (itc_t.var), fixed at itc_init: the per-period branches test one
 * word of the state instead of the configuration's fields. */
#define ITC_VAR_FSTP 1U       /* the four-switch inverter (board.topology) */
#define ITC_VAR_MID_REG 2U    /* FSTP with the mid-point regulation (u.pm_itc.mid.g_iq > 0) */
#define ITC_VAR_VCOMP 4U      /* the voltage model with a drop compensation (itc_vcomp) */
#define ITC_VAR_VMID_MEAS 8U  /* the FSTP mid-point voltage measured (board.fstp_vmid_measured) */
#define ITC_VAR_CM 16U        /* the current-model estimator (est.estimator) */

typedef struct {
    const dtc_config_t *cfg;
    /* parameters derived at init */
    flux_est_params_t fe_p;
    vcomp_params_t vc_p;
    vcomp_tab_t vc_t;     /* vc_p as a table of the currents' signs (itc_vcomp's base term) */
    speed_meas_params_t sm_p;
    speed_pi_params_t pi_p;
    dqpi_params_t cc_p;
    svm_params_t svm_p;
    svm4_params_t svm4_p;
    /* block states */
    flux_est_t fe;
    speed_meas_t sm;
    speed_pi_t pi;
    dqpi_t cc;
    svm_t svm;
    svm4_t svm4;
    svm_out_t svm_o;
    /* references in force and the shadow set */
    dtc_refs_t act;
    dtc_shadow_t sh;
    /* timing */
    uint16_t div_cnt;
    uint16_t speed_primed;
    uint16_t var; /* ITC_VAR_* of the configuration, fixed at init (itc_init): the step's branches */
    iq_t te_ref_iq;
    iq_t te_trim_iq; /* dtc_refs_adopt's trim (ITC maps T* onto i_q* exactly: never used) */
    iq_t speed_iq;
    iq_t wls_iq, wpsi_iq, adv_iq; /* w l_s (l_d), w psi_m, 1.5 w Ts: at the speed-loop rate */
    iq_t wlq_iq;                  /* w l_q (= w l_s on a surface PM), at the speed-loop rate */
    iq_t wpsi_ts_iq;              /* w psi_m Ts (itc_i_pred), at the speed-loop rate */
    /* the voltage of the duties returned by the previous step (acting now) and by the one before
     * (acting over the period just ended: the observer's input), alpha/beta, and their effective
     * duties for the drop compensation */
    iq_t v1_alpha_iq, v1_beta_iq, v2_alpha_iq, v2_beta_iq;
    iq_t d1_iq[2], d2_iq[2]; /* legs B and C */
    iq_t ts15_iq;                         /* 1.5 Ts, pu (the command's advance) */
    iq_t vcd_alpha_iq[2], vcd_beta_iq[2]; /* drop compensation, state 1 less state 0, legs B, C */
    /* low-pass correction (lpfcorr.h) */
    iq_t lpf_y_iq, lpf_r_iq;
    iq_t vmid_y_iq;    /* the mid-point deviation low-passed (FSTP mid-point regulation) */
    iq_t vmid_imax_iq; /* the bound of its phase-A current */
    /* i_q* of T* (itc_set_te_ref); the dq currents of the step are cc_in's meas_d_iq, meas_q_iq */
    iq_t iq_ref_iq;
    /* the step's rotor angle, for the rotor frame and the current prediction (itc_i_pred; its
     * measured current is i_k's) */
    park_sc_t sc;
    /* working values of the step, kept here and not in the frames of itc_step and its parts
     * (itc_step heads the call chains of the Cortex-M0 stack budget): the measured currents
     * (Clarke), the observer's input, the current PI's input and output, the stator-frame voltage
     * command (itc_cc_out) */
    clarke_out_t i_k;
    flux_est_in_t fin;
    dqpi_in_t cc_in;
    dqpi_out_t cc_out;
    iq_t vs_alpha_iq, vs_beta_iq;
} itc_t;

/* The law's configuration check: dtc_config_check_common, then the law (DTC_LAW_PM_ITC) and its
 * part u.pm_itc (DTC_ERR_PART for another law's part; DTC_ERR_MACHINE, DTC_ERR_SVM for the
 * current regulator, DTC_ERR_DCSUPP for the mid-point regulation, DTC_ERR_LPFCOMP, and
 * DTC_ERR_VARIANT for an estimator other than voltage or current model or a speed sensor other
 * than the encoder). *field (if not null) names the field ("u.pm_itc.cc.kp_iq"), "" on DTC_OK.
 * Pure, init only (itc_check.c). */
int16_t itc_check(const dtc_config_t *cfg, const char **field);
/* Checks cfg (itc_check) and initialises c. Returns DTC_OK or an enum dtc_err code. On error
 * c->cfg = 0. */
int16_t itc_init(itc_t *c, const dtc_config_t *cfg);
/* Back to the initial state (speed unknown, integrals at zero, references kept). */
void itc_reset(itc_t *c);
/* One control period: the duties (o->duty_iq, law_io.h LAW_OUT_DUTY) for the next period. */
void itc_step(itc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* The phase currents predicted for the next sample, for the application's current-sensor
 * plausibility (law.h law_i_pred; the law itself does not use them). The PM machine of Hoang
 * eqs. 6-9 with L_d = L_q, psi = l_s i + psi_m e^{j theta}, over the period after the step:
 *   i(k+1) = i(k) + (1/l_s) [Ts (v - r_s i) - w Ts j psi_m e^{j theta}]
 * with v the voltage of the duties computed one step earlier (they act in that period: itc_step
 * keeps them as v2), theta and i of the step, w psi_m of the speed loop. What it leaves out (the
 * devices' drops, the rotation within the period, parameter errors) is nearly constant over a few
 * periods: the plausibility (app/app_plaus.h) learns and removes such a bias. Formats: IQ pu,
 * products rounded, sums saturated; |i1| saturates at 128 pu at worst (no wrap). */
void itc_i_pred(const itc_t *c, iq_t i1[3]);

/* Internal to itc_step (ISR side): adopts the shadow set whose (even) sequence number is seq.
 * External linkage on purpose: a static function called once is inlined, and its copy of the set
 * would then sit in itc_step's frame on the deepest stack path. */
void itc_shadow_adopt(itc_t *c, uint16_t seq);
/* Internal to itc_step: the measured currents through Clarke into c->i_k, and the observer (the
 * estimator on the voltage of the period just ended, with its drop compensation); returns the
 * torque of Hoang eq. 10 from its flux. External linkage on purpose, as itc_shadow_adopt (its
 * temporaries would sit in itc_step's frame). */
iq_t itc_observe(itc_t *c, const dtc_meas_t *m);
/* Internal to itc_observe: the measured currents through Clarke into c->i_k and the estimator's
 * input c->fin with its drop compensation. External linkage on purpose: inlined, its temporaries
 * would sit in itc_observe's frame, under the estimator's on the deepest stack path. */
void itc_observe_in(itc_t *c, const dtc_meas_t *m);
/* Internal to itc_step: the speed loop's step (every speed_div-th step, as dtc_step; itc_step
 * counts the steps and calls it only then): measured speed, the speed's products, the low-pass
 * correction factor, and T* in speed mode. External linkage on purpose, as itc_shadow_adopt. */
void itc_speed(itc_t *c, const dtc_meas_t *m);
/* Internal to itc_step: the rotor frame at the encoder's angle of the step (c->sc, whose sine and
 * cosine itc_observe took once for the estimator and this), the dq
 * currents and the current PI's input c->cc_in (references, mid-point regulation, decoupling and
 * back-EMF feed-forward, the voltage limit from the link and vlo_iq, the FSTP's lower half-link).
 * External linkage on purpose, as itc_shadow_adopt. */
void itc_cc_in(itc_t *c, const dtc_meas_t *m, iq_t vlo_iq);
/* Internal to itc_step: the current PI's output c->cc_out back in the stator frame, advanced by
 * 1.5 w Ts: the voltage command c->vs_alpha_iq, c->vs_beta_iq, IQ pu. External linkage on purpose,
 * as itc_shadow_adopt. */
void itc_cc_out(itc_t *c);
/* Internal to itc_step: the voltage of the SVM's effective duties on the link measured now
 * (vrec_from_legs), kept for the observer of the step after next, and the legs B, C duties for its
 * drop compensation. External linkage on purpose, as itc_shadow_adopt. */
void itc_keep(itc_t *c, const dtc_meas_t *m);

#endif /* ITC_H */
