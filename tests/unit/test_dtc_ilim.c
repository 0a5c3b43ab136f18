/* Current limit (firmware/dtc/ilim.h): below the limit the table's vector passes; above it the
 * vector chosen is the one of least v . i, checked against a double transcription of the
 * inverter's vectors (Hoang Table I and eqs. 1-5 for the FSTP, with the mid-point off centre;
 * Casadei eq. 2 for the SSTP), and
 * applying it reduces |i| of a surface PM machine over one period (l_s di = (v - e) Ts). */
#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "fixtest.h"

#include "dtc_config.h"
#include "ilim.h"
#include "dtc_config_si.h"

static double iq_d(iq_t x) { return (double)x / 16777216.0; }
static iq_t d_iq(double x) { return (iq_t)lround(x * 16777216.0); }

/* ilim_select with the parameters the PM law takes from cfg (dtc.c dtc_block_params). */
static uint16_t ilim_select_cfg(const dtc_config_t *c, const clarke_out_t *i, uint16_t vec, uint16_t *limited)
{
    const ilim_params_t p = {c->prot.i_lim_iq, c->board.topology == DTC_TOPO_FSTP ? 1U : 0U};
    return ilim_select(&p, i, vec, limited);
}

/* Amplitude-invariant space vector of leg voltages (Hoang eqs. 1-5), V_dc = 1 pu. */
static void vec_d(int fstp, unsigned k, double vmid, double *va, double *vb)
{
    static const unsigned sstp[7][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 1, 1}, {0, 0, 1}, {1, 0, 1}};
    static const unsigned fst[5][2] = {{0, 0}, {0, 0}, {1, 0}, {1, 1}, {0, 1}};
    double a, b, c;
    if (fstp) {
        a = vmid;
        b = fst[k][0];
        c = fst[k][1];
    } else {
        a = sstp[k][0];
        b = sstp[k][1];
        c = sstp[k][2];
    }
    *va = (2.0 * a - b - c) / 3.0;
    *vb = (b - c) / sqrt(3.0);
}

static void run_topology(int fstp)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    const unsigned n = fstp ? 4U : 6U;
    unsigned replaced = 0U;
    dtc_config_si_defaults(&si);
    si.topology = fstp ? DTC_TOPO_FSTP : DTC_TOPO_SSTP;
    si.compensation = fstp ? DTC_COMP_FSTP_PROPOSED : DTC_COMP_SSTP;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_true(cfg.prot.i_lim_iq > 0 && cfg.prot.i_lim_iq < cfg.prot.i_trip_iq);
    const double lim = iq_d(cfg.prot.i_lim_iq);
    const double vmid = fstp ? 0.47 : 0.5; /* a mid-point off centre (FSTP) */
    for (int a = 0; a < 360; a += 7) {
        for (int r = 0; r < 3; r++) {
            const double mag = lim * (r == 0 ? 0.9 : r == 1 ? 1.05 : 1.3);
            const double ia = mag * cos(a * M_PI / 180.0), ib = mag * sin(a * M_PI / 180.0);
            uint16_t limited = 9U;
            const uint16_t table_vec = fstp ? 2U : 3U;
            clarke_out_t ci;
            clarke_inv(d_iq(ia), d_iq(ib), &ci);
            uint16_t v = ilim_select_cfg(&cfg, &ci, table_vec, &limited);
            if (r == 0) {
                assert_int_equal(v, table_vec);
                assert_int_equal(limited, 0U);
                continue;
            }
            assert_int_equal(limited, 1U);
            replaced++;
            /* the double reference: least v . i among the candidates */
            double best = 1e9, va, vb;
            for (unsigned k = 1U; k <= n; k++) {
                vec_d(fstp, k, vmid, &va, &vb);
                double p = va * ia + vb * ib;
                if (p < best) {
                    best = p;
                }
            }
            vec_d(fstp, v, vmid, &va, &vb);
            assert_true(va * ia + vb * ib <= best + 1e-6);
            /* one period with that vector against the back-EMF of the rated speed (Hoang Table VIII:
             * psi_m = 0.416 pu, w = 1 pu) reduces |i|: di = Ts (v - e) / l_s, Ts = 0.0157 pu,
             * l_s = 0.0315 pu, e perpendicular to the magnet flux (worst case: along i). */
            const double ts = 0.0157, ls = 0.0315, e = 0.416;
            double ja = ia + ts * (va - e * ia / mag) / ls, jb = ib + ts * (vb - e * ib / mag) / ls;
            assert_true(sqrt(ja * ja + jb * jb) < mag);
        }
    }
    assert_true(replaced > 0U);
    /* off: never replaced */
    cfg.prot.i_lim_iq = 0;
    uint16_t limited = 9U;
    clarke_out_t big;
    clarke_inv(d_iq(50.0), 0, &big);
    assert_int_equal(ilim_select_cfg(&cfg, &big, 2U, &limited), 2U);
    assert_int_equal(limited, 0U);
}

static void test_ilim_fstp(void **state)
{
    (void)state;
    run_topology(1);
}

static void test_ilim_sstp(void **state)
{
    (void)state;
    run_topology(0);
}

/* The derived limit (tools/config dtc_ilim_default_a) from its formula: Hoang Table VIII, 70 V FSTP,
 * 50 us, 3000 rpm, 6 A trip: dI = 50e-6 (70/sqrt(3) + 314.16 * 0.0928 + 0.466 * 6) / 3.19e-3. */
static void test_ilim_default(void **state)
{
    (void)state;
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    const double di = 50e-6 * (70.0 / sqrt(3.0) + 2.0 * M_PI * 50.0 * 0.0928 + 0.466 * 6.0) / 3.19e-3;
    assert_true(fabs(di - 1.134) < 0.002);
    assert_true(fabs(dtc_ilim_default_a(&si) - (6.0 - di)) < 1e-9);
    si.delay_comp = 0;
    assert_true(fabs(dtc_ilim_default_a(&si) - (6.0 - 2.0 * di)) < 1e-9);
    si.topology = DTC_TOPO_SSTP;
    si.delay_comp = 1;
    const double di6 = 50e-6 * (2.0 * 70.0 / 3.0 + 2.0 * M_PI * 50.0 * 0.0928 + 0.466 * 6.0) / 3.19e-3;
    assert_true(fabs(dtc_ilim_default_a(&si) - (6.0 - di6)) < 1e-9);
    /* the back-EMF term stops at V_max (16 pole pairs: 466 V at 3000 rpm) */
    si.pole_pairs = 16;
    const double di16 = 50e-6 * (2.0 * 2.0 * 70.0 / 3.0 + 0.466 * 6.0) / 3.19e-3;
    assert_true(fabs(dtc_ilim_default_a(&si) - (6.0 - di16)) < 1e-9);
    /* a trip level inside one period's change: no limit (0), the converter accepts it */
    si.pole_pairs = 1;
    si.topology = DTC_TOPO_FSTP;
    si.i_trip_a = 1.0;
    assert_true(dtc_ilim_default_a(&si) == 0.0);
    dtc_config_t cfg;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    assert_int_equal(cfg.prot.i_lim_iq, 0);
}

/* Currents at the rail of the saturated conversion (+-128 pu: a configuration whose trip level is
 * that high passes them to the law): SSTP i_a = i_b = +max, i_c = -max (clarke_sstp). Per vector
 * the limit sums S_x i_x: V_2 (110) has the largest, +2 max, V_5 (001) the least, -max, so V_5
 * is the choice. The sum must not overflow (found by the fuzzer, tests/fuzz: halved currents
 * summed to 2^31, wrapped to the least value and picked V_2, the vector that drives both large
 * currents further up). */
static void test_ilim_currents_at_the_rail(void **state)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    clarke_out_t ci;
    uint16_t limited = 9U;
    (void)state;
    dtc_config_si_defaults(&si);
    si.topology = DTC_TOPO_SSTP;
    si.compensation = DTC_COMP_SSTP;
    assert_int_equal(dtc_config_from_si(&si, &cfg, NULL, 0), 0);
    clarke_sstp(INT32_MAX, INT32_MAX, &ci);
    assert_int_equal(ci.ic_iq, -INT32_MAX);
    assert_int_equal(ilim_select_cfg(&cfg, &ci, 3U, &limited), 5U);
    assert_int_equal(limited, 1U);
}

/* The FSTP choice written out (ilim_pick) against the candidates' sums S_b i_b + S_c i_c of
 * Hoang Table I's V_1..V_4 (00 10 11 01) on the quartered currents, first of least sum: random
 * currents over the whole int32 range, small ones, ties (zero, equal and opposite phases) and the
 * rails. */
static long long quarter_rounded(iq_t x) /* floor(x / 4 + 1/2), exact */
{
    const long long q = (long long)x + 2;
    return q >= 0 ? q / 4 : -((-q + 3) / 4);
}

static void test_ilim_fstp_first_of_least_sum(void **state)
{
    static const int legs_b[4] = {0, 1, 1, 0}, legs_c[4] = {0, 0, 1, 1};
    const ilim_params_t p = {1, 1U};
    uint32_t r = 88172645U;
    (void)state;
    for (long n = 0; n < 200000; n++) {
        clarke_out_t ci = {0, 0, 0, 0, 0};
        r ^= r << 13;
        r ^= r >> 17;
        r ^= r << 5;
        ci.ib_iq = (iq_t)r >> ((n & 3) == 0 ? 20 : 0);
        r ^= r << 13;
        r ^= r >> 17;
        r ^= r << 5;
        ci.ic_iq = (iq_t)r >> ((n & 3) == 0 ? 20 : 0);
        if ((n & 7) == 1) {
            ci.ic_iq = -ci.ib_iq; /* b + c = 0 */
        } else if ((n & 7) == 2) {
            ci.ic_iq = 0;
        } else if ((n & 7) == 3) {
            ci.ib_iq = 0;
        } else if ((n & 7) == 5) {
            ci.ic_iq = ci.ib_iq;
        } else if (n == 6) {
            ci.ib_iq = INT32_MIN;
            ci.ic_iq = INT32_MIN;
        }
        {
            const long long qb = quarter_rounded(ci.ib_iq), qc = quarter_rounded(ci.ic_iq);
            long long best_s = 0;
            unsigned best = 1U;
            for (unsigned k = 0U; k < 4U; k++) {
                const long long s = legs_b[k] * qb + legs_c[k] * qc;
                if (k == 0U || s < best_s) {
                    best_s = s;
                    best = k + 1U;
                }
            }
            assert_int_equal(ilim_pick(&p, &ci), best);
        }
    }
}

UNIT_TEST_MAIN("dtc ilim", NULL,
               cmocka_unit_test(test_ilim_fstp),
               cmocka_unit_test(test_ilim_sstp),
               cmocka_unit_test(test_ilim_currents_at_the_rail),
               cmocka_unit_test(test_ilim_fstp_first_of_least_sum),
               cmocka_unit_test(test_ilim_default))
