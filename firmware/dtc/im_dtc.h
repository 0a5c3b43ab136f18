/*
 * im_dtc.h - the induction-machine control law: DTC and DSC of Casadei et al. 2006 (sections 2-9,
 * 10.1-10.2, 12), one im_dtc_step() per control period, the speed loop every speed_div-th call.
 * A module beside the PM law (dtc.h), with the same init/reset/step shape; the application
 * dispatches between them (app/law.h). Shared blocks, not copies: Clarke (clarke.h), voltage
 * reconstruction (vrec.h) with drop (vcomp.h) and dead-time (dtc_deadtime) compensation, the
 * hysteresis comparators (hyst.h), the switching tables and the null-vector choice (swtab.h),
 * the sector (sector.h), speed measurement and PI (speed_meas.h, speed_pi.h), the reference set
 * and its shadow (dtc_refs.h).
 *
 *   Clarke -> v(legs applied over the period that ends now) + drop and dead-time compensation
 *   -> stator flux: voltage model (Casadei eq. 1, low-pass) or improved estimator (eq. 20, tau
 *      fixed or speed-dependent, section 10.2)                                        (im_est.h)
 *   -> rotor flux (eq. 21), its angle (eq. 22) and magnitude; torque (appendix eq. A10, torque.h)
 *   -> speed: encoder (speed_meas.h) or sensorless, rotor-flux angular speed minus the slip of
 *      eq. 16 (im_ref.h); speed PI every speed_div-th step (speed mode)
 *   -> references: start-up (magnetise at zero torque, Fig. 17b), flux weakening (section 12:
 *      phi_s* from the torque-comparator monitor, T* by eqs. 33-34, im_fw.h), stator flux from a
 *      constant rotor flux (eq. 19, im_ref.h) or the stator-flux reference
 *   -> flux comparator on |phi_s|^2 (hyst2_sq_step), torque comparator three-level (Table 1) or
 *      two-level (Table 3)
 *   -> scheme DTC: Table 1 (basic), ST-A..ST-D (Table 3), speed-dependent (section 8: ST-D below
 *      the configured speed, ST-A above); or DSC (section 9, dsc.h: hexagon by the phase-flux
 *      comparators, torque by null vectors); the null vector chosen for the fewest commutations
 *   -> leg states for the next period.
 * The scheme DTC_SCHEME_DSVM (im_dsvm.c) keeps the comparators with a five-level torque comparator
 * and the DSVM tables of Casadei section 11 (dsvm.h), three sub-intervals per period in the PWM
 * form. The schemes DTC_SCHEME_SFVC and DTC_SCHEME_DFOC (im_sfvc.c, im_dfoc.c) share the estimator,
 * speed loop, start-up and references (im_dtc_front, im_dtc_refs) and replace the comparators and
 * the table by a voltage reference applied through the SVM (svm.h): the PWM form for the next
 * period (im_pwm_out).
 *
 * Start-up (Casadei section 10.2, Fig. 17b): after a reset the torque reference is held at zero
 * and the speed PI at rest for im_magn_periods control periods. The stator-flux reference is
 * ramped from zero to its no-load value by im_magn_ramp_iq per period: at DC (Casadei eqs. 7-9,
 * w = 0) phi_s = sigma l_s i + (m/l_r) phi_r and d phi_r/dt = (m i - phi_r)/tau_r, so a step of
 * phi_s* sends the current towards phi_s* / (sigma l_s) (5.7x rated on the default IM), while a ramp
 * at rho holds it at phi_r/m + tau_r rho/l_s: the host derives rho = (I_n - I_m) l_s/tau_r from the
 * rated current I_n and the final magnetising current I_m (dtc_config_si.c), so the current
 * stays below I_n. The estimator's rotor-flux reference is meanwhile the rotor flux of the current
 * model, tau_r d|phi_r|/dt = m i_d - |phi_r| (exact at DC). After the ramp the estimate cannot tell when the
 * machine is magnetised: at DC the improved estimator's correction (eq. 20) pulls the estimated
 * rotor flux to its reference within tau whatever the machine's, while the machine's rotor flux
 * rises as 1 - exp(-t/tau_r) (eq. 9 with the estimator's DC error: d phi_r/dt = -(r_r/l_r)
 * (phi_r - phi_r*)); the host converts the fraction to reach into that time.
 * Meanwhile, with the rotor at rest (a turning rotor: im_magn_vector), the flux is built by the
 * radial vector: the active vector V_k of the stator flux's own sector k while the flux
 * comparator asks for more flux, a null vector otherwise. V_k lies
 * within +-30 degrees of the flux: it raises |phi_s| and applies almost no torque, so the phase
 * currents settle to the DC magnetising current, as in Fig. 17b. (Table 1 itself cannot start a
 * demagnetised machine at zero torque: with T* = T = 0 the three-level comparator stays at 0 and
 * the table gives null vectors only.) With the pure-integrator voltage model the estimate of this
 * DC flux decays through the low-pass and the machine is over-magnetised instead (the paper's
 * Fig. 17a statement that the pure integrator cannot magnetise the machine at zero torque); the
 * improved estimator's correction holds it.
 *
 * Timing contract as the PM law (dtc.h): the command of step k acts in period k+1; the voltage
 * integrated at step k is that of the legs returned at step k-2. The IM law has no actuation-
 * delay prediction (est.delay_comp is the PM law's): the comparators see the estimate at k.
 *
 * Ownership: caller-owned state, no static state; cfg must outlive the controller.
 * Formats: IQ pu (dtc_base.h bases, chosen for the IM by the host), angle_t, Q15/Q31 gains.
 * Scaling and overflow: every block documents its own; this file adds only saturating sums,
 * comparisons and the ramp (a 64-bit product of the increment and the period count, clamped to
 * the final reference).
 */
#ifndef IM_DTC_H
#define IM_DTC_H

#include <stdint.h>

#include "clarke.h"
#include "dsc.h"
#include "dsvm.h"
#include "dtc.h"
#include "dtc_config.h"
#include "dtc_refs.h"
#include "hyst.h"
#include "im_est.h"
#include "im_fw.h"
#include "im_ref.h"
#include "speed_meas.h"
#include "speed_pi.h"
#include "svm.h"
#include "swtab.h"
#include "torque.h"
#include "vcomp.h"
#include "vrec.h"

typedef struct {
    const dtc_config_t *cfg;
    /* parameters derived at init */
    im_est_params_t est_p;
    vcomp_params_t vc_p;
    speed_meas_params_t sm_p;
    speed_pi_params_t pi_p;
    im_speed_params_t isp_p;
    im_fw_params_t fw_p;
    /* block states */
    im_est_t est;
    im_speed_t isp;
    im_fw_t fw;
    speed_meas_t sm;
    speed_pi_t pi;
    hyst2_t h_flux;
    hyst2_t h_torque2;
    hyst3_t h_torque3;
    hyst5_t h_torque5;    /* DSVM: the five-level torque comparator */
    dsc_t dsc;
    /* references in force and the shadow set */
    dtc_refs_t act;
    dtc_shadow_t sh;
    /* timing and history */
    uint16_t div_cnt;
    uint16_t speed_primed;
    uint16_t magnetised;  /* 0 during the start-up magnetisation */
    uint16_t dsc_on;      /* DSC: 1 once the hexagon runs (dsc_reset done) */
    swtab_legs_t legs_1;  /* returned by the previous step: applied during this period */
    swtab_legs_t legs_2;  /* returned two steps ago: applied during the period just ended */
    swtab_legs_t legs_3;  /* returned three steps ago (dead time) */
    uint16_t vec_1;       /* vector returned by the previous step */
    int16_t tdem_1;       /* torque comparator's demand of the previous step (+1, 0, -1) */
    iq_t te_cmd_iq;       /* torque command: speed PI output or the torque reference */
    iq_t te_trim_iq;      /* torque mode: mean-torque trim (dtc_trim_step) */
    iq_t te_ref_iq;       /* torque reference in force (after start-up and eqs. 33-34) */
    iq_t psi_ref_iq;      /* stator-flux reference in force (eq. 19, section 12, or the set) */
    iq_t psir_ref_iq;     /* rotor-flux reference of the improved estimator (eq. 20) */
    uint16_t magn_n;      /* start-up: periods of magnetisation so far */
    iq_t magn_psir_iq;    /* start-up: rotor-flux magnitude of the current model (im_dtc_refs) */
    uint16_t ref_due;     /* eq. 19 to be evaluated (im_dtc_refs) */
    iq_t speed_iq;        /* electrical speed in use (encoder or estimated), pu */
    /* working values of one step, kept here rather than on the stack (budget: <= 256 bytes of
     * stack on the Cortex-M0 proxy, tools/bench) */
    clarke_out_t i;       /* currents of this step */
    im_est_in_t ein;      /* estimator input */
    iq_t dva_iq, dvb_iq;  /* a compensation term */
    /* the SVM schemes: stator-flux vector control (DTC_SCHEME_SFVC, im_sfvc.c) and rotor-flux-
     * oriented control (DTC_SCHEME_DFOC, im_dfoc.c) */
    uint16_t pwm_law;     /* 0: DTC/DSC (im_dtc_step), 1: SFVC (im_sfvc_step), 2: DFOC (im_dfoc_step),
                           * 3: DSVM (im_dsvm_step) */
    svm_params_t svm_p;
    svm_t svm;
    svm_out_t svm_o;      /* the modulation of this step */
    iq_t v1_alpha_iq, v1_beta_iq; /* voltage of the duties returned by the previous step (their
                                   * d_eff on the link measured then): acts in this period, pu */
    iq_t v2_alpha_iq, v2_beta_iq; /* returned two steps ago: the period that ends now, pu */
    iq_t vs_alpha_iq, vs_beta_iq; /* stator-voltage reference v_s* of eq. 24 of this step, pu */
    /* constant products of the configuration (im_dtc_init), eqs. 16, 18, 24 */
    iq_t sfvc_kpd_iq;     /* K_p (l_s/m) phi_r*: K_p times the d component of eq. 18 */
    iq_t sfvc_kpq_iq;     /* K_p (l_s/m) sigma l_r / phi_r*: K_p times eq. 18's q component per pu T* */
    iq_t sfvc_kslip_iq;   /* r_r / phi_r*^2: eq. 16's slip per pu torque */
    iq_t foc_id_int_iq, foc_iq_int_iq; /* DFOC: the current PIs' integral parts, pu voltage */
} im_dtc_t;

/* Validates cfg (dtc_config_validate; law DTC_LAW_IM_DTC) and initialises c. Returns DTC_OK or an
 * enum dtc_err code; on error c->cfg = 0 and c must not be stepped. */
int16_t im_dtc_init(im_dtc_t *c, const dtc_config_t *cfg);
/* Back to the start: demagnetised estimate, start-up magnetisation pending, references kept. */
void im_dtc_reset(im_dtc_t *c);
/* One control period (dtc_out_t as the PM law; theta_e is the rotor-flux angle, eq. 22). */
void im_dtc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);
/* Background: publish a new reference set (dtc_refs.h). */
int16_t im_dtc_shadow_write(im_dtc_t *c, const dtc_refs_t *r);
/* The set in force. */
void im_dtc_refs_get(const im_dtc_t *c, dtc_refs_t *r);

/* Internal: the rotor-flux reference for a stator-flux reference, and the adoption of a reference
 * set (shared by im_dtc_init and the shadow set). */
void im_dtc_psir_ref(im_dtc_t *c, iq_t psi_s_ref_iq);
void im_dtc_apply(im_dtc_t *c, const dtc_refs_t *r);
/* Internal to im_dtc_step, out of line for the stack (as dtc.c's helpers). */
void im_dtc_adopt(im_dtc_t *c, uint16_t seq);
void im_dtc_estimate(im_dtc_t *c, const dtc_meas_t *m);
void im_dtc_speed(im_dtc_t *c, const dtc_meas_t *m, iq_t te, dtc_out_t *o);
void im_dtc_refs(im_dtc_t *c);
uint16_t im_dtc_select(im_dtc_t *c, iq_t te, dtc_out_t *o);

/* The scheme DTC_SCHEME_SFVC's control period (im_sfvc.c): the same estimator, speed loop,
 * start-up and references as im_dtc_step, then the stator-flux regulator of Casadei eqs. 18, 23,
 * 24 and the SVM (svm.h); the output is the PWM form (dtc_out_t.pwm = 1, duty_iq). law.h calls
 * it in place of im_dtc_step when c->sfvc. */
void im_sfvc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);
/* Internal to im_sfvc_step, out of line for the stack. */
void im_sfvc_estimate(im_dtc_t *c, const dtc_meas_t *m);
void im_sfvc_regulate(im_dtc_t *c);
/* The scheme DTC_SCHEME_DFOC's control period (im_dfoc.c): rotor-flux-oriented control of Casadei
 * section 13 with the same estimator, speed loop, start-up and references, PI current regulators
 * in the rotor-flux frame, the SVM. law.h calls it in place of im_dtc_step when c->pwm_law = 2. */
void im_dfoc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);
/* Internal to im_dfoc_step, out of line for the stack. */
void im_dfoc_regulate(im_dtc_t *c);

/* The scheme DTC_SCHEME_DSVM's control period (im_dsvm.c): the same estimator, speed loop,
 * start-up and references as im_dtc_step, then the flux comparator, the five-level torque
 * comparator and the switching tables of Casadei section 11 (dsvm.h); the output is the three
 * sub-interval states per leg (dtc_out_t.pwm = 2, thirds). law.h calls it when c->pwm_law = 3. */
void im_dsvm_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);
/* Internal to im_dsvm_step, out of line for the stack. */
void im_dsvm_select(im_dtc_t *c, const dtc_meas_t *m, iq_t te, dtc_out_t *o);

/* Steps 1-5 of a control period, common to both schemes: the shadow set (dtc_refs.h), Clarke
 * (Hoang eqs. 4-5, the same transform as Casadei's space vectors), the stator and rotor flux
 * (Casadei eqs. 1, 20-22) from the scheme's voltage (pwm = 0: the legs, im_dtc_estimate; 1: the
 * modulated duties, im_sfvc_estimate), the torque (Casadei eq. A10 = Hoang eq. 10 in these bases),
 * the speed and the speed loop. Returns the estimated torque. Inline with a constant pwm: each
 * scheme's step gets its own copy (no call or branch added to the DTC path). */
static inline iq_t im_dtc_front(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, uint16_t pwm)
{
    iq_t te;
    {
        const uint16_t seq = dtc_shadow_pending(&c->sh);
        if (seq != 0U) {
            im_dtc_adopt(c, seq);
        }
    }
    clarke_sstp(m->ia_iq, m->ib_iq, &c->i);
    if (pwm != 0U) {
        im_sfvc_estimate(c, m);
    } else {
        im_dtc_estimate(c, m);
    }
    im_est_step(&c->est, &c->ein);
    te = torque_eq10(c->est.psi_alpha_iq, c->est.psi_beta_iq, c->i.i_alpha_iq, c->i.i_beta_iq);
    im_dtc_speed(c, m, te, o);
    return te;
}

/* The start-up's vector (SSTP 1..6 or SWTAB_NULL) for the flux in sector 1..6, the flux
 * comparator's flux_up and the torque error err = T* - T, T* = 0 (im_dtc_refs).
 *   Rotor at rest (the encoder's speed 0): the radial vector V_k while the flux must rise, a null
 *     otherwise (Fig. 17b; file comment).
 *   Rotor turning (a flying start): a stationary flux would brake it (DC injection: the slip is
 *     the rotor's own speed, Casadei eq. 16), and the machine's rotor flux would not follow the
 *     magnetising ramp the estimator's reference assumes, so the estimate would settle on a
 *     flux the machine does not have. Instead ST-D's vectors under a two-level torque
 *     comparator held at T* = 0 (Casadei Table 3: V_k+1 / V_k-1 while the flux must rise,
 *     V_k+2 / V_k-2 while it must fall) turn the flux with the rotor in either sense, at a
 *     small mean torque against the motion (the zero band with the period's actuation delay;
 *     docs/sil.md gives the figures). At rest they would alternate about the radial direction
 *     with a torque ripple of about a quarter of the rated torque, hence the radial vector there.
 * Without an encoder the speed is not known before the flux is: the radial vector always, and a
 * start into a turning rotor is not supported (docs/sil.md). */
static inline uint16_t im_magn_vector(im_dtc_t *c, uint16_t sector, uint16_t flux_up, iq_t err, int16_t *tdem)
{
    uint16_t up;
    if (c->cfg->speed.sensor == DTC_SPEED_NONE || c->speed_iq == 0) {
        *tdem = 0;
        return flux_up != 0U ? sector : SWTAB_NULL;
    }
    up = hyst2_step(&c->h_torque2, err);
    *tdem = up != 0U ? 1 : -1;
    return swtab_sstp_st(DTC_ST_D, sector, flux_up, up);
}

/* What every IM scheme reports besides its command: the estimate (flux, torque at k), the
 * references, the speed and the rotor-flux angle and magnitude (updated on the speed-loop
 * periods); the IM law has no current model and no current limit. */
static inline void im_out_report(const im_dtc_t *c, dtc_out_t *o, iq_t te)
{
    o->psi_alpha_iq = c->est.psi_alpha_iq;
    o->psi_beta_iq = c->est.psi_beta_iq;
    o->te_iq = te;
    o->te_ref_iq = c->te_ref_iq;
    o->speed_iq = c->speed_iq;
    o->theta_e = c->est.theta_r;
    o->on_cm = 0U;
    o->psi_ref_iq = c->psi_ref_iq; /* the start-up ramp, then (l_s/m) phi_r*: eq. 18's d part */
    o->psir_mag_iq = c->est.psir_mag_iq;
    o->i_limited = 0U;
}

/* The end of an SVM scheme's period (SFVC, DFOC): the SVM of c->vs_* on the measured link with
 * dead-time compensation (svm.h), the voltage the new duties will apply kept for the estimator
 * and the prediction (d_eff on the link measured now, Casadei eq. 2 / Hoang eqs. 1-5: (2 d_a -
 * d_b - d_c)/3 V_dc, (d_b - d_c)/sqrt3 V_dc; vrec_from_legs saturates, IQ products rounded),
 * and the outputs: the PWM form (duty_iq), the estimate, the references. */
static inline void im_pwm_out(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o, iq_t te)
{
    uint16_t x;
    svm_step(&c->svm, &c->svm_p, c->vs_alpha_iq, c->vs_beta_iq, m->vdc_iq, &c->i, &c->svm_o);
    c->v2_alpha_iq = c->v1_alpha_iq;
    c->v2_beta_iq = c->v1_beta_iq;
    {
        iq_t a, b;
        vrec_from_legs(c->svm_o.d_eff_iq[0], c->svm_o.d_eff_iq[1], c->svm_o.d_eff_iq[2], &a, &b);
        c->v1_alpha_iq = iq_mpy(a, m->vdc_iq);
        c->v1_beta_iq = iq_mpy(b, m->vdc_iq);
    }
    for (x = 0U; x < 3U; x++) {
        o->duty_iq[x] = c->svm_o.d_iq[x];
    }
    o->pwm = 1U;
    o->sa = 0U; /* the PWM form carries the command (duty_iq) */
    o->sb = 0U;
    o->sc = 0U;
    o->vector = 0U;
    o->sector = 0U;
    o->flux_up = 0U;
    o->torque_dem = 0;
    im_out_report(c, o, te);
}

/* The estimator input's part common to both schemes (currents, rotor-flux reference, speed, and
 * the angle on the speed-loop periods). */
static inline void im_dtc_ein_common(im_dtc_t *c)
{
    im_est_in_t *in = &c->ein;
    in->i_alpha_iq = c->i.i_alpha_iq;
    in->i_beta_iq = c->i.i_beta_iq;
    in->psir_ref_iq = c->psir_ref_iq;
    in->speed_iq = c->speed_iq;
    /* the rotor-flux angle and magnitude (CORDIC) only where the speed loop runs: sensorless
     * speed, telemetry */
    in->want_polar = (uint16_t)(c->div_cnt == 0U ? 1U : 0U);
}

#endif /* IM_DTC_H */
