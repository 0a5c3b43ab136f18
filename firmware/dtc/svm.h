/*
 * svm.h - space-vector modulation in fixed point (Casadei et al. 2006 sections 10.3-10.5: the SFVC
 * scheme of Casadei Fig. 18 applies the stator-voltage reference v_s* of eq. 24 through SVM at a constant
 * switching frequency; section 13's DFOC uses two-phase modulation).
 *
 * Input: the stator-voltage reference (v_alpha, v_beta), pu of the configuration's voltage base,
 * amplitude-invariant Clarke (dtc_base.h), and the measured DC-link voltage V_dc, pu. Output: the
 * duty cycle d_x of the upper device of each leg over one PWM period, which the caller turns into
 * the EV-A's compare values with svm_cmpr() (centred pulses, hal.h HAL_CMD_PWM with
 * cmpr_up = cmpr_dn, HAL_PWM_UPPER_ACTIVE_HIGH).
 *
 * Carrier-based form of SVM (the duty of a leg is its mean leg-to-negative-rail voltage over V_dc):
 *   phase references (inverse of the amplitude-invariant Clarke transform, Hoang eqs. 4-5):
 *     v_a = v_alpha,  v_b = -v_alpha/2 + (sqrt3/2) v_beta,  v_c = -v_alpha/2 - (sqrt3/2) v_beta
 *   n_x = v_x / V_dc (by the reciprocal 1/V_dc, tracked by Newton steps: no division),
 *   d_x = 1/2 + n_x + n_0, the zero-sequence n_0 chosen by the mode:
 *     SVM_SYMMETRIC  n_0 = -(max n + min n)/2 (min-max injection): the two null vectors share the
 *                    null time equally and the pulses are centred, i.e. seven-segment SVM
 *                    (0-1-2-7-2-1-0 in the up/down count), every leg switches twice per period;
 *     SVM_TWO_PHASE  the leg with the largest |n_x| is clamped to its rail (n_0 = 1/2 - max n when
 *                    max n + min n >= 0, else -1/2 - min n): one null vector per period, each leg
 *                    clamped for 60 degrees around the peak of its phase voltage (discontinuous
 *                    modulation, "DPWM1"); 2/3 of the commutations of the symmetric mode at the same
 *                    carrier.
 *   The line-to-line duty differences are n_x - n_y in both modes, so both produce the same mean
 *   vector (the volt-seconds of the sector's two active vectors, t1 V_k + t2 V_k+1).
 *   Linear range: max n - min n <= 1, i.e. the reference inside the hexagon of the six active
 *   vectors (|v| <= V_dc/sqrt3 in every direction, 2/3 V_dc at the active vectors).
 * Overmodulation: a reference outside the hexagon (span s = max n - min n > 1) is scaled by 1/s
 * onto the hexagon boundary, keeping its angle: d_x = 1/2 + (n_x - (max n + min n)/2)/s, no null
 * vector, the same duties in both modes. (Not the inscribed circle: the hexagon gives up to
 * 2/sqrt3 = 1.155 times more voltage between the active vectors.) The flag overmod says it
 * happened. 1/s rounded exactly (svm_recip_span: a quadratic seed and two Newton steps).
 * Dead-time compensation (Casadei sec. 10.5; the sign rule of vrec.h deadtime_error): a leg that switches
 * in the period (0 < d < 1) loses T_d/T_s of duty when its current leaves the leg (i > 0: the
 * upper device's turn-on is delayed by T_d while the lower diode conducts) and gains T_d/T_s when
 * it enters (i < 0: the upper diode holds the leg high for T_d after the upper turn-off), one edge
 * of the two per period. With compensation on, the command is d + sgn(i) T_d/T_s, clamped to
 * [0, 1]; a clamped leg (two-phase, or a compensated duty at 0 or 1) has no edge and no error.
 * i = 0 is not compensated. The duty the machine is expected to get, d_eff = d_cmd -
 * sgn(i) T_d/T_s for a switching leg and d_cmd otherwise, is returned for the voltage
 * reconstruction of the estimator: the commanded duty when the compensation is on and exact, the
 * dead-time-corrupted one when it is off. Valid while the pulse and the gap are longer than T_d
 * (T_d/T_s <= d_cmd <= 1 - T_d/T_s); a narrower pulse is eaten by the dead band and the error is
 * smaller than modelled (at most T_d/T_s of duty).
 *
 * Formats: voltages IQ pu; duties IQ in [0, IQ(1)]; T_d/T_s IQ; currents IQ
 * pu; compare values timer counts.
 * Scaling and overflow: v_alpha/V_dc and v_beta/V_dc are rounded IQ products clamped to +-32
 * (the angle is preserved for |v| < 32 V_dc); then |n_x| < 60 and every sum (n_x + n_0, the span,
 * the mid-point) stays below 120 pu, inside int32 without saturation; the Newton reciprocal keeps
 * y within (0, 2/x) by re-seeding (svm_recip); duties are clamped to [0, 1] and the dead-time sums
 * stay within (-1/2, 3/2); svm_cmpr forms T1PR (1 - d) in 64 bits and rounds it. V_dc <= 0 gives
 * d = 1/2 on every leg (zero volts) and leaves the reciprocal untouched (the application trips on
 * under-voltage first). No division.
 */
#ifndef SVM_H
#define SVM_H

#include <stdint.h>

#include "clarke.h"
#include "fixmath.h"

enum svm_mode {
    SVM_SYMMETRIC = 0, /* seven-segment: centred pulses, min-max zero-sequence injection */
    SVM_TWO_PHASE = 1  /* discontinuous: the leg of the largest |phase voltage| clamped */
};

typedef struct {
    uint16_t mode;    /* enum svm_mode */
    uint16_t dt_comp; /* 1: dead-time compensation by the current sign */
    iq_t td_iq;       /* T_d / T_s, [0, 0.5) (dtc_board_cfg_t td_ts_q15 in IQ) */
} svm_params_t;

typedef struct {
    iq_t inv_vdc_iq; /* 1 / V_dc, Newton state (0: not known, re-seeded) */
} svm_t;

typedef struct {
    iq_t d_iq[3];     /* duty of the upper device commanded, legs A, B, C, [0, 1] */
    iq_t d_eff_iq[3]; /* duty the leg is expected to produce (after the dead time) */
    uint16_t overmod; /* 1: the reference was outside the hexagon and scaled onto it */
} svm_out_t;

void svm_reset(svm_t *s);

/* One PWM period: reference (v_alpha, v_beta), DC link vdc, phase currents i (the dead-time
 * sign; null: no dead-time handling at all, d_eff = d, whatever p->dt_comp). */
void svm_step(svm_t *s, const svm_params_t *p, iq_t v_alpha_iq, iq_t v_beta_iq, iq_t vdc_iq,
              const clarke_out_t *i, svm_out_t *o);

#define SVM_ONE_IQ ((iq_t)1 << FIX_IQ_Q)

/* Dead time of one leg (the rule above, shared with svm4.h): the command *d_cmd and the duty the
 * leg is expected to produce *d_eff for the duty d, the leg's current i and td = T_d/T_s; comp = 0
 * leaves the command at d. d in [0, 1], td in [0, 1/2): the sums stay within (-1/2, 3/2), no
 * overflow. */
static inline void svm_leg_dt(uint16_t comp, iq_t d, iq_t i, iq_t td, iq_t *d_cmd, iq_t *d_eff)
{
    const iq_t sgn_td = i > 0 ? td : (i < 0 ? -td : 0);
    if (comp != 0U && d > 0 && d < SVM_ONE_IQ) {
        /* a command left inside (0, 1) is d + sgn(i) T_d/T_s exactly: the leg produces d */
        const iq_t c = fix_clamp32(d + sgn_td, 0, SVM_ONE_IQ);
        *d_cmd = c;
        *d_eff = (c > 0 && c < SVM_ONE_IQ) ? d : c;
    } else {
        *d_cmd = d;
        *d_eff = (d > 0 && d < SVM_ONE_IQ) ? d - sgn_td : d;
    }
}

/* v / V_dc as v times the reciprocal inv (IQ), rounded, clamped to [lo, hi] (svm_step, svm4_step:
 * +-32 pu for the references, [0, 1] for the FSTP's mid-point).
 * Scaling and overflow: requires lo <= hi. The product is exact in 64 bits (|v inv| <= 2^62), the
 * rounded shift by 24 is below 2^38 in magnitude, and it is clamped to [lo, hi] before the
 * conversion: the same value as iq_mpy's saturation to int32 followed by the clamp (whose range
 * lies inside int32), one comparison pair instead of two. */
static inline iq_t svm_norm(iq_t v, iq_t inv, iq_t lo, iq_t hi)
{
    const int64_t x = ((int64_t)v * (int64_t)inv + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q;
    return (iq_t)(x < (int64_t)lo ? (int64_t)lo : (x > (int64_t)hi ? (int64_t)hi : x));
}

iq_t svm_recip_slow(iq_t y, iq_t x, iq_t e);

/* 1/x for x > 0 (IQ) by Newton steps from the caller's previous y: with e = 1 - x y, one step
 * y (1 + e) (= y (2 - x y)) when |e| <= 2^-12, leaving e^2 <= 2^-24 (a slowly varying V_dc takes
 * this path); else svm_recip_slow: two steps when |e| <= 1/4, a re-seed from the power of two of x
 * and eight steps otherwise. The result is within a few IQ LSB of 1/x (relative 2^-24) whatever
 * y was. x <= 0 returns y unchanged. Scaling: IQ products rounded; for x >= 2^-7 pu (1/x <= 128)
 * only.
 * The fast path's arithmetic without the saturation tests that cannot act there, the same values:
 * for x, y > 0 the product x y < 2^62 and its rounding r = (x y + 2^23) >> 24 are exact in 64 bits,
 * and 1 - r lies in [-2^-12, 2^-12] exactly when iq_sub(1, iq_mpy(x, y)) does (a saturated r >=
 * 2^31 gives e < -2^30 either way); then |y e| < 2^43 rounds below 2^19 (no saturation) and only
 * the final sum saturates (y near 128 pu). The slow path gets iq_sub(1, iq_mpy(x, y)) as before. */
static inline iq_t svm_recip(iq_t y, iq_t x)
{
    if (x > 0 && y > 0) {
        const int64_t e = (int64_t)SVM_ONE_IQ - (((int64_t)x * (int64_t)y + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q);
        if (e <= (int64_t)(SVM_ONE_IQ >> 12) && e >= -(int64_t)(SVM_ONE_IQ >> 12)) {
            return fix_add32(y, (iq_t)(((int64_t)y * e + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q));
        }
    }
    return svm_recip_slow(y, x, iq_sub(SVM_ONE_IQ, iq_mpy(x, y)));
}

/* 1/x for x in [1, 128) pu (the overmodulation's span, svm_step), rounded to the nearest IQ LSB
 * (half up): round(2^48 / x). A seed by the minimax quadratic of 1/x on x's octave (relative error
 * <= 1/99; no table), two Newton steps on the exact residual 2^48 - x y in 64 bits (error
 * below 1.5 LSB) and one rounding correction by the residual's sign; the proof in svm.c. The
 * products are exact in 64 bits (< 2^61); no division. */
iq_t svm_recip_span(iq_t x);

/* Compare value of a centred pulse of duty d (hal.h, HAL_PWM_UPPER_ACTIVE_HIGH, cmpr_up =
 * cmpr_dn): on-time ts (1 - c/T1PR), so c = round(T1PR (1 - d)); c >= T1PR (a pulse of zero
 * width) is written T1PR + 1 (never matched: duty 0 exactly, hal.h); d = 1 gives 0.
 * Scaling: d clamped to [0, IQ(1)]; T1PR (1 - d) < 2^16 * 2^24 formed in 64 bits. */
static inline uint16_t svm_cmpr(iq_t d_iq, uint16_t t1pr)
{
    const iq_t d = fix_clamp32(d_iq, 0, SVM_ONE_IQ);
    const int64_t c = ((int64_t)t1pr * (int64_t)(SVM_ONE_IQ - d) + ((int64_t)1 << (FIX_IQ_Q - 1))) >> FIX_IQ_Q;
    return c >= (int64_t)t1pr ? (uint16_t)(t1pr + 1U) : (uint16_t)c;
}

#endif /* SVM_H */
