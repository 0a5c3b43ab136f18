/*
 * test_fixmath_trig.c - fix_sin, fix_cos, fix_sector6 and fix_quadrant against double sin, cos
 * and atan2.
 *
 * fix_sin / fix_cos: all 65536 angles against sin/cos of the same angle (the true value, not
 * clamped: at the peaks Q15 cannot hold 1.0 and the 1 LSB that costs is part of the bound).
 * The a-priori bound of a quarter-wave table of 256 segments in Q15 is 1.154 LSB (table rounding
 * 0.5, linear interpolation (pi/512)^2/8 = 4.7e-6 = 0.154, final rounding 0.5); the sweep is
 * exhaustive, so its worst case (1.0007 LSB, at the peaks where 1.0 saturates to 32767) is exact,
 * and SIN_MAX_LSB = 1.01 sits just above it: a truncating interpolation or the former whole-turn
 * table (3.5 LSB) fails. Trajectories: sin/cos of a 50 Hz angle ramp and of a 0..400 Hz chirp,
 * and the radius of the (cos, sin) pair, against double.
 *
 * fix_sector6 / fix_quadrant: dense angle sweeps at radii from 1 LSB to the IQ limit, every
 * point with |alpha|, |beta| <= 40 LSB, seeded random points of every magnitude, and the
 * extremes, all against the sector atan2 gives. A point closer than BOUNDARY_TOL_RAD to a
 * boundary ray may land in either adjacent sector (the rays at 30 + 60k degrees are irrational
 * and the implementation approximates sqrt(3)); points built on the boundary rays must land in
 * one of the two adjacent sectors. Measured figures print as "[ MEASURE  ]" lines.
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
#define SEED 0x5EEDF1C5ULL
#define SIN_MAX_LSB 1.01
/* The implementation's sqrt(3) (Q30) puts the 30 + 60k degree rays within 9e-11 rad of the true
 * ones; closer than this to a ray, either adjacent sector is right. */
#define BOUNDARY_TOL_RAD 2e-10

/* ---------------------------------------------------------------------------------------- */

static void test_sin_cos_all_angles(void **state)
{
    fixtest_lsb_t ts;
    fixtest_lsb_t tc;
    int32_t a;
    (void)state;
    fixtest_lsb_init(&ts);
    fixtest_lsb_init(&tc);
    for (a = 0; a < 65536; a++) {
        double th = 2.0 * FIXTEST_PI * (double)a / 65536.0;
        q15_t s = fix_sin((angle_t)a);
        q15_t c = fix_cos((angle_t)a);
        fixtest_lsb_add(&ts, fixtest_q15_to_d(s), sin(th), LSB_Q15, a, 0);
        fixtest_lsb_add(&tc, fixtest_q15_to_d(c), cos(th), LSB_Q15, a, 0);
        /* Never the one Q15 value without a positive counterpart; exactly odd / even. */
        assert_true(s != Q15_MIN && c != Q15_MIN);
        assert_int_equal(fix_sin((angle_t)(65536 - a)), -s);
        assert_int_equal(fix_cos((angle_t)(65536 - a)), c);
        {
            /* the pair from one decode: the same two values (and so the same bounds) */
            q15_t s2, c2;
            fix_sincos((angle_t)a, &s2, &c2);
            assert_int_equal(s2, s);
            assert_int_equal(c2, c);
        }
    }
    fixtest_lsb_check(&ts, SIN_MAX_LSB, "fix_sin, all 65536 angles");
    fixtest_lsb_check(&tc, SIN_MAX_LSB, "fix_cos, all 65536 angles");
    assert_int_equal(fix_sin(ANGLE(0.0)), 0);
    assert_int_equal(fix_sin(ANGLE(0.5)), 0);
    assert_int_equal(fix_sin(ANGLE(0.25)), Q15_MAX);
    assert_int_equal(fix_sin(ANGLE(0.75)), -Q15_MAX);
    assert_int_equal(fix_cos(ANGLE(0.0)), Q15_MAX);
    assert_int_equal(fix_cos(ANGLE(0.5)), -Q15_MAX);
    assert_int_equal(fix_cos(ANGLE(0.25)), 0);
    assert_int_equal(fix_sin(65535U), -fix_sin(1U)); /* the zero crossing, both sides */
}


/* Angle ramps: 50 Hz at the 50 us control rate (phase accumulated in double and quantised to
 * angle_t, as a speed integrator would), and a chirp 0 -> 400 Hz over 2 s. Reference: sin/cos of
 * the same quantised angle. Bound: the SNR of ideal Q15 rounding of a unit sine (98.1 dB) minus
 * SIN_SNR_LOSS_DB: the table's rounding noise, interpolated (variance x E[(1-f)^2 + f^2] = 2/3),
 * adds to the final rounding, 10*log10(5/3) = 2.2 dB, plus 0.3 dB margin. Also the radius
 * hypot(cos, sin) of the rotating unit vector against 1.0: the components' errors are partly
 * correlated, so the worst case is bounded by sqrt(2) * SIN_MAX_LSB. */
#define SIN_SNR_LOSS_DB 2.5
static void test_sin_cos_trajectories(void **state)
{
    fixtest_acc_t as;
    fixtest_acc_t ac;
    fixtest_acc_t am;
    double phase = 0.0;
    const int32_t n = 40000;
    int32_t k;
    int pass;
    (void)state;
    for (pass = 0; pass < 2; pass++) {
        fixtest_acc_init(&as);
        fixtest_acc_init(&ac);
        fixtest_acc_init(&am);
        phase = 0.0;
        for (k = 0; k < n; k++) {
            double t = (double)k * 50e-6;
            double f = pass == 0 ? 50.0 : 400.0 * t / 2.0;
            angle_t a;
            double th;
            q15_t s;
            q15_t c;
            phase += f * 50e-6; /* turns */
            a = (angle_t)((int64_t)floor(phase * 65536.0 + 0.5) & 0xFFFF);
            th = 2.0 * FIXTEST_PI * (double)a / 65536.0;
            s = fix_sin(a);
            c = fix_cos(a);
            fixtest_acc_add(&as, fixtest_q15_to_d(s), sin(th));
            fixtest_acc_add(&ac, fixtest_q15_to_d(c), cos(th));
            fixtest_acc_add(&am, hypot(fixtest_q15_to_d(c), fixtest_q15_to_d(s)), 1.0);
        }
        {
            double bound_s = fixtest_acc_ideal_snr_db(&as, LSB_Q15) - SIN_SNR_LOSS_DB;
            double bound_c = fixtest_acc_ideal_snr_db(&ac, LSB_Q15) - SIN_SNR_LOSS_DB;
            fixtest_snr_check(&as, bound_s, pass == 0 ? "fix_sin, 50 Hz angle ramp" : "fix_sin, 0..400 Hz chirp");
            fixtest_snr_check(&ac, bound_c, pass == 0 ? "fix_cos, 50 Hz angle ramp" : "fix_cos, 0..400 Hz chirp");
            /* Radius of (cos, sin): SNR against the unit circle, bound as for the components
             * plus 0.5 dB (the saturated peaks add a -1 LSB radius error four times per turn),
             * and worst case within sqrt(2) * SIN_MAX_LSB. */
            fixtest_snr_check(&am, fixtest_ideal_rounding_snr_db(1.0, LSB_Q15) - SIN_SNR_LOSS_DB - 0.5,
                              pass == 0 ? "hypot(fix_cos, fix_sin) vs 1, 50 Hz ramp"
                                        : "hypot(fix_cos, fix_sin) vs 1, chirp");
            print_message("[ MEASURE  ] radius error max %.4f LSB (bound %.4f)\n",
                          am.max_abs_err / LSB_Q15, sqrt(2.0) * SIN_MAX_LSB);
            assert_true(am.max_abs_err <= sqrt(2.0) * SIN_MAX_LSB * LSB_Q15);
        }
    }
}

/* ---------------------------------------------------------------------------------------- */
/* Sector and quadrant                                                                        */

/* Angle of (alpha, beta) in [0, 2*pi) from atan2 of the exact integers. */
static double angle_of(iq_t alpha, iq_t beta)
{
    double th = atan2((double)beta, (double)alpha);
    return th < 0.0 ? th + 2.0 * FIXTEST_PI : th;
}

/* Sector 1..6 of an angle: sector s covers [60(s-1) - 30, 60(s-1) + 30) degrees. */
static uint16_t sector_of(double th)
{
    double d = th / (FIXTEST_PI / 3.0) + 0.5; /* sector width pi/3, centred on k*pi/3 */
    int32_t s = (int32_t)floor(d);
    return (uint16_t)(((s % 6) + 6) % 6 + 1);
}

static uint16_t quadrant_of(double th)
{
    int32_t q = (int32_t)floor(th / (FIXTEST_PI / 2.0));
    return (uint16_t)(((q % 4) + 4) % 4 + 1);
}

typedef struct {
    size_t n;
    size_t near_boundary; /* points within BOUNDARY_TOL_RAD of a boundary (either side accepted) */
} sector_stats_t;

static void sector_point(sector_stats_t *st, iq_t alpha, iq_t beta)
{
    uint16_t s = fix_sector6(alpha, beta);
    uint16_t q = fix_quadrant(alpha, beta);
    st->n++;
    if (alpha == 0 && beta == 0) {
        assert_int_equal(s, 1U);
        assert_int_equal(q, 1U);
        return;
    }
    {
        double th = angle_of(alpha, beta);
        uint16_t s_lo = sector_of(th - BOUNDARY_TOL_RAD);
        uint16_t s_hi = sector_of(th + BOUNDARY_TOL_RAD);
        uint16_t q_lo = quadrant_of(th - BOUNDARY_TOL_RAD < 0.0 ? th - BOUNDARY_TOL_RAD + 2.0 * FIXTEST_PI
                                                                : th - BOUNDARY_TOL_RAD);
        uint16_t q_hi = quadrant_of(th + BOUNDARY_TOL_RAD);
        if (s_lo != s_hi || q_lo != q_hi) {
            st->near_boundary++;
        }
        if (s != s_lo && s != s_hi) {
            fail_msg("fix_sector6(%d, %d) = %u, atan2 gives %.12f deg: sector %u (or %u)", alpha,
                     beta, s, th * 180.0 / FIXTEST_PI, s_lo, s_hi);
        }
        if (q != q_lo && q != q_hi) {
            fail_msg("fix_quadrant(%d, %d) = %u, atan2 gives %.12f deg: quadrant %u (or %u)", alpha,
                     beta, q, th * 180.0 / FIXTEST_PI, q_lo, q_hi);
        }
    }
}

static iq_t round_sat_iq(double x)
{
    double r = floor(x + 0.5);
    return (iq_t)fmin(fmax(r, (double)INT32_MIN), (double)INT32_MAX);
}

static void test_sector_quadrant_sweeps(void **state)
{
    /* Radii in LSB: tiny (1.5, 7, 100 LSB), per-unit (2^-8, 1, 2 pu), huge (100 pu, and the IQ
     * limit, where the diagonal saturates one component). */
    static const double radii[] = {1.5, 7.0, 100.0, 65536.0, 16777216.0, 33554432.0,
                                   1677721600.0, 2147483647.0, 3037000499.0};
    sector_stats_t st = {0U, 0U};
    fixtest_rng_t rng;
    size_t i;
    int32_t k;
    int32_t a;
    int32_t b;
    (void)state;
    for (i = 0U; i < sizeof radii / sizeof radii[0]; i++) {
        for (k = 0; k < 4 * 65536; k++) { /* 1/4 angle LSB steps, offset off the axes */
            double th = 2.0 * FIXTEST_PI * ((double)k + 0.37) / (4.0 * 65536.0);
            sector_point(&st, round_sat_iq(radii[i] * cos(th)), round_sat_iq(radii[i] * sin(th)));
        }
    }
    for (a = -40; a <= 40; a++) { /* every small integer point, including the origin */
        for (b = -40; b <= 40; b++) {
            sector_point(&st, a, b);
        }
    }
    {
        const iq_t e[] = {IQ_MIN, IQ_MIN + 1, -1, 0, 1, IQ_MAX - 1, IQ_MAX};
        size_t j;
        for (i = 0U; i < sizeof e / sizeof e[0]; i++) {
            for (j = 0U; j < sizeof e / sizeof e[0]; j++) {
                sector_point(&st, e[i], e[j]);
            }
        }
    }
    fixtest_rng_seed(&rng, SEED);
    for (i = 0U; i < 2000000U; i++) {
        iq_t x = (i & 1U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng);
        sector_point(&st, x, (i & 2U) ? fixtest_rng_i32(&rng) : fixtest_rng_i32_log(&rng));
    }
    print_message("[ MEASURE  ] fix_sector6 / fix_quadrant: %zu points vs atan2, all in the atan2 "
                  "sector; %zu within %.0e rad of a boundary (either side accepted)\n",
                  st.n, st.near_boundary, BOUNDARY_TOL_RAD);
}

/* Points built on the boundary rays (30 + 60k degrees for sectors, the axes for quadrants),
 * rounded to the integer grid, at many radii: each must land in one of the two sectors that
 * meet there. On the axes the documented choice is checked exactly. */
static void test_sector_quadrant_boundaries(void **state)
{
    int32_t ray;
    int32_t e;
    size_t n = 0U;
    (void)state;
    for (ray = 0; ray < 6; ray++) {
        double th = FIXTEST_PI / 6.0 + (double)ray * FIXTEST_PI / 3.0;
        uint16_t before = (uint16_t)(ray + 1);            /* sector ending at this ray */
        uint16_t after = (uint16_t)((ray + 1) % 6 + 1);   /* sector starting at it */
        for (e = 0; e <= 310; e++) {
            double r = pow(2.0, (double)e / 10.0); /* 1 LSB .. 2^31 LSB */
            int32_t da;
            int32_t db;
            /* The rounded point, and from r = 64 LSB on (where a 1 LSB step is < 1.3 degrees)
             * its 8 grid neighbours, which straddle the ray. */
            int32_t nb = r >= 64.0 ? 1 : 0;
            for (da = -nb; da <= nb; da++) {
                for (db = -nb; db <= nb; db++) {
                    double ar = floor(r * cos(th) + 0.5) + da;
                    double br = floor(r * sin(th) + 0.5) + db;
                    uint16_t s;
                    if (fabs(ar) > 2147483647.0 || fabs(br) > 2147483647.0 || (ar == 0.0 && br == 0.0)) {
                        continue;
                    }
                    s = fix_sector6((iq_t)ar, (iq_t)br);
                    n++;
                    if (s != before && s != after) {
                        fail_msg("fix_sector6(%.0f, %.0f) on the %d deg ray = %u, expected %u or %u",
                                 ar, br, 30 + 60 * ray, s, before, after);
                    }
                }
            }
        }
    }
    print_message("[ MEASURE  ] fix_sector6: %zu points on/next to the six boundary rays, all in an "
                  "adjacent sector\n", n);
    /* The axes are exact rays: documented choices. */
    for (e = 0; e <= 31; e++) {
        iq_t r = (iq_t)(((int64_t)1 << e) - (e == 31 ? 1 : 0));
        assert_int_equal(fix_sector6(0, r), 3U);  /* +90 deg: sector 3 (adjacent: 2) */
        assert_int_equal(fix_sector6(0, -r), 5U); /* -90 deg: sector 5 (adjacent: 6) */
        assert_int_equal(fix_sector6(r, 0), 1U);  /* 0 deg: centre of sector 1 */
        assert_int_equal(fix_sector6(-r, 0), 4U); /* 180 deg: centre of sector 4 */
        assert_int_equal(fix_quadrant(r, 0), 1U);
        assert_int_equal(fix_quadrant(0, r), 2U);
        assert_int_equal(fix_quadrant(-r, 0), 3U);
        assert_int_equal(fix_quadrant(0, -r), 4U);
    }
    assert_int_equal(fix_sector6(0, IQ_MIN), 5U);
    assert_int_equal(fix_sector6(IQ_MIN, 0), 4U);
    assert_int_equal(fix_quadrant(IQ_MIN, 0), 3U);
    assert_int_equal(fix_quadrant(0, IQ_MIN), 4U);
    assert_int_equal(fix_sector6(0, 0), 1U);
    assert_int_equal(fix_quadrant(0, 0), 1U);
}

UNIT_TEST_MAIN("fixmath sine, cosine, sector", NULL,
               cmocka_unit_test(test_sin_cos_all_angles),
               cmocka_unit_test(test_sin_cos_trajectories),
               cmocka_unit_test(test_sector_quadrant_sweeps),
               cmocka_unit_test(test_sector_quadrant_boundaries))
