/*
 * test_fixmath_mul.c - the rounding multiplies (q15_mul, q15_mul_q30, q31_mul, iq_mpy,
 * iq_mpy_q15, iq_mpy_uq16) against a double reference; q31_mul_k equal to q31_mul wherever its
 * factor is not Q31_MIN (the edge and random pairs of the q31_mul sweep).
 *
 * Sweeps: the error of every product against the real value a*b/2^shift clamped to the output
 * format (the saturating reference) must be <= 0.5 LSB (the best a rounding multiply can do;
 * q15_mul_q30 is exact, 0 LSB). The reference numerator a*b needs up to 63 bits, more than a
 * double's 53-bit mantissa, so the difference is formed exactly (fixtest_err_lsb_exact) and only
 * the error is a double. A wrap-around on overflow would show as ~2^32 LSB.
 *
 * Trajectories: memoryless products of quantised signals must reach the SNR of ideal rounding
 * noise (LSB^2/12 against the signal power) within 0.5 dB; chains of iq_mpy / iq_mpy_uq16 run as
 * first-order low-pass filters for tens of thousands of steps must stay within 1.5 dB of the SNR
 * predicted for ideal rounding noise shaped by the filter (a truncating multiply leaves a
 * drifting bias and loses > 20 dB). Measured figures are printed as "[ MEASURE  ]" lines.
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
#define N_RANDOM_PAIRS 1000000U
#define TS_S 50e-6 /* control period of the 50 us ISR */

/* ---------------------------------------------------------------------------------------- */
/* Q15 x Q15                                                                                 */

static const int32_t q15_edges[] = {INT16_MIN, INT16_MIN + 1, INT16_MIN + 2, -16385, -16384,
                                    -16383, -256, -2, -1, 0, 1, 2, 256, 16383, 16384, 16385,
                                    INT16_MAX - 2, INT16_MAX - 1, INT16_MAX};
#define N_Q15_EDGES (sizeof q15_edges / sizeof q15_edges[0])

static void q15_mul_point(fixtest_lsb_t *t, fixtest_lsb_t *t30, q15_t a, q15_t b)
{
    int64_t p = (int64_t)a * b;
    q15_t r = q15_mul(a, b);
    int32_t r30 = q15_mul_q30(a, b);
    fixtest_lsb_add_err(t, fixtest_err_lsb_exact(r, p, 15U, INT16_MIN, INT16_MAX), r,
                        ldexp((double)p, -15), a, b);
    fixtest_lsb_add_err(t30, fixtest_err_lsb_exact(r30, p, 0U, INT32_MIN, INT32_MAX), r30,
                        (double)p, a, b);
}

static void test_q15_mul_sweep(void **state)
{
    fixtest_lsb_t t;
    fixtest_lsb_t t30;
    fixtest_rng_t rng;
    int32_t a;
    int32_t b;
    size_t i;
    size_t j;
    (void)state;
    fixtest_lsb_init(&t);
    fixtest_lsb_init(&t30);
    for (a = INT16_MIN; a <= INT16_MAX; a += 61) { /* dense grid, 1.16 M pairs */
        for (b = INT16_MIN; b <= INT16_MAX; b += 61) {
            q15_mul_point(&t, &t30, (q15_t)a, (q15_t)b);
        }
    }
    for (i = 0U; i < N_Q15_EDGES; i++) { /* every edge against every value */
        for (b = INT16_MIN; b <= INT16_MAX; b++) {
            q15_mul_point(&t, &t30, (q15_t)q15_edges[i], (q15_t)b);
            q15_mul_point(&t, &t30, (q15_t)b, (q15_t)q15_edges[i]);
        }
        for (j = 0U; j < N_Q15_EDGES; j++) {
            q15_mul_point(&t, &t30, (q15_t)q15_edges[i], (q15_t)q15_edges[j]);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < N_RANDOM_PAIRS; i++) {
        q15_t x = fixtest_rng_i16(&rng);
        q15_mul_point(&t, &t30, x, fixtest_rng_i16(&rng));
    }
    fixtest_lsb_check(&t, 0.5, "q15_mul, grid + edges + random (rounded, saturating)");
    fixtest_lsb_check(&t30, 0.0, "q15_mul_q30, grid + edges + random (exact)");
    assert_int_equal(q15_mul(Q15_MIN, Q15_MIN), Q15_MAX); /* (-1)(-1) = +1 saturates */
    assert_int_equal(q15_mul(Q15_MIN, Q15_MAX), Q15_MIN + 1);
    assert_int_equal(q15_mul(Q15(0.5), Q15(-0.5)), Q15(-0.25));
    assert_int_equal(q15_mul(0, Q15_MIN), 0);
    assert_int_equal(q15_mul(1, 16384), 1);   /* 0.5 LSB rounds up */
    assert_int_equal(q15_mul(-1, 16384), 0);  /* -0.5 LSB rounds up */
    assert_int_equal(q15_mul_q30(Q15_MIN, Q15_MIN), 1073741824);
}

/* ---------------------------------------------------------------------------------------- */
/* 32-bit x 32-bit (Q31, IQ) and IQ x Q15 / UQ16                                             */

static size_t edges_i32(int32_t *out, size_t cap)
{
    size_t n = 0U;
    int k;
    out[n++] = 0;
    out[n++] = INT32_MIN;
    out[n++] = INT32_MIN + 1;
    out[n++] = INT32_MAX;
    out[n++] = INT32_MAX - 1;
    for (k = 0; k <= 30 && n + 6U <= cap; k++) {
        int32_t p = (int32_t)((int64_t)1 << k);
        out[n++] = p;
        out[n++] = -p;
        out[n++] = p + 1;
        out[n++] = -p - 1;
        out[n++] = p - 1;
        out[n++] = -p + 1;
    }
    return n;
}

typedef struct {
    fixtest_lsb_t q31;
    fixtest_lsb_t iq;
    int32_t sat_hits;  /* how many pairs exercised saturation (must be > 0) */
} mul32_ctx_t;

static void mul32_point(mul32_ctx_t *c, int32_t a, int32_t b)
{
    int64_t p = (int64_t)a * b;
    q31_t r31 = q31_mul(a, b);
    iq_t riq = iq_mpy(a, b);
    fixtest_lsb_add_err(&c->q31, fixtest_err_lsb_exact(r31, p, 31U, INT32_MIN, INT32_MAX), r31,
                        ldexp((double)p, -31), a, b);
    fixtest_lsb_add_err(&c->iq, fixtest_err_lsb_exact(riq, p, 24U, INT32_MIN, INT32_MAX), riq,
                        ldexp((double)p, -24), a, b);
    if (riq == IQ_MAX || riq == IQ_MIN) {
        c->sat_hits++;
    }
    if (b != INT32_MIN) { /* q31_mul_k: the same product without the saturation test */
        assert_int_equal(q31_mul_k(a, b), r31);
    }
}

static void test_q31_mul_iq_mpy_sweep(void **state)
{
    mul32_ctx_t c;
    fixtest_rng_t rng;
    int32_t e[256];
    size_t ne = edges_i32(e, 256U);
    size_t i;
    size_t j;
    int32_t a;
    (void)state;
    fixtest_lsb_init(&c.q31);
    fixtest_lsb_init(&c.iq);
    c.sat_hits = 0;
    for (i = 0U; i < ne; i++) { /* edges x edges */
        for (j = 0U; j < ne; j++) {
            mul32_point(&c, e[i], e[j]);
        }
    }
    /* Dense grid around the IQ products that matter (|a|, |b| < 16 pu, crossing the 128 pu
     * saturation) and over the full int32 range. */
    for (a = -(16 << 24); a < (16 << 24); a += 1234567) {
        int32_t b;
        for (b = -(16 << 24); b < (16 << 24); b += 1234567) {
            mul32_point(&c, a, b);
        }
    }
    for (i = 0U; i < 700U; i++) {
        for (j = 0U; j < 700U; j++) {
            mul32_point(&c, (int32_t)((int64_t)INT32_MIN + (int64_t)i * 6135667),
                        (int32_t)((int64_t)INT32_MIN + (int64_t)j * 6135667));
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < N_RANDOM_PAIRS; i++) {
        int32_t x = (i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        mul32_point(&c, x, (i & 2U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng));
    }
    fixtest_lsb_check(&c.q31, 0.5, "q31_mul, edges + grids + random (rounded, saturating)");
    fixtest_lsb_check(&c.iq, 0.5, "iq_mpy, edges + grids + random (rounded, saturating)");
    assert_true(c.sat_hits > 1000);
    /* Overflow saturates with the sign of the true product. */
    assert_int_equal(q31_mul(Q31_MIN, Q31_MIN), Q31_MAX);
    assert_int_equal(q31_mul(Q31_MIN, Q31_MAX), Q31_MIN + 1);
    assert_int_equal(iq_mpy(IQ(100.0), IQ(2.0)), IQ_MAX);
    assert_int_equal(iq_mpy(IQ(-100.0), IQ(2.0)), IQ_MIN);
    assert_int_equal(iq_mpy(IQ(100.0), IQ(-2.0)), IQ_MIN);
    assert_int_equal(iq_mpy(IQ(-100.0), IQ(-2.0)), IQ_MAX);
    assert_int_equal(iq_mpy(IQ_MIN, IQ_MIN), IQ_MAX);
    assert_int_equal(iq_mpy(IQ_MAX, IQ_MAX), IQ_MAX);
    assert_int_equal(iq_mpy(IQ_MIN, IQ(1.0)), IQ_MIN);
    assert_int_equal(iq_mpy(IQ_MAX, IQ(-1.0)), -IQ_MAX);
    assert_int_equal(iq_mpy(IQ(-8.0), IQ(16.0)), IQ_MIN);             /* exactly -128 */
    assert_int_equal(iq_mpy(IQ(8.0), IQ(16.0)), IQ_MAX);              /* +128: 1 LSB over */
    assert_int_equal(iq_mpy(IQ(1.5), IQ(-2.0)), IQ(-3.0));
    assert_int_equal(iq_mpy(1, IQ(0.5)), 1);  /* 0.5 LSB rounds up */
    assert_int_equal(iq_mpy(-1, IQ(0.5)), 0);
    assert_int_equal(iq_mpy(0, IQ_MIN), 0);
}

static void test_iq_mpy_q15_uq16_sweep(void **state)
{
    fixtest_lsb_t tq;
    fixtest_lsb_t tu;
    fixtest_rng_t rng;
    int32_t e[256];
    size_t ne = edges_i32(e, 256U);
    size_t i;
    int32_t b;
    (void)state;
    fixtest_lsb_init(&tq);
    fixtest_lsb_init(&tu);
    /* Every IQ edge against every Q15 gain and every UQ16 gain. */
    for (i = 0U; i < ne; i++) {
        for (b = INT16_MIN; b <= INT16_MAX; b++) {
            int64_t pq = (int64_t)e[i] * b;
            int64_t pu = (int64_t)e[i] * (b + 32768);
            iq_t rq = iq_mpy_q15(e[i], (q15_t)b);
            iq_t ru = iq_mpy_uq16(e[i], (uint16_t)(b + 32768));
            fixtest_lsb_add_err(&tq, fixtest_err_lsb_exact(rq, pq, 15U, INT32_MIN, INT32_MAX), rq,
                                ldexp((double)pq, -15), e[i], b);
            fixtest_lsb_add_err(&tu, fixtest_err_lsb_exact(ru, pu, 16U, INT32_MIN, INT32_MAX), ru,
                                ldexp((double)pu, -16), e[i], b + 32768);
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 2U * N_RANDOM_PAIRS; i++) {
        int32_t a = (i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        q15_t g = fixtest_rng_i16(&rng);
        uint16_t u = (uint16_t)(fixtest_rng_u64(&rng) >> 48);
        int64_t pq = (int64_t)a * g;
        int64_t pu = (int64_t)a * u;
        iq_t rq = iq_mpy_q15(a, g);
        iq_t ru = iq_mpy_uq16(a, u);
        fixtest_lsb_add_err(&tq, fixtest_err_lsb_exact(rq, pq, 15U, INT32_MIN, INT32_MAX), rq,
                            ldexp((double)pq, -15), a, g);
        fixtest_lsb_add_err(&tu, fixtest_err_lsb_exact(ru, pu, 16U, INT32_MIN, INT32_MAX), ru,
                            ldexp((double)pu, -16), a, u);
    }
    fixtest_lsb_check(&tq, 0.5, "iq_mpy_q15, edges x all gains + random (rounded, saturating)");
    fixtest_lsb_check(&tu, 0.5, "iq_mpy_uq16, edges x all gains + random (rounded)");
    assert_int_equal(iq_mpy_q15(IQ_MIN, Q15_MIN), IQ_MAX); /* -128 * -1 saturates */
    assert_int_equal(iq_mpy_q15(IQ_MAX, Q15_MIN), -IQ_MAX);
    assert_int_equal(iq_mpy_q15(IQ_MIN, Q15_MAX), -2147418112); /* exact: -2^31 + 2^16 */
    assert_int_equal(iq_mpy_uq16(IQ_MAX, UINT16_MAX), 2147450879); /* 2147450879.00002 */
    assert_int_equal(iq_mpy_uq16(IQ_MIN, UINT16_MAX), -2147450880); /* exact: -2^31 + 2^15 */
    assert_int_equal(iq_mpy_uq16(IQ(3.0), 32768U), IQ(1.5));
}

/* ---------------------------------------------------------------------------------------- */
/* Trajectories                                                                               */

/* SNR of ideal rounding to a grid of step lsb, for a signal of mean power p. */

/* Memoryless products of quantised signals: mixing two sines (q15_mul, q31_mul, iq_mpy) and
 * scaling an IQ sine by a Q15 / UQ16 gain ramp. Reference: the double product of the same
 * quantised inputs. Bound: ideal rounding SNR - 0.5 dB. */
/* iq_mac2: a*b + c*d rounded once, against the exact sum (128-bit on the host) divided by 2^24,
 * rounded half up and clamped to int32: equal for random operands over the whole IQ range and
 * over +-4 pu (the per-unit quantities it is used with), and at the edges (saturation, no wrap;
 * IQ_MIN^4 excluded, as the header says). */
static void test_iq_mac2_exact(void **state)
{
    fixtest_rng_t rng;
    (void)state;
    fixtest_rng_seed(&rng, 0x5fc0ffeeULL);
    for (long k = 0; k < 400000; k++) {
        const int full = k & 1;
        int32_t v[4];
        for (int j = 0; j < 4; j++) {
            const uint32_t r = (uint32_t)fixtest_rng_u64(&rng);
            v[j] = full ? (int32_t)r : (int32_t)(r >> 5) - (int32_t)(1 << 26);
        }
        if (v[0] == INT32_MIN && v[1] == INT32_MIN && v[2] == INT32_MIN && v[3] == INT32_MIN) {
            continue;
        }
        {
            const __int128 sum = (__int128)v[0] * v[1] + (__int128)v[2] * v[3];
            __int128 q = (sum + ((__int128)1 << 23)) >> 24;
            if (q > INT32_MAX) {
                q = INT32_MAX;
            }
            if (q < INT32_MIN) {
                q = INT32_MIN;
            }
            if (iq_mac2(v[0], v[1], v[2], v[3]) != (int32_t)q) {
                fail_msg("iq_mac2(%ld, %ld, %ld, %ld) = %ld, want %ld", (long)v[0], (long)v[1], (long)v[2],
                         (long)v[3], (long)iq_mac2(v[0], v[1], v[2], v[3]), (long)q);
            }
        }
    }
    assert_int_equal(iq_mac2(IQ_MAX, IQ_MAX, IQ_MAX, IQ_MAX), IQ_MAX);
    assert_int_equal(iq_mac2(IQ_MIN, IQ_MAX, IQ_MIN, IQ_MAX), IQ_MIN);
    assert_int_equal(iq_mac2(IQ(1.5), IQ(2.0), IQ(-0.5), IQ(3.0)), IQ(1.5));
}

static void test_product_trajectories(void **state)
{
    fixtest_acc_t a15;
    fixtest_acc_t a31;
    fixtest_acc_t aiq;
    fixtest_acc_t aq15;
    fixtest_acc_t au16;
    const int32_t n = 40000;
    int32_t k;
    (void)state;
    fixtest_acc_init(&a15);
    fixtest_acc_init(&a31);
    fixtest_acc_init(&aiq);
    fixtest_acc_init(&aq15);
    fixtest_acc_init(&au16);
    for (k = 0; k < n; k++) {
        double t = (double)k * TS_S;
        double s1 = 0.95 * sin(2.0 * FIXTEST_PI * 50.0 * t);
        double s2 = 0.9 * cos(2.0 * FIXTEST_PI * 173.0 * t + 0.3);
        double ramp = -1.0 + 2.0 * (double)k / (double)n; /* gain sweeps -1 .. 1 */
        q15_t x15 = fixtest_d_to_q15(s1);
        q15_t y15 = fixtest_d_to_q15(s2);
        q31_t x31 = fixtest_d_to_q31(s1);
        q31_t y31 = fixtest_d_to_q31(s2);
        iq_t xiq = fixtest_d_to_iq(9.0 * s1); /* up to ~8.6 pu x 11.5 pu: below 128 */
        iq_t yiq = fixtest_d_to_iq(12.0 * s2);
        q15_t g15 = fixtest_d_to_q15(ramp);
        uint16_t g16 = (uint16_t)floor(65535.0 * (double)k / (double)n + 0.5);
        double r;

        r = fixtest_q15_to_d(x15) * fixtest_q15_to_d(y15);
        fixtest_acc_add(&a15, fixtest_q15_to_d(q15_mul(x15, y15)), r);
        r = fixtest_q31_to_d(x31) * fixtest_q31_to_d(y31);
        fixtest_acc_add(&a31, fixtest_q31_to_d(q31_mul(x31, y31)), r);
        r = fixtest_iq_to_d(xiq) * fixtest_iq_to_d(yiq);
        fixtest_acc_add(&aiq, fixtest_iq_to_d(iq_mpy(xiq, yiq)), r);
        r = fixtest_iq_to_d(xiq) * fixtest_q15_to_d(g15);
        fixtest_acc_add(&aq15, fixtest_iq_to_d(iq_mpy_q15(xiq, g15)), r);
        r = fixtest_iq_to_d(xiq) * ((double)g16 / 65536.0);
        fixtest_acc_add(&au16, fixtest_iq_to_d(iq_mpy_uq16(xiq, g16)), r);
    }
    fixtest_snr_check(&a15, fixtest_acc_ideal_snr_db(&a15, LSB_Q15) - 0.5,
                      "q15_mul, 50 Hz x 173 Hz mixing (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&a31, fixtest_acc_ideal_snr_db(&a31, LSB_Q31) - 0.5,
                      "q31_mul, 50 Hz x 173 Hz mixing (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&aiq, fixtest_acc_ideal_snr_db(&aiq, LSB_IQ) - 0.5,
                      "iq_mpy, 50 Hz x 173 Hz mixing (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&aq15, fixtest_acc_ideal_snr_db(&aq15, LSB_IQ) - 0.5,
                      "iq_mpy_q15, sine x gain ramp -1..1 (bound = ideal rounding - 0.5 dB)");
    fixtest_snr_check(&au16, fixtest_acc_ideal_snr_db(&au16, LSB_IQ) - 0.5,
                      "iq_mpy_uq16, sine x gain ramp 0..1 (bound = ideal rounding - 0.5 dB)");
}

/* A first-order low-pass y += g*(x - y), the building block of the flux estimator's leaky
 * integrator, run in IQ with iq_mpy (g in IQ) and with iq_mpy_uq16 (g in UQ16), against the
 * same recursion in double with the same quantised gain and input. Each step adds one rounding
 * error e (variance LSB^2/12) that the filter accumulates: var(y_err) = (LSB^2/12) / (1 -
 * (1-g)^2). That model needs rounding errors that are white; a strictly periodic input makes them
 * periodic instead (measured 2 dB off the model), so the input carries 0.01 pu of seeded
 * uniform "measurement noise", as a real ADC signal does. The error is low-pass with a correlation
 * time of ~1/(2g) steps, so one run holds only n*2g independent samples: the bound is the
 * predicted SNR minus margin_db (1 dB at 50 Hz over 100 k steps, 1.5 dB at 5 rad/s over 400 k
 * steps, ~3.5 standard deviations of the estimate); a truncating multiply loses > 25 dB. */
static void run_lpf(const char *what, bool use_uq16, double fc_hz, int32_t n_steps,
                    double margin_db)
{
    fixtest_rng_t rng;
    fixtest_acc_t acc;
    double wts = 2.0 * FIXTEST_PI * fc_hz * TS_S;
    iq_t g_iq = fixtest_d_to_iq(wts);
    uint16_t g_u16 = (uint16_t)floor(wts * 65536.0 + 0.5);
    double g = use_uq16 ? (double)g_u16 / 65536.0 : fixtest_iq_to_d(g_iq);
    iq_t y = 0;
    double yd = 0.0;
    int32_t k;
    fixtest_acc_init(&acc);
    fixtest_rng_seed(&rng, SEED);
    for (k = 0; k < n_steps; k++) {
        double t = (double)k * TS_S;
        /* Input: DC step to 0.8 pu at 10 % of the run, a 1.2 pu fundamental at 20 Hz and a
         * 0.3 pu fifth harmonic: the filter sees steps, sines and a slow transient. */
        double xv = (k >= n_steps / 10 ? 0.8 : 0.0) + 1.2 * sin(2.0 * FIXTEST_PI * 20.0 * t) +
                    0.3 * sin(2.0 * FIXTEST_PI * 100.0 * t + 1.0) +
                    0.01 * (fixtest_rng_unit(&rng) - 0.5);
        iq_t x = fixtest_d_to_iq(xv);
        double xq = fixtest_iq_to_d(x);
        iq_t e = iq_sub(x, y);
        y = iq_add(y, use_uq16 ? iq_mpy_uq16(e, g_u16) : iq_mpy(g_iq, e));
        yd += g * (xq - yd);
        fixtest_acc_add(&acc, fixtest_iq_to_d(y), yd);
    }
    {
        double var_lsb2 = (1.0 / 12.0) / (1.0 - (1.0 - g) * (1.0 - g));
        double predicted = 10.0 * log10(fixtest_acc_ref_power(&acc) / (var_lsb2 * LSB_IQ * LSB_IQ));
        print_message("[ MEASURE  ] %s: predicted SNR for ideal rounding %.2f dB (g = %.6g)\n",
                      what, predicted, g);
        fixtest_snr_check(&acc, predicted - margin_db, what);
    }
}

static void test_lpf_chain_iq_mpy(void **state)
{
    (void)state;
    run_lpf("iq_mpy low-pass chain, fc = 50 Hz, 100000 steps (bound = predicted - 1 dB)", false,
            50.0, 100000, 1.0);
}

static void test_lpf_chain_iq_mpy_uq16(void **state)
{
    (void)state;
    /* wc = 5 rad/s as in the fixmath.h rationale (the voltage-model leak); 20 s = 100 time
     * constants, so the slow error process is sampled often enough. */
    run_lpf("iq_mpy_uq16 low-pass chain, wc = 5 rad/s, 400000 steps (bound = predicted - 1.5 dB)",
            true, 5.0 / (2.0 * FIXTEST_PI), 400000, 1.5);
}

UNIT_TEST_MAIN("fixmath multiplies", NULL,
               cmocka_unit_test(test_q15_mul_sweep),
               cmocka_unit_test(test_q31_mul_iq_mpy_sweep),
               cmocka_unit_test(test_iq_mpy_q15_uq16_sweep),
               cmocka_unit_test(test_iq_mac2_exact),
               cmocka_unit_test(test_product_trajectories),
               cmocka_unit_test(test_lpf_chain_iq_mpy),
               cmocka_unit_test(test_lpf_chain_iq_mpy_uq16))
