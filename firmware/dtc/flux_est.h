/*
 * flux_est.h - stator-flux estimators of the PM BLAC machine (Hoang section II-B).
 *
 * Voltage model (Hoang eqs. 15-16; with compensation eqs. 31-32, 37-38):
 *     d psi/dt = v + v_f - r_s i
 *   integrated, as in the paper's experiments, by a first-order low-pass with cut-off w_c
 *   (5 rad/s) instead of a pure integrator, to stop the drift caused by measurement offsets:
 *     psi(s) = (v + v_f - r_s i)(s) / (s + w_c)
 *   discretised exactly for a zero-order-held input over Ts (the input is piecewise constant
 *   within a period: the leg states are):
 *     psi[k+1] = psi[k] - k_leak * psi[k] + k_in * e[k],
 *     k_leak = 1 - exp(-w_c Ts),  k_in = k_leak / w_c,pu  (-> Ts_pu = Ts*w_base as w_c -> 0).
 *   The filter's known error against the true flux at electrical speed w (sinusoidal steady
 *   state): gain w/sqrt(w^2 + w_c^2), phase lead atan(w_c/w). At 1500 rpm (157 rad/s) that is
 *   -0.05 % and 1.8 deg; at 100 rpm (10.5 rad/s), -9.8 % and 25.5 deg.
 *
 *   Why the state needs 32 bits at 50 us: the per-sample leak is k_leak*psi = 2.5e-4 * 0.42 pu
 *   ~ 1.0e-4 pu. In Q15 that is 3.4 LSB: rounded, the low-pass becomes a dead band (any flux
 *   below 0.5/2.5e-4 = 2000 LSB = 0.061 pu does not leak at all, so an offset integrates freely
 *   up to there) and its cut-off is off by up to +-15 %. The per-sample increment at 100 rpm,
 *   Ts_pu * |v| ~ 0.0157 * 0.014 pu = 2.2e-4 pu = 7 Q15 LSB, would carry a 7 % rounding error
 *   every sample. In Q24 (and with k_leak, k_in in Q31) the leak is 1750 LSB and the increment
 *   3700 LSB: rounding is 3e-4 relative, and the state keeps the 7 integer bits of IQ. What is
 *   left of the dead band in Q24: the update is rounded once per step, so a quasi-static input
 *   settles within 0.5 LSB / k_leak = 2000 LSB = 1.2e-4 pu (0.03 % of psi_m) of the ideal
 *   equilibrium (test_dtc_flux_est measures it); with a moving input the rounding averages out
 *   (1e-6 relative at 100 and 1500 rpm).
 *
 *   With the gain/phase correction (lpfcorr.h, in->r_iq = r = w_c / w) the filtered input is
 *   e (1 - j r) instead of e: psi(s) = (1 - j r) e(s) / (s + w_c), whose state is the flux itself
 *   at the speed w, not the low-passed one.
 *
 * Current model (Hoang eqs. 8-9), surface PM (L_d = L_q = L_s):
 *     psi_alpha = l_s i_alpha + psi_m cos(theta_e),  psi_beta = l_s i_beta + psi_m sin(theta_e)
 *   theta_e from the encoder count: theta_e = count * enc_gain + enc_offset (angle_t).
 *   A salient PM (l_q != l_d; dl = l_q - l_d) has in the rotor frame psi_d = l_d i_d + psi_m,
 *   psi_q = l_q i_q (the rotor-frame model of which Hoang eqs. 8-9 are the l_d = l_q case);
 *   turned by theta_e into the stationary frame that is Hoang eqs. 8-9 with l_s = l_d plus the
 *   q axis's excess dl i_q along j e^{j theta_e}:
 *     psi_alpha += -dl i_q sin(theta_e),  psi_beta += dl i_q cos(theta_e),
 *     i_q = -i_alpha sin(theta_e) + i_beta cos(theta_e) (the Park transform's q axis).
 *   dl = 0 (a surface PM) skips it: the surface PM's flux is bit for bit Hoang eqs. 8-9.
 *
 * Formats: v, i, psi IQ pu; k_in, k_leak Q31 in (0, 1); theta angle_t.
 * Scaling and overflow: voltage model: k_in*e - k_leak*psi is accumulated in 64 bits (each
 * product < 2^62) and rounded ONCE (fix_rshift_rnd64_sat32), then added with saturation, so the
 * state saturates at +-128 pu and never wraps. The correction e (1 - j r) is two rounded products
 * and saturated sums (iq_cmul_1jx); |r| <= 1/2 (the host's speed floor) keeps it within 1.12 |e|.
 * Current model: two rounded IQ products (<= 0.5 LSB each) and fix_sincos (<= 2 Q15 LSB),
 * summed with saturation; the salient term: i_q of two rounded Q15 products (<= 1 LSB, |i_q| <=
 * |i|), dl i_q one rounded IQ product, its projections two rounded Q15 products, added with
 * saturation (no wrap for any input).
 */
#ifndef FLUX_EST_H
#define FLUX_EST_H

#include <stdint.h>

#include "fixmath.h"
#include "lpfcorr.h"

typedef struct {
    uint16_t estimator; /* enum dtc_estimator */
    q31_t k_in_q31;
    q31_t k_leak_q31;
    iq_t rs_iq;
    iq_t ls_iq;
    iq_t psi_m_iq;
    uint32_t enc_gain_q16; /* angle_t LSB per count, unsigned Q16 */
    angle_t enc_offset;
    iq_t dl_iq;            /* l_q - l_d (l_s), pu: 0 on a surface PM */
    iq_t inv_lq_iq;        /* 1 / l_q, pu (the salient PM laws' predictions; formed at init) */
} flux_est_params_t;

typedef struct {
    const flux_est_params_t *p;
    iq_t psi_alpha_iq; /* 32-bit state: see above */
    iq_t psi_beta_iq;
    angle_t theta_e;   /* last electrical angle (current model; also reported) */
} flux_est_t;

/* Input of one step: the voltage applied over the last period (already including the
 * compensation v_f), the stator currents, the encoder count for the current model, and the
 * low-pass correction r = w_c / w (lpfcorr.h; 0 = none): the voltage model then filters
 * e (1 - j r) instead of e, which makes the low-pass output the flux itself at the speed w. */
typedef struct {
    iq_t v_alpha_iq, v_beta_iq;
    iq_t i_alpha_iq, i_beta_iq;
    uint16_t enc_count;
    iq_t r_iq;
} flux_est_in_t;

/* Fills the input of one step (the fields above, in the same order). Inline: six stores. */
static inline void flux_est_in_set(flux_est_in_t *in, iq_t v_alpha, iq_t v_beta, iq_t i_alpha, iq_t i_beta,
                                   uint16_t enc_count, iq_t r)
{
    in->v_alpha_iq = v_alpha;
    in->v_beta_iq = v_beta;
    in->i_alpha_iq = i_alpha;
    in->i_beta_iq = i_beta;
    in->enc_count = enc_count;
    in->r_iq = r;
}

void flux_est_init(flux_est_t *s, const flux_est_params_t *p);
/* Zero flux (voltage model); the current model needs no memory. */
void flux_est_reset(flux_est_t *s);
/* Voltage model start-up: seeds the state with the current-model flux (Hoang eqs. 8-9) of the
 * measured currents and encoder angle. Without it the low-pass starts from zero and needs
 * several time constants (1/w_c = 0.2 s) to find the magnet flux, during which the DTC selects
 * vectors for the wrong flux position (the machine can stall or reverse). dtc_step() calls it
 * on the first step after a reset. */
void flux_est_seed(flux_est_t *s, const flux_est_in_t *in);
/* Hoang eqs. 8-9 into the state at the angle whose Q15 sine sn and cosine cs are given (the
 * surface PM's current model; flux_est_cm below adds the salient term). */
void flux_est_cm_surface(flux_est_t *s, const flux_est_in_t *in, q15_t sn, q15_t cs);
/* One 50 us step; the estimate is in s->psi_alpha_iq, s->psi_beta_iq afterwards. */
void flux_est_step(flux_est_t *s, const flux_est_in_t *in);
/* The current model's salient-PM term (above; pm_salient.c), added to the state's flux; the current
 * model calls it after Hoang eqs. 8-9 when dl_iq != 0. */
void flux_est_cm_salient(flux_est_t *s, const flux_est_in_t *in, q15_t sn, q15_t cs);
/* The current model (Hoang eqs. 8-9 and the salient term) at the angle already in s->theta_e,
 * whose Q15 sine sn and cosine cs (fix_sincos) the caller took, for a caller that needs the pair
 * elsewhere in the period (itc.c: the Park transform): flux_est_seed(s, in) is s->theta_e =
 * flux_est_angle(..), fix_sincos(s->theta_e, &sn, &cs), flux_est_cm(s, in, sn, cs), bit for bit.
 * Inline, the two parts called one after the other: on the Cortex-M0 stack chains (dtc_step,
 * itc_step) the salient part's frame does not sit on the surface part's. */
static inline void flux_est_cm(flux_est_t *s, const flux_est_in_t *in, q15_t sn, q15_t cs)
{
    flux_est_cm_surface(s, in, sn, cs);
    if (s->p->dl_iq != 0) {
        flux_est_cm_salient(s, in, sn, cs);
    }
}
/* The voltage model's step (Hoang eqs. 15-16) with the resistive drop r_s i (IQ pu, alpha/beta)
 * formed by the caller, for a caller that needs the same product elsewhere in the period
 * (dtc.c: the delay compensation). flux_est_step(s, in) of a voltage-model estimator is
 * flux_est_vm_step(s, in, iq_mpy(rs, i_alpha), iq_mpy(rs, i_beta)), bit for bit. Inline (after
 * flux_est_angle and flux_est_lpf below): the PM laws' 50 us path, where the call and its
 * arguments through memory cost a fifth of the step's own work. */
static inline void flux_est_vm_step(flux_est_t *s, const flux_est_in_t *in, iq_t ri_alpha_iq, iq_t ri_beta_iq);

/* The q-axis component of the stationary-frame vector (x_alpha, x_beta) at the angle whose Q15
 * sine and cosine are sn, cs (the Park transform's q axis): -x_alpha sin + x_beta cos. IQ; two
 * rounded Q15 products (<= 1 LSB), saturating difference. Inline: the salient current model and
 * the PM law's salient prediction (dtc.c) take the same projection. */
static inline iq_t flux_est_park_q(iq_t x_alpha_iq, iq_t x_beta_iq, q15_t sn, q15_t cs)
{
    return fix_sub32(iq_mpy_q15(x_beta_iq, cs), iq_mpy_q15(x_alpha_iq, sn));
}

/* Encoder count -> electrical angle (modulo one turn by design): bits 16-31 of the product of
 * the count and the Q16 gain, truncated; the error is < 1 angle LSB + count * 0.5/65536 LSB.
 * The product is formed modulo 2^32: the bits above 31 of the exact (48-bit) product are whole
 * turns, which the angle drops anyway, so the 32-bit product gives the same angle as the exact one
 * (one 32-bit multiply instead of a 64-bit one on the 16- and 32-bit targets). */
static inline angle_t flux_est_angle(uint16_t count, uint32_t gain_q16, angle_t offset)
{
    uint32_t a = ((uint32_t)count * gain_q16) >> 16;
    return (angle_t)((angle_t)(a & 0xFFFFU) + offset);
}

/* Voltage model, one exact-discretised low-pass step for one axis (exposed for the tests). */
static inline iq_t flux_est_lpf(iq_t psi_iq, iq_t e_iq, q31_t k_in_q31, q31_t k_leak_q31)
{
    int64_t acc = (int64_t)e_iq * (int64_t)k_in_q31 - (int64_t)psi_iq * (int64_t)k_leak_q31;
    return fix_add32(psi_iq, fix_rshift_rnd64_sat32(acc, 31U));
}

static inline void flux_est_vm_step(flux_est_t *s, const flux_est_in_t *in, iq_t ri_alpha_iq, iq_t ri_beta_iq)
{
    const flux_est_params_t *p = s->p;
    /* Hoang eqs. 15-16 (31-32, 37-38 with the compensation already in v), low-pass; the
     * gain/phase correction on its input (lpfcorr.h). */
    iq_t e_a = fix_sub32(in->v_alpha_iq, ri_alpha_iq);
    iq_t e_b = fix_sub32(in->v_beta_iq, ri_beta_iq);

    s->theta_e = flux_est_angle(in->enc_count, p->enc_gain_q16, p->enc_offset);
    lpfcorr_rotate(in->r_iq, &e_a, &e_b); /* r = 0: unchanged */
    s->psi_alpha_iq = flux_est_lpf(s->psi_alpha_iq, e_a, p->k_in_q31, p->k_leak_q31);
    s->psi_beta_iq = flux_est_lpf(s->psi_beta_iq, e_b, p->k_in_q31, p->k_leak_q31);
}

#endif /* FLUX_EST_H */
