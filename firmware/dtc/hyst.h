/*
 * hyst.h - hysteresis comparators of the DTC (Hoang eqs. 13-14, Casadei section 4).
 *
 * Two-level (Hoang eq. 13 for the flux, eq. 14 for the torque), error e = reference - estimate,
 * half band h = band/2 >= 0:
 *     e >  h -> 1 (increase),   e < -h -> 0 (decrease),   otherwise hold.
 * Three-level torque comparator (Casadei section 4, Fig. 4; used with Table 1):
 *     e >  h -> +1,  e < -h -> -1,
 *     from +1: e < 0 -> 0 (the torque has reached the reference; a null vector lets it fall),
 *     from -1: e > 0 -> 0,
 *     otherwise hold.
 *   In motoring the output alternates between +1 and 0 and the torque ripples in
 *   [T* - h, T*]; -1 only appears when the torque overshoots by more than h (braking,
 *   reversal), so the zero vectors do the ordinary work, as Casadei's Table 1 intends.
 * Bands of zero are allowed (Hoang section IV sets both to zero): the comparators then switch
 * on the sign of the error, holding at exactly zero error.
 *
 * Formats: errors and bands IQ pu. The errors are formed by the caller with saturating
 * subtraction; the comparators only compare (no arithmetic, no overflow).
 */
#ifndef HYST_H
#define HYST_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    iq_t half_band_iq;
    uint16_t out; /* 1 = increase, 0 = decrease */
} hyst2_t;

typedef struct {
    iq_t half_band_iq;
    int16_t out; /* +1, 0, -1 */
} hyst3_t;

/* Five-level torque comparator of the DSVM (dsvm.h; Casadei section 11: more torque levels than
 * Casadei Table 1 so that the 19 vectors can be graded): inner half band h1, outer h2 >= h1,
 *     e > h2 -> +2,  h1 < e <= h2 -> +1,  e < -h2 -> -2,  -h2 <= e < -h1 -> -1,
 *     |e| <= h1: as hyst3 (from + with e < 0 -> 0, from - with e > 0 -> 0, else hold the sign,
 *     +-2 held as +-1).
 * Comparisons only. */
typedef struct {
    iq_t half_band_iq;  /* h1 */
    iq_t half_band2_iq; /* h2 */
    int16_t out;        /* +2 .. -2 */
} hyst5_t;

/* band_iq is the full width (Delta in Hoang eqs. 13-14); out_init the initial output. */
void hyst2_init(hyst2_t *h, iq_t band_iq, uint16_t out_init);
void hyst3_init(hyst3_t *h, iq_t band_iq);
/* band2_iq: the outer full width (taken as band_iq when smaller). */
void hyst5_init(hyst5_t *h, iq_t band_iq, iq_t band2_iq);

static inline uint16_t hyst2_step(hyst2_t *h, iq_t err_iq)
{
    if (err_iq > h->half_band_iq) {
        h->out = 1U;
    } else if (err_iq < -h->half_band_iq) {
        h->out = 0U;
    }
    return h->out;
}

/* hyst2_sq_step's two parts, for a law whose reference and band change only when it adopts a
 * reference set or resets (dtc.h: the PM law squares the bounds there, not every period):
 * hyst2_sq_bounds squares lo and hi of hyst2_sq_step (below) into lo2 = lo^2 (0 when lo <= 0: no unsigned
 * |psi|^2 is below it, so the first decision is never taken) and hi2p1 = hi^2 + 1 (0 when
 * hi < 0: every |psi|^2 is at or above it), so that |psi|^2 > hi^2 is |psi|^2 >= hi2p1
 * (hi^2 <= 2^62: the + 1 cannot wrap); hyst2_sq_step_b makes the decisions on them. The same
 * decisions, bit for bit. */
typedef struct {
    uint64_t lo2_q48;   /* (psi* - h)^2, Q48; 0 when psi* - h <= 0 */
    uint64_t hi2p1_q48; /* (psi* + h)^2 + 1, Q48; 0 when psi* + h < 0 */
} hyst2_sq_t;

static inline void hyst2_sq_bounds(const hyst2_t *h, iq_t ref_iq, hyst2_sq_t *b)
{
    const iq_t lo = iq_sub(ref_iq, h->half_band_iq);
    const iq_t hi = iq_add(ref_iq, h->half_band_iq);
    b->lo2_q48 = lo > 0 ? (uint64_t)((int64_t)lo * (int64_t)lo) : 0U;
    b->hi2p1_q48 = hi < 0 ? 0U : (uint64_t)((int64_t)hi * (int64_t)hi) + 1U;
}

static inline uint16_t hyst2_sq_step_b(hyst2_t *h, const hyst2_sq_t *b, uint64_t mag2_q48)
{
    if (mag2_q48 < b->lo2_q48) {
        h->out = 1U;
    } else if (mag2_q48 >= b->hi2p1_q48) {
        h->out = 0U;
    }
    return h->out;
}

/*
 * The flux comparator (Hoang eq. 13) on the squared magnitude, so the control path needs no square
 * root for eq. 11. With e = psi* - |psi| and the half band h:
 *     e >  h  <=>  |psi| < lo = psi* - h  <=>  |psi|^2 < lo^2   (never when lo <= 0)
 *     e < -h  <=>  |psi| > hi = psi* + h  <=>  |psi|^2 > hi^2   (always when hi < 0)
 * These are the decisions of hyst2_step on the exact magnitude; hyst2_step on the rounded
 * iq_mag() can differ from them only when |psi| lies within 0.5 LSB of lo or hi.
 * Formats: ref_iq IQ pu; mag2_q48 = iq_sumsq_q48(psi_alpha, psi_beta), the exact sum of squares in
 * Q48 (< 2^64). lo and hi are formed with saturating arithmetic; |lo|, |hi| <= 2^31, so their
 * squares are exact in 64 bits. No rounding, no overflow.
 * hyst2_sq_bounds, then hyst2_sq_step_b (above) make the same decisions; this form squares
 * the bounds in the step, for a reference that changes every period (the IM laws).
 */
static inline uint16_t hyst2_sq_step(hyst2_t *h, iq_t ref_iq, uint64_t mag2_q48)
{
    const iq_t lo = iq_sub(ref_iq, h->half_band_iq);
    const iq_t hi = iq_add(ref_iq, h->half_band_iq);
    if (lo > 0 && mag2_q48 < (uint64_t)((int64_t)lo * (int64_t)lo)) {
        h->out = 1U;
    } else if (hi < 0 || mag2_q48 > (uint64_t)((int64_t)hi * (int64_t)hi)) {
        h->out = 0U;
    }
    return h->out;
}

static inline int16_t hyst3_step(hyst3_t *h, iq_t err_iq)
{
    if (err_iq > h->half_band_iq) {
        h->out = 1;
    } else if (err_iq < -h->half_band_iq) {
        h->out = -1;
    } else if ((h->out > 0 && err_iq < 0) || (h->out < 0 && err_iq > 0)) {
        h->out = 0;
    }
    return h->out;
}

static inline int16_t hyst5_step(hyst5_t *h, iq_t err_iq)
{
    if (err_iq > h->half_band2_iq) {
        h->out = 2;
    } else if (err_iq < -h->half_band2_iq) {
        h->out = -2;
    } else if (err_iq > h->half_band_iq) {
        h->out = 1;
    } else if (err_iq < -h->half_band_iq) {
        h->out = -1;
    } else if ((h->out > 0 && err_iq < 0) || (h->out < 0 && err_iq > 0)) {
        h->out = 0;
    } else if (h->out > 1) {
        h->out = 1;
    } else if (h->out < -1) {
        h->out = -1;
    }
    return h->out;
}

#endif /* HYST_H */
