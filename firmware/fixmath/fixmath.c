/*
 * fixmath.c - the out-of-line parts of the fixed-point core: square root, vector magnitude,
 * table sine/cosine and sector finding. Formats and bounds are documented in fixmath.h.
 */
#include "fixmath.h"

/* sin(2*pi*k/256) in Q15 for k = 0..256 (one turn plus the wrap sample). */
static const q15_t fix_sin_table[257] = {
#include "fix_sin_table.inc"
};

/* Digit-by-digit square root of x < 4^n_digits: n_digits iterations, each a compare and a
 * subtract; returns floor(sqrt(x)) and leaves x - floor(sqrt(x))^2 in *rem_out.
 * Scaling and overflow: root < 2^n_digits <= 2^32 and bit <= 2^62, so root + bit < 2^64. */
static uint64_t fix_isqrt_core(uint64_t x, uint16_t n_digits, uint64_t *rem_out)
{
    uint64_t rem = x;
    uint64_t root = 0U;
    uint64_t bit = (uint64_t)1 << (2U * (n_digits - 1U));
    uint16_t i;

    for (i = 0U; i < n_digits; i++) {
        if (rem >= root + bit) {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    *rem_out = rem;
    return root;
}

/* Square root rounded to nearest: r = floor(sqrt(x)) is rounded up when x - r^2 > r, i.e. when
 * x >= r^2 + r + 1 > (r + 1/2)^2 (x <= r^2 + r < (r + 1/2)^2 otherwise; no ties, since
 * (r + 1/2)^2 is never an integer). Result <= 2^n_digits, returned in 64 bits. */
static uint64_t fix_isqrt_rnd(uint64_t x, uint16_t n_digits)
{
    uint64_t rem;
    uint64_t root = fix_isqrt_core(x, n_digits, &rem);
    return rem > root ? root + 1U : root;
}

uint32_t fix_isqrt64(uint64_t x)
{
    uint64_t rem;
    return (uint32_t)fix_isqrt_core(x, 32U, &rem);
}

iq_t iq_sqrt(iq_t x)
{
    /* sqrt(X / 2^24) * 2^24 = sqrt(X * 2^24): the argument is < 2^55, so 28 digits suffice and
     * the rounded result is <= 2^27.5 + 1, far inside iq_t. */
    if (x <= 0) {
        return 0;
    }
    return (iq_t)fix_isqrt_rnd((uint64_t)x << FIX_IQ_Q, 28U);
}

iq_t iq_mag(iq_t a, iq_t b)
{
    /* a^2 + b^2 in Q48 is at most 2 * 2^62 = 2^63: fits uint64. Its root is Q24, at most
     * 2^31.5 before saturation. */
    uint64_t r = fix_isqrt_rnd(iq_sumsq_q48(a, b), 32U);
    if (r > (uint64_t)IQ_MAX) {
        return IQ_MAX;
    }
    return (iq_t)r;
}

q15_t q15_mag(q15_t a, q15_t b)
{
    /* a^2 + b^2 in Q30 is at most 2^31 < 4^16: exact in uint64, 16 digits suffice. Its root is
     * Q15, at most 2^15.5 before saturation. */
    uint64_t s = (uint64_t)((int32_t)a * (int32_t)a) + (uint64_t)((int32_t)b * (int32_t)b);
    uint64_t r = fix_isqrt_rnd(s, 16U);
    if (r > (uint64_t)Q15_MAX) {
        return Q15_MAX;
    }
    return (q15_t)r;
}

q15_t fix_sin(angle_t angle)
{
    /* Upper 8 bits pick the segment, lower 8 bits interpolate linearly inside it.
     * Scaling and overflow: |t1 - t0| <= 805, times frac <= 255 fits in 32 bits easily; the
     * interpolated value lies between t0 and t1, both within +-32767. */
    uint16_t idx = (uint16_t)(angle >> 8);
    int32_t frac = (int32_t)(angle & 0xFFU);
    int32_t t0 = (int32_t)fix_sin_table[idx];
    int32_t t1 = (int32_t)fix_sin_table[idx + 1U];
    return q15_sat(t0 + fix_rshift_rnd32((t1 - t0) * frac, 8U));
}

q15_t fix_cos(angle_t angle)
{
    return fix_sin((angle_t)(angle + ANGLE(0.25)));
}

uint16_t fix_sector6(iq_t alpha, iq_t beta)
{
    /* sqrt(3) in Q14 (28378) keeps the product exact in 64 bits; alpha is scaled by 2^14 to match.
     * Sign pattern (p >= 0, q >= 0, alpha > 0) -> sector, derived at the sector centres:
     *   0 deg (0,1,1)->1, 60 deg (1,1,1)->2, 120 deg (1,1,0)->3,
     * 180 deg (1,0,0)->4, 240 deg (0,0,0)->5, 300 deg (0,0,1)->6. */
    static const uint16_t sector_of_code[8] = {5U, 6U, 1U, 1U, 4U, 4U, 3U, 2U};
    const int64_t sqrt3_q14 = 28378;
    int64_t b3 = (int64_t)beta * sqrt3_q14;
    int64_t a14 = (int64_t)alpha * (int64_t)16384;
    uint16_t code = 0U;

    if (b3 - a14 >= 0) {
        code |= 4U;
    }
    if (b3 + a14 >= 0) {
        code |= 2U;
    }
    if (alpha > 0) {
        code |= 1U;
    }
    /* Codes 2 (0,1,0) and 5 (1,0,1) cannot occur for a real vector except on boundary rays
     * through the origin; they map to an adjacent sector so the result is always 1..6. */
    if (alpha == 0 && beta == 0) {
        return 1U;
    }
    return sector_of_code[code];
}

uint16_t fix_quadrant(iq_t alpha, iq_t beta)
{
    if (alpha > 0 && beta >= 0) {
        return 1U;
    }
    if (alpha <= 0 && beta > 0) {
        return 2U;
    }
    if (alpha < 0 && beta <= 0) {
        return 3U;
    }
    if (alpha >= 0 && beta < 0) {
        return 4U;
    }
    return 1U; /* origin */
}
