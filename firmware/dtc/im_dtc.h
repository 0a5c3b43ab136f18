/*
 * im_dtc.h - the induction-machine control law: DTC and DSC of Casadei et al. 2006 (sections 2-9,
 * 10.1-10.2, 12), one im_dtc_step() per control period, the speed loop every speed_div-th call.
 * A module beside the PM law (dtc.h), with the same init/reset/step shape; the application
 * dispatches between them (app/law.h). Its functions internal to its files: im_dtc_internal.h. Shared blocks, not copies: Clarke (clarke.h), voltage
 * reconstruction (vrec.h) with drop (vcomp.h) and dead-time (vrec.h deadtime_error) compensation, the
 * hysteresis comparators (hyst.h), the switching tables and the null-vector choice (swtab.h),
 * the sector (sector.h), speed measurement and PI (speed_meas.h, speed_pi.h), the reference set
 * and its shadow (dtc_refs.h).
 *
 *   Clarke -> v(legs applied over the period that ends now) + drop and dead-time compensation
 *   -> stator flux: voltage model (Casadei eq. 1, low-pass) or improved estimator (eq. 20, tau
 *      fixed or speed-dependent, section 10.2)                                        (im_est.h)
 *   -> rotor flux (eq. 21), its angle (eq. 22) and magnitude; torque (appendix Casadei eq. A10, torque.h)
 *   -> speed: encoder (speed_meas.h) or sensorless, rotor-flux angular speed minus the slip of
 *      Casadei eq. 16 (im_ref.h); speed PI every speed_div-th step (speed mode)
 *   -> references: start-up (magnetise at zero torque, Casadei Fig. 17b), flux weakening (section 12:
 *      phi_s* from the torque-comparator monitor, T* by Casadei eqs. 33-34, im_fw.h), stator flux from a
 *      constant rotor flux (eq. 19, im_ref.h) or the stator-flux reference
 *   -> flux comparator on |phi_s|^2 (hyst2_sq_step), torque comparator three-level (Table 1) or
 *      two-level (Table 3)
 *   -> scheme DTC: Casadei Table 1 (basic), ST-A..ST-D (Table 3), speed-dependent (section 8: ST-D below
 *      the configured speed, ST-A above); or DSC (section 9, dsc.h: hexagon by the phase-flux
 *      comparators, torque by null vectors, above the section 8 speed; ST-D's circle below it,
 *      im_dsc_hexagon); the null vector chosen for the fewest commutations
 *   -> leg states for the next period.
 * The law DTC_LAW_IM_DSVM (im_dsvm.c) keeps the comparators with a five-level torque comparator
 * and the DSVM tables of Casadei section 11 (dsvm.h), three sub-intervals per period in the PWM
 * form. The laws DTC_LAW_IM_SFVC and DTC_LAW_IM_DFOC (im_sfvc.c, im_dfoc.c) share the estimator,
 * speed loop, start-up and references (im_dtc_front, im_dtc_refs) and replace the comparators and
 * the table by a voltage reference applied through the SVM (svm.h): the PWM form for the next
 * period (im_pwm_out).
 *
 * Start-up (Casadei section 10.2, Fig. 17b): after a reset the torque reference is held at zero
 * and the speed PI at rest for im_magn_periods control periods. The stator-flux reference is
 * ramped from zero to its no-load value by im_magn_ramp_iq per period: at DC (Casadei eqs. A7-A9,
 * w = 0) phi_s = sigma l_s i + (m/l_r) phi_r and d phi_r/dt = (m i - phi_r)/tau_r, so a step of
 * phi_s* sends the current towards phi_s* / (sigma l_s) (5.7x rated on the default IM), while a ramp
 * at rho holds it at phi_r/m + tau_r rho/l_s: the host derives rho = (I_n - I_m) l_s/tau_r from the
 * rated current I_n and the final magnetising current I_m (dtc_config_si.c), so the current
 * stays below I_n. The estimator's rotor-flux reference is meanwhile the rotor flux of the current
 * model, tau_r d|phi_r|/dt = m i_d - |phi_r| (exact at DC). After the ramp the estimate cannot tell when the
 * machine is magnetised: at DC the improved estimator's correction (Casadei eq. 20) pulls the estimated
 * rotor flux to its reference within tau whatever the machine's, while the machine's rotor flux
 * rises as 1 - exp(-t/tau_r) (eq. 9 with the estimator's DC error: d phi_r/dt = -(r_r/l_r)
 * (phi_r - phi_r*)); the host converts the fraction to reach into that time.
 * Meanwhile, with the rotor at rest (a turning rotor, or no encoder: im_magn_vector), the flux is built by the
 * radial vector: the active vector V_k of the stator flux's own sector k while the flux
 * comparator asks for more flux, a null vector otherwise. V_k lies
 * within +-30 degrees of the flux: it raises |phi_s| and applies almost no torque, so the phase
 * currents settle to the DC magnetising current, as in Casadei Fig. 17b. (Table 1 itself cannot start a
 * demagnetised machine at zero torque: with T* = T = 0 the three-level comparator stays at 0 and
 * the table gives null vectors only.) The low-pass voltage model alone would lose the estimate of
 * this DC flux and over-magnetise the machine (the paper's Casadei Fig. 17a statement that the pure
 * integrator cannot magnetise the machine at zero torque); the improved estimator's correction
 * holds it, and the voltage model takes the same correction during the start-up (im_est.h).
 *
 * Encoder plausibility (speed.sensor = DTC_SPEED_ENCODER and u.im.ref.enc_plaus_iq > 0): on every
 * speed-loop period the sensorless speed (the rotor-flux angular speed minus the slip of Casadei
 * eq. 16, im_ref.h) is formed as well, and the encoder's speed is passed through the same
 * first-order filter, so that a change of speed delays both alike; their difference is the
 * application's to judge (app/law.h law_enc_plaus, app_enc.h). The check holds while the estimated
 * rotor flux is below phi_r* / 16 (its angle is not yet defined: the start of the magnetisation),
 * the filtered encoder speed following the sensorless one meanwhile, so both filters leave the
 * same state. It costs one im_speed_step and one filter step per speed period, in a step of its
 * own before the model supervision's (the second step, im_dtc_internal.h im_plaus_slot), on the
 * speed-loop step's values (the angle and |phi_r| of the CORDIC that ended before it, the
 * encoder's speed, the torque estimate and whether the machine was magnetised, all held since):
 * the same sums and decisions as in the speed-loop step, the application's judgement
 * (plaus_on) one period later, and the speed-loop step carries none of it.
 *
 * Timing contract as the PM law (dtc.h): the command of step k acts in period k+1; the voltage
 * integrated at step k is that of the legs returned at step k-2. The IM law has no actuation-
 * delay prediction (u.pm_dtc.est.delay_comp is the PM law's): the comparators see the estimate at k.
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
#include "dtc_config.h"
#include "dtc_refs.h"
#include "hyst.h"
#include "ilim.h"
#include "im_est.h"
#include "im_fw.h"
#include "im_ref.h"
#include "im_sup.h"
#include "law_io.h"
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
    uint16_t dsc_on;      /* DSC: 1 while the hexagon runs (dsc_reset done), 0 on the circular path */
    swtab_legs_t legs_1;  /* returned by the previous step: applied during this period */
    swtab_legs_t legs_2;  /* returned two steps ago: applied during the period just ended */
    swtab_legs_t legs_3;  /* returned three steps ago (dead time) */
    uint16_t vec_1;       /* vector returned by the previous step */
    int16_t tdem_1;       /* torque comparator's demand of the previous step (+1, 0, -1) */
    iq_t te_cmd_iq;       /* torque command: speed PI output or the torque reference */
    iq_t te_trim_iq;      /* torque mode: mean-torque trim (dtc_trim_step) */
    iq_t te_ref_iq;       /* torque reference in force (after start-up and Casadei eqs. 33-34) */
    iq_t psi_ref_iq;      /* stator-flux reference in force (Casadei eq. 19, section 12, or the set) */
    iq_t psir_ref_iq;     /* rotor-flux reference of the improved estimator (Casadei eq. 20) */
    iq_t psir_trim_iq;    /* constant rotor flux: the integral of phi_r* - |phi_r| (im_psir_trim), pu */
    uint16_t magn_n;      /* start-up: periods of magnetisation so far */
    iq_t magn_psir_iq;    /* rotor-flux magnitude of the current model: the start-up's (im_dtc_refs)
                           * and, after a reconfiguration, the FSTP's (im_dtc_fstp.c) */
    uint16_t ref_due;     /* the rotor-flux trim (1) or Casadei eq. 19 (2) to be evaluated (im_dtc_refs) */
    uint16_t ref_slot;    /* the step whose div_cnt (after its increment in im_dtc_speed) evaluates
                           * Casadei eq. 19: 6, a step of its own, the one after the rotor-flux
                           * trim's (5, im_dtc_internal.h im_trim_slot), that carries neither the
                           * CORDIC's halves (9, 0), nor the speed loop (1), nor the encoder
                           * plausibility's comparison (2), nor the supervision (4), and is even
                           * (the application's plausibility window of 2^k periods ends on steps
                           * of one parity of div_cnt: the odd ones, im_dtc_internal.h); 2 (with
                           * the trim) for speed_div 3..6, 0 below */
    iq_t speed_iq;        /* electrical speed in use (encoder or estimated), pu */
    /* encoder plausibility (u.im.ref.enc_plaus_iq > 0 with the encoder; im_dtc_speed) */
    iq_t enc_filt_iq;     /* the encoder's speed through the sensorless speed's filter, pu */
    iq_t plaus_err_iq;    /* sensorless speed - enc_filt_iq of the last speed period, pu; from the
                           * speed-loop step to the comparison's (plaus_on 0 meanwhile) it holds
                           * that step's torque estimate, which the comparison takes */
    uint16_t plaus_on;    /* 1: plaus_err_iq compared in this step (the third step after a
                           * speed-loop step, flux built: im_dtc_speed) */
    iq_t plaus_psir_iq;   /* |phi_r| from which the flux angle is trusted: phi_r* / 16, pu */
    /* the comparison waits in sup.due (bit 1; bit 2: the machine was magnetised in the speed-loop
     * step) for the step whose div_cnt (after its increment in im_dtc_speed) is 2, the one after
     * the speed loop's (im_dtc_internal.h im_plaus_slot: 3 for speed_div 4..6, 0 below); the
     * supervision (im_sup.h slot) comes after it */
    /* working values of one step, kept here rather than on the stack (budget: <= 256 bytes of
     * stack on the Cortex-M0 proxy, tools/bench) */
    clarke_out_t i;       /* currents of this step */
    clarke_out_t i_prev;  /* currents of the previous step: the switching instant of the period that
                           * ends now, for its dead-time error (im_dtc_estimate) */
    im_est_in_t ein;      /* estimator input */
    iq_t dva_iq, dvb_iq;  /* a compensation term */
    vcomp_tab_t vc_t;     /* vc_p as a table of the currents' signs (im_vcomp) */
    /* the SVM schemes: stator-flux vector control (DTC_LAW_IM_SFVC, im_sfvc.c) and rotor-flux-
     * oriented control (DTC_LAW_IM_DFOC, im_dfoc.c) */
    svm_params_t svm_p;
    svm_t svm;
    svm_out_t svm_o;      /* the modulation of this step */
    iq_t v1_alpha_iq, v1_beta_iq; /* voltage of the duties returned by the previous step (their
                                   * d_eff on the link measured then): acts in this period, pu */
    iq_t v2_alpha_iq, v2_beta_iq; /* returned two steps ago: the period that ends now, pu */
    iq_t vs_alpha_iq, vs_beta_iq; /* stator-voltage reference v_s* of Casadei eq. 24 of this step, pu */
    /* constant products of the configuration (im_dtc_init), Casadei eqs. 16, 18, 24 */
    iq_t sfvc_kpd_iq;     /* K_p (l_s/m)(phi_r* + psir_trim): K_p times the d component of Casadei eq. 18
                           * (im_sfvc_kpd: at init, at a reset and when the trim moves) */
    iq_t sfvc_kpq_iq;     /* K_p (l_s/m) sigma l_r / phi_r*: K_p times Casadei eq. 18's q component per pu T* */
    iq_t sfvc_kslip_iq;   /* r_r / phi_r*^2: Casadei eq. 16's slip per pu torque */
    /* SFVC, DFOC: the period's terms of T* and w (im_svm_rate), kept with the T*, w and slip gain
     * they were formed for (sr_valid = 0: none formed since the reset) */
    iq_t sr_te_iq, sr_w_iq, sr_kslip_iq;
    iq_t sr_ws_iq;        /* w_s = w + w_slip (Casadei eq. 16), pu */
    iq_t sr_adv_iq;       /* w_s t_adv: the SFVC's w_s Ts, the DFOC's 1.5 w_s Ts, pu */
    iq_t sr_gt_iq;        /* g T*: the SFVC's K_p times Casadei eq. 18's q component, the DFOC's i_q*, pu */
    uint16_t sr_valid;
    iq_t foc_id_int_iq, foc_iq_int_iq; /* DFOC: the current PIs' integral parts, pu voltage */
    iq_t foc_id_ref_iq;   /* DFOC: i_d* = phi_r* / m with the rotor-flux trim and the flux term (im_dfoc_id_ref), pu */
    int32_t foc_kf_q16;   /* DFOC: (l_r/m)(tau_r/Ts), Q16: the rotor-flux term's gain per Ts/tau (im_dfoc_init) */
    deadtime_params_t dt_p; /* dead-time block's parameters (vrec.h), derived at init */
    /* the current limit of the switching-table laws (DTC, DSC, DSVM; ilim.h): its parameters
     * (prot.i_lim_iq, six-switch) and whether it replaced this step's vector */
    ilim_params_t il_p;
    iq_t il_box_iq;       /* I_lim / sqrt2: the square inside the limit's circle (im_ilim) */
    uint16_t i_limited;
    /* the current prediction's constants (im_dtc_i_pred), derived at init */
    iq_t ip_a_iq;         /* a = Ts / (sigma l_s) */
    iq_t ip_b_iq;         /* b = (Ts/tau_r) / (sigma l_s), Ts/tau_r = Ts r_r / l_r */
    iq_t ip_g_iq;         /* g = a r_s + b (m^2/l_r + sigma l_s) */
    iq_t pwm_dv_iq;       /* the modulated laws (SFVC, DFOC, DSVM): V_d - V_CE under the per-leg
                           * compensation (Hoang Table III, DTC_COMP_SSTP_PROPOSED), else 0, pu.
                           * A leg at duty d carrying i > 0 gives d (V_dc - V_CE) - (1 - d) V_d, with
                           * i < 0 d (V_dc + V_d) + (1 - d) V_CE: the state-0 drops the estimator
                           * adds (im_sfvc_estimate: +V_d, -V_CE) plus d (V_dc + V_d - V_CE) in
                           * both cases, so the duties act on V_dc + V_d - V_CE (0.35 V more on
                           * the IM rig's devices: at 72 rpm the estimate's voltage 0.06 % short
                           * of the machine's, +0.8 % of torque at 10 % of rated, SFVC) */
    iq_t dsvm_rip_iq[8];  /* DSVM: by a leg's pattern s1 s2 s3 (bit 2 = s1), k (s1 - s3) with
                           * k = r_s a / 9: the resistive drop of the period's mean ripple current
                           * in duty (im_dsvm.c), IQ */
    im_sup_t sup;         /* the model's supervision and the on-line r_r (im_sup.h) */
    /* after a live reconfiguration (im_dtc_reconfigure): the periods left until the relay has
     * tied the failed phase A' to the mid-point (A' open meanwhile, im_dtc_fstp.c), and the
     * rotor's r_r / l_r for that interval's alpha voltage, pu */
    uint16_t open_wait;
    iq_t rr_lr_iq;
    /* from the reconfiguration until the machine's rotor flux has fallen to the FSTP's reference:
     * 1 while the estimator's rotor-flux reference follows the current model's rotor flux
     * (magn_psir_iq, im_dtc_fstp.c im_fstp_psir_fall) */
    uint16_t psir_fall;
    /* while phase A' is open after the reconfiguration (im_dtc_fstp.c), pu: V_dc / sqrt3, the
     * beta vectors' length (Hoang Table I), and the shorter alpha vector on the measured
     * mid-point, (2/3) min(V_mid, V_dc - V_mid) */
    iq_t vb_max_iq;
    iq_t va_min_iq;
} im_dtc_t;

/* The IM laws' configuration check (im_dtc_check.c): the common part, then one of the laws
 * DTC_LAW_IM_DTC .. DTC_LAW_IM_DSVM and its part u.im. Returns DTC_OK or the first enum dtc_err
 * code; *field (if not null) names the field ("u.im.machine.rr_iq"), "" on DTC_OK. Pure, init
 * only. */
int16_t im_dtc_check(const dtc_config_t *cfg, const char **field);
/* Checks cfg (im_dtc_check) and initialises c. Returns DTC_OK or an enum dtc_err code; on error
 * c->cfg = 0 and c must not be stepped. */
int16_t im_dtc_init(im_dtc_t *c, const dtc_config_t *cfg);
/* Back to the start: demagnetised estimate, start-up magnetisation pending, references kept. */
void im_dtc_reset(im_dtc_t *c);
/* One control period (dtc_out_t as the PM law; theta_e is the rotor-flux angle, Casadei eq. 22). */
void im_dtc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* The phase currents (IQ pu, phases a, b, c) predicted for the next sample, after a step, from
 * the voltage committed for the coming period (the legs returned by the previous step with the
 * link voltage vdc_iq for DTC and DSC; the duties' or thirds' mean voltage kept by SFVC, DFOC and
 * DSVM) and the T model of Casadei eqs. A7-A9 in the stator frame, with
 * phi_s = sigma l_s i + x, x = (m/l_r) phi_r (eq. 21 over k_r = l_r/m):
 *   sigma l_s di/dt = v - r_s i - dx/dt,
 *   dx/dt = (r_r/l_r) ((m^2/l_r) i - x) + j w x      (the rotor equation, w the rotor's
 *                                                     electrical speed in use: the slip is in the
 *                                                     first term, so no torque or slip estimate)
 * by forward Euler over one period:
 *   i(k+1) = i(k) + (1/(sigma l_s)) [Ts (v - r_s i) - (Ts/tau_r) ((m^2/l_r) i - x) - w Ts j x]
 *          = i(k) + a v - g i + b phi_s - w a j x
 * with the constants of init (im_dtc_t ip_*): a = Ts/(sigma l_s), b = (Ts/tau_r)/(sigma l_s),
 * g = a r_s + b (m^2/l_r + sigma l_s). The rotation over the period is taken to second order,
 * w Ts j x -> (e^{j w Ts} - 1) x ~ (j w Ts - (w Ts)^2 / 2) x, which adds h x, h = w a (w Ts) / 2:
 * with a long period at speed (DFOC at a 1.6 kHz carrier, 1440 rpm: w Ts = 0.18 rad) the
 * first-order step leaves (w Ts)^2 / 2 = 1.6 % of the back-EMF's change a period, more than the
 * SVM's current change. Fifteen IQ products a period.
 * What it leaves out (the devices' drops and dead time, parameter errors) is nearly constant
 * over a few periods: the plausibility that reads it (app/app_plaus.h) learns and removes such a
 * bias. For the application's current-sensor plausibility only; the law itself does not use it.
 * Formats IQ pu; rounded IQ products, saturating sums (|di| saturates at +-128 pu, no wrap). */
void im_dtc_i_pred(const im_dtc_t *c, iq_t vdc_iq, iq_t i1[3]);

/* The law DTC_LAW_IM_DTC's control period on the four-switch inverter (board.topology =
 * DTC_TOPO_FSTP, im_dtc_fstp.c): the same estimator, speed loop, start-up and references as
 * im_dtc_step on the FSTP's currents and phase voltages (leg A on the measured mid-point), the
 * two-level comparators and Hoang Table II's four-sector table, the current limit over its four
 * vectors. law.c calls it for that configuration, chosen at init or by im_dtc_reconfigure. */
void im_dtc_step_fstp(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* Live reconfiguration of a six-switch DTC_LAW_IM_DTC drive after leg `phase` (0..2 = A..C)
 * failed (im_dtc_reconfig.c): the law goes on as DTC_LAW_IM_DTC on the FSTP of post (post must be
 * that law on the FSTP and pass im_dtc_check), with phase A' = `phase` on the mid-point and
 * B', C' the legs phase+1, phase+2 (mod 3); the caller permutes the measurements and the legs
 * (app_core.c reconfigure). Returns DTC_OK, or DTC_ERR_RECONFIG with c unchanged. Init-time code
 * (flash on the F2812), run once in the ISR that found the failure; then step with
 * im_dtc_step_fstp. */
int16_t im_dtc_reconfigure(im_dtc_t *c, const dtc_config_t *post, uint16_t phase);

/* The law DTC_LAW_IM_SFVC's control period (im_sfvc.c): the same estimator, speed loop,
 * start-up and references as im_dtc_step, then the stator-flux regulator of Casadei eqs. 18, 23,
 * 24 and the SVM (svm.h); the output is the PWM form (LAW_OUT_DUTY, duty_iq). law.c calls
 * it for DTC_LAW_IM_SFVC. */
void im_sfvc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* The law DTC_LAW_IM_DFOC's control period (im_dfoc.c): rotor-flux-oriented control of Casadei
 * section 13 with the same estimator, speed loop, start-up and references, PI current regulators
 * in the rotor-flux frame, the SVM. law.c calls it for DTC_LAW_IM_DFOC. */
void im_dfoc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

/* The law DTC_LAW_IM_DSVM's control period (im_dsvm.c): the same estimator, speed loop,
 * start-up and references as im_dtc_step, then the flux comparator, the five-level torque
 * comparator and the switching tables of Casadei section 11 (dsvm.h); the output is the three
 * sub-interval states per leg (LAW_OUT_THIRDS, thirds). law.c calls it for DTC_LAW_IM_DSVM. */
void im_dsvm_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o);

#endif /* IM_DTC_H */
