/*
 * park.h - rotation between the stationary (alpha, beta) frame and a rotating (d, q) frame at the
 * angle theta (Park; with the amplitude-invariant Clarke of clarke.h, Hoang eqs. 4-5, the d and q
 * components keep the peak phase values):
 *     x_d =  x_alpha cos(theta) + x_beta sin(theta)
 *     x_q = -x_alpha sin(theta) + x_beta cos(theta)
 * and back (inverse Park):
 *     x_alpha = x_d cos(theta) - x_q sin(theta)
 *     x_beta  = x_d sin(theta) + x_q cos(theta)
 * For the PM machine theta is the electrical rotor angle from the encoder (flux_est_angle), the
 * d axis on the magnet flux (the direction of the current model's psi_m e^{j theta_e}, Hoang
 * eqs. 8-9). The sine and cosine are taken once per period (park_sincos) and shared by the
 * forward and inverse rotation.
 *
 * Formats: x IQ pu (any IQ quantity: currents, voltages, fluxes); sin/cos Q15 (fix_sin, fix_cos:
 * within 1.2 Q15 LSB of the true values).
 * Scaling and overflow: each output is a two-term sum of IQ x Q15 products formed exactly in 64
 * bits (each |product| < 2^46) and rounded once (<= 0.5 IQ LSB), then saturated to the IQ range
 * (only for |x| beyond 90 pu). The error against the exact rotation is dominated by the Q15
 * sine: |x| * 1.7 * 2^-15 relative, 5e-5 pu at 1 pu.
 */
#ifndef PARK_H
#define PARK_H

#include "fixmath.h"

typedef struct {
    q15_t cos_q15, sin_q15;
} park_sc_t;

/* cos and sin of theta (angle_t, one turn = 65536), Q15. */
static inline void park_sincos(angle_t theta, park_sc_t *sc)
{
    fix_sincos(theta, &sc->sin_q15, &sc->cos_q15);
}

/* (alpha, beta) -> (d, q). */
static inline void park_fwd(const park_sc_t *sc, iq_t x_alpha_iq, iq_t x_beta_iq, iq_t *x_d_iq, iq_t *x_q_iq)
{
    *x_d_iq = fix_rshift_rnd64_sat32((int64_t)x_alpha_iq * sc->cos_q15 + (int64_t)x_beta_iq * sc->sin_q15, 15U);
    *x_q_iq = fix_rshift_rnd64_sat32((int64_t)x_beta_iq * sc->cos_q15 - (int64_t)x_alpha_iq * sc->sin_q15, 15U);
}

/* (d, q) -> (alpha, beta). */
static inline void park_inv(const park_sc_t *sc, iq_t x_d_iq, iq_t x_q_iq, iq_t *x_alpha_iq, iq_t *x_beta_iq)
{
    *x_alpha_iq = fix_rshift_rnd64_sat32((int64_t)x_d_iq * sc->cos_q15 - (int64_t)x_q_iq * sc->sin_q15, 15U);
    *x_beta_iq = fix_rshift_rnd64_sat32((int64_t)x_d_iq * sc->sin_q15 + (int64_t)x_q_iq * sc->cos_q15, 15U);
}

#endif /* PARK_H */
