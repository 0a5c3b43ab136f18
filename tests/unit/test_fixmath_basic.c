/*
 * test_fixmath_basic.c - saturation, shifts, Q15 and 32-bit add/sub/neg/abs, the format
 * conversions and the Q15()/Q31()/IQ()/ANGLE() literal macros, each against a double reference.
 *
 * Every sweep compares the fixed-point result with the real value the operation should produce,
 * clamped to the output format (the saturating reference). A wrap-around would show as an error
 * of ~2^16 or ~2^32 LSB, so "saturates, never wraps" is part of every bound below; the named edge
 * checks (Q15_MAX + 1 LSB, -INT32_MIN, ...) restate the important cases explicitly.
 *
 * Bounds: exact operations (add/sub/neg/abs/sat/clamp, widening conversions) 0 LSB; rounding
 * operations (shifts, narrowing conversions) 0.5 LSB, the best a round-to-nearest can do; the
 * literal macros 0.5 LSB. Measured figures are printed as "[ MEASURE  ]" lines.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "fixmath.h"
#include "fixtest.h"

#define LSB_Q15 (1.0 / 32768.0)
#define LSB_Q31 (1.0 / 2147483648.0)
#define LSB_IQ (1.0 / 16777216.0)
#define SEED 0x5EEDF1C5ULL

/* Interesting int32 inputs: 0, +-1, +-2, the extremes and, for every power of two 2^k, the values
 * 2^k, 2^k +- 1 and 2^k - 2^j (+- 1): the latter are the rounding and saturation thresholds of
 * every shift and conversion (e.g. 1.0 - 0.5 LSB(Q15) in IQ is 2^24 - 2^8). Both signs. */
static size_t edges_i32(int64_t *out, size_t cap)
{
    size_t n = 0U;
    int k;
    int j;
    int64_t base[4096];
    size_t nb = 0U;
    size_t i;
    base[nb++] = 0;
    base[nb++] = 1;
    base[nb++] = 2;
    base[nb++] = 3;
    for (k = 1; k <= 31; k++) {
        int64_t p = (int64_t)1 << k;
        base[nb++] = p;
        base[nb++] = p + 1;
        base[nb++] = p - 1;
        for (j = 0; j < k; j++) {
            base[nb++] = p - ((int64_t)1 << j);
            base[nb++] = p - ((int64_t)1 << j) + 1;
            base[nb++] = p - ((int64_t)1 << j) - 1;
        }
    }
    for (i = 0U; i < nb && n + 2U <= cap; i++) {
        int64_t v = base[i];
        if (v <= INT32_MAX) {
            out[n++] = v;
        }
        if (-v >= INT32_MIN && v != 0) {
            out[n++] = -v;
        }
    }
    return n;
}

/* ---------------------------------------------------------------------------------------- */
/* Saturation and clamping: exact, bound 0 LSB.                                              */

static void test_q15_sat(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    int32_t x;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    for (x = -70000; x <= 70000; x++) { /* every value around the Q15 range, and far beyond */
        fixtest_lsb_add(&t, q15_sat(x), fmin(fmax((double)x, -32768.0), 32767.0), 1.0, x, 0);
    }
    for (i = 0U; i < ne; i++) {
        x = (int32_t)e[i];
        fixtest_lsb_add(&t, q15_sat(x), fmin(fmax((double)x, -32768.0), 32767.0), 1.0, x, 0);
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        x = fixtest_rng_i32_log(&rng);
        fixtest_lsb_add(&t, q15_sat(x), fmin(fmax((double)x, -32768.0), 32767.0), 1.0, x, 0);
    }
    fixtest_lsb_check(&t, 0.0, "q15_sat (exact)");
    /* Named edges: one LSB past either end saturates. */
    assert_int_equal(q15_sat((int32_t)INT16_MAX + 1), Q15_MAX);
    assert_int_equal(q15_sat((int32_t)INT16_MIN - 1), Q15_MIN);
    assert_int_equal(q15_sat(INT32_MAX), Q15_MAX);
    assert_int_equal(q15_sat(INT32_MIN), Q15_MIN);
}

static void test_fix_sat32_clamp32(void **state)
{
    fixtest_lsb_t t;
    fixtest_lsb_t tc;
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    size_t i;
    int64_t d;
    (void)state;
    fixtest_lsb_init(&t);
    for (i = 0U; i < ne; i++) {
        for (d = -3; d <= 3; d++) { /* the int32 edges and their neighbours outside int32 */
            int64_t x = e[i] * 2 + d;
            fixtest_lsb_add_err(&t, fixtest_err_lsb_exact(fix_sat32(x), x, 0U, INT32_MIN, INT32_MAX),
                                fix_sat32(x), (double)x, x, 0);
        }
    }
    {
        const int64_t big[] = {INT64_MIN, INT64_MIN + 1, -((int64_t)1 << 62), INT64_MAX,
                               INT64_MAX - 1, (int64_t)INT32_MAX + 1, (int64_t)INT32_MIN - 1};
        for (i = 0U; i < sizeof big / sizeof big[0]; i++) {
            fixtest_lsb_add_err(&t,
                                fixtest_err_lsb_exact(fix_sat32(big[i]), big[i], 0U, INT32_MIN,
                                                      INT32_MAX),
                                fix_sat32(big[i]), (double)big[i], big[i], 0);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 1000000U; i++) {
        int64_t x = (int64_t)fixtest_rng_u64(&rng) >> (fixtest_rng_u64(&rng) % 63U);
        fixtest_lsb_add_err(&t, fixtest_err_lsb_exact(fix_sat32(x), x, 0U, INT32_MIN, INT32_MAX),
                            fix_sat32(x), (double)x, x, 0);
    }
    fixtest_lsb_check(&t, 0.0, "fix_sat32 (exact)");
    assert_int_equal(fix_sat32((int64_t)INT32_MAX + 1), INT32_MAX);
    assert_int_equal(fix_sat32((int64_t)INT32_MIN - 1), INT32_MIN);

    /* fix_clamp32 / iq_sat: random ordered bounds (including degenerate lo == hi and the
     * full range) against fmin/fmax. */
    fixtest_lsb_init(&tc);
    for (i = 0U; i < 1000000U; i++) {
        int32_t x = fixtest_rng_i32_log(&rng);
        int32_t a = fixtest_rng_i32_log(&rng);
        int32_t b = (i % 7U == 0U) ? a : fixtest_rng_i32_log(&rng);
        int32_t lo = a < b ? a : b;
        int32_t hi = a < b ? b : a;
        double ref = fmin(fmax((double)x, (double)lo), (double)hi);
        fixtest_lsb_add(&tc, fix_clamp32(x, lo, hi), ref, 1.0, x, lo);
        fixtest_lsb_add(&tc, iq_sat(x, lo, hi), ref, 1.0, x, hi);
    }
    for (i = 0U; i < ne; i++) {
        int32_t x = (int32_t)e[i];
        fixtest_lsb_add(&tc, fix_clamp32(x, INT32_MIN, INT32_MAX), (double)x, 1.0, x, 0);
        fixtest_lsb_add(&tc, iq_sat(x, IQ(-1.0), IQ(1.0)),
                        fmin(fmax((double)x, (double)IQ(-1.0)), (double)IQ(1.0)), 1.0, x, 1);
    }
    fixtest_lsb_check(&tc, 0.0, "fix_clamp32 / iq_sat (exact)");
    assert_int_equal(iq_sat(IQ(1.0) + 1, IQ(-1.0), IQ(1.0)), IQ(1.0));
    assert_int_equal(iq_sat(IQ(-1.0) - 1, IQ(-1.0), IQ(1.0)), IQ(-1.0));
}

/* ---------------------------------------------------------------------------------------- */
/* Rounding shifts: bound 0.5 LSB, and ties round up (documented round-half-up).              */

static void test_fix_rshift_rnd32(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    uint16_t n;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    fixtest_rng_seed(&rng, SEED);
    for (n = 1U; n <= 31U; n++) {
        double scale = ldexp(1.0, -(int)n);
        for (i = 0U; i < ne + 200000U; i++) {
            int32_t x = i < ne ? (int32_t)e[i] : fixtest_rng_i32_log(&rng);
            int32_t r = fix_rshift_rnd32(x, n);
            double ref = (double)x * scale; /* exact in double */
            fixtest_lsb_add(&t, r, ref, 1.0, x, n);
            if (r != (int32_t)floor(ref + 0.5)) {
                fail_msg("fix_rshift_rnd32(%d, %u) = %d, round-half-up gives %.0f", x, n, r,
                         floor(ref + 0.5));
            }
#if FIX_WORD64
            /* the 32-bit targets' form (fixmath.h FIX_WORD64), exactly */
            if (fix_rshift_rnd32_w32(x, n) != r) {
                fail_msg("fix_rshift_rnd32_w32(%d, %u) = %d, fix_rshift_rnd32 %d", x, n,
                         fix_rshift_rnd32_w32(x, n), r);
            }
#endif
        }
    }
    fixtest_lsb_check(&t, 0.5, "fix_rshift_rnd32, n = 1..31");
    assert_int_equal(fix_rshift_rnd32(INT32_MAX, 1U), 1073741824); /* 2^30, no overflow */
    assert_int_equal(fix_rshift_rnd32(INT32_MIN, 31U), -1);
    assert_int_equal(fix_rshift_rnd32(-1, 1U), 0); /* -0.5 rounds up to 0 */
}

static void test_fix_rshift_rnd64_sat32(void **state)
{
    fixtest_lsb_t t;
    fixtest_rng_t rng;
    uint16_t n;
    size_t i;
    (void)state;
    fixtest_lsb_init(&t);
    fixtest_rng_seed(&rng, SEED);
    for (n = 1U; n <= 62U; n++) {
        /* Documented domain |x| < 2^62 (the rounding add must not overflow). */
        const int64_t lim = ((int64_t)1 << 62) - 1;
        const int64_t sat_hi = n <= 31U ? ((int64_t)INT32_MAX << n) : lim;
        const int64_t edges[] = {0, 1, -1, lim, -lim, (int64_t)1 << (n - 1U),
                                 -((int64_t)1 << (n - 1U)), sat_hi, sat_hi - 1, sat_hi + 1,
                                 -sat_hi, -sat_hi - 1, -sat_hi + 1};
        for (i = 0U; i < sizeof edges / sizeof edges[0]; i++) {
            int64_t x = edges[i] > lim ? lim : (edges[i] < -lim ? -lim : edges[i]);
            int32_t r = fix_rshift_rnd64_sat32(x, n);
            fixtest_lsb_add_err(&t, fixtest_err_lsb_exact(r, x, n, INT32_MIN, INT32_MAX), r,
                                ldexp((double)x, -(int)n), x, n);
        }
        for (i = 0U; i < 100000U; i++) {
            int64_t x = ((int64_t)fixtest_rng_u64(&rng) >> 2) >> (fixtest_rng_u64(&rng) % 62U);
            int32_t r = fix_rshift_rnd64_sat32(x, n);
            fixtest_lsb_add_err(&t, fixtest_err_lsb_exact(r, x, n, INT32_MIN, INT32_MAX), r,
                                ldexp((double)x, -(int)n), x, n);
        }
    }
    fixtest_lsb_check(&t, 0.5, "fix_rshift_rnd64_sat32, n = 1..62, |x| < 2^62");
    assert_int_equal(fix_rshift_rnd64_sat32((int64_t)INT32_MAX * 2 + 2, 1U), INT32_MAX);
    assert_int_equal(fix_rshift_rnd64_sat32((int64_t)INT32_MIN * 2 - 2, 1U), INT32_MIN);
    assert_int_equal(fix_rshift_rnd64_sat32(-((int64_t)1 << 61), 62U), 0); /* -0.5 -> 0 */
}

/* ---------------------------------------------------------------------------------------- */
/* Q15 add/sub/neg/abs: exact with saturation, bound 0 LSB.                                   */

static double clamp_q15_d(double x) { return fmin(fmax(x, -1.0), 32767.0 / 32768.0); }

static void test_q15_unary_exhaustive(void **state)
{
    fixtest_lsb_t tn;
    fixtest_lsb_t ta;
    int32_t i;
    (void)state;
    fixtest_lsb_init(&tn);
    fixtest_lsb_init(&ta);
    for (i = INT16_MIN; i <= INT16_MAX; i++) {
        q15_t a = (q15_t)i;
        double ad = fixtest_q15_to_d(a);
        fixtest_lsb_add(&tn, fixtest_q15_to_d(q15_neg(a)), clamp_q15_d(-ad), LSB_Q15, a, 0);
        fixtest_lsb_add(&ta, fixtest_q15_to_d(q15_abs(a)), clamp_q15_d(fabs(ad)), LSB_Q15, a, 0);
    }
    fixtest_lsb_check(&tn, 0.0, "q15_neg, all 65536 inputs (exact)");
    fixtest_lsb_check(&ta, 0.0, "q15_abs, all 65536 inputs (exact)");
    assert_int_equal(q15_neg(Q15_MIN), Q15_MAX);
    assert_int_equal(q15_abs(Q15_MIN), Q15_MAX);
    assert_int_equal(q15_neg(Q15_MAX), Q15_MIN + 1);
    assert_int_equal(q15_neg(0), 0);
    assert_int_equal(q15_abs(-1), 1);
}

/* The Q15 pair sets: a dense grid, the edges, and seeded random pairs. */
static const int32_t q15_edges[] = {INT16_MIN, INT16_MIN + 1, INT16_MIN + 2, -16385, -16384,
                                    -16383, -256, -2, -1, 0, 1, 2, 256, 16383, 16384, 16385,
                                    INT16_MAX - 2, INT16_MAX - 1, INT16_MAX};
#define N_Q15_EDGES (sizeof q15_edges / sizeof q15_edges[0])
#define Q15_GRID_STRIDE 61 /* 1075 values x 1075 = 1.16 M grid pairs */
#define N_RANDOM_PAIRS 1000000U

typedef void (*q15_pair_fn)(q15_t a, q15_t b, void *ctx);

static void for_q15_pairs(q15_pair_fn fn, void *ctx)
{
    fixtest_rng_t rng;
    int32_t a;
    int32_t b;
    size_t i;
    size_t j;
    for (a = INT16_MIN; a <= INT16_MAX; a += Q15_GRID_STRIDE) {
        for (b = INT16_MIN; b <= INT16_MAX; b += Q15_GRID_STRIDE) {
            fn((q15_t)a, (q15_t)b, ctx);
        }
    }
    for (i = 0U; i < N_Q15_EDGES; i++) {
        for (j = 0U; j < N_Q15_EDGES; j++) {
            fn((q15_t)q15_edges[i], (q15_t)q15_edges[j], ctx);
        }
        for (b = INT16_MIN; b <= INT16_MAX; b++) { /* each edge against every value */
            fn((q15_t)q15_edges[i], (q15_t)b, ctx);
            fn((q15_t)b, (q15_t)q15_edges[i], ctx);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < N_RANDOM_PAIRS; i++) {
        q15_t x = fixtest_rng_i16(&rng);
        fn(x, fixtest_rng_i16(&rng), ctx);
    }
}

typedef struct {
    fixtest_lsb_t add;
    fixtest_lsb_t sub;
} q15_addsub_ctx_t;

static void q15_addsub_point(q15_t a, q15_t b, void *vctx)
{
    q15_addsub_ctx_t *c = vctx;
    double ad = fixtest_q15_to_d(a);
    double bd = fixtest_q15_to_d(b);
    fixtest_lsb_add(&c->add, fixtest_q15_to_d(q15_add(a, b)), clamp_q15_d(ad + bd), LSB_Q15, a, b);
    fixtest_lsb_add(&c->sub, fixtest_q15_to_d(q15_sub(a, b)), clamp_q15_d(ad - bd), LSB_Q15, a, b);
}

static void test_q15_add_sub(void **state)
{
    q15_addsub_ctx_t c;
    (void)state;
    fixtest_lsb_init(&c.add);
    fixtest_lsb_init(&c.sub);
    for_q15_pairs(q15_addsub_point, &c);
    fixtest_lsb_check(&c.add, 0.0, "q15_add, grid + edges + random (exact, saturating)");
    fixtest_lsb_check(&c.sub, 0.0, "q15_sub, grid + edges + random (exact, saturating)");
    assert_int_equal(q15_add(Q15_MAX, 1), Q15_MAX);
    assert_int_equal(q15_add(Q15_MIN, -1), Q15_MIN);
    assert_int_equal(q15_sub(Q15_MIN, 1), Q15_MIN);
    assert_int_equal(q15_sub(0, Q15_MIN), Q15_MAX);
    assert_int_equal(q15_add(-1, 1), 0);
    assert_int_equal(q15_sub(Q15_MAX, Q15_MAX), 0);
}

/* ---------------------------------------------------------------------------------------- */
/* 32-bit add/sub/neg/abs (format-agnostic) and the q31_/iq_ wrappers: exact, bound 0 LSB.    */

static void check_add32_point(fixtest_lsb_t *t, int32_t a, int32_t b)
{
    int64_t s = (int64_t)a + b;
    int64_t d = (int64_t)a - b;
    int32_t r[6];
    size_t k;
    r[0] = fix_add32(a, b);
    r[1] = q31_add(a, b);
    r[2] = iq_add(a, b);
    r[3] = fix_sub32(a, b);
    r[4] = q31_sub(a, b);
    r[5] = iq_sub(a, b);
    for (k = 0U; k < 6U; k++) {
        int64_t ref = k < 3U ? s : d;
        fixtest_lsb_add_err(&t[k], fixtest_err_lsb_exact(r[k], ref, 0U, INT32_MIN, INT32_MAX),
                            r[k], (double)ref, a, b);
    }
#if FIX_WORD64
    /* the 32-bit targets' forms (fixmath.h FIX_WORD64), exactly */
    if (fix_add32_w32(a, b) != r[0] || fix_sub32_w32(a, b) != r[3]) {
        fail_msg("fix_add32/fix_sub32(%d, %d): the 32- and 64-bit forms differ", a, b);
    }
#endif
}

static void test_add32_sub32(void **state)
{
    static const char *names[6] = {
        "fix_add32, edges x edges + random (exact, saturating)",
        "q31_add (wrapper of fix_add32)", "iq_add (wrapper of fix_add32)",
        "fix_sub32, edges x edges + random (exact, saturating)",
        "q31_sub (wrapper of fix_sub32)", "iq_sub (wrapper of fix_sub32)"};
    fixtest_lsb_t t[6];
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    size_t i;
    size_t j;
    (void)state;
    for (i = 0U; i < 6U; i++) {
        fixtest_lsb_init(&t[i]);
    }
    /* Edge pairs: every 7th edge against every edge (~700 x 4000 pairs). */
    for (i = 0U; i < ne; i += 7U) {
        for (j = 0U; j < ne; j++) {
            check_add32_point(t, (int32_t)e[i], (int32_t)e[j]);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < N_RANDOM_PAIRS; i++) {
        int32_t a = (i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        check_add32_point(t, a, (i & 2U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng));
    }
    for (i = 0U; i < 6U; i++) {
        fixtest_lsb_check(&t[i], 0.0, names[i]);
    }
    assert_int_equal(fix_add32(INT32_MAX, 1), INT32_MAX);
    assert_int_equal(iq_add(IQ_MAX, IQ_MAX), IQ_MAX);
    assert_int_equal(q31_add(Q31_MIN, -1), Q31_MIN);
    assert_int_equal(fix_sub32(INT32_MIN, 1), INT32_MIN);
    assert_int_equal(iq_sub(0, IQ_MIN), IQ_MAX);
    assert_int_equal(q31_sub(Q31_MAX, Q31_MIN), Q31_MAX);
    assert_int_equal(iq_add(-1, 1), 0);
}

static void test_neg32_abs32(void **state)
{
    fixtest_lsb_t tn;
    fixtest_lsb_t ta;
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    size_t i;
    (void)state;
    fixtest_lsb_init(&tn);
    fixtest_lsb_init(&ta);
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < ne + 2000000U; i++) {
        int32_t a = i < ne ? (int32_t)e[i] : ((i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng));
        int32_t n = fix_neg32(a);
        int32_t b = fix_abs32(a);
        fixtest_lsb_add_err(&tn, fixtest_err_lsb_exact(n, -(int64_t)a, 0U, INT32_MIN, INT32_MAX),
                            n, -(double)a, a, 0);
        fixtest_lsb_add_err(&ta,
                            fixtest_err_lsb_exact(b, a < 0 ? -(int64_t)a : a, 0U, INT32_MIN,
                                                  INT32_MAX),
                            b, fabs((double)a), a, 0);
#if FIX_WORD64
        /* the 32-bit targets' forms (fixmath.h FIX_WORD64), exactly */
        if (fix_neg32_w32(a) != n) {
            fail_msg("fix_neg32(%d): the 32- and 64-bit forms differ", a);
        }
#endif
    }
    fixtest_lsb_check(&tn, 0.0, "fix_neg32, edges + random (exact, saturating)");
    fixtest_lsb_check(&ta, 0.0, "fix_abs32, edges + random (exact, saturating)");
    assert_int_equal(fix_neg32(INT32_MIN), INT32_MAX);
    assert_int_equal(fix_abs32(INT32_MIN), INT32_MAX);
    assert_int_equal(fix_neg32(INT32_MAX), INT32_MIN + 1);
    assert_int_equal(fix_neg32(0), 0);
    assert_int_equal(fix_abs32(-1), 1);
}

/* ---------------------------------------------------------------------------------------- */
/* Conversions. Widening ones are exact (0 LSB); narrowing ones round (0.5 LSB of the output);  */
/* out-of-range inputs saturate.                                                              */

static void test_conversions_from_16bit(void **state)
{
    fixtest_lsb_t t_iq;
    fixtest_lsb_t t_q31;
    fixtest_lsb_t t_int;
    int32_t i;
    (void)state;
    fixtest_lsb_init(&t_iq);
    fixtest_lsb_init(&t_q31);
    fixtest_lsb_init(&t_int);
    for (i = INT16_MIN; i <= INT16_MAX; i++) {
        double v = fixtest_q15_to_d((q15_t)i);
        fixtest_lsb_add(&t_iq, fixtest_iq_to_d(iq_from_q15((q15_t)i)), v, LSB_IQ, i, 0);
        fixtest_lsb_add(&t_q31, fixtest_q31_to_d(q31_from_q15((q15_t)i)), v, LSB_Q31, i, 0);
        fixtest_lsb_add(&t_int, fixtest_iq_to_d(iq_from_int((int16_t)i)),
                        fmin(fmax((double)i, -128.0), 128.0 - LSB_IQ), LSB_IQ, i, 0);
    }
    fixtest_lsb_check(&t_iq, 0.0, "iq_from_q15, all 65536 inputs (exact)");
    fixtest_lsb_check(&t_q31, 0.0, "q31_from_q15, all 65536 inputs (exact)");
    fixtest_lsb_check(&t_int, 0.0, "iq_from_int, all int16 inputs (exact, saturating)");
    assert_int_equal(iq_from_int(127), IQ(127.0));
    assert_int_equal(iq_from_int(128), IQ_MAX);
    assert_int_equal(iq_from_int(-128), IQ_MIN);
    assert_int_equal(iq_from_int(-129), IQ_MIN);
    assert_int_equal(iq_from_int(INT16_MAX), IQ_MAX);
    assert_int_equal(iq_from_q15(Q15_MIN), IQ(-1.0));
}

static void test_conversions_from_32bit(void **state)
{
    fixtest_lsb_t t_q15_iq;
    fixtest_lsb_t t_q15_q31;
    fixtest_lsb_t t_q31_iq;
    fixtest_lsb_t t_iq_q31;
    fixtest_rng_t rng;
    int64_t e[4096];
    size_t ne = edges_i32(e, 4096U);
    size_t i;
    (void)state;
    fixtest_lsb_init(&t_q15_iq);
    fixtest_lsb_init(&t_q15_q31);
    fixtest_lsb_init(&t_q31_iq);
    fixtest_lsb_init(&t_iq_q31);
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < ne + 2000000U; i++) {
        int32_t a = i < ne ? (int32_t)e[i] : ((i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng));
        double a_iq = fixtest_iq_to_d(a);
        double a_q31 = fixtest_q31_to_d(a);
        fixtest_lsb_add(&t_q15_iq, fixtest_q15_to_d(q15_from_iq(a)), clamp_q15_d(a_iq), LSB_Q15, a, 0);
        fixtest_lsb_add(&t_q15_q31, fixtest_q15_to_d(q15_from_q31(a)), clamp_q15_d(a_q31), LSB_Q15,
                        a, 0);
        fixtest_lsb_add(&t_q31_iq, fixtest_q31_to_d(q31_from_iq(a)),
                        fmin(fmax(a_iq, -1.0), 1.0 - LSB_Q31), LSB_Q31, a, 0);
        fixtest_lsb_add(&t_iq_q31, fixtest_iq_to_d(iq_from_q31(a)), a_q31, LSB_IQ, a, 0);
    }
    fixtest_lsb_check(&t_q15_iq, 0.5, "q15_from_iq, edges + random (rounded, saturating)");
    fixtest_lsb_check(&t_q15_q31, 0.5, "q15_from_q31, edges + random (rounded, saturating)");
    fixtest_lsb_check(&t_q31_iq, 0.0, "q31_from_iq, edges + random (exact, saturating)");
    fixtest_lsb_check(&t_iq_q31, 0.5, "iq_from_q31, edges + random (rounded)");
    assert_int_equal(q15_from_iq(IQ(1.0)), Q15_MAX);
    assert_int_equal(q15_from_iq(IQ(-1.0) - 1), Q15_MIN);
    assert_int_equal(q15_from_iq(IQ_MAX), Q15_MAX);
    assert_int_equal(q15_from_iq(IQ_MIN), Q15_MIN);
    assert_int_equal(q15_from_q31(Q31_MAX), Q15_MAX); /* rounds to 2^15: must saturate */
    assert_int_equal(q15_from_q31(Q31_MIN), Q15_MIN);
    assert_int_equal(q31_from_iq(IQ(1.0)), Q31_MAX);
    assert_int_equal(q31_from_iq(IQ(-1.0)), Q31_MIN);
    assert_int_equal(q31_from_iq(IQ(-1.0) - 1), Q31_MIN);
    assert_int_equal(iq_from_q31(Q31_MAX), IQ(1.0));
}

/* Trajectory through the narrowing conversions: a 0.9 pu sine with a slow 0.05 pu ripple in IQ,
 * converted to Q15. Bound: ideal rounding noise (LSB^2/12 against the signal power) minus
 * 0.5 dB; a truncating conversion would lose about 6 dB. */
static void test_conversion_trajectory_snr(void **state)
{
    fixtest_acc_t acc;
    fixtest_acc_t acc31;
    int32_t k;
    const int32_t n = 20000;
    (void)state;
    fixtest_acc_init(&acc);
    fixtest_acc_init(&acc31);
    for (k = 0; k < n; k++) {
        double t = (double)k * 50e-6;
        double x = 0.9 * sin(2.0 * FIXTEST_PI * 50.0 * t) + 0.05 * sin(2.0 * FIXTEST_PI * 3.1 * t);
        iq_t xi = fixtest_d_to_iq(x);
        q31_t xq = fixtest_d_to_q31(x);
        double xr = fixtest_iq_to_d(xi);
        fixtest_acc_add(&acc, fixtest_q15_to_d(q15_from_iq(xi)), xr);
        fixtest_acc_add(&acc31, fixtest_q15_to_d(q15_from_q31(xq)), fixtest_q31_to_d(xq));
    }
    {
        double ideal = fixtest_acc_ideal_snr_db(&acc, LSB_Q15);
        print_message("[ MEASURE  ] ideal Q15 rounding SNR for this signal: %.2f dB\n", ideal);
        fixtest_snr_check(&acc, ideal - 0.5, "q15_from_iq, 50 Hz sine trajectory");
        fixtest_snr_check(&acc31, ideal - 0.5, "q15_from_q31, 50 Hz sine trajectory");
    }
}

/* ---------------------------------------------------------------------------------------- */
/* Literal macros. Q15()/Q31()/IQ() round to nearest and saturate: bound 0.5 LSB against the   */
/* clamped value. ANGLE() reduces modulo one turn: bound 0.5 LSB on the circle.               */

static const q15_t k_static_q15 = Q15(0.5); /* must be a constant expression */
static const iq_t k_static_iq = IQ(-2.25);
static const angle_t k_static_angle = ANGLE(-0.25);

static void test_literal_macros(void **state)
{
    fixtest_lsb_t t15;
    fixtest_lsb_t t31;
    fixtest_lsb_t tiq;
    fixtest_lsb_t tang;
    fixtest_rng_t rng;
    int32_t k;
    (void)state;
    fixtest_lsb_init(&t15);
    fixtest_lsb_init(&t31);
    fixtest_lsb_init(&tiq);
    fixtest_lsb_init(&tang);
    fixtest_rng_seed(&rng, SEED);
    for (k = 0; k < 400000; k++) {
        /* Dense grid over +-1.5 (crossing both saturation limits), then random values. The
         * grid step is not a multiple of any LSB, so every rounding phase is visited. */
        double x = k < 200000 ? -1.5 + 3.0 * (double)k / 199999.0 : 3.0 * fixtest_rng_unit(&rng) - 1.5;
        double xi = 200.0 * x; /* IQ range is +-128 */
        fixtest_lsb_add(&t15, fixtest_q15_to_d(Q15(x)), clamp_q15_d(x), LSB_Q15, k, 0);
        fixtest_lsb_add(&t31, fixtest_q31_to_d(Q31(x)), fmin(fmax(x, -1.0), 1.0 - LSB_Q31), LSB_Q31,
                        k, 0);
        fixtest_lsb_add(&tiq, fixtest_iq_to_d(IQ(xi)), fmin(fmax(xi, -128.0), 128.0 - LSB_IQ),
                        LSB_IQ, k, 0);
    }
    /* Half-LSB values: round to nearest, halves away from zero. */
    fixtest_lsb_add(&t15, fixtest_q15_to_d(Q15(0.5 * LSB_Q15)), 0.5 * LSB_Q15, LSB_Q15, -1, 0);
    fixtest_lsb_add(&t15, fixtest_q15_to_d(Q15(-0.5 * LSB_Q15)), -0.5 * LSB_Q15, LSB_Q15, -2, 0);
    fixtest_lsb_check(&t15, 0.5, "Q15() macro, grid + random over +-1.5 (rounded, saturating)");
    fixtest_lsb_check(&t31, 0.5, "Q31() macro, grid + random over +-1.5 (rounded, saturating)");
    fixtest_lsb_check(&tiq, 0.5, "IQ() macro, grid + random over +-300 (rounded, saturating)");
    assert_int_equal(Q15(1.0), Q15_MAX);
    assert_int_equal(Q15(1.0 - LSB_Q15), Q15_MAX);
    assert_int_equal(Q15(1.0 - 0.5 * LSB_Q15), Q15_MAX); /* rounds to 2^15: must saturate */
    assert_int_equal(Q15(-1.0), Q15_MIN);
    assert_int_equal(Q15(-1.0 - LSB_Q15), Q15_MIN);
    assert_int_equal(Q15(-1.0 + LSB_Q15), Q15_MIN + 1);
    assert_int_equal(Q15(0.0), 0);
    assert_int_equal(Q15(0.5), 16384);
    assert_int_equal(Q31(1.0), Q31_MAX);
    assert_int_equal(Q31(-1.0), Q31_MIN);
    assert_int_equal(Q31(-0.5), -1073741824);
    assert_int_equal(IQ(128.0), IQ_MAX);
    assert_int_equal(IQ(-128.0), IQ_MIN);
    assert_int_equal(IQ(-1.0), -16777216);
    assert_int_equal(IQ(1e12), IQ_MAX);
    assert_int_equal(k_static_q15, 16384);
    assert_int_equal(k_static_iq, -37748736);
    /* The irrational Q31 factors written as integers: round(x * 2^31) of the double reference. */
    assert_int_equal(FIX_Q31_THIRD, (q31_t)llround(2147483648.0 / 3.0));
    assert_int_equal(FIX_Q31_INV_SQRT3, (q31_t)llround(2147483648.0 / sqrt(3.0)));
    assert_int_equal(FIX_Q31_SQRT3_2, (q31_t)llround(2147483648.0 * sqrt(3.0) / 2.0));

    /* ANGLE(): turns over +-3 (several wraps, both signs). The reference is the nearest
     * 1/65536 turn, compared on the circle (distance modulo 65536). */
    for (k = 0; k <= 600000; k++) {
        double turns = k <= 300000 ? -3.0 + 6.0 * (double)k / 300000.0 * (1.0 - 1e-9)
                                   : 6.0 * fixtest_rng_unit(&rng) - 3.0;
        double ref = turns * 65536.0;
        double d = fmod((double)ANGLE(turns) - ref, 65536.0);
        if (d > 32768.0) {
            d -= 65536.0;
        }
        if (d < -32768.0) {
            d += 65536.0;
        }
        fixtest_lsb_add_err(&tang, d, ANGLE(turns), ref, k, 0);
    }
    /* Exact quarter turns of both signs (representable: error must be 0). */
    for (k = -12; k <= 12; k++) {
        double turns = 0.25 * k;
        double ref = fmod(fmod(turns * 65536.0, 65536.0) + 65536.0, 65536.0);
        fixtest_lsb_add_err(&tang, (double)ANGLE(turns) - ref, ANGLE(turns), ref, k, 1);
    }
    fixtest_lsb_check(&tang, 0.5, "ANGLE() macro, turns in [-3, 3] (rounded, modulo one turn)");
    assert_int_equal(ANGLE(0.25), 16384);
    assert_int_equal(ANGLE(-0.25), 49152);
    assert_int_equal(ANGLE(1.0), 0);
    assert_int_equal(ANGLE(-1.0), 0);
    assert_int_equal(ANGLE(0.5), 32768);
    assert_int_equal(ANGLE(-0.5), 32768);
    assert_int_equal(k_static_angle, 49152);
}

UNIT_TEST_MAIN("fixmath basic", NULL,
               cmocka_unit_test(test_q15_sat),
               cmocka_unit_test(test_fix_sat32_clamp32),
               cmocka_unit_test(test_fix_rshift_rnd32),
               cmocka_unit_test(test_fix_rshift_rnd64_sat32),
               cmocka_unit_test(test_q15_unary_exhaustive),
               cmocka_unit_test(test_q15_add_sub),
               cmocka_unit_test(test_add32_sub32),
               cmocka_unit_test(test_neg32_abs32),
               cmocka_unit_test(test_conversions_from_16bit),
               cmocka_unit_test(test_conversions_from_32bit),
               cmocka_unit_test(test_conversion_trajectory_snr),
               cmocka_unit_test(test_literal_macros))
