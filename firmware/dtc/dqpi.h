/*
 * dqpi.h - PI current regulator pair in a rotating (d, q) frame, with a feed-forward per axis, a
 * circular voltage limit and anti-windup; one dqpi_step() per control period. Used by the PM
 * indirect torque control (itc.h: rotor frame, Hoang sec. I's ITC), and written so that any
 * rotor-frame current control can use it (the IM DFOC's regulators, Casadei sec. 13, have the same
 * form: PI per axis on a feed-forward).
 *
 *   e_x = i_x* - i_x                                   (x = d, q)
 *   I_x[k] = clamp(I_x[k-1] + K_i Ts e_x, +-I_max)      (backward-Euler integral, dqpi_integrate)
 *   u_x = f_x + K_p e_x + I_x[k]                        (f_x: the caller's feed-forward)
 *   voltage limit, d axis first (|v| <= V_max, the largest vector the modulator makes without
 *   distortion in every direction):
 *     v_d = clamp(u_d, +-V_max),  v_q = clamp(u_q, +-sqrt(V_max^2 - v_d^2))
 *   anti-windup by conditional integration: an axis whose output was limited keeps its previous
 *   integral when its error pushes the output further into the limit (the same rule as
 *   speed_pi.h).
 * With a plant L di/dt = v - R i (the back-EMF and the cross-coupling in f_x), K_p = L w_c and
 * K_i = R w_c put the PI zero on the plant pole R/L and leave the open loop w_c / s: the closed
 * loop is first order with bandwidth w_c (tools/config derives w_c from the control period).
 *
 * Formats: currents, voltages, feed-forwards, V_max, I_max IQ pu; K_p IQ (pu voltage per pu
 * current), K_i Ts IQ (the same per period).
 * Scaling and overflow: the errors are saturating differences; K_p e and K_i Ts e are rounded IQ
 * products saturating at +-128 pu; the sums saturate; the integrals are clamped to +-I_max; the
 * limit compares |u|^2 with V_max^2 in unsigned Q48 (exact, < 2^63) and takes the square root of
 * V_max^2 - v_d^2 (Q48 -> Q24 by fix_isqrt64, floor, < 1 LSB) only when the vector is outside
 * the circle. V_max <= 0 gives zero volts.
 */
#ifndef DQPI_H
#define DQPI_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    iq_t kp_iq;      /* K_p, pu voltage per pu current (may exceed 1) */
    iq_t ki_ts_iq;   /* K_i Ts, pu voltage per pu current per period */
    iq_t int_max_iq; /* I_max in (0, 64]: clamp of each integral, pu voltage */
} dqpi_params_t;

typedef struct {
    iq_t int_d_iq, int_q_iq; /* the integrals I_d, I_q, pu voltage */
} dqpi_t;

typedef struct {
    iq_t ref_d_iq, ref_q_iq;   /* i_d*, i_q* */
    iq_t meas_d_iq, meas_q_iq; /* i_d, i_q */
    iq_t ff_d_iq, ff_q_iq;     /* f_d, f_q */
    iq_t vmax_iq;              /* V_max */
} dqpi_in_t;

typedef struct {
    iq_t v_d_iq, v_q_iq; /* the limited voltage command */
    uint16_t limited;    /* 1: the voltage limit acted in this period */
} dqpi_out_t;

/* One backward-Euler step of a PI integral, I + k e clamped to [-lim, lim] with k e an IQ product
 * rounded (dqpi_step, and the IM DFOC's current regulators, im_dfoc.c).
 * Scaling and overflow: requires 0 <= lim <= 2^30 (64 pu) and |integ| <= lim (the integral as this
 * function left it). The product is exact in 64 bits, the rounded shift below 2^38 and the sum
 * below 2^39, clamped there: the same value as iq_mpy's saturation, the saturating sum and the
 * clamp in 32 bits (a saturated product of either sign takes the sum beyond +-lim either way,
 * since 2^31 - lim >= lim), without their two saturation tests. */
static inline iq_t dqpi_integrate(iq_t integ, iq_t k, iq_t e, iq_t lim)
{
    const int64_t x = (int64_t)integ + (((int64_t)k * (int64_t)e + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q);
    return (iq_t)(x > (int64_t)lim ? (int64_t)lim : (x < -(int64_t)lim ? -(int64_t)lim : x));
}

/* Both integrals to the given voltages (bumpless start: the voltage the regulator should hold;
 * within +-I_max, dqpi_integrate). */
void dqpi_reset(dqpi_t *s, iq_t int_d_iq, iq_t int_q_iq);
void dqpi_step(dqpi_t *s, const dqpi_params_t *p, const dqpi_in_t *in, dqpi_out_t *o);

#endif /* DQPI_H */
