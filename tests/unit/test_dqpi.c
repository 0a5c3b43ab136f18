/*
 * test_dqpi.c - the dq current PI pair (firmware/dtc/dqpi.h) and the Park rotation
 * (firmware/dtc/park.h) against double-precision references: the discrete PI law step by step,
 * the closed loop on an R-L plant with K_p = L w_c, K_i = R w_c (first order, time constant
 * 1/w_c), the circular voltage limit with d-axis priority, and the anti-windup.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "dqpi.h"
#include "fixtest.h"
#include "park.h"

#define PI 3.14159265358979323846
#define LSB (1.0 / 16777216.0)

/* The discrete law of dqpi.h in double (no limit active). */
typedef struct {
    double kp, ki_ts, imax, id, iq;
} ref_pi_t;

static double ref_axis(const ref_pi_t *r, double e, double *integ, double ff)
{
    *integ = fmax(-r->imax, fmin(r->imax, *integ + r->ki_ts * e));
    return ff + r->kp * e + *integ;
}

/* Inputs that move every period (references, measurements, feed-forwards), the limit far away:
 * both outputs within 1 + k/2 LSB of the double law at step k (the integral adds one rounding per
 * period), and the integrals likewise. */
static void test_steps_match_discrete_reference(void **state)
{
    (void)state;
    const dqpi_params_t p = {IQ(0.35), IQ(0.012), IQ(2.0)};
    ref_pi_t r = {fixtest_iq_to_d(p.kp_iq), fixtest_iq_to_d(p.ki_ts_iq), 2.0, 0.0, 0.0};
    dqpi_t s;
    dqpi_reset(&s, 0, 0);
    for (int k = 0; k < 400; k++) {
        dqpi_in_t in;
        dqpi_out_t o;
        const double rd = k < 100 ? 0.0 : -0.2, rq = k < 50 ? 0.5 : 0.8 * cos(k * 0.03);
        const double md = 0.1 * sin(k * 0.11), mq = 0.4 * sin(k * 0.05 + 0.3);
        const double fd = -0.05 * mq, fq = 0.3 + 0.02 * md;
        double vd, vq;
        in.ref_d_iq = fixtest_d_to_iq(rd);
        in.ref_q_iq = fixtest_d_to_iq(rq);
        in.meas_d_iq = fixtest_d_to_iq(md);
        in.meas_q_iq = fixtest_d_to_iq(mq);
        in.ff_d_iq = fixtest_d_to_iq(fd);
        in.ff_q_iq = fixtest_d_to_iq(fq);
        in.vmax_iq = IQ(50.0);
        dqpi_step(&s, &p, &in, &o);
        vd = ref_axis(&r, fixtest_iq_to_d(in.ref_d_iq) - fixtest_iq_to_d(in.meas_d_iq), &r.id, fixtest_iq_to_d(in.ff_d_iq));
        vq = ref_axis(&r, fixtest_iq_to_d(in.ref_q_iq) - fixtest_iq_to_d(in.meas_q_iq), &r.iq, fixtest_iq_to_d(in.ff_q_iq));
        fixtest_assert_lsb(fixtest_iq_to_d(o.v_d_iq), vd, LSB, 1.0 + 0.5 * k, "v_d against the discrete PI");
        fixtest_assert_lsb(fixtest_iq_to_d(o.v_q_iq), vq, LSB, 1.0 + 0.5 * k, "v_q against the discrete PI");
        fixtest_assert_lsb(fixtest_iq_to_d(s.int_q_iq), r.iq, LSB, 0.5 * (k + 1), "q integral");
        assert_int_equal(o.limited, 0U);
    }
}

/* Closed loop on L di/dt = v - R i (exact zero-order-hold discretisation, pu) with K_p = L w_c,
 * K_i = R w_c: the zero cancels the plant pole and the loop is w_c/s sampled, a first-order lag
 * with its pole at 1 - w_c Ts: a current step settles as 1 - (1 - w_c Ts)^k (within 0.5 % of the
 * step at every sample, no overshoot), and within 5 % of the continuous 1 - exp(-w_c t) (4.2 % at
 * w_c Ts = 0.2, the sampling lag). */
static void test_closed_loop_is_first_order_at_the_derived_bandwidth(void **state)
{
    (void)state;
    const double ts = 50e-6, wb = 2.0 * PI * 50.0; /* any base: only products with Ts matter */
    const double l = 0.10, rr = 0.05;              /* pu inductance (x w_base) and resistance */
    const double wc = 0.2 / ts;                    /* rad/s */
    const dqpi_params_t p = {fixtest_d_to_iq(l * wc / wb), fixtest_d_to_iq(rr * wc * ts), IQ(2.0)};
    const double a = exp(-rr / l * wb * ts), b = (1.0 - a) / rr;
    double i = 0.0;
    dqpi_t s;
    dqpi_reset(&s, 0, 0);
    for (int k = 1; k <= 200; k++) {
        dqpi_in_t in = {0, IQ(0.5), 0, fixtest_d_to_iq(i), 0, 0, IQ(10.0)};
        dqpi_out_t o;
        dqpi_step(&s, &p, &in, &o);
        i = a * i + b * fixtest_iq_to_d(o.v_q_iq);
        {
            const double discrete = 0.5 * (1.0 - pow(1.0 - wc * ts, k));
            const double cont = 0.5 * (1.0 - exp(-wc * k * ts));
            assert_true(fabs(i - discrete) < 0.005 * 0.5);
            assert_true(fabs(i - cont) < 0.05 * 0.5);
            assert_true(i <= 0.5 + 1e-6);
        }
    }
}

/* Voltage limit: |v| <= V_max (within 1 LSB), the d axis served first (v_d = u_d inside +-V_max,
 * v_q = sqrt(V_max^2 - v_d^2) in the direction of u_q), and the integral of a limited axis frozen
 * while its error pushes further: after 500 saturated periods the integral is where it was
 * when the limit was reached, and once the error reverses the output leaves the limit within 3
 * periods. */
static void test_voltage_limit_and_anti_windup(void **state)
{
    (void)state;
    const dqpi_params_t p = {IQ(0.3), IQ(0.01), IQ(4.0)};
    dqpi_t s;
    dqpi_out_t o;
    dqpi_in_t in = {0, IQ(3.0), 0, 0, IQ(0.02), IQ(0.1), IQ(0.5)};
    iq_t int_at_limit = 0;
    dqpi_reset(&s, 0, 0);
    for (int k = 0; k < 500; k++) {
        dqpi_step(&s, &p, &in, &o);
        {
            const double vd = fixtest_iq_to_d(o.v_d_iq), vq = fixtest_iq_to_d(o.v_q_iq);
            assert_true(sqrt(vd * vd + vq * vq) <= 0.5 + LSB);
            assert_int_equal(o.limited, 1U);
            fixtest_assert_lsb(vd, 0.02, LSB, 1.0, "d axis first");
            fixtest_assert_lsb(vq, sqrt(0.25 - vd * vd), LSB, 2.0, "q gets what the circle leaves");
        }
        if (k == 0) {
            int_at_limit = s.int_q_iq;
        }
    }
    assert_int_equal(s.int_q_iq, int_at_limit);
    /* the error reverses: the unlimited output is back inside within 3 periods */
    in.ref_q_iq = 0;
    in.meas_q_iq = IQ(0.2);
    {
        int k = 0;
        do {
            dqpi_step(&s, &p, &in, &o);
            k++;
        } while (o.limited != 0U && k < 10);
        assert_true(k <= 3);
    }
    /* a negative limit is zero volts */
    in.vmax_iq = -IQ(1.0);
    dqpi_step(&s, &p, &in, &o);
    assert_int_equal(o.v_d_iq, 0);
    assert_int_equal(o.v_q_iq, 0);
}

/* Park and its inverse against the double rotation over every 1/512 turn: within 2e-4 of |x| for
 * a 1.5 pu vector (Q15 sine), and the round trip within the same. */
/* dqpi_integrate against a double-precision reference of I + k e clamped to +-lim (k e rounded to
 * the IQ LSB), and against the 32-bit chain it replaces (iq_mpy's saturation, the saturating sum,
 * the clamp): identical over random integrals within the clamp, gains and errors up to the IQ
 * range's ends (saturated products of both signs included), for clamps from one LSB to 64 pu. */
static void test_integrate_matches_reference(void **state)
{
    (void)state;
    uint64_t x = 0x9E3779B97F4A7C15ULL;
    long n, saturated = 0;
    for (n = 0; n < 2000000; n++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        const iq_t lim = (iq_t)(1 + (x % ((uint64_t)1 << 30)));
        const iq_t integ = (iq_t)((int64_t)((x >> 8) % (2ULL * (uint64_t)lim + 1U)) - lim);
        const iq_t k = (iq_t)(uint32_t)(x >> 17);
        const iq_t e = (iq_t)(uint32_t)(x >> 29) >> (unsigned)(n % 24);
        const iq_t got = dqpi_integrate(integ, k, e, lim);
        const iq_t chain = fix_clamp32(iq_add(integ, iq_mpy(k, e)), -lim, lim);
        double ref = (double)integ + floor((double)k * (double)e / 16777216.0 + 0.5);
        ref = ref > lim ? lim : (ref < -lim ? -lim : ref);
        assert_int_equal(got, chain);
        assert_true(fabs((double)got - ref) < 0.5);
        if (fabs((double)k * (double)e / 16777216.0) > 2147483647.0) {
            saturated++;
        }
    }
    assert_true(saturated > 1000); /* the saturated products were reached */
}

static void test_park_against_double_rotation(void **state)
{
    (void)state;
    for (int n = 0; n < 512; n++) {
        const angle_t th = (angle_t)(n * 128);
        const double t = 2.0 * PI * th / 65536.0;
        const double xa = 1.5 * cos(0.3 + n * 0.01), xb = 1.5 * sin(0.3 + n * 0.01);
        park_sc_t sc;
        iq_t d, q, a, b;
        park_sincos(th, &sc);
        park_fwd(&sc, fixtest_d_to_iq(xa), fixtest_d_to_iq(xb), &d, &q);
        assert_true(fabs(fixtest_iq_to_d(d) - (xa * cos(t) + xb * sin(t))) < 2e-4 * 1.5);
        assert_true(fabs(fixtest_iq_to_d(q) - (-xa * sin(t) + xb * cos(t))) < 2e-4 * 1.5);
        park_inv(&sc, d, q, &a, &b);
        assert_true(fabs(fixtest_iq_to_d(a) - xa) < 2e-4 * 1.5);
        assert_true(fabs(fixtest_iq_to_d(b) - xb) < 2e-4 * 1.5);
    }
}

UNIT_TEST_MAIN("dqpi", NULL,
               cmocka_unit_test(test_steps_match_discrete_reference),
               cmocka_unit_test(test_closed_loop_is_first_order_at_the_derived_bandwidth),
               cmocka_unit_test(test_voltage_limit_and_anti_windup),
               cmocka_unit_test(test_integrate_matches_reference),
               cmocka_unit_test(test_park_against_double_rotation))
