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
 * dtc_shadow_write(); dtc_step() adopts a complete set atomically at its top (dtc_refs.h: the
 * sequence lock every law shares).
 */
#ifndef DTC_H
#define DTC_H

#include <stdint.h>

#include "clarke.h"
#include "dtc_config.h"
#include "dtc_refs.h"
#include "fixmath.h"
#include "flux_est.h"
#include "hyst.h"
#include "speed_meas.h"
#include "speed_pi.h"
#include "swtab.h"
#include "torque.h"
#include "vcomp.h"

/* Per-unit measurements of one period (the app converts ADC and QEP counts with the
 * configuration's ADC scaling). Which currents are read (clarke.h): SSTP i_a, i_b; FSTP i_b, i_c;
 * the third field is ignored. */
typedef struct {
    iq_t ia_iq, ib_iq, ic_iq; /* phase currents, pu */
    iq_t vdc_iq;              /* DC-link voltage, pu */
    iq_t vmid_iq;             /* FSTP: lower capacitor (mid-point to negative rail), pu */
    uint16_t enc_count;       /* quadrature counter 0 .. 4*lines - 1 */
} dtc_meas_t;

typedef struct {
    uint16_t sa, sb, sc;   /* leg states for the next period (FSTP: sa = 0, unused) */
    uint16_t vector;       /* SSTP 0..7, FSTP 1..4 (swtab.h); IM DSVM: the code 0..36 (dsvm.h) */
    uint16_t sector;       /* SSTP 1..6, FSTP 1..4 */
    uint16_t flux_up;      /* flux comparator output (1 = increase) */
    int16_t torque_dem;    /* torque comparator output: +1 / 0 / -1 (two-level: +1 / -1) */
    uint16_t speed_tick;   /* 1 when the speed loop ran in this step */
    iq_t psi_alpha_iq, psi_beta_iq; /* estimated stator flux, pu (|psi|: dtc_out_flux_mag) */
    iq_t te_iq;            /* estimated torque (Hoang eq. 10), pu */
    iq_t te_ref_iq;        /* torque reference in force, pu */
    iq_t speed_iq;         /* measured electrical speed, pu */
    angle_t theta_e;       /* encoder electrical angle */
    uint16_t on_cm;        /* 1: the flux came from the current model (estimator = current, or
                            * the voltage model below its hand-over speed) */
    iq_t psi_ref_iq;       /* stator-flux reference in force, pu */
    iq_t psir_mag_iq;      /* IM law: estimated rotor-flux magnitude (Casadei eq. 21), updated on
                            * the speed-loop periods; PM: 0 */
    uint16_t i_limited;    /* 1: the current limit (ilim.h) replaced the table's vector */
    /* PWM form (IM law, schemes SFVC, DFOC, DSVM): pwm = 1 says the command is duty_iq, one
     * centred pulse per leg (the application writes the compare values, svm_cmpr, hal.h
     * HAL_CMD_PWM); pwm = 2 (DSVM) says it is thirds, the upper device's state in each third of
     * the period (the application maps them onto one pulse per leg, dsvm_pwm), duty_iq then the
     * mean; sa/sb/sc are then 0. The DTC laws never write these fields: the application clears
     * pwm once at init. */
    uint16_t pwm;
    iq_t duty_iq[3];       /* upper-device duty of legs A, B, C over the next period, [0, 1] */
    uint16_t thirds[3];    /* pwm = 2: legs A, B, C, bit 2 = first third, 1 = upper on */
} dtc_out_t;

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
} dtc_t;

/* Largest beta of the restoring mid-point reconstruction (dtc.c dtc_vmid_dev): 2^-4. */
#define DTC_VMID_BETA_MAX_LOG2 4U

/* Validates cfg (dtc_config_validate) and initialises c. Returns DTC_OK or an enum dtc_err code;
 * on error c is left unusable (c->cfg = 0) and must not be stepped. */
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

/* Background: publish a new parameter set. Returns DTC_OK, or DTC_ERR_REFERENCE / DTC_ERR_PI /
 * DTC_ERR_VARIANT for a set that would be refused (nothing is published then). */
int16_t dtc_shadow_write(dtc_t *c, const dtc_refs_t *r);

/* Used by dtc_step() (ISR side): adopts the shadow set whose (even) sequence number is seq.
 * Not for the background. */
void dtc_shadow_adopt(dtc_t *c, uint16_t seq);
/* Dead-time compensation, shared by the laws (dtc_step, im_dtc_step): the error of the
 * reconstructed voltage of a period whose legs went from prev to cur, alpha/beta, IQ pu, with the
 * link voltage and the phase currents at the switching instant (PM law with polarity_mid: the
 * previous sample for the estimator's period). 0 when no leg changed. */
void dtc_deadtime(const dtc_config_t *cfg, iq_t vdc_iq, const clarke_out_t *i, const swtab_legs_t *prev,
                  const swtab_legs_t *cur, iq_t *dva, iq_t *dvb);
/* Internal to dtc_step (actuation-delay compensation); out of line for the stack. On entry
 * *psi_a, *psi_b, *te hold the estimate at k; on return the prediction for k+1; the predicted current goes to c->i1_*. */
void dtc_predict(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te);
/* Internal to dtc_step (ripple-robust polarity: the period-mean current into c->i_mid); out of line
 * for the stack (inlined, its saturating sums widen dtc_step's frame on the deepest chain). */
void dtc_pol_mid(dtc_t *c, const clarke_out_t *i);
/* Internal to dtc_step (torque mode: reference plus mean-torque trim); out of line for the stack. */
void dtc_torque_trim(dtc_t *c, iq_t te);

/* Internal to dtc_step (DC-current suppression): updates the correction from the measured
 * current (and, FSTP, the mid-point deviation c->vmid_dev_iq of this step) and adds it to the
 * estimate *psi_a, *psi_b. */
void dtc_dcsupp(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b);
/* Internal to dtc_step (restoring mid-point reconstruction, dtc.c dtc_vmid_beta; dtc_dcsupp reads
 * the step's value from c->vmid_dev_iq):
 * the mid-point's deviation from V_dc/2 as the law uses it, (1 - beta)(vmid - V_dc/2), IQ pu;
 * the shift rounds, the product rounds and saturates, the differences saturate. */
static inline iq_t dtc_vmid_dev(const dtc_t *c, const dtc_meas_t *m)
{
    const iq_t d = iq_sub(m->vmid_iq, fix_rshift_rnd32(m->vdc_iq, 1U));
    return iq_sub(d, iq_mpy(c->vmid_beta_iq, d));
}
/* Internal to dtc_step: beta = min(2^-DTC_VMID_BETA_MAX_LOG2, (s w)^2) at the measured speed. */
void dtc_vmid_beta(dtc_t *c);
/* Internal to dtc_reset and dtc_reconfigure: the currents kept from earlier periods (previous
 * sample, period mean, prediction) and the current-limit flag back to zero. */
void dtc_reset_currents(dtc_t *c);
/* Internal to dtc_step and dtc_reconfigure: the hand-over decision on c->speed_iq (dtc.c). */
void dtc_handover(dtc_t *c);
/* Internal to dtc_step (low-pass correction factor, lpfcorr.h). */
void dtc_lpf_r(dtc_t *c);

/* The set in force (for the background's display). */
void dtc_refs_get(const dtc_t *c, dtc_refs_t *r);

#endif /* DTC_H */
