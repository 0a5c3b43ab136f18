/*
 * im_sup.h - supervision of the induction machine's model (IM laws, im_dtc.h): the improved
 * estimator's rotor flux (Casadei eqs. 20-22) set against a current model's, a mismatch of r_r or m
 * reported as a warning (app_warn.h APP_WARN_IM_MODEL_MISMATCH), and r_r tracked on line.
 * Everything here runs once per speed period, on the speed and the encoder plausibility's values
 * of the speed period (im_dtc_speed) and the sample of its own step, in a later step that carries
 * neither the speed loop, nor Casadei eq. 19, nor the plausibility's comparison (slot), so the
 * worst step does not grow; never in the other control periods.
 *
 * Current model of the rotor-flux magnitude (Casadei eqs. A7, A9 in the frame of the rotor flux,
 * the form of the start-up model in im_dtc_refs):
 *     tau_r d|phi_r|/dt = m i_d - |phi_r|,   i_d = i . e^{j theta} (Casadei eq. 22's direction),
 * forward Euler over the speed period T_sp (T_sp/tau_r = speed_div Ts r_r/l_r < 0.05). At steady
 * state |phi_r| = m i_d whatever r_r: with the configured m it is the machine's rotor flux only if
 * m is the machine's, while the improved estimator's |phi_r| (eq. 21, voltage model pulled towards
 * phi_r*) does not use m's value at speed. Their difference beyond 1/8 of the estimator's |phi_r| is
 * a magnetising-inductance (or leakage) mismatch.
 *
 * Rotor resistance, encoder fitted: a model-reference adaptive scheme (MRAS; the reference model is
 * the improved estimator's rotor-flux angle, independent of r_r; the adjustable model is the
 * current model's rotor-flux angle, which turns at the rotor speed plus the slip of Casadei eq. 16;
 * the adaptation drives the rate of their angle error to zero: the rotor-time-constant
 * identification by flux-angle/slip comparison reviewed by Krishnan and Bharadwaj, "A review of
 * parameter sensitivity and adaptation in indirect vector controlled induction motor drive
 * systems", IEEE Trans. Power Electron. 6(4), 1991). The measured slip is the rotor-flux angular
 * speed (Casadei eq. 22's angle over the speed period, filtered) less the encoder's speed through the
 * same filter (im_dtc_enc_plaus); the model's slip is Casadei eq. 16 with the estimate r_r^ =
 * rho r_r,cfg and the current model's flux,
 *     w_slip^ = r_r^ T / |phi_r,cm|^2 = r_r^ T (1/phi_r*^2) / q,  q = |phi_r,cm|^2 / phi_r*^2,
 * 1/q ~ 1 - d + d^2 (d = q - 1, |d| < 1/4: error below d^3, 1.6 %), so no division. The
 * adaptation (integral, the error's sign times the torque's sign: the slip grows with r_r in the
 * sense of the torque):
 *     rho += k_rho (w_slip,meas - w_slip^) sgn(T),  k_rho = k_filt / (4 w_slip,lim),
 * with k_filt = T_sp / T_filt the speed filter's gain and w_slip,lim eq. 16's slip at the torque limit:
 * its time constant is 4 T_filt T_lim / |T|, four times the filter's lag at the torque limit
 * (stable with the filter in the loop), longer at lower torque. It runs while the machine is
 * magnetised, |T| > T_lim / 32, |w| above the speed w_min = r_s I_lim / phi_s* at which the
 * resistive drop at the current limit equals the back-EMF (below it an error of r_s moves the
 * voltage model's angle more than r_r moves the slip), and |d| < 1/4 (the rotor flux near its
 * reference: not during the build-up, not deep in the flux weakening). rho stays in [1/2, 2].
 * |rho - 1| > 1/5 is a rotor-resistance mismatch (an error of m also moves rho: the slip goes with
 * 1/|phi_r|^2; the flux check tells them apart).
 * Tracking (u.im.ref.rr_track = 1): the sensorless speed's and the SFVC's slip use r_r^, and the
 * estimator's r_s is scaled by the same rho: the stator and rotor windings are taken at one
 * temperature with one coefficient (copper both, 0.39 %/K), so the rotor's resistance tells the
 * stator's (an r_s error is what biases the voltage model's flux and the torque estimate at low
 * speed; r_r itself enters no torque estimate). Without tracking rho is estimated and reported only.
 *
 * Without the encoder the slip cannot be measured (the speed is the flux speed less eq. 16's
 * slip, in which r_r is the unknown): an r_r error becomes a speed error and nothing in the
 * stator's quantities shows it in steady state. The flux check (m) runs without the encoder.
 *
 * The current model as the improved estimator's reference at low speed (u.im.ref.cm_ref, encoder
 * fitted, improved estimator; the converter's default: the torque target at 5 % of rated speed
 * needs it. With it the estimator is not Casadei's at low speed: the paper's figures reproduced
 * in tests/sil/test_im_casadei*.cpp run with it off, eq. 20 alone). Casadei eq. 20's correction
 * (phi_r* e^{j theta} - phi_r)/tau is radial: an error of
 * the estimate's angle decays only as the stator frequency turns it into a radial one, through the
 * estimator's slow pole w_s^2 tau / k_r (tau from k_lo), and the rotor-flux trim's integral
 * (im_psir_trim, gain 1/tau_r) closes its loop through that pole: damping sqrt(a tau_r)/2 with
 * a = w^2 tau / k_r, below 1/2 when a < 1/tau_r (measured: the mean torque per stator period
 * ringing +-2-3 % of T* at 0.65 Hz for seconds at 72 rpm). Below that speed the correction pulls
 * towards the rotor flux of the current model, which sees the angle (the classic current-model /
 * voltage-model observer; Casadei eq. 20 keeps phi_r* e^{j theta} at every speed), the T model's
 * rotor equation in the stator frame with the encoder's electrical speed w (Casadei eqs. A7, A9),
 *     d phi_r,cm/dt = (m i_s - phi_r,cm)/tau_r + j w phi_r,cm,
 * every period by a symplectic Euler step (alpha with the old beta, beta with the new alpha: the
 * rotation's determinant is 1, so the step adds no growth of |phi_r,cm|),
 *     cm_a += (Ts/tau_r)(m i_a - cm_a) - w Ts cm_b,  cm_b += (Ts/tau_r)(m i_b - cm_b) + w Ts cm_a,
 * i of the previous sampling instant (forward Euler), and the reference of the previous instant
 * (im_dtc_internal.h im_cm_ref: the instant of the estimate that eq. 20 corrects). The rotation
 * w Ts is the rotor's electrical angle step between the two instants, the encoder's count
 * difference times 2 pi p / counts: the model is as sensitive to its speed as the slip it
 * carries (an error dw of w turns its flux by about dw tau_r against the current's), and the
 * measured speed (speed_meas.h) is a mean over up to 16 speed periods, late by half its window:
 * measured, a free rotor accelerating at 19,000 rpm/s under rated torque (4 kW, ideal inverter)
 * had the machine's rotor flux moving 4.9 % of phi_r* with the speed period's speed, 0.9 % with
 * the count difference. The count's quantisation (2 pi p / counts, 1.6 mrad electrical at 8000
 * counts and p = 2) enters each step's rotation but not the sum over steps.
 * The reference is phi_r* e^{j theta} + b (phi_r,cm - phi_r* e^{j theta}), with b linear in the
 * slow pole: 1 while a <= 1/tau_r (damping <= 1/2), 0 from a >= 4/tau_r (damping 1), that is
 * b = clamp(4/3 - (w Ts)^2 / (3W), 0, 1), W = k_r (Ts/tau)(Ts/tau_r) the (w Ts)^2 at which
 * a = 1/tau_r. Above the blend the reference is the paper's alone and the current model (whose
 * angle rests on r_r) is not run; when b rises again it starts from the estimate's rotor flux. It
 * takes over once the start-up's magnetisation ends (before it, the start-up's reference: im_dtc.h).
 * Not with DSVM: its thirds in a fixed order move the period's mean current off the line between
 * the samples (im_dsvm.c, dsvm_rip_iq), and the model's input, the sampled current, then carries
 * that mean: measured +1.7 % (4 kW) / +1.9 % (second machine) of torque at 10 % speed and torque
 * with the model, against +0.48 % on the second machine without it (the ripple's mean current is not
 * fed to the model).
 * The flux check above compares the magnitude model with the estimate, which at low speed follows
 * the current model of the same m: an m mismatch shows there above the blend only.
 *
 * Warning: a condition held for n_confirm consecutive speed periods (4 T_filt) sets warn; it
 * clears when no condition holds. Formats: IQ pu; rho IQ (1.0 = configured); gains Q31 / IQ.
 * Overflow: rounded IQ products and saturating sums; rho and the errors are clamped.
 */
#ifndef IM_SUP_H
#define IM_SUP_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    /* derived at init (im_sup_init, from the configuration) */
    iq_t rr_cfg_iq;       /* r_r of the configuration, pu */
    iq_t rs_cfg_iq;       /* r_s of the configuration, pu */
    iq_t kslip_cfg_iq;    /* SFVC's r_r / phi_r*^2 of the configuration */
    iq_t k_rho_iq;        /* k_rho: change of rho per speed period per pu slip error */
    q31_t k_cm_q31;       /* T_sp / tau_r of the current model */
    iq_t w_min_iq;        /* |speed| from which rho adapts, pu */
    iq_t te_min_iq;       /* |torque| from which rho adapts, pu */
    uint16_t n_confirm;   /* speed periods a condition must hold for the warning */
    uint16_t track;       /* 1: r_r^ (and r_s by rho) in use */
    uint16_t slot;        /* im_sup_step runs in the step whose div_cnt (after its increment in
                           * im_dtc_speed) is this: 4, three steps after the speed loop's, two after
                           * the encoder plausibility's comparison (im_dtc_internal.h im_plaus_slot)
                           * and before the rotor-flux trim's (im_trim_slot); 0 (the last step
                           * of the speed period) for speed_div < 5 */
    uint16_t cm_on;       /* 1: the improved estimator with the encoder, not DSVM: the current model's vector
                           * (below) blended into Casadei eq. 20's reference at low speed */
    uint16_t cm_n;        /* 3W's normalising shift: 3W 2^cm_n in [1/2, 1) (Q31) */
    iq_t cm_inv_iq;       /* 1 / (3W 2^cm_n), IQ in (1, 2] */
    q31_t cm_k_q31;       /* the electrical angle of one encoder count, 2 pi p / counts, rad Q31 */
    /* state */
    iq_t rho_iq;          /* r_r^ / r_r,cfg */
    iq_t psir_cm_iq;      /* the current model's |phi_r|, pu */
    uint16_t due;         /* 1: a speed period's values wait for im_sup_step */
    uint16_t compared;    /* 1: the encoder plausibility compared in that speed period */
    uint16_t adapting;    /* 1: rho adapted in the last speed period */
    uint16_t n_bad;       /* consecutive speed periods with a condition */
    uint16_t cause;       /* bit 0: rho beyond 1/5, bit 1: |phi_r| differ beyond 1/8 (last period) */
    uint16_t warn;        /* 1: model mismatch (im_model_mismatch) */
    /* the rotor-flux current model's vector and its blend (im_dtc_internal.h im_cm_ref) */
    uint16_t cm_count;    /* the encoder count of the previous step (the model's rotation) */
    iq_t cm_b_iq;         /* blend weight b in [0, 1], IQ; 0: the paper's reference alone */
    iq_t cm_alpha_iq, cm_beta_iq; /* the current model's rotor flux, pu (stator frame) */
    iq_t cm_mi_alpha_iq, cm_mi_beta_iq; /* m i of the previous sampling instant, pu */
    uint16_t cm_run;      /* 1: the model is integrating (b > 0); 0: re-seeded when b rises */
} im_sup_t;

#endif /* IM_SUP_H */
