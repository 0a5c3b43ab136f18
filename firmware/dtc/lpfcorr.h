/*
 * lpfcorr.h - gain and phase correction of the voltage model's low-pass (dtc_config.h lpf_comp).
 *
 * The voltage model integrates with 1/(s + w_c) instead of 1/s (flux_est.h), so in sinusoidal
 * steady state at electrical speed w its output is psi_l = psi jw / (jw + w_c) = psi / (1 - j r),
 * r = w_c / w: a gain w/sqrt(w^2 + w_c^2) and a lead atan(r) (6.8 / 15.8 / 23.4 % vector
 * error at 700 / 300 / 200 rpm for 5 rad/s). The correction multiplies the low-pass's INPUT by
 * (1 - j r), with the measured speed:
 *     d psi/dt = (1 - j r) e - w_c psi,   e = v - r_s i  (Hoang eqs. 15-16),
 *   so a DC error E of e still ends as a bounded flux offset (1 - j r) E / w_c, while for the
 * flux the machine has, psi_t = |psi| e^{j theta} with d theta/dt = w (e = j w psi_t), the error
 * eps = psi - psi_t obeys
 *     d eps/dt = (1 - j r) j w psi_t - j w psi_t - w_c psi_t - w_c eps = -w_c eps    (r w = w_c),
 * at every instant, however the speed changes, as long as r is that of the present speed (it is
 * recomputed every speed-loop period from the measured speed, which lags by its window) and
 * |w| >= w_min (below, r w < w_c): the estimate converges on the true flux at w_c and stays there
 * through an acceleration. What does not turn at w is not covered: the radial part of the
 * hysteresis ripple is turned by (1 - j r) into an error of r times that ripple. The alternative, undoing the filter on its output
 * (psi = psi_l (1 - j r)), is exact only in steady state: the filter's state stores the flux
 * predistorted by the r of the past, and a changing speed (d r/dt = -w_c (dw/dt) / w^2) leaves an
 * error of about |psi| times the change of r over 1/w_c, in the stationary frame, i.e. a DC flux
 * error that the DTC turns into a DC current (SIL, proposed FSTP accelerating at the
 * torque limit to 200 rpm through a 100 rpm hand-over: 17 % of the flux 0.1 s after the start; on
 * the FSTP that DC current is phase A's and drains the split link's mid-point). At the hand-over
 * the state is simply the current-model flux (bumpless).
 * r from the measured speed without a division: y ~ 1/max(|w|, w_min) by Newton's iteration
 * y <- y (2 - w y) (quadratic convergence for 0 < y < 2/w; two iterations per speed period from
 * the previous value track any physical speed change; restarted at y = 1/2 pu if w y > 3/2),
 * r = sign(w) w_c y. Below w_min the correction stays at its value for w_min (continuous, no
 * switching bump); w_min = 2 w_c (r <= 1/2, the corrected magnitude at most 1.12 times the
 * low-pass's) is set by the host. Measured with the output form (SIL, proposed FSTP, 0.075 N*m,
 * voltage model from standstill): with the floor at 4 w_c the estimated torque is 10 % low at
 * 150 rpm and 81 % low at 100 rpm; at 2 w_c within 1.2 % and 1.4 %.
 *
 * Formats: IQ pu (w, w_c, y, r, fluxes); products rounded (iq_mpy), sums saturated; y <= 1/w_min
 * (~31 pu for 2 w_c = 10 rad/s and w_base = 314 rad/s) stays far inside the IQ range.
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

/* (a + j b)(1 - j r): the corrected low-pass input (flux_est.c). */
static inline void lpfcorr_rotate(iq_t r_iq, iq_t *a, iq_t *b)
{
    iq_cmul_1jx_inline(fix_neg32(r_iq), a, b);
}

#endif /* LPFCORR_H */
