/*
 * test_fixmath_sqrt.c - fix_isqrt64, fix_isqrt_rnd, iq_sqrt, iq_mag, q15_mag and iq_sumsq_q48 against a double
 * reference.
 *
 * Bounds: fix_isqrt64 is a floor: 0 <= sqrt(x) - r < 1 LSB (checked in double, and exactly as
 * r^2 <= x < (r+1)^2 in 128-bit integers). iq_sqrt, iq_mag and q15_mag round to nearest:
 * |r - sqrt| <= 0.5 LSB against the saturated reference, plus 1e-6 LSB for the double reference
 * itself (sqrt of a sum near 2^63 carries ~3e-7 LSB; an integer root is never exactly k + 1/2, so
 * a correct result can sit closer to 0.5 LSB than that); rounding is also checked exactly as
 * (2r-1)^2 <= 4x < (2r+1)^2. iq_sumsq_q48 is exact (0 LSB).
 * Trajectories: magnitudes of rotating vectors with varying radius and the root of a varying
 * signal must reach the SNR of ideal rounding noise (LSB^2/12) within 0.5 dB; a floor (truncating)
 * root has a 0.5 LSB bias and loses about 6 dB. Measured figures print as "[ MEASURE  ]" lines.
 * Bit-exactness: every root matches the plain digit-by-digit algorithm over all bit pairs (64-bit
 * throughout) on edge cases and 2 million random inputs per function.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fixmath.h"
#include "fixtest.h"

__extension__ typedef unsigned __int128 u128;

#define LSB_Q15 (1.0 / 32768.0)
#define LSB_IQ (1.0 / 16777216.0)
#define SEED 0x5EEDF1C5ULL
#define REF_EPS_LSB 1e-6 /* accuracy of the double reference sqrt, in LSB */

/* Exact check that r is sqrt(x) rounded to nearest: (2r - 1)^2 <= 4x < (2r + 1)^2. */
static int is_rounded_root(uint64_t r, u128 x)
{
    u128 lo = r == 0U ? 0U : (u128)(2U * r - 1U) * (2U * r - 1U);
    u128 hi = (u128)(2U * r + 1U) * (2U * r + 1U);
    return lo <= 4U * x && 4U * x < hi;
}

/* ---------------------------------------------------------------------------------------- */

static void isqrt_point(fixtest_lsb_t *t, uint64_t x)
{
    uint32_t r = fix_isqrt64(x);
    double ref = sqrt((double)x);
    /* floor: the error r - sqrt(x) must lie in (-1, 0]; record it signed-shifted so the bound
     * on |err + 0.5| <= 0.5 covers both ends, then check exactly. */
    fixtest_lsb_add_err(t, (ref - (double)r), r, ref, (int64_t)(x >> 1), (int64_t)(x & 1U));
    if (!((double)r <= ref + 1e-6 && (u128)r * r <= x && (u128)(r + (u128)1) * (r + (u128)1) > x)) {
        fail_msg("fix_isqrt64(%llu) = %u is not floor(sqrt) (%.6f)", (unsigned long long)x, r, ref);
    }
}

static void test_fix_isqrt64(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    uint64_t x;
    uint64_t k;
    int s;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    for (x = 0U; x <= (1U << 20); x++) { /* exhaustive over the first 2^20 integers */
        isqrt_point(&t, x);
    }
    for (s = 0; s <= 32; s++) { /* k^2 - 1, k^2, k^2 + 1 around roots k = 2^s - 1 .. 2^s + 1 */
        int64_t d;
        for (d = -1; d <= 1; d++) {
            k = ((uint64_t)1 << s) + (uint64_t)d;
            if (k >= ((uint64_t)1 << 32)) {
                continue;
            }
            isqrt_point(&t, k * k);
            isqrt_point(&t, k * k + 1U);
            if (k > 0U) {
                isqrt_point(&t, k * k - 1U);
            }
        }
    }
    isqrt_point(&t, UINT64_MAX);
    isqrt_point(&t, UINT64_MAX - 1U);
    isqrt_point(&t, ((uint64_t)1 << 63));
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        uint64_t u = fixtest_rng_u64(&rng);
        isqrt_point(&t, u >> (u % 64U)); /* log-uniform magnitudes */
        k = fixtest_rng_u64(&rng) >> 32;  /* and perfect squares +-1 of random roots */
        isqrt_point(&t, k * k);
        if (k > 0U) {
            isqrt_point(&t, k * k - 1U);
        }
    }
    fixtest_lsb_check(&t, 1.0, "fix_isqrt64: sqrt(x) - r in [0, 1) (floor), exhaustive 0..2^20 + "
                               "squares +-1 + random");
    assert_int_equal(fix_isqrt64(UINT64_MAX), UINT32_MAX);
    assert_int_equal(fix_isqrt64(0U), 0U);
}

/* ---------------------------------------------------------------------------------------- */

static void iq_sqrt_point(fixtest_lsb_t *t, iq_t x)
{
    iq_t r = iq_sqrt(x);
    double ref = x > 0 ? sqrt((double)x * 16777216.0) : 0.0; /* in LSB, exact argument */
    fixtest_lsb_add_err(t, (double)r - ref, r, ref, x, 0);
    if (x > 0 && !is_rounded_root((uint64_t)r, (u128)x << 24)) {
        fail_msg("iq_sqrt(%d) = %d is not sqrt rounded to nearest (%.6f)", x, r, ref);
    }
}

static void test_iq_sqrt(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    int64_t x;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    for (x = -1000; x <= (1 << 20); x++) { /* negatives (-> 0), zero, small values exhaustive */
        iq_sqrt_point(&t, (iq_t)x);
    }
    for (x = 0; x <= INT32_MAX; x += 997) { /* dense grid over the whole range, 2.15 M points */
        iq_sqrt_point(&t, (iq_t)x);
    }
    iq_sqrt_point(&t, IQ_MAX);
    iq_sqrt_point(&t, IQ_MAX - 1);
    iq_sqrt_point(&t, IQ_MIN);
    iq_sqrt_point(&t, IQ(1.0));
    iq_sqrt_point(&t, IQ(1.0) - 1);
    iq_sqrt_point(&t, IQ(1.0) + 1);
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        iq_sqrt_point(&t, fixtest_rng_i32_log(&rng));
    }
    fixtest_lsb_check(&t, 0.5 + REF_EPS_LSB, "iq_sqrt: exhaustive to 2^20 + grid + random (rounded)");
    assert_int_equal(iq_sqrt(IQ(4.0)), IQ(2.0));
    assert_int_equal(iq_sqrt(IQ(0.25)), IQ(0.5));
    assert_int_equal(iq_sqrt(IQ(-4.0)), 0);
    assert_int_equal(iq_sqrt(IQ_MIN), 0);
    assert_int_equal(iq_sqrt(0), 0);
    assert_int_equal(iq_sqrt(1), 4096); /* sqrt(2^-24) = 2^-12 exactly */
}

/* ---------------------------------------------------------------------------------------- */

static void iq_mag_point(fixtest_lsb_t *t, fixtest_lsb_t *tsq, iq_t a, iq_t b)
{
    iq_t r = iq_mag(a, b);
    u128 s = (u128)((int64_t)a * a) + (u128)((int64_t)b * b);
    double ref = fmin(sqrt((double)s), (double)IQ_MAX); /* in LSB, saturated */
    uint64_t sq = iq_sumsq_q48(a, b);
    fixtest_lsb_add_err(t, (double)r - ref, r, ref, a, b);
    if (r != IQ_MAX && !is_rounded_root((uint64_t)r, s)) {
        fail_msg("iq_mag(%d, %d) = %d is not the root rounded to nearest (%.6f)", a, b, r, ref);
    }
    fixtest_lsb_add_err(tsq, (u128)sq == s ? 0.0 : 1.0 + fabs((double)sq - (double)s), (double)sq,
                        (double)s, a, b);
}

static void test_iq_mag_sumsq(void **state)
{
    fixtest_lsb_t t;
    fixtest_lsb_t tsq;
    fixtest_rng_t rng;
    size_t i;
    int32_t a;
    int32_t b;
    int k;
    (void)state;
    fixtest_lsb_init(&t);
    fixtest_lsb_init(&tsq);
    /* Edges: every combination of extremes, zero and +-1 LSB, and each alone on one axis. */
    {
        const iq_t e[] = {IQ_MIN, IQ_MIN + 1, IQ_MAX - 1, IQ_MAX, -1, 0, 1, IQ(1.0), IQ(-1.0),
                          IQ(90.5), IQ(-90.5), IQ(90.6), IQ(-90.6), IQ(127.0), IQ(-127.0)};
        size_t n = sizeof e / sizeof e[0];
        size_t j;
        for (i = 0U; i < n; i++) {
            for (j = 0U; j < n; j++) {
                iq_mag_point(&t, &tsq, e[i], e[j]);
            }
        }
    }
    /* Grid over +-128 pu (saturates beyond radius 128) and over +-2 pu. */
    for (a = INT32_MIN; a <= INT32_MAX - 9999991; a += 9999991) {
        for (b = INT32_MIN; b <= INT32_MAX - 9999991; b += 9999991) {
            iq_mag_point(&t, &tsq, a, b);
        }
    }
    for (a = -IQ(2.0); a <= IQ(2.0); a += 77773) {
        for (b = -IQ(2.0); b <= IQ(2.0); b += 77773) {
            iq_mag_point(&t, &tsq, a, b);
        }
    }
    /* Tiny vectors: every pair with |a|, |b| <= 64 LSB. */
    for (a = -64; a <= 64; a++) {
        for (b = -64; b <= 64; b++) {
            iq_mag_point(&t, &tsq, a, b);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        a = (i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        b = (i & 2U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        iq_mag_point(&t, &tsq, a, b);
    }
    fixtest_lsb_check(&t, 0.5 + REF_EPS_LSB, "iq_mag: edges + grids + random (rounded, saturating)");
    fixtest_lsb_check(&tsq, 0.0, "iq_sumsq_q48: same points (exact)");
    /* Saturation, never wrap, for every sign combination. */
    for (k = 0; k < 4; k++) {
        iq_t sa = (k & 1) ? IQ_MIN : IQ_MAX;
        iq_t sb = (k & 2) ? IQ_MIN : IQ_MAX;
        assert_int_equal(iq_mag(sa, sb), IQ_MAX);
        assert_int_equal(iq_mag(sa, 0), IQ_MAX);
        assert_int_equal(iq_mag(0, sb), IQ_MAX);
    }
    assert_int_equal(iq_mag(IQ_MAX, 0), IQ_MAX);
    assert_int_equal(iq_mag(IQ(3.0), IQ(-4.0)), IQ(5.0));
    assert_int_equal(iq_mag(0, 0), 0);
    assert_int_equal(iq_mag(-1, 0), 1);
    assert_true(iq_sumsq_q48(IQ_MIN, IQ_MIN) == ((uint64_t)1 << 63));
}

/* ---------------------------------------------------------------------------------------- */

static void q15_mag_point(fixtest_lsb_t *t, q15_t a, q15_t b)
{
    q15_t r = q15_mag(a, b);
    uint64_t s = (uint64_t)((int64_t)a * a) + (uint64_t)((int64_t)b * b);
    double ref = fmin(sqrt((double)s), 32767.0);
    fixtest_lsb_add_err(t, (double)r - ref, r, ref, a, b);
    if (r != Q15_MAX && !is_rounded_root((uint64_t)r, s)) {
        fail_msg("q15_mag(%d, %d) = %d is not the root rounded to nearest (%.6f)", a, b, r, ref);
    }
}

static void test_q15_mag(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    int32_t a;
    int32_t b;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    /* Exhaustive in one quadrant's worth of structure: every a against a grid of b (and the
     * b = 0, +-1, extremes rows exactly), 16.8 M points. */
    for (a = INT16_MIN; a <= INT16_MAX; a++) {
        static const int32_t rows[] = {INT16_MIN, INT16_MIN + 1, -1, 0, 1, INT16_MAX - 1, INT16_MAX};
        size_t j;
        for (j = 0U; j < sizeof rows / sizeof rows[0]; j++) {
            q15_mag_point(&t, (q15_t)a, (q15_t)rows[j]);
        }
        for (b = INT16_MIN + (a & 127); b <= INT16_MAX; b += 257) {
            q15_mag_point(&t, (q15_t)a, (q15_t)b);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        q15_t x = fixtest_rng_i16(&rng);
        q15_mag_point(&t, x, fixtest_rng_i16(&rng));
    }
    fixtest_lsb_check(&t, 0.5 + REF_EPS_LSB, "q15_mag: every a x (edge rows + grid) + random (rounded, saturating)");
    assert_int_equal(q15_mag(Q15_MIN, 0), Q15_MAX);
    assert_int_equal(q15_mag(0, Q15_MIN), Q15_MAX);
    assert_int_equal(q15_mag(Q15_MIN, Q15_MIN), Q15_MAX);
    assert_int_equal(q15_mag(Q15_MAX, Q15_MAX), Q15_MAX);
    assert_int_equal(q15_mag(Q15(0.6), Q15(-0.8)), Q15(1.0)); /* rounds to 1.0: saturates */
    assert_int_equal(q15_mag(Q15(0.3), Q15(0.4)), Q15(0.5));
    assert_int_equal(q15_mag(0, 0), 0);
}

/* ---------------------------------------------------------------------------------------- */
/* Trajectories                                                                               */


/* A rotating vector at 50 Hz whose radius swings 0.2 .. 1.8 pu at 3 Hz (IQ), and one at 0.1 ..
 * 0.95 pu (Q15): magnitude vs hypot of the same quantised components. Also iq_sqrt of a signal
 * swinging 0.05 .. 4 pu. Bound: ideal rounding SNR - 0.5 dB. */
static void test_mag_sqrt_trajectories(void **state)
{
    fixtest_acc_t aiq;
    fixtest_acc_t aq15;
    fixtest_acc_t asq;
    const int32_t n = 40000;
    int32_t k;
    (void)state;
    fixtest_acc_init(&aiq);
    fixtest_acc_init(&aq15);
    fixtest_acc_init(&asq);
    for (k = 0; k < n; k++) {
        double t = (double)k * 50e-6;
        double th = 2.0 * FIXTEST_PI * 50.0 * t;
        double r1 = 1.0 + 0.8 * sin(2.0 * FIXTEST_PI * 3.0 * t);
        double r2 = 0.525 + 0.425 * sin(2.0 * FIXTEST_PI * 3.0 * t);
        iq_t a = fixtest_d_to_iq(r1 * cos(th));
        iq_t b = fixtest_d_to_iq(r1 * sin(th));
        q15_t a15 = fixtest_d_to_q15(r2 * cos(th));
        q15_t b15 = fixtest_d_to_q15(r2 * sin(th));
        iq_t x = fixtest_d_to_iq(2.025 + 1.975 * sin(2.0 * FIXTEST_PI * 7.0 * t));
        double ref;
        ref = hypot(fixtest_iq_to_d(a), fixtest_iq_to_d(b));
        fixtest_acc_add(&aiq, fixtest_iq_to_d(iq_mag(a, b)), ref);
        ref = hypot(fixtest_q15_to_d(a15), fixtest_q15_to_d(b15));
        fixtest_acc_add(&aq15, fixtest_q15_to_d(q15_mag(a15, b15)), ref);
        ref = sqrt(fixtest_iq_to_d(x));
        fixtest_acc_add(&asq, fixtest_iq_to_d(iq_sqrt(x)), ref);
    }
    fixtest_snr_check(&aiq, fixtest_acc_ideal_snr_db(&aiq, LSB_IQ) - 0.5,
                      "iq_mag, rotating vector radius 0.2..1.8 pu (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&aq15, fixtest_acc_ideal_snr_db(&aq15, LSB_Q15) - 0.5,
                      "q15_mag, rotating vector radius 0.1..0.95 (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&asq, fixtest_acc_ideal_snr_db(&asq, LSB_IQ) - 0.5,
                      "iq_sqrt, signal 0.05..4 pu (bound = ideal rounding - 0.5 dB)");
}

/* ---------------------------------------------------------------------------------------- */
/* The plain digit-by-digit root over all n_digits bit pairs of x < 4^n_digits, with 64-bit
 * remainder, root and trial bit throughout: the reference that fix_isqrt64, fix_isqrt_rnd, iq_sqrt,
 * iq_mag and q15_mag must match bit for bit (floor, and rounded up when x - r^2 > r). */
static uint64_t ref_isqrt(uint64_t x, unsigned n_digits, int rounded)
{
    uint64_t rem = x;
    uint64_t root = 0U;
    uint64_t bit = (uint64_t)1 << (2U * (n_digits - 1U));
    unsigned i;
    for (i = 0U; i < n_digits; i++) {
        if (rem >= root + bit) {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    return rounded && rem > root ? root + 1U : root;
}

static void same_isqrt(uint64_t x)
{
    uint32_t r = fix_isqrt64(x);
    uint32_t fl;
    uint64_t rr = fix_isqrt_rnd(x, &fl);
    if ((uint64_t)r != ref_isqrt(x, 32U, 0)) {
        fail_msg("fix_isqrt64(%llu) = %u, bit-by-bit reference %llu", (unsigned long long)x, r,
                 (unsigned long long)ref_isqrt(x, 32U, 0));
    }
    if ((uint64_t)fl != ref_isqrt(x, 32U, 0) || rr != ref_isqrt(x, 32U, 1)) {
        fail_msg("fix_isqrt_rnd(%llu) = %llu (floor %u), bit-by-bit reference %llu (floor %llu)",
                 (unsigned long long)x, (unsigned long long)rr, fl, (unsigned long long)ref_isqrt(x, 32U, 1),
                 (unsigned long long)ref_isqrt(x, 32U, 0));
    }
}

static void same_sqrt(iq_t x)
{
    iq_t r = iq_sqrt(x);
    iq_t e = x <= 0 ? 0 : (iq_t)ref_isqrt((uint64_t)x << FIX_IQ_Q, 28U, 1);
    if (r != e) {
        fail_msg("iq_sqrt(%ld) = %ld, bit-by-bit reference %ld", (long)x, (long)r, (long)e);
    }
}

static void same_mag(iq_t a, iq_t b)
{
    iq_t r = iq_mag(a, b);
    uint64_t e = ref_isqrt(iq_sumsq_q48(a, b), 32U, 1);
    if (e > (uint64_t)IQ_MAX) {
        e = (uint64_t)IQ_MAX;
    }
    if ((uint64_t)r != e) {
        fail_msg("iq_mag(%ld, %ld) = %ld, bit-by-bit reference %llu", (long)a, (long)b, (long)r,
                 (unsigned long long)e);
    }
}

static void same_q15_mag(q15_t a, q15_t b)
{
    q15_t r = q15_mag(a, b);
    uint64_t s = (uint64_t)((int64_t)a * a + (int64_t)b * b);
    uint64_t e = ref_isqrt(s, 16U, 1);
    if (e > (uint64_t)Q15_MAX) {
        e = (uint64_t)Q15_MAX;
    }
    if ((uint64_t)r != e) {
        fail_msg("q15_mag(%d, %d) = %d, bit-by-bit reference %llu", a, b, r, (unsigned long long)e);
    }
}

/* Edge cases: 0, 1, every power of 4 and power of 2 with their neighbours, perfect squares +-1,
 * the rounding boundaries r^2 + r and r^2 + r + 1, each caller's largest input; then a few million
 * random inputs, log-uniform over every magnitude. */
static void test_sqrt_matches_bit_by_bit(void **state)
{
    fixtest_rng_t rng;
    uint64_t x;
    uint64_t k;
    unsigned s;
    size_t i;
    (void)state;
    for (x = 0U; x <= (1U << 18); x++) {
        same_isqrt(x);
        same_sqrt((iq_t)x);
    }
    for (s = 0U; s < 64U; s++) {
        uint64_t p = (uint64_t)1 << s;
        same_isqrt(p);
        same_isqrt(p - 1U);
        same_isqrt(p + 1U);
        if (s < 31U) {
            same_sqrt((iq_t)p);
            same_sqrt((iq_t)(p - 1U));
            same_sqrt((iq_t)(p + 1U));
            same_mag((iq_t)p, 0);
            same_mag((iq_t)(p - 1U), (iq_t)(p + 1U));
            same_mag(-(iq_t)p, (iq_t)(p - 1U));
        }
        if (s < 15U) {
            same_q15_mag((q15_t)p, (q15_t)(p - 1U));
            same_q15_mag((q15_t)(p + 1U), 0);
        }
    }
    for (k = 0U; k < ((uint64_t)1 << 32); k += (k >> 4) + 1U) { /* squares, +-1, boundaries */
        uint64_t sq = k * k;
        same_isqrt(sq);
        same_isqrt(sq + 1U);
        same_isqrt(sq + k);
        same_isqrt(sq + k + 1U);
        same_isqrt(sq + 2U * k);
        if (k > 0U) {
            same_isqrt(sq - 1U);
        }
    }
    same_isqrt(UINT64_MAX);
    same_isqrt(UINT64_MAX - 1U);
    same_isqrt(0xFFFFFFFE00000001ULL); /* (2^32 - 1)^2 */
    same_sqrt(IQ_MAX);
    same_sqrt(IQ_MIN);
    same_sqrt(-1);
    same_mag(IQ_MAX, IQ_MAX);
    same_mag(IQ_MIN, IQ_MIN);
    same_mag(IQ_MIN, IQ_MAX);
    same_mag(IQ_MAX, 0);
    same_mag(0, IQ_MIN);
    same_mag(0, 0);
    same_mag(1, 0);
    same_mag(1, 1);
    same_q15_mag(Q15_MAX, Q15_MAX);
    same_q15_mag(Q15_MIN, Q15_MIN);
    same_q15_mag(Q15_MIN, 0);
    same_q15_mag(0, 0);
    fixtest_rng_seed(&rng, SEED ^ 0xB17B17ULL);
    for (i = 0U; i < 2000000U; i++) {
        uint64_t u = fixtest_rng_u64(&rng);
        uint64_t v = fixtest_rng_u64(&rng);
        unsigned sa = (unsigned)(v % 32U);
        unsigned sb = (unsigned)((v >> 8) % 32U);
        same_isqrt(u >> (v % 64U));
        same_sqrt((iq_t)(uint32_t)((u >> 32) >> sa));
        same_mag((iq_t)((int32_t)(uint32_t)u >> sa), (iq_t)((int32_t)(uint32_t)(u >> 32) >> sb));
        same_q15_mag((q15_t)((int16_t)(uint16_t)v >> (sa % 16U)),
                     (q15_t)((int16_t)(uint16_t)(v >> 16) >> (sb % 16U)));
    }
}

UNIT_TEST_MAIN("fixmath square root and magnitude", NULL,
               cmocka_unit_test(test_fix_isqrt64),
               cmocka_unit_test(test_iq_sqrt),
               cmocka_unit_test(test_iq_mag_sumsq),
               cmocka_unit_test(test_q15_mag),
               cmocka_unit_test(test_mag_sqrt_trajectories),
               cmocka_unit_test(test_sqrt_matches_bit_by_bit))
