/*
 * lpfcorr.h - gain and phase correction of the voltage model's low-pass (dtc_config.h lpf_comp).
 *
 * The voltage model integrates with 1/(s + w_c) instead of 1/s (flux_est.h), so in sinusoidal
 * steady state at electrical speed w its output is psi_l = psi jw / (jw + w_c) = psi / (1 - j r),
 * r = w_c / w: a gain w/sqrt(w^2 + w_c^2) and a lead atan(r) (issue 10: 6.8 / 15.8 / 23.4 % vector
 * error at 700 / 300 / 200 rpm for 5 rad/s). Undone on the output with the measured speed:
 *     psi = psi_l (1 - j r):  psi_a = psi_la + r psi_lb,  psi_b = psi_lb - r psi_la,
 * while the low-pass itself stays what bounds a DC error (E / w_c, flux_est.h). At the hand-over
 * the low-pass state must be the filter's steady state of the current-model flux psi_cm, so that
 * the corrected output starts at psi_cm (bumpless):
 *     state = psi_cm / (1 - j r) = psi_cm (1 + j r) / (1 + r^2) ~ psi_cm (1 + j r)(1 - r^2 + r^4)
 * (relative error r^6: 1.6 % at the floor r = 1/2, 4e-6 at r = 0.125).
 * r from the measured speed without a division: y ~ 1/max(|w|, w_min) by Newton's iteration
 * y <- y (2 - w y) (quadratic convergence for 0 < y < 2/w; two iterations per speed period from
 * the previous value track any physical speed change; restarted at y = 1/2 pu if w y > 3/2),
 * r = sign(w) w_c y. Below w_min the correction stays at its value for w_min (continuous, no
 * switching bump); w_min = 2 w_c (r <= 1/2, the corrected magnitude at most 1.12 times the
 * low-pass's) is set by the host. Measured (SIL, proposed FSTP, 0.075 N*m, voltage model from
 * standstill): with the floor at 4 w_c the estimated torque was 10 % low at 150 rpm and 81 % low
 * at 100 rpm; at 2 w_c it is within 1.2 % and 1.4 %.
 *
 * Formats: IQ pu (w, w_c, y, r, fluxes); products rounded (iq_mpy), sums saturated; y <= 1/w_min
 * (~16 pu for 5 rad/s and w_base = 314 rad/s) stays far inside the IQ range.
 */
#ifndef LPFCORR_H
#define LPFCORR_H

#include "fixmath.h"

/* y -> 1/w for w = max(|w_iq|, w_min_iq) (> 0): two Newton steps (fixmath iq_recip_newton),
 * restarted at y = 1/2 pu when w y > 3/2 or y <= 0. */
static inline iq_t lpfcorr_recip(iq_t y_iq, iq_t w_iq, iq_t w_min_iq)
{
    iq_t w = fix_abs32(w_iq);
    if (w < w_min_iq) {
        w = w_min_iq;
    }
    if (iq_mpy(w, y_iq) > fix_rshift_rnd32(iq_from_int(3), 1U) || y_iq <= 0) {
        y_iq = fix_rshift_rnd32(iq_from_int(1), 1U);
    }
    return iq_recip_newton(y_iq, w);
}

/* (a + j b)(1 - j r): the corrected flux. */
static inline void lpfcorr_rotate(iq_t r_iq, iq_t *a, iq_t *b)
{
    iq_cmul_1jx(fix_neg32(r_iq), a, b);
}

/* (a + j b)(1 + j r)(1 - r^2 + r^4): the low-pass state whose corrected output is a + j b. */
static inline void lpfcorr_predistort(iq_t r_iq, iq_t *a, iq_t *b)
{
    const iq_t r2 = iq_mpy(r_iq, r_iq);
    const iq_t g = iq_add(iq_sub(iq_from_int(1), r2), iq_mpy(r2, r2));
    iq_cmul_1jx(r_iq, a, b);
    *a = iq_mpy(g, *a);
    *b = iq_mpy(g, *b);
}

#endif /* LPFCORR_H */
