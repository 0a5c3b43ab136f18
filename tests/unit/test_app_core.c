/*
 * test_app_core.c - the drive state machine and ISR body (firmware/app/app_core.h):
 * calibration, per-unit conversion against a double reference, every trip on the very sample that
 * exceeds its level (and not one LSB below it), latching with gates off, fault clearing, encoder
 * plausibility, and that RUN forwards exactly what the controller decides.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "app_core.h"
#include "law.h"
#include "flux_est.h"
#include "svm.h"
#include "dtc_config_si.h"
#include "fixtest.h"

typedef struct {
    dtc_config_si_t si;
    dtc_config_t cfg;
    dtc_bases_t b;
    app_core_t app;
    hal_meas_t m;
    hal_cmd_t cmd;
} fx_t;

static fx_t fx;

/* ADC counts for a physical value (the inverse of the sensing chain the config describes). */
static uint16_t i_counts(double amps, int offset)
{
    double c = floor(offset + amps / fx.si.adc_i_a_per_count + 0.5);
    return (uint16_t)(c < 0 ? 0 : c > 4095 ? 4095 : c);
}
static uint16_t v_counts(double volts) { return (uint16_t)floor(volts / fx.si.adc_vdc_v_per_count + 0.5); }

static void meas_idle(void)
{
    fx.m.adc[HAL_ADC_IA] = (uint16_t)fx.si.adc_i_offset[0];
    fx.m.adc[HAL_ADC_IB] = (uint16_t)fx.si.adc_i_offset[1];
    fx.m.adc[HAL_ADC_IC] = (uint16_t)fx.si.adc_i_offset[2];
    fx.m.adc[HAL_ADC_VDC] = v_counts(fx.si.vdc_v);
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0);
    fx.m.qep_count = 100U;
    fx.m.qep_index_seen = 0U;
    fx.m.trip = 0U;
    fx.m.desat = 0U;
}

/* Calibration length: the current offsets take 2^APP_CAL_LOG2 samples, the FSTP mid-point
 * calibration (cfg.vmid_cal) 2^APP_VMID_CAL_LOG2. */
static uint16_t cal_len(void)
{
    return (uint16_t)(1U << (fx.cfg.board.vmid_cal != 0U ? APP_VMID_CAL_LOG2 : APP_CAL_LOG2));
}

static uint16_t step(void)
{
    uint16_t off = app_core_step(&fx.app, &fx.m, &fx.cmd);
    fx.m.tick++;
    return off;
}

/* This test's currents are scripted, not a machine's: they do not follow the voltage the law
 * applies, which the current-sensor plausibility check (app_plaus.h) rightly trips on; it is off
 * for the test (prot.i_plaus = 0; the app reads the configuration live). */
static void static_currents(void)
{
    fx.cfg.prot.i_plaus = 0U;
}

static void setup_topology(int topology)
{
    char msg[200];
    dtc_config_si_defaults(&fx.si);
    fx.si.topology = topology;
    if (topology == DTC_TOPO_FSTP) {
        fx.si.compensation = DTC_COMP_FSTP_PROPOSED;
        fx.si.fstp_vmid_measured = 1;
    } else {
        fx.si.compensation = DTC_COMP_SSTP;
    }
    fx.si.mode = DTC_MODE_TORQUE;
    if (dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("default configuration refused: %s", msg);
    }
    dtc_bases_from_si(&fx.si, &fx.b);
    fx.m.tick = 0U;
    meas_idle();
}

/* Init, then run the calibration with the given constant offset error on the measured channels. */
static void run_to_state(int topology, int offset_error)
{
    uint16_t k;
    setup_topology(topology);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
    for (k = 0; k < 3; k++) {
        fx.m.adc[k] = (uint16_t)(fx.si.adc_i_offset[k] + offset_error);
    }
    for (k = 0; k < cal_len(); k++) {
        /* Gates off while the current offsets are measured; then, with the FSTP mid-point
         * calibration and a hold current, the rotor hold: legs B and C only, complementary. */
        const uint16_t hold = (uint16_t)(k >= (1U << APP_CAL_LOG2) && fx.cfg.prot.i_hold_iq > 0 &&
                                         fx.cfg.board.vmid_cal != 0U && offset_error == 0);
        const uint16_t off = step();
        if (fx.app.st.state == APP_STATE_FAULT) {
            break;
        }
        assert_int_equal(off, hold ? 0U : 1U);
        assert_int_equal(fx.cmd.enable, hold);
        if (hold != 0U) {
            assert_int_equal(fx.cmd.sb + fx.cmd.sc, 1U);
        }
    }
}

static void test_calibration_finds_offsets_then_runs(void **state)
{
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 7);
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    assert_int_equal(fx.app.offset[HAL_ADC_IA], fx.si.adc_i_offset[0] + 7);
    assert_int_equal(fx.app.offset[HAL_ADC_IB], fx.si.adc_i_offset[1] + 7);
    /* The first RUN period enables the gates. */
    assert_int_equal(step(), 0);
    assert_int_equal(fx.cmd.enable, 1);
}

static void test_calibration_mean_is_rounded_with_noise(void **state)
{
    uint16_t k;
    (void)state;
    setup_topology(DTC_TOPO_FSTP);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    /* Alternating +3 / -2 counts around nominal+10: mean = nominal + 10.5 -> rounds to +11 (B)
     * and a constant +10 on C. FSTP calibrates B and C only. */
    for (k = 0; k < cal_len(); k++) {
        fx.m.adc[HAL_ADC_IB] = (uint16_t)(fx.si.adc_i_offset[1] + 10 + ((k & 1U) ? 3 : -2));
        fx.m.adc[HAL_ADC_IC] = (uint16_t)(fx.si.adc_i_offset[2] + 10);
        fx.m.adc[HAL_ADC_IA] = 0U; /* not fitted on the FSTP board: must not matter */
        step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    assert_int_equal(fx.app.offset[HAL_ADC_IB], fx.si.adc_i_offset[1] + 11);
    assert_int_equal(fx.app.offset[HAL_ADC_IC], fx.si.adc_i_offset[2] + 10);
    assert_int_equal(fx.app.offset[HAL_ADC_IA], fx.si.adc_i_offset[0]);
}

/* FSTP mid-point calibration (app_core.c app_vmid_cal_add/set): a mid-point sensor reading 1.5 V
 * high (+-1 count of noise) against V_dc/2 is calibrated out to within one ADC count of voltage,
 * so the per-unit mid-point in RUN is V_dc/2; one reading 5 V high (above V_dc/16 = 4.4 V) is a
 * broken sensor: ADC-offset fault naming the channel. Off (vmid_cal = 0) the mid-point passes
 * as measured. */
static void test_midpoint_calibration(void **state)
{
    (void)state;
    setup_topology(DTC_TOPO_FSTP);
    assert_int_equal(fx.cfg.board.vmid_cal, 1U);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    const uint16_t mid = v_counts(fx.si.vdc_v / 2.0 + 1.5);
    for (uint16_t k = 0; k < cal_len(); k++) {
        fx.m.adc[HAL_ADC_VMID] = (uint16_t)(mid + ((k & 1U) ? 1 : -1));
        assert_int_equal(step(), k < (1U << APP_CAL_LOG2) ? 1 : 0); /* then the rotor hold */
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    fx.m.adc[HAL_ADC_VMID] = mid;
    dtc_meas_t pu;
    app_core_convert(&fx.app, &fx.m, &pu);
    const double lsb_v = fx.si.adc_vmid_v_per_count;
    const double vmid_v = (double)pu.vmid_iq / 16777216.0 * fx.b.v_base_v;
    const double vdc_v = (double)pu.vdc_iq / 16777216.0 * fx.b.v_base_v;
    assert_true(fabs(vmid_v - vdc_v / 2.0) < lsb_v);
    /* a mid-point 12 V above V_dc/2 (plus the 1.5 V the calibration removes) reaches the law
     * 12 V above: the conversion only calibrates (the restoring reconstruction is the law's,
     * dtc.c dtc_vmid_dev) */
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0 + 1.5 + 12.0);
    app_core_convert(&fx.app, &fx.m, &pu);
    const double dev_v = (double)pu.vmid_iq / 16777216.0 * fx.b.v_base_v -
                         (double)pu.vdc_iq / 16777216.0 * fx.b.v_base_v / 2.0;
    assert_true(fabs(dev_v - 12.0) < 2.0 * lsb_v);

    setup_topology(DTC_TOPO_FSTP);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0 + 5.0);
    for (uint16_t k = 0; k < cal_len(); k++) {
        step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_ADC_OFFSET);
    assert_int_equal(fx.app.st.fault_detail, HAL_ADC_VMID);

    setup_topology(DTC_TOPO_FSTP);
    fx.si.vmid_cal = 0;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, NULL, 0), 0);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    fx.m.adc[HAL_ADC_VMID] = mid;
    for (uint16_t k = 0; k < cal_len(); k++) {
        step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    app_core_convert(&fx.app, &fx.m, &pu);
    assert_true(fabs((double)pu.vmid_iq / 16777216.0 * fx.b.v_base_v - vdc_v / 2.0 - 1.5) < lsb_v);
}

/* Count at which the current model's electrical angle (flux_est_angle) is nearest to the given
 * fraction of a turn. */
static uint16_t count_at_angle(double turns)
{
    uint16_t best = 0U;
    double best_e = 2.0;
    for (uint32_t n = 0U; n < fx.cfg.board.enc_counts; n++) {
        const angle_t a = flux_est_angle((uint16_t)n, fx.cfg.board.enc_gain_q16, fx.cfg.board.enc_offset);
        double e = fabs((double)a / 65536.0 - turns);
        e = e > 0.5 ? 1.0 - e : e;
        if (e < best_e) {
            best_e = e;
            best = (uint16_t)n;
        }
    }
    return best;
}

/* Rotor hold during the FSTP mid-point calibration (app_hold.c app_hold_step), against the physics:
 * the hold may only use (S_B, S_C) = (1, 0), which raises i_b - i_c (v_beta = +V_dc/sqrt(3)),
 * or (0, 1); the torque of a phase-B/C current is T = 3/2 p psi_m (i_b - i_c)/sqrt(3) cos theta_e
 * (Hoang eq. 10 with i_alpha = 0), so the target of i_b - i_c is 2 i_hold (saturated beyond two
 * counts) with the sign of -deviation * cos theta_e, and the leg pair is the one that moves
 * i_b - i_c towards it. Cases: deviation 0, +-1, +-5 counts at theta_e = 0 and pi, with i_b - i_c
 * just below and above the double-precision target. An over-current in the hold trips with the
 * gates off; cal_hold = 0 keeps the gates off for the whole calibration. */
static void test_rotor_hold(void **state)
{
    (void)state;
    for (int half = 0; half < 2; half++) {
        setup_topology(DTC_TOPO_FSTP);
        static_currents();
        assert_true(fx.cfg.prot.i_hold_iq > 0);
        const double ih_a = (double)fx.cfg.prot.i_hold_iq / 16777216.0 * fx.b.i_base_a;
        /* the derived hold current: the torque limit's current, 0.6 / (1.5 * 0.0928) = 4.31 A, below the 4.87 A limit */
        assert_true(fabs(ih_a - fx.si.torque_limit_nm / (1.5 * fx.si.pole_pairs * fx.si.psi_m_wb)) < 1e-3);
        const uint16_t c0 = count_at_angle(half != 0 ? 0.5 : 0.0);
        fx.m.qep_count = c0;
        assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
        for (uint16_t k = 0; k < (1U << APP_CAL_LOG2); k++) {
            assert_int_equal(step(), 1);
        }
        const int devs[] = {0, 1, -1, 5, -5};
        for (unsigned d = 0; d < sizeof devs / sizeof devs[0]; d++) {
            const double cos_sign = half != 0 ? -1.0 : 1.0;
            double u = -(double)devs[d] * ih_a / 2.0;
            u = u > ih_a ? ih_a : u < -ih_a ? -ih_a : u;
            const double target = 2.0 * u * cos_sign; /* i_b - i_c, A */
            for (int side = -1; side <= 1; side += 2) {
                const double ibc = target + 0.2 * side; /* i_b - i_c, with i_b = -i_c */
                fx.m.qep_count = (uint16_t)((int)c0 + devs[d] + (int)fx.cfg.board.enc_counts) % fx.cfg.board.enc_counts;
                fx.m.adc[HAL_ADC_IB] = i_counts(ibc / 2.0, fx.si.adc_i_offset[1]);
                fx.m.adc[HAL_ADC_IC] = i_counts(-ibc / 2.0, fx.si.adc_i_offset[2]);
                /* the rotor at rest at this count: the hold's speed estimate (the jump to it)
                 * decays, (15/16)^100 < 0.002, before the first decision checked */
                for (int n = 0; n < (side < 0 ? 100 : 1); n++) {
                    assert_int_equal(step(), 0);
                }
                assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
                assert_int_equal(fx.cmd.enable, 1U);
                assert_int_equal(fx.cmd.sb, side < 0 ? 1U : 0U);
                assert_int_equal(fx.cmd.sc, side < 0 ? 0U : 1U);
            }
        }
    }
    /* a rotor still turning when the calibration ends (one count every 4 periods, above the
     * settled speed of one count per 16 periods) is held until it stops; one that never stops
     * is released 2^APP_VMID_CAL_LOG2 periods later */
    for (int stops = 1; stops >= 0; stops--) {
        setup_topology(DTC_TOPO_FSTP);
        static_currents();
        fx.m.qep_count = 1000U;
        assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
        uint32_t k = 0U;
        for (; k < cal_len() + 200U; k++) {
            if (k >= (1U << APP_CAL_LOG2) && (k & 3U) == 0U) {
                fx.m.qep_count++;
            }
            step();
        }
        assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
        for (; k < 2U * cal_len() - 1U; k++) {
            if (stops == 0 && (k & 3U) == 0U) {
                fx.m.qep_count++;
            }
            step();
            if (stops != 0 && k == cal_len() + 400U) {
                assert_int_equal(fx.app.st.state, APP_STATE_RUN); /* settled within 200 periods */
            }
        }
        if (stops == 0) {
            assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
            step();
            assert_int_equal(fx.app.st.state, APP_STATE_RUN);
        }
    }
    setup_topology(DTC_TOPO_FSTP);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    for (uint16_t k = 0; k < (1U << APP_CAL_LOG2) + 10U; k++) {
        step();
    }
    /* an over-current during the hold: trip on the sample, gates off */
    fx.m.adc[HAL_ADC_IB] = i_counts(fx.si.i_trip_a + 0.5, fx.si.adc_i_offset[1]);
    fx.m.adc[HAL_ADC_IC] = i_counts(-(fx.si.i_trip_a + 0.5), fx.si.adc_i_offset[2]);
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_OVERCURRENT);
    assert_int_equal(fx.cmd.enable, 0U);
    /* the hold off: gates off for the whole calibration, then RUN */
    setup_topology(DTC_TOPO_FSTP);
    fx.si.cal_hold = 0;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, NULL, 0), 0);
    assert_int_equal(fx.cfg.prot.i_hold_iq, 0);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    for (uint16_t k = 0; k < cal_len(); k++) {
        assert_int_equal(step(), 1);
        assert_int_equal(fx.cmd.enable, 0U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
}

/* The hold engages only on a rotor at rest when the calibration begins (app_hold.h
 * APP_HOLD_REST_COUNTS): the gates-off offset window fed with the counts of a rotor at speed v0 and
 * constant acceleration a (theta(k) = v0 k + a k^2 / 2 counts, floored as a quadrature counter
 * counts), from a fractional start. The double-precision reference of the test: |3 d1 - d2| of
 * the samples 1, 32 and 63 above 4 counts is a turning rotor (no hold: the gates stay off), and
 * the continuous 2 v0 h (h = 31) it measures lies within 4 counts of it. Cases: at rest and an
 * active load pulling it from rest (a up to 0.01 counts/period^2: 0.3 N*m on 5e-4 kg m^2 with 8000
 * counts is 0.0019) are held; 0.1 counts/period (15 rpm at 8000 counts, 50 us) and faster, either
 * sign, with or without a load against or along, are not; the counter's wrap at enc_counts is
 * folded. */
static void test_rotor_hold_only_at_rest(void **state)
{
    (void)state;
    const double v0s[] = {0.0, 0.1, -0.1, 0.5, -3.0, 6.67, 10.0};
    const double as[] = {0.0, 0.01, -0.01, 0.002};
    for (unsigned i = 0; i < sizeof v0s / sizeof v0s[0]; i++) {
        for (unsigned j = 0; j < sizeof as / sizeof as[0]; j++) {
            setup_topology(DTC_TOPO_FSTP);
            static_currents();
            const double start = (double)fx.cfg.board.enc_counts - 40.3; /* wraps within the window */
            const int32_t n = (int32_t)fx.cfg.board.enc_counts;
            double th[64];
            for (int k = 0; k < 64; k++) {
                th[k] = floor(start + v0s[i] * k + as[j] * k * k / 2.0);
            }
            fx.m.qep_count = (uint16_t)(((int32_t)th[0] % n + n) % n);
            assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
            for (int k = 0; k < 64; k++) {
                fx.m.qep_count = (uint16_t)(((int32_t)th[k] % n + n) % n);
                assert_int_equal(step(), 1);
            }
            const double d1 = th[32] - th[1], d2 = th[63] - th[32];
            const int turning = fabs(3.0 * d1 - d2) > 4.0;
            assert_true(fabs((3.0 * d1 - d2) - 2.0 * v0s[i] * 31.0 - 2.0 * as[j] * 31.0) <= 4.0 + 1e-9);
            if (v0s[i] == 0.0) {
                assert_false(turning);
            }
            if (fabs(v0s[i]) >= 0.1) {
                assert_true(turning);
            }
            fx.m.qep_count = (uint16_t)(((int32_t)floor(start + v0s[i] * 64 + as[j] * 64 * 64 / 2.0) % n + n) % n);
            step();
            assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
            assert_int_equal(fx.cmd.enable, turning ? 0U : 1U);
        }
    }
}

static void test_offset_too_far_is_a_fault(void **state)
{
    (void)state;
    run_to_state(DTC_TOPO_SSTP, DTC_ADC_OFFSET_TOL_COUNTS + 1);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_ADC_OFFSET);
    run_to_state(DTC_TOPO_SSTP, -DTC_ADC_OFFSET_TOL_COUNTS);
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
}

static void test_bad_config_latches_config_fault(void **state)
{
    uint16_t k;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    fx.cfg.version = (uint16_t)(DTC_CONFIG_VERSION + 1U);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), DTC_ERR_VERSION);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    assert_int_equal(fx.app.st.fault_detail, DTC_ERR_VERSION);
    fx.app.clear_request = 1U; /* a configuration fault cannot be cleared */
    for (k = 0; k < 200; k++) {
        assert_int_equal(step(), 1);
        assert_int_equal(fx.cmd.enable, 0);
    }
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
}

static void test_conversion_matches_double_reference(void **state)
{
    int c;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    for (c = 0; c <= 4095; c += 3) {
        dtc_meas_t pu;
        double ia_ref, ib_ref, vdc_ref, err_lsb;
        fx.m.adc[HAL_ADC_IA] = (uint16_t)c;
        fx.m.adc[HAL_ADC_IB] = (uint16_t)(4095 - c);
        fx.m.adc[HAL_ADC_VDC] = (uint16_t)c;
        app_core_convert(&fx.app, &fx.m, &pu);
        ia_ref = (c - fx.si.adc_i_offset[0]) * fx.si.adc_i_a_per_count / fx.b.i_base_a;
        ib_ref = ((4095 - c) - fx.si.adc_i_offset[1]) * fx.si.adc_i_a_per_count / fx.b.i_base_a;
        vdc_ref = c * fx.si.adc_vdc_v_per_count / fx.b.v_base_v;
        /* The gain is rounded to 0.5 LSB of Q24, so the error grows with the count difference:
         * bound = 0.5 LSB x |counts| + 0.5 LSB. */
        err_lsb = 0.5 * fabs((double)(c - fx.si.adc_i_offset[0])) + 0.5;
        fixtest_assert_lsb(fixtest_iq_to_d(pu.ia_iq), ia_ref, ldexp(1.0, -FIX_IQ_Q), err_lsb, "ia");
        err_lsb = 0.5 * fabs((double)((4095 - c) - fx.si.adc_i_offset[1])) + 0.5;
        fixtest_assert_lsb(fixtest_iq_to_d(pu.ib_iq), ib_ref, ldexp(1.0, -FIX_IQ_Q), err_lsb, "ib");
        /* Kirchhoff: the third current is minus the sum of the two measured ones, exactly. */
        assert_int_equal(pu.ic_iq, -(pu.ia_iq + pu.ib_iq));
        fixtest_assert_lsb(fixtest_iq_to_d(pu.vdc_iq), vdc_ref, ldexp(1.0, -FIX_IQ_Q), 0.5 * c + 0.5, "vdc");
    }
}

/* Over-current: trips on the sample that exceeds i_trip on any phase (the derived one too), not
 * on the one just below; gates off at once and they stay off. */
static void test_overcurrent_trips_on_the_sample(void **state)
{
    const double lsb_a = fx.si.adc_i_a_per_count;
    double trip_a;
    uint16_t k;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    trip_a = fixtest_iq_to_d(fx.cfg.prot.i_trip_iq) * fx.b.i_base_a;
    /* Highest count not above the trip level on phase B: no trip. */
    fx.m.adc[HAL_ADC_IB] = (uint16_t)(fx.si.adc_i_offset[1] + (int)floor(trip_a / lsb_a - 1e-9));
    fx.m.adc[HAL_ADC_IA] = (uint16_t)(fx.si.adc_i_offset[0] - (int)floor(trip_a / lsb_a - 1e-9) / 2);
    assert_int_equal(step(), 0);
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    /* One count more: trip on this sample. */
    fx.m.adc[HAL_ADC_IB]++;
    assert_int_equal(step(), 1);
    assert_int_equal(fx.cmd.enable, 0);
    assert_int_equal(fx.app.st.fault, APP_FAULT_OVERCURRENT);
    assert_int_equal(fx.app.st.fault_detail, 1);
    assert_int_equal(fx.app.st.fault_tick, fx.m.tick - 1U);
    /* Latched: back to normal currents, the gates stay off. */
    meas_idle();
    for (k = 0; k < 100; k++) {
        assert_int_equal(step(), 1);
        assert_int_equal(fx.cmd.enable, 0);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);

    /* The unmeasured phase C = -(A + B) trips too, although A and B are each below the level. */
    run_to_state(DTC_TOPO_SSTP, 0);
    fx.m.adc[HAL_ADC_IA] = i_counts(0.6 * trip_a, fx.si.adc_i_offset[0]);
    fx.m.adc[HAL_ADC_IB] = i_counts(0.6 * trip_a, fx.si.adc_i_offset[1]);
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_OVERCURRENT);
    assert_int_equal(fx.app.st.fault_detail, 2);
}

static void test_dc_link_window(void **state)
{
    (void)state;
    run_to_state(DTC_TOPO_FSTP, 0);
    fx.m.adc[HAL_ADC_VDC] = v_counts(fx.si.vdc_max_v - 0.5);
    assert_int_equal(step(), 0);
    fx.m.adc[HAL_ADC_VDC] = v_counts(fx.si.vdc_max_v + 0.5);
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_DC_OVERVOLTAGE);

    run_to_state(DTC_TOPO_FSTP, 0);
    fx.m.adc[HAL_ADC_VDC] = v_counts(fx.si.vdc_min_v + 0.5);
    assert_int_equal(step(), 0);
    fx.m.adc[HAL_ADC_VDC] = v_counts(fx.si.vdc_min_v - 0.5);
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_DC_UNDERVOLTAGE);

    /* A DC link that is absent at the end of calibration never lets the drive run. */
    setup_topology(DTC_TOPO_SSTP);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    fx.m.adc[HAL_ADC_VDC] = v_counts(10.0);
    while (fx.app.st.state == APP_STATE_CALIBRATE) {
        assert_int_equal(step(), 1);
    }
    assert_int_equal(fx.app.st.fault, APP_FAULT_DC_UNDERVOLTAGE);
}

static void test_hw_trip_and_clear(void **state)
{
    uint16_t k;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    fx.m.trip = 1U;
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_HW_TRIP);
    fx.m.trip = 0U;
    assert_int_equal(step(), 1); /* still latched without a clear request */
    fx.app.clear_request = 1U;
    for (k = 0; k < cal_len(); k++) {
        assert_int_equal(step(), 1); /* recalibrates with the gates off */
        assert_int_equal(fx.app.st.state, k + 1U < cal_len() ? APP_STATE_CALIBRATE : APP_STATE_RUN);
    }
    assert_int_equal(step(), 0);
    assert_int_equal(fx.cmd.enable, 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_NONE);
}

/* Encoder: constant rotation with an index pulse each turn is healthy; a jump worth more than
 * twice the speed limit, or an index pulse at a shifted count (lost counts), is a fault. */
/* One encoder period of the fixture: the shaft advances by adv (1/100 counts); the counter reads
 * the true position minus the lost counts; the capture unit latches the counter at the pulse. */
static void encoder_advance(uint32_t *pos, uint32_t adv, uint32_t lost)
{
    const uint32_t n100 = 100U * 8000U;
    uint32_t next = *pos + adv;
    fx.m.qep_index_seen = (uint16_t)((next / n100) != (*pos / n100));
    if (fx.m.qep_index_seen != 0U) {
        fx.m.qep_index_count = (uint16_t)(((next / n100) * 8000U - lost) % 8000U);
    }
    *pos = next;
    fx.m.qep_count = (uint16_t)((*pos / 100U - lost) % 8000U);
}

/* Encoder: rotation with an index pulse each turn is healthy; a jump worth more than twice the
 * speed limit, or an index pulse latched at a shifted count (lost counts), is a fault. */
static void test_encoder_plausibility(void **state)
{
    /* 19.37 counts per 50 us (2906 rpm): not a divisor of a turn, so the sampling instant falls at
     * a different place after each index pulse. Position in 1/100 counts. */
    const uint32_t adv = 1937U;
    uint32_t pos = 12300U;
    uint32_t k, pulses = 0U;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    for (k = 0; k < 20000U; k++) { /* 48 turns */
        encoder_advance(&pos, adv, 0U);
        pulses += fx.m.qep_index_seen;
        assert_int_equal(step(), 0);
    }
    assert_true(pulses >= 48U);
    /* Lose APP_INDEX_TOL_COUNTS + 1 counts (noise on the A/B lines): the next pulse must trip,
     * on that very pulse and not before. */
    {
        const uint32_t lost = APP_INDEX_TOL_COUNTS + 1U;
        do {
            encoder_advance(&pos, adv, lost);
            if (fx.m.qep_index_seen == 0U) {
                assert_int_equal(step(), 0);
            }
        } while (fx.m.qep_index_seen == 0U);
        assert_int_equal(step(), 1);
    }
    assert_int_equal(fx.app.st.fault, APP_FAULT_ENCODER);
    assert_int_equal(fx.app.st.fault_detail, 2);

    /* APP_INDEX_TOL_COUNTS lost counts are tolerated (edge jitter). */
    run_to_state(DTC_TOPO_SSTP, 0);
    pos = 12300U;
    for (k = 0; k < 2000U; k++) {
        encoder_advance(&pos, adv, k < 1000U ? 0U : APP_INDEX_TOL_COUNTS);
        assert_int_equal(step(), 0);
    }

    /* A glitch of a quarter turn in one period (15000 rpm x 20) is implausible. */
    run_to_state(DTC_TOPO_SSTP, 0);
    fx.m.qep_count = 100U;
    assert_int_equal(step(), 0);
    fx.m.qep_count = 2100U;
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_ENCODER);
    assert_int_equal(fx.app.st.fault_detail, 1);
}

/* The encoder against the flux speed (app_enc_flux_check): a difference beyond the tolerance trips
 * on the APP_ENC_FLUX_PERIODS-th compared period in a row, with the sign of (flux - encoder); one
 * period back inside restarts the count; a difference at the tolerance itself is credible. */
static void test_encoder_flux_check_counts_periods_in_a_row(void **state)
{
    const iq_t tol = IQ(0.2);
    app_enc_t e;
    uint16_t k;
    (void)state;
    app_enc_reset(&e);
    for (k = 1U; k < APP_ENC_FLUX_PERIODS; k++) {
        assert_int_equal(app_enc_flux_check(&e, tol + 1, tol), 0);
    }
    assert_int_equal(app_enc_flux_check(&e, tol, tol), 0); /* back inside: the count restarts */
    for (k = 1U; k < APP_ENC_FLUX_PERIODS; k++) {
        assert_int_equal(app_enc_flux_check(&e, -tol - 1, tol), 0);
    }
    assert_int_equal(app_enc_flux_check(&e, -tol - 1, tol), -1);
    app_enc_reset(&e);
    for (k = 1U; k < APP_ENC_FLUX_PERIODS; k++) {
        assert_int_equal(app_enc_flux_check(&e, IQ(5.0), tol), 0);
    }
    assert_int_equal(app_enc_flux_check(&e, IQ(5.0), tol), 1);
}

/* The plausible count change per control period: twice the speed limit, never below one count
 * (a single count step is quantisation: at ts = 1 us one count per period already reads 7500 rpm). */
static void test_encoder_jump_threshold_scales_with_ts_and_lines(void **state)
{
    const double ts_list[3] = {50e-6, 10e-6, 1e-6};
    (void)state;
    for (int t = 0; t < 3; ++t) {
        char msg[200];
        dtc_config_si_defaults(&fx.si);
        fx.si.ts_s = ts_list[t];
        fx.si.dead_time_s = 0.0;
        fx.si.mode = DTC_MODE_TORQUE;
        if (dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg) != DTC_SI_OK) {
            fail_msg("config refused at ts %g: %s", ts_list[t], msg);
        }
        assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
        /* Double reference: 2 x speed limit in counts per period. */
        const double counts = 2.0 * fx.si.speed_limit_rpm / 60.0 * 4.0 * fx.si.enc_lines * ts_list[t];
        const double want = counts < 1.0 ? 1.0 : floor(counts);
        printf("MEASURE encoder jump at ts %g s: %u counts (double %.3f)\n", ts_list[t],
               (unsigned)fx.app.enc.jump_counts, counts);
        assert_true(fabs((double)fx.app.enc.jump_counts - want) <= 1.0);
        assert_true(fx.app.enc.jump_counts >= 1U);
        /* One count per period at 1 us must not trip; the threshold + 1 must. */
        fx.m.tick = 0U;
        meas_idle();
        for (uint16_t k = 0; k < cal_len(); k++) {
            (void)step();
        }
        assert_int_equal(fx.app.st.state, APP_STATE_RUN);
        fx.m.qep_count = 100U;
        assert_int_equal(step(), 0);
        fx.m.qep_count = 101U;
        assert_int_equal(step(), 0);
        fx.m.qep_count = (uint16_t)(101U + fx.app.enc.jump_counts + 1U);
        assert_int_equal(step(), 1);
        assert_int_equal(fx.app.st.fault, APP_FAULT_ENCODER);
    }
}

/* Stall: speed mode, a locked rotor (encoder still) with the speed reference at 1000 rpm: the PI
 * drives the torque reference to its limit and the speed error does not shrink: STALL, after the
 * window and not before. An accelerating rotor at the limit (error shrinking) is not a stall. */
static void test_stall_is_a_fault_and_acceleration_is_not(void **state)
{
    char msg[200];
    (void)state;
    for (int accelerate = 0; accelerate < 2; ++accelerate) {
        dtc_config_si_defaults(&fx.si);
        fx.si.mode = DTC_MODE_SPEED;
        fx.si.speed_ref_rpm = 1000.0;
        if (dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg) != DTC_SI_OK) {
            fail_msg("config refused: %s", msg);
        }
        static_currents();
        assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
        fx.m.tick = 0U;
        meas_idle();
        for (uint16_t k = 0; k < cal_len(); k++) {
            (void)step();
        }
        assert_int_equal(fx.app.st.state, APP_STATE_RUN);
        uint32_t pos = 10000U, adv = 0U, k, tripped_at = 0U, at_limit_since = 0U;
        for (k = 1; k <= 20000U && tripped_at == 0U; ++k) {
            if (accelerate != 0 && k % 50U == 0U && adv < 2600U) {
                adv += 2U; /* +0.02 counts per period every 50 periods: 0 -> about 900 rpm in 1.3 s */
            }
            encoder_advance(&pos, adv, 0U);
            if (step() != 0U) {
                tripped_at = k;
            }
            if (at_limit_since == 0U && fx.app.st.out.te_ref_iq >= fx.cfg.speed.torque_limit_iq) {
                at_limit_since = k;
            }
        }
        if (accelerate == 0) {
            printf("MEASURE stall: torque limit reached at period %u, STALL at period %u\n", (unsigned)at_limit_since,
                   (unsigned)tripped_at);
            assert_int_equal(fx.app.st.fault, APP_FAULT_STALL);
            assert_int_equal(fx.app.st.fault_detail, 1);
            assert_true(at_limit_since > 0U);
            /* Not before a whole window at the limit, and within two windows of reaching it. */
            assert_true(tripped_at >= at_limit_since + (fx.cfg.prot.stall_speed_periods - 1U) * fx.cfg.speed.speed_div);
            assert_true(tripped_at <= at_limit_since + 2U * fx.cfg.prot.stall_speed_periods * fx.cfg.speed.speed_div);
        } else {
            assert_int_equal(tripped_at, 0U);
            assert_int_equal(fx.app.st.fault, APP_FAULT_NONE);
            assert_true(at_limit_since > 0U); /* it did accelerate at the limit */
        }
    }
}

/* In RUN the command is exactly what dtc_step decides on the same per-unit measurement. */
static void test_run_forwards_controller_decision(void **state)
{
    dtc_t ref;
    uint16_t k;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    assert_int_equal(dtc_init(&ref, &fx.cfg), DTC_OK);
    dtc_reset(&ref);
    for (k = 0; k < 500; k++) {
        dtc_meas_t pu;
        dtc_out_t o;
        double th = 2.0 * FIXTEST_PI * k / 400.0;
        fx.m.adc[HAL_ADC_IA] = i_counts(2.0 * cos(th), fx.si.adc_i_offset[0]);
        fx.m.adc[HAL_ADC_IB] = i_counts(2.0 * cos(th - 2.0 * FIXTEST_PI / 3.0), fx.si.adc_i_offset[1]);
        fx.m.qep_count = (uint16_t)((k * 20U) % 8000U);
        app_core_convert(&fx.app, &fx.m, &pu);
        dtc_step(&ref, &pu, &o);
        assert_int_equal(step(), 0);
        assert_int_equal(fx.cmd.enable, 1);
        assert_int_equal(fx.cmd.sa, o.sa);
        assert_int_equal(fx.cmd.sb, o.sb);
        assert_int_equal(fx.cmd.sc, o.sc);
        assert_int_equal(fx.app.st.out.vector, o.vector);
    }
}

/* The IM stator-flux vector control (scheme SFVC) commands the PWM form: after the calibration
 * every RUN period writes HAL_CMD_PWM with centred pulses (cmpr_up = cmpr_dn, upper active high)
 * whose compare values are the law's duties on the timer period the HAL gave (svm_cmpr), the
 * null time shared equally (symmetric SVM). Without a timer
 * period (hal_pwm_period() = 0) the configuration cannot run: APP_FAULT_CONFIG, DTC_ERR_SVM. */
static void test_sfvc_writes_the_pwm_form(void **state)
{
    char msg[200];
    const uint16_t t1pr = 6000U;
    uint16_t k;
    (void)state;
    dtc_config_si_im_defaults(&fx.si);
    fx.si.law = DTC_LAW_IM_SFVC;
    fx.si.ts_s = 160e-6;
    fx.si.psir_ref_wb = 0.53;
    fx.si.mode = DTC_MODE_TORQUE;
    if (dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("SFVC configuration refused: %s", msg);
    }
    /* no machine here: the currents read stand still whatever the law applies, which the
     * current-sensor plausibility (app_plaus.h) rightly takes for stuck sensors */
    fx.cfg.prot.i_plaus = 0U;
    fx.m.tick = 0U;
    meas_idle();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_pwm_period(&fx.app, 0U), DTC_ERR_SVM);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    /* T1PR = 0xFFFF leaves no compare value above it (hal.h: duty 0 is T1PR + 1), so a zero duty
     * would wrap to 0, a whole period on (found by the fuzzer, tests/fuzz) */
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_pwm_period(&fx.app, 0xFFFFU), DTC_ERR_SVM);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_pwm_period(&fx.app, 0xFFFEU), 0);
    assert_int_equal(fx.app.st.state, APP_STATE_CALIBRATE);
    /* A period refused while a trip is latched replaces the trip's reason: the clear request
     * that would end the trip must not start a law that cannot run (found by the fuzzer) */
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_pwm_period(&fx.app, t1pr), 0);
    fx.m.trip = 1U;
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.app.st.fault, APP_FAULT_HW_TRIP);
    fx.m.trip = 0U;
    assert_int_equal(app_core_set_pwm_period(&fx.app, 0U), DTC_ERR_SVM);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    assert_int_equal(fx.app.st.fault_detail, DTC_ERR_SVM);
    fx.app.clear_request = 1U;
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_pwm_period(&fx.app, t1pr), 0);
    for (k = 0; k < cal_len(); k++) {
        assert_int_equal(step(), 1);
        assert_int_equal(fx.cmd.enable, 0);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    for (k = 0; k < 50U; k++) {
        uint16_t x;
        assert_int_equal(step(), 0);
        assert_int_equal(fx.cmd.enable, 1);
        assert_int_equal(fx.cmd.form, HAL_CMD_PWM);
        for (x = 0; x < 3U; x++) {
            assert_int_equal(fx.cmd.cmpr_up[x], fx.cmd.cmpr_dn[x]);
            assert_int_equal(fx.cmd.act[x], HAL_PWM_UPPER_ACTIVE_HIGH);
            assert_int_equal(fx.cmd.cmpr_up[x], svm_cmpr(fx.app.st.out.duty_iq[x], t1pr));
        }
        {
            /* symmetric SVM: the two null vectors share the null time, the largest and smallest
             * compare values sum to T1PR (seven-segment), within the rounding of two counts */
            uint16_t mx = fx.cmd.cmpr_up[0], mn = fx.cmd.cmpr_up[0];
            for (x = 1; x < 3U; x++) {
                mx = fx.cmd.cmpr_up[x] > mx ? fx.cmd.cmpr_up[x] : mx;
                mn = fx.cmd.cmpr_up[x] < mn ? fx.cmd.cmpr_up[x] : mn;
            }
            assert_true(abs((int)mx + (int)mn - (int)t1pr) <= 2);
            assert_true(mx > mn); /* the magnetising ramp asks for a voltage from the first period */
        }
    }
}

/* ---- fault detection and reconfiguration --------------------------------------------------- */

/* A gate driver's desaturation output trips at once with every gate off and names its leg, in RUN
 * and while calibrating; a plain PDPINTA trip stays a hardware trip. */
static void test_desat_names_the_leg(void **state)
{
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    assert_int_equal(step(), 0);
    fx.m.desat = 1U << 2;
    fx.m.trip = 1U;
    assert_int_equal(step(), 1);
    assert_int_equal(fx.cmd.enable, 0);
    assert_int_equal(fx.app.st.fault, APP_FAULT_DESAT);
    assert_int_equal(fx.app.st.fault_detail, 2);
    assert_string_equal(app_fault_name(APP_FAULT_DESAT), "desat");
    fx.m.desat = 0U;
    fx.m.trip = 0U;
    setup_topology(DTC_TOPO_SSTP);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    fx.m.desat = 1U;
    fx.m.trip = 1U;
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_DESAT);
    assert_int_equal(fx.app.st.fault_detail, 0);
    fx.m.desat = 0U;
    fx.m.trip = 0U;
}

/* Three sensors: currents that sum to zero run; a sensor stuck at its zero (phase A reads 0 A
 * while B and C carry -0.5 A each, so the sum is 1 A, above a quarter of the 2.2 A rated current)
 * trips on the APP_ISUM_PERIODS-th sample, naming phase A; a sum just below the level never does. */
static void test_current_sum_finds_a_stuck_sensor(void **state)
{
    char msg[200];
    const double level = 0.25 * fx.si.rated_current_a;
    uint16_t k;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    fx.si.i_sensors3 = 1;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg), DTC_SI_OK);
    assert_true(fabs(fx.cfg.prot.i_sum_max_iq / 16777216.0 * fx.b.i_base_a - 0.25 * 2.2) < 1e-6);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    for (k = 0; k < cal_len(); k++) {
        step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    fx.m.adc[HAL_ADC_IA] = i_counts(1.0, fx.si.adc_i_offset[0]);
    fx.m.adc[HAL_ADC_IB] = i_counts(-0.5, fx.si.adc_i_offset[1]);
    fx.m.adc[HAL_ADC_IC] = i_counts(-0.5, fx.si.adc_i_offset[2]);
    for (k = 0; k < 100; k++) {
        assert_int_equal(step(), 0);
    }
    /* a sum 3 % below the level, forever: no trip */
    fx.m.adc[HAL_ADC_IA] = i_counts(1.0 - 0.97 * level, fx.si.adc_i_offset[0]);
    for (k = 0; k < 100; k++) {
        assert_int_equal(step(), 0);
    }
    fx.m.adc[HAL_ADC_IA] = (uint16_t)fx.si.adc_i_offset[0]; /* stuck at mid-scale */
    for (k = 1; k < APP_ISUM_PERIODS; k++) {
        assert_int_equal(step(), 0);
    }
    assert_int_equal(step(), 1);
    assert_int_equal(fx.cmd.enable, 0);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CURRENT_SENSOR);
    /* every reading stood still (static currents): the sum cannot tell which sensor failed */
    assert_int_equal(fx.app.st.fault_detail, 9);
}

/* Three sensors, one stuck at a code away from its zero while the other two carry a switching
 * ripple (+-0.2 A about -0.5 A, 20 ADC counts and more each way): the sum check names the phase
 * whose reading stood still, B or C as A, though it does not read the least. */
static void test_current_sum_names_the_phase_that_stood_still(void **state)
{
    char msg[200];
    uint16_t k, stuck;
    (void)state;
    for (stuck = 0U; stuck < 3U; stuck++) {
        const uint16_t ch[3] = {HAL_ADC_IA, HAL_ADC_IB, HAL_ADC_IC};
        setup_topology(DTC_TOPO_SSTP);
        fx.si.i_sensors3 = 1;
        assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg), DTC_SI_OK);
        static_currents();
        assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
        for (k = 0; k < cal_len(); k++) {
            step();
        }
        assert_int_equal(fx.app.st.state, APP_STATE_RUN);
        for (k = 0; k < APP_ISUM_PERIODS; k++) {
            const double r = (k & 1U) != 0U ? 0.2 : -0.2;
            uint16_t x;
            for (x = 0U; x < 3U; x++) {
                /* the stuck one reads +2 A whatever flows (the sum 1 A); the others -0.5 A plus the ripple */
                fx.m.adc[ch[x]] = x == stuck ? i_counts(2.0, fx.si.adc_i_offset[x])
                                             : i_counts(-0.5 + (x == (stuck + 1U) % 3U ? r : -r), fx.si.adc_i_offset[x]);
            }
            assert_int_equal(step(), k + 1U == APP_ISUM_PERIODS ? 1 : 0);
        }
        assert_int_equal(fx.app.st.fault, APP_FAULT_CURRENT_SENSOR);
        assert_int_equal(fx.app.st.fault_detail, 3 + (int)stuck); /* APP_SENSOR_DETAIL_LIST 1 */
    }
    /* with two sensors the check cannot exist: a configuration asking for it is refused */
    fx.cfg.board.i_sensors3 = 0U;
    {
        const char *field = "";
        assert_int_equal(law_check(&fx.cfg, &field), DTC_ERR_FAULTDET);
        assert_string_equal(field, "prot.i_sum_max_iq");
    }
}

/* Lost encoder signal: at 1500 rpm (10 counts per period) a counter that stops trips on the
 * APP_ENC_FREEZE_PERIODS-th unchanged sample (detail 3); turning at half the derived speed, where
 * a count may stand still that long, it runs on with the counter stopped. The derived speed is
 * the physics of dtc_fault_levels: 8 counts in N Ts, and 4 times what the largest deceleration
 * 2 T_lim / J takes away in N Ts. */
static void test_lost_encoder_at_speed_trips(void **state)
{
    const double n_ts = APP_ENC_FREEZE_PERIODS * fx.si.ts_s;
    uint32_t pos = 0U, k;
    (void)state;
    run_to_state(DTC_TOPO_SSTP, 0);
    {
        const double w_f = fmax(2.0 * FIXTEST_PI * 8.0 / (8000.0 * n_ts),
                                4.0 * 2.0 * fx.si.torque_limit_nm / fx.si.inertia_kgm2 * n_ts);
        assert_true(fabs(fx.cfg.prot.enc_freeze_speed_iq / 16777216.0 * fx.b.w_base_rad_s - w_f) < 1e-4 * w_f);
    }
    for (k = 0; k < 4000U; k++) { /* 1500 rpm: 10 counts per 50 us */
        fx.m.qep_count = (uint16_t)((pos += 10U) % 8000U);
        assert_int_equal(step(), 0);
    }
    for (k = 1; k < APP_ENC_FREEZE_PERIODS; k++) {
        assert_int_equal(step(), 0);
    }
    assert_int_equal(step(), 1);
    assert_int_equal(fx.app.st.fault, APP_FAULT_ENCODER);
    assert_int_equal(fx.app.st.fault_detail, 3);

    run_to_state(DTC_TOPO_SSTP, 0);
    {
        /* half the derived speed, in 1/1000 counts per period */
        const double w_f = fx.cfg.prot.enc_freeze_speed_iq / 16777216.0 * fx.b.w_base_rad_s;
        const uint32_t adv = (uint32_t)(0.5 * w_f / (2.0 * FIXTEST_PI) * 8000.0 * fx.si.ts_s * 1000.0);
        pos = 0U;
        for (k = 0; k < 4000U; k++) {
            pos += adv;
            fx.m.qep_count = (uint16_t)((pos / 1000U) % 8000U);
            assert_int_equal(step(), 0);
        }
        for (k = 0; k < 10U * APP_ENC_FREEZE_PERIODS; k++) {
            assert_int_equal(step(), 0);
        }
    }
}

/* Currents of a machine turning at 1500 rpm (p = 1, 10 counts per period: 400 periods per
 * electrical turn), amplitude amp, with phase `open` (0..2) carrying none (the other two -+ each
 * other), or all three healthy for open = 3. The encoder follows the same angle. */
static void drive_currents(uint32_t k, double amp, int open)
{
    const double th = 2.0 * FIXTEST_PI * k / 400.0;
    double i[3];
    int x;
    for (x = 0; x < 3; x++) {
        i[x] = amp * cos(th - 2.0 * FIXTEST_PI * x / 3.0);
    }
    if (open < 3) {
        const int y = (open + 1) % 3, z = (open + 2) % 3;
        const double d = 0.5 * (i[y] - i[z]) * 2.0 / sqrt(3.0) * 1.5; /* the pair's current */
        i[open] = 0.0;
        i[y] = d;
        i[z] = -d;
    }
    for (x = 0; x < 3; x++) {
        fx.m.adc[x] = i_counts(i[x], fx.si.adc_i_offset[x]);
    }
    fx.m.qep_count = (uint16_t)((k * 10U) % 8000U);
}

static dtc_config_t post_cfg;

/* SSTP with three sensors and, if relay, the reconfiguration relays and the post-fault FSTP. */
static void setup_reconfig(int relay)
{
    char msg[200];
    dtc_config_si_t post_si;
    uint16_t k;
    setup_topology(DTC_TOPO_SSTP);
    fx.si.i_sensors3 = 1;
    fx.si.reconfig_relay = relay;
    fx.si.relay_delay_s = 5e-3;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg), DTC_SI_OK);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    if (relay != 0) {
        assert_int_equal(dtc_config_post_fault_si(&fx.si, &post_si), DTC_SI_OK);
        assert_int_equal(dtc_config_from_si(&post_si, &post_cfg, msg, sizeof msg), DTC_SI_OK);
        post_cfg.prot.i_plaus = 0U; /* scripted currents, as static_currents() */
        assert_int_equal(app_core_set_reconfig(&fx.app, &post_cfg), 0);
        /* 1.5 x 5 ms + one period */
        assert_int_equal(post_cfg.prot.relay_periods, 151);
    }
    for (k = 0; k < cal_len(); k++) {
        step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
}

/* Open phase: five healthy electrical turns never look open; then phase x opens. Without a relay
 * the drive trips (APP_FAULT_LEG, phase x); with one it reconfigures: the relay command names x,
 * leg x stays off from that period on, the law runs the FSTP. Found after at least 60 deg (133
 * periods of continuous zero current with |i| above a quarter of rated) and within one turn. */
static void test_open_phase_trips_or_reconfigures(void **state)
{
    int x, relay;
    (void)state;
    for (relay = 0; relay < 2; relay++) {
        for (x = 0; x < 3; x++) {
            uint32_t k, found = 0U;
            setup_reconfig(relay);
            for (k = 0; k < 2000U; k++) {
                drive_currents(k, 2.0, 3);
                assert_int_equal(step(), 0);
            }
            for (k = 2000U; k < 2400U && found == 0U; k++) {
                drive_currents(k, 2.0, x);
                if (step() != 0U || fx.app.st.reconfigured != 0U) {
                    found = k - 2000U + 1U;
                }
            }
            assert_true(found >= 133U && found <= 400U);
            if (relay == 0) {
                assert_int_equal(fx.app.st.fault, APP_FAULT_LEG);
                assert_int_equal(fx.app.st.fault_detail, x);
                assert_int_equal(fx.cmd.enable, 0);
                continue;
            }
            assert_int_equal(fx.app.st.state, APP_STATE_RUN);
            assert_int_equal(fx.app.st.reconfigured, x + 1);
            assert_int_equal(fx.app.law.u.pm.cfg->board.topology, DTC_TOPO_FSTP);
            for (; k < 3000U; k++) {
                const uint16_t legs[3] = {fx.cmd.sa, fx.cmd.sb, fx.cmd.sc};
                assert_int_equal(fx.cmd.relay, x + 1);
                assert_int_equal(fx.cmd.enable, 1);
                assert_int_equal(legs[x], 0);
                drive_currents(k, 2.0, 3); /* the relay closed: three currents again */
                assert_int_equal(step(), 0);
            }
            /* the law's legs b', c' are the physical legs x+1, x+2 */
            {
                const uint16_t legs[3] = {fx.cmd.sa, fx.cmd.sb, fx.cmd.sc};
                assert_int_equal(legs[(x + 1) % 3], fx.app.st.out.sb);
                assert_int_equal(legs[(x + 2) % 3], fx.app.st.out.sc);
            }
            /* a trip after the reconfiguration keeps the relay closed */
            fx.m.trip = 1U;
            assert_int_equal(step(), 1);
            assert_int_equal(fx.cmd.relay, x + 1);
            fx.m.trip = 0U;
        }
    }
}

/* Feeds app_fault_open_phase n periods of three phase currents of amplitude amp (pu) at the angle
 * step dth (rad per period) from angle th0: shape 0 healthy; 1 the current phasor reversed once,
 * at the first downward zero crossing of phase A (a torque reversal that extends A's positive
 * half-wave by a whole half-turn); 2 phase A's current never positive: where it would be, it reads
 * -2 zero bands (outside the band, one direction: an open upper device under the voltage model),
 * the difference shared by B and C (an isolated star). Returns the period (1..n) the check found
 * a phase open in, 0 if none, the phase in *ph, and in *waits the periods with too little current
 * to judge (2 sum i^2 <= 3 leg_i_min^2, app_fault.c: there the angle waits). */

static uint32_t feed_open_phase(app_fault_t *f, iq_t speed_iq, double dth, double amp, int shape, uint32_t n,
                                uint16_t hold_div, uint16_t *ph, uint32_t *waits)
{
    const double imin = (double)fx.cfg.prot.leg_i_min_iq / 16777216.0;
    const double zero = (double)fx.cfg.prot.leg_i_min_iq / 16777216.0 / 4.0;
    double sgn = 1.0;
    uint32_t k;
    for (k = 0U; k < n; k++) {
        const double th = dth * k;
        double i[3];
        int x;
        dtc_meas_t pu;
        for (x = 0; x < 3; x++) {
            i[x] = sgn * amp * sin(th - 2.0 * FIXTEST_PI * x / 3.0);
        }
        if (shape == 1 && sgn > 0.0 && i[0] < 0.0 && sin(th - dth) > 0.0) {
            sgn = -1.0;
            for (x = 0; x < 3; x++) {
                i[x] = -i[x];
            }
        }
        if (shape == 2 && i[0] > -2.0 * zero) {
            const double d = i[0] + 2.0 * zero;
            i[0] -= d;
            i[1] += d / 2.0;
            i[2] += d / 2.0;
        }
        if (2.0 * (i[0] * i[0] + i[1] * i[1] + i[2] * i[2]) <= 3.0 * imin * imin) {
            ++*waits;
        }
        pu.ia_iq = IQ(i[0]);
        pu.ib_iq = IQ(i[1]);
        pu.ic_iq = IQ(i[2]);
        pu.vdc_iq = fx.cfg.prot.vdc_min_iq;
        /* hold_div > 0: a speed-loop period every hold_div-th (the first of each group, as the laws) */
        if (app_fault_open_phase(f, &fx.cfg, &pu, speed_iq, 0U, hold_div > 0U && k % hold_div == 0U ? 1U : 0U, ph) !=
            0U) {
            return k + 1U;
        }
    }
    return 0U;
}

/* The open-phase check with two sensors (the three currents sum to zero) judges a sample without
 * forming the squares when a phase carries 1.5 leg_i_min or more (app_fault.c): its decision must be
 * the squares' own, 2 sum(i_k^2 >> 5) > 3 (leg_i_min^2 >> 5), at every level down to the shortcut's
 * least leg_i_min (8 LSB) and around the 1.5 leg_i_min edge. A sample is judged when it moves an
 * angle sum (each set to 1 rad before, at a speed of 1 pu); one that waits leaves them all. */
static void test_open_phase_shortcut_decides_as_the_squares(void **state)
{
    static const iq_t imins[] = {8, 9, 15, 23, 100, 4097, 838861, ((iq_t)1 << 29) - 1, (iq_t)1 << 29};
    uint32_t lcg = 12345U, n_judged = 0U, n_wait = 0U;
    uint16_t a, r;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    for (a = 0U; a < (uint16_t)(sizeof imins / sizeof imins[0]); a++) {
        const iq_t imin = imins[a];
        const int64_t edge = (int64_t)imin + (imin >> 1);
        fx.cfg.prot.leg_i_min_iq = imin;
        for (r = 0U; r < 2000U; r++) {
            app_fault_t f;
            dtc_meas_t pu;
            uint16_t ph = 9U, k, moved = 0U;
            int64_t i0, i1, tot;
            uint64_t sq_min;
            lcg = lcg * 1664525U + 1013904223U;
            /* the largest phase within +-4 LSB of the edge, or anywhere in 0.5 .. 2 times it */
            i0 = r % 2U == 0U ? edge - 4 + (int64_t)(lcg >> 29) : edge / 2 + (int64_t)((lcg >> 8) % (uint32_t)(edge + 1));
            lcg = lcg * 1664525U + 1013904223U;
            i1 = -(int64_t)((lcg >> 8) % (uint32_t)(i0 + 1)); /* |i1| <= i0, i2 = -(i0 + i1) in -i0 .. 0 */
            if (r % 3U == 1U) {
                i0 = -i0;
                i1 = -i1;
            }
            pu.ia_iq = (iq_t)i0;
            pu.ib_iq = (iq_t)i1;
            pu.ic_iq = (iq_t)(-(i0 + i1));
            pu.vdc_iq = fx.cfg.prot.vdc_min_iq;
            app_fault_init(&f);
            for (k = 0U; k < 3U; k++) {
                f.leg_acc_iq[k] = IQ(1.0);
                f.pos_acc_iq[k] = IQ(1.0);
                f.neg_acc_iq[k] = IQ(1.0);
            }
            (void)app_fault_open_phase(&f, &fx.cfg, &pu, IQ(1.0), 0U, 0U, &ph);
            for (k = 0U; k < 3U; k++) {
                if (f.leg_acc_iq[k] != IQ(1.0) || f.pos_acc_iq[k] != IQ(1.0) || f.neg_acc_iq[k] != IQ(1.0)) {
                    moved = 1U;
                }
            }
            tot = (i0 * i0 >> 5) + (i1 * i1 >> 5) + ((i0 + i1) * (i0 + i1) >> 5);
            sq_min = 3U * ((uint64_t)((int64_t)imin * imin) >> 5);
            if (moved != (uint16_t)(2U * (uint64_t)tot > sq_min ? 1U : 0U)) {
                fail_msg("leg_i_min %ld, i = %ld %ld: judged %u, the squares say %u", (long)imin, (long)i0, (long)i1,
                         (unsigned)moved, (unsigned)(2U * (uint64_t)tot > sq_min));
            }
            if (moved != 0U) {
                n_judged++;
            } else {
                n_wait++;
            }
        }
    }
    /* both decisions were met (the draws reach below the level to judge as well as above it) */
    assert_true(n_judged > 1000U);
    assert_true(n_wait > 100U);
    setup_topology(DTC_TOPO_SSTP);
}

/* Open device (PM laws): a phase whose current keeps one direction over 7 pi/3 of electrical angle
 * while the others alternate is open, found in the period the angle passes 7 pi/3; a healthy set
 * over ten turns is not, nor one whose phasor reverses on a zero crossing of A (A then keeps its
 * sign for a whole turn, 2 pi < 7 pi/3). 400 periods per turn at 8 times the open-phase level (the
 * rated current). */
static void test_open_device_keeps_one_direction(void **state)
{
    const double dth = 2.0 * FIXTEST_PI / 400.0;
    iq_t speed_iq;
    double amp;
    app_fault_t f;
    uint16_t ph = 9U;
    uint32_t found, waits = 0U;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    amp = 8.0 * (double)fx.cfg.prot.leg_i_min_iq / 16777216.0; /* never below the level to judge */
    speed_iq = IQ(dth / ((double)fx.cfg.board.ts_pu_iq / 16777216.0));
    app_fault_init(&f);
    assert_int_equal(feed_open_phase(&f, speed_iq, dth, amp, 0, 4000U, 0U, &ph, &waits), 0U);
    app_fault_init(&f);
    assert_int_equal(feed_open_phase(&f, speed_iq, dth, amp, 1, 4000U, 0U, &ph, &waits), 0U);
    app_fault_init(&f);
    waits = 0U;
    found = feed_open_phase(&f, speed_iq, dth, amp, 2, 4000U, 0U, &ph, &waits);
    assert_int_equal(ph, 0U);
    /* the speed-loop periods' samples held over (app_fault_open_phase's hold, at the configured
     * speed-loop rate and at every period): the healthy sets still pass, the open device is found
     * at most one period later, the held periods' angle counted */
    {
        const uint16_t divs[2] = {fx.cfg.speed.speed_div, 1U};
        uint16_t d;
        for (d = 0U; d < 2U; d++) {
            uint16_t ph_h = 9U;
            uint32_t found_h, waits_h = 0U;
            app_fault_init(&f);
            assert_int_equal(feed_open_phase(&f, speed_iq, dth, amp, 0, 4000U, divs[d], &ph_h, &waits_h), 0U);
            app_fault_init(&f);
            assert_int_equal(feed_open_phase(&f, speed_iq, dth, amp, 1, 4000U, divs[d], &ph_h, &waits_h), 0U);
            app_fault_init(&f);
            found_h = feed_open_phase(&f, speed_iq, dth, amp, 2, 4000U, divs[d], &ph_h, &waits_h);
            assert_int_equal(ph_h, 0U);
            if (!(found_h >= found && found_h <= found + 1U)) {
                fail_msg("speed loop every %u periods: found in period %u, every sample judged: %u", (unsigned)divs[d],
                         (unsigned)found_h, (unsigned)found);
            }
        }
    }
    /* the angle the firmware sums is iq_mpy(speed, ts_pu) per judged period: 7 pi/3 of it (where
     * the open phase takes the others' current to near zero with it, the periods wait), within
     * two periods for the roundings */
    {
        const double step = (double)iq_mpy(speed_iq, fx.cfg.board.ts_pu_iq) / 16777216.0;
        const double want = 7.0 * FIXTEST_PI / 3.0 / step + (double)waits;
        if (!(fabs((double)found - want) <= 2.0)) {
            fail_msg("found in period %u, 7 pi/3 at %.1f", (unsigned)found, want);
        }
    }
}

/* The post-fault configuration must be the same drive as an FSTP with three sensors; anything
 * else is refused at set-up with DTC_ERR_RECONFIG (config fault, gates off). */
static void test_bad_post_fault_config_is_refused(void **state)
{
    char msg[200];
    dtc_config_si_t post_si;
    dtc_config_t bad;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    fx.si.i_sensors3 = 1;
    fx.si.reconfig_relay = 1;
    fx.si.relay_delay_s = 5e-3;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg), DTC_SI_OK);
    assert_int_equal(dtc_config_post_fault_si(&fx.si, &post_si), DTC_SI_OK);
    assert_int_equal(post_si.compensation, DTC_COMP_FSTP_SIMPLE); /* [29]'s equal drop: Hoang Table V */
    assert_int_equal(dtc_config_from_si(&post_si, &post_cfg, msg, sizeof msg), DTC_SI_OK);
    bad = fx.cfg; /* an SSTP is not a post-fault configuration */
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_reconfig(&fx.app, &bad), DTC_ERR_RECONFIG);
    assert_int_equal(fx.app.st.fault, APP_FAULT_CONFIG);
    assert_int_equal(step(), 1);
    bad = post_cfg;
    bad.board.enc_offset = (angle_t)(bad.board.enc_offset + 1U); /* another encoder */
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_reconfig(&fx.app, &bad), DTC_ERR_RECONFIG);
    fx.cfg.board.i_sensors3 = 0U; /* two sensors cannot tell a sensor from a leg */
    fx.cfg.prot.i_sum_max_iq = 0;
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(app_core_set_reconfig(&fx.app, &post_cfg), DTC_ERR_RECONFIG);
    assert_int_equal(app_core_set_reconfig(&fx.app, NULL), 0);
}

/* The frame change keeps the flux: the current model (Hoang eqs. 8-9) after dtc_reconfigure, fed
 * the permuted currents and the same encoder count, gives the physical flux turned by -x 120 deg
 * (the space vector in the frame whose phase A' is x), against a double reference; and a voltage-
 * model state is turned by the same angle. */
static void test_reconfigure_turns_the_flux_into_the_new_frame(void **state)
{
    char msg[200];
    dtc_config_si_t post_si;
    int x;
    (void)state;
    for (x = 0; x < 3; x++) {
        dtc_t c;
        dtc_meas_t m;
        dtc_out_t o;
        const double th_m = 0.7; /* rad, mechanical = electrical (p = 1) */
        const double amp = 1.5, ph = 0.4;
        double i[3], ref_a, ref_b, psi_a, psi_b;
        const double L = fx.si.ls_h, pm = fx.si.psi_m_wb, enc_off = fx.si.enc_offset_rad;
        int k;
        setup_topology(DTC_TOPO_SSTP);
        fx.si.estimator = DTC_EST_CURRENT;
        fx.si.i_sensors3 = 1;
        fx.si.reconfig_relay = 1;
        fx.si.relay_delay_s = 5e-3;
        assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, msg, sizeof msg), DTC_SI_OK);
        assert_int_equal(dtc_config_post_fault_si(&fx.si, &post_si), DTC_SI_OK);
        assert_int_equal(dtc_config_from_si(&post_si, &post_cfg, msg, sizeof msg), DTC_SI_OK);
        assert_int_equal(dtc_init(&c, &fx.cfg), DTC_OK);
        for (k = 0; k < 3; k++) {
            i[k] = amp * cos(th_m + enc_off + ph - 2.0 * FIXTEST_PI * k / 3.0);
        }
        /* physical flux: L i + psi_m e^{j theta}, theta = count angle + offset */
        ref_a = L * i[0] + pm * cos(th_m + enc_off);
        ref_b = L * (i[1] - i[2]) / sqrt(3.0) + pm * sin(th_m + enc_off);
        {
            const double r = -2.0 * FIXTEST_PI * x / 3.0;
            const double ra = cos(r) * ref_a - sin(r) * ref_b, rb = sin(r) * ref_a + cos(r) * ref_b;
            ref_a = ra;
            ref_b = rb;
        }
        assert_int_equal(dtc_reconfigure(&c, &post_cfg, (uint16_t)x), DTC_OK);
        m.ia_iq = IQ(i[x] / fx.b.i_base_a);
        m.ib_iq = IQ(i[(x + 1) % 3] / fx.b.i_base_a);
        m.ic_iq = IQ(i[(x + 2) % 3] / fx.b.i_base_a);
        m.vdc_iq = IQ(1.0);
        m.vmid_iq = IQ(0.5);
        m.enc_count = (uint16_t)lround(th_m / (2.0 * FIXTEST_PI) * 8000.0);
        dtc_step(&c, &m, &o);
        psi_a = o.psi_alpha_iq / 16777216.0 * fx.b.psi_base_wb;
        psi_b = o.psi_beta_iq / 16777216.0 * fx.b.psi_base_wb;
        /* the count's quantisation (1/8000 turn) moves psi_m by 0.8 mrad */
        assert_true(fabs(psi_a - ref_a) < 2e-4 && fabs(psi_b - ref_b) < 2e-4);

        /* voltage-model state: turned by -x 120 deg */
        assert_int_equal(dtc_init(&c, &fx.cfg), DTC_OK);
        c.fe.psi_alpha_iq = IQ(0.6);
        c.fe.psi_beta_iq = IQ(-0.3);
        assert_int_equal(dtc_reconfigure(&c, &post_cfg, (uint16_t)x), DTC_OK);
        {
            const double r = -2.0 * FIXTEST_PI * x / 3.0;
            assert_true(fabs(c.fe.psi_alpha_iq / 16777216.0 - (0.6 * cos(r) + 0.3 * sin(r))) < 1e-4);
            assert_true(fabs(c.fe.psi_beta_iq / 16777216.0 - (0.6 * sin(r) - 0.3 * cos(r))) < 1e-4);
        }
        assert_int_equal(dtc_reconfigure(&c, &post_cfg, 3U), DTC_ERR_RECONFIG);
    }
}

/* The fault names are an interface (metrics.json "fault", the SIL tests): every number of the
 * table keeps its name, and a number outside the table is "unknown". */
static void test_fault_names(void **state)
{
    static const char *const want[] = {"none", "config", "overcurrent", "dc_overvoltage",
                                       "dc_undervoltage", "encoder", "hw_trip", "adc_offset",
                                       "stall", "desat", "current_sensor", "leg", "overspeed",
                                       "encoder_speed", "comm_timeout"};
    const uint16_t n = (uint16_t)(sizeof want / sizeof want[0]);
    uint16_t k;
    (void)state;
    assert_int_equal(APP_FAULT_COUNT_, n);
    for (k = 0U; k < n; k++) {
        assert_string_equal(app_fault_name(k), want[k]);
    }
    assert_int_equal(APP_FAULT_LEG, 11);
    assert_string_equal(app_fault_name(n), "unknown");
    assert_string_equal(app_fault_name(999U), "unknown");
}

/* FSTP with the mid-point measured: an arm request is refused (vmid_range) while the split link's
 * mid-point sits off V_dc / 2 by more than V_dc / 16 (after a trip at speed the rectified back-EMF
 * charges one capacitor), and taken again once it is back within that. */
static void test_arming_refused_with_the_mid_point_off(void **state)
{
    app_status_t st;
    const dtc_refs_t r = {0, 0, 1, 0, 0, DTC_MODE_TORQUE};
    const double tol = fx.si.vdc_v / 16.0;
    uint16_t k;
    (void)state;
    setup_topology(DTC_TOPO_FSTP);
    fx.si.cal_hold = 0;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, NULL, 0), 0);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    app_core_set_arming(&fx.app, APP_ARM_COMMAND);
    for (k = 0; k < cal_len() + 10U; k++) {
        (void)step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_OK);
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0 + 1.2 * tol); /* the upper capacitor low */
    (void)step();
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_VMID_RANGE);
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0 - 1.2 * tol);
    (void)step();
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_VMID_RANGE);
    fx.m.adc[HAL_ADC_VMID] = v_counts(fx.si.vdc_v / 2.0 + 0.8 * tol); /* back within: armed */
    (void)step();
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_OK);
    /* the six-switch inverter has no mid-point: never refused for it */
    setup_topology(DTC_TOPO_SSTP);
    st.meas.vmid_iq = 0;
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    st.state = APP_STATE_READY;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_OK);
}

/* Command arming (app_core.h APP_ARM_COMMAND): the calibration ends in READY with every gate off
 * however long it waits; an arm request is refused (app_core_arm_refusal) with a reference not
 * zero, the DC link out of range or a latched fault, and taken otherwise; a disarm request turns
 * the gates off at the next period; a fault clear ends in READY, never in RUN. */
static void test_command_arming(void **state)
{
    app_status_t st;
    dtc_refs_t r = {0, 0, 1, 0, 0, DTC_MODE_TORQUE};
    uint16_t k;
    (void)state;
    /* without the rotor hold (nothing converts the measurement while calibrating): the status
     * read between the period that ends the calibration and the next shows the link as measured
     * (the console's "powers up READY, V_dc at the bench's" once read 0 V in that window) */
    setup_topology(DTC_TOPO_SSTP);
    static_currents();
    fx.si.cal_hold = 0;
    assert_int_equal(dtc_config_from_si(&fx.si, &fx.cfg, NULL, 0), 0);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    app_core_set_arming(&fx.app, APP_ARM_COMMAND);
    for (k = 0; k < cal_len() && fx.app.st.state == APP_STATE_CALIBRATE; k++) {
        assert_int_equal(step(), 1U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    assert_true(fx.app.st.meas.vdc_iq >= fx.cfg.prot.vdc_min_iq);
    assert_true(fx.app.st.meas.vdc_iq <= fx.cfg.prot.vdc_max_iq);
    setup_topology(DTC_TOPO_SSTP);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    app_core_set_arming(&fx.app, APP_ARM_COMMAND);
    for (k = 0; k < cal_len() + 2000U; k++) {
        assert_int_equal(step(), 1U);
        assert_int_equal(fx.cmd.enable, 0U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    st = fx.app.st;
    r.torque_ref_iq = 1;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_REF_NONZERO);
    r.torque_ref_iq = 0;
    r.speed_ref_iq = -1;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_REF_NONZERO);
    r.speed_ref_iq = 0;
    st.meas.vdc_iq = fx.cfg.prot.vdc_max_iq + 1;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_VDC_RANGE);
    st.meas.vdc_iq = fx.cfg.prot.vdc_min_iq - 1;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_VDC_RANGE);
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_OK);
    /* arming calibrates again, gates off, and checks the link at the end: a link that sagged
     * meanwhile is a fault, not a run */
    fx.m.adc[HAL_ADC_VDC] = v_counts(0.5 * fx.si.vdc_v * fx.cfg.prot.vdc_min_iq / fx.cfg.prot.vdc_max_iq);
    app_core_request_arm(&fx.app, APP_REQ_ARM);
    for (k = 0; k < cal_len(); k++) {
        assert_int_equal(step(), 1U);
        assert_int_equal(fx.cmd.enable, 0U);
    }
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_DC_UNDERVOLTAGE);
    meas_idle();
    fx.app.clear_request = 1U;
    for (k = 0; k < cal_len() + 10U; k++) {
        assert_int_equal(step(), 1U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    app_core_request_arm(&fx.app, APP_REQ_ARM);
    for (k = 0; k < cal_len(); k++) {
        assert_int_equal(step(), 1U);
        assert_int_equal(fx.cmd.enable, 0U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    assert_int_equal(step(), 0U);
    assert_int_equal(fx.cmd.enable, 1U);
    app_core_request_arm(&fx.app, APP_REQ_DISARM);
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.cmd.enable, 0U);
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    /* a fault, then its clear: READY again after the calibration, not RUN */
    fx.m.trip = 1U;
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    st = fx.app.st;
    assert_int_equal(app_core_arm_refusal(&fx.app, &st, &r), APP_ARM_FAULT);
    fx.m.trip = 0U;
    fx.app.clear_request = 1U;
    for (k = 0; k < cal_len() + 100U; k++) {
        assert_int_equal(step(), 1U);
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
}

/* The command timeout: armed, N periods without a valid frame latch comm_timeout on the N-th
 * (gates off: no torque, disarmed); every valid frame restarts the count; 0 is off. */
static void test_comm_timeout(void **state)
{
    uint16_t k;
    const uint32_t n = 200U;
    (void)state;
    setup_topology(DTC_TOPO_SSTP);
    static_currents();
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    app_core_set_arming(&fx.app, APP_ARM_COMMAND);
    for (k = 0; k < cal_len(); k++) {
        (void)step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_READY);
    app_core_request_arm(&fx.app, APP_REQ_ARM);
    for (k = 0; k < cal_len(); k++) {
        (void)step();
    }
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    for (k = 0; k < 3000U; k++) { /* off: runs on */
        assert_int_equal(step(), 0U);
    }
    app_core_set_comm_timeout(&fx.app, n);
    for (k = 0; k < 1000U; k++) { /* a frame every n - 1 periods keeps it armed */
        if (k % (n - 1U) == 0U) {
            app_core_comm_seen(&fx.app);
        }
        assert_int_equal(step(), 0U);
    }
    app_core_comm_seen(&fx.app);
    assert_int_equal(step(), 0U);
    for (k = 1; k < n; k++) {
        assert_int_equal(step(), 0U);
    }
    assert_int_equal(step(), 1U);
    assert_int_equal(fx.cmd.enable, 0U);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.app.st.fault, APP_FAULT_COMM_TIMEOUT);
    assert_string_equal(app_fault_name(fx.app.st.fault), "comm_timeout");
}

/* The fault log gets one entry per latched fault with the tick, reason and the sample that
 * tripped; the capture's fault trigger fires on it. */
static void test_faultlog_and_capture_fed(void **state)
{
    static capture_t cap;
    static faultlog_t flog;
    faultlog_entry_t e;
    capture_setup_t cs = {1U, {CAPTURE_Q_I_A, 0U, 0U, 0U}, 8U, 4U, 1U, CAPTURE_TRIG_FAULT, 0U, 0};
    uint32_t trip_tick;
    (void)state;
    capture_init(&cap);
    faultlog_init(&flog);
    run_to_state(DTC_TOPO_SSTP, 0);
    app_core_attach(&fx.app, &cap, &flog);
    assert_int_equal(capture_setup(&cap, &cs), CAPTURE_OK);
    for (uint16_t k = 0; k < 20U; k++) {
        assert_int_equal(step(), 0U);
    }
    fx.m.adc[HAL_ADC_IA] = 4095U; /* far above the trip level */
    trip_tick = fx.m.tick;
    assert_int_equal(step(), 1U);
    fx.m.adc[HAL_ADC_IA] = (uint16_t)fx.si.adc_i_offset[0];
    for (uint16_t k = 0; k < 10U; k++) {
        (void)step();
    }
    assert_int_equal(faultlog_count(&flog), 1U);
    assert_int_equal(faultlog_get(&flog, 0U, &e), FAULTLOG_OK);
    assert_int_equal(e.tick, trip_tick);
    assert_int_equal(e.reason, APP_FAULT_OVERCURRENT);
    assert_int_equal(e.detail, 0);
    assert_int_equal(e.snap.state, APP_STATE_RUN);
    assert_true(e.snap.ia_iq > fx.cfg.prot.i_trip_iq);
    assert_int_equal(capture_state(&cap), CAPTURE_DONE);
    assert_int_equal(capture_first_tick(&cap), trip_tick - 4U);
    assert_int_equal(capture_read(&cap, 4U, 0U), e.snap.ia_iq);
}

/* Every step writes the whole command, the relay included: app.c hands hal_write() a local
 * hal_cmd_t that only app_core_step fills, so a field it skips carries whatever the stack held
 * (found by the fuzzer, tests/fuzz). Without a reconfiguration the relay is open (enum hal_relay)
 * in every state: calibration, the rotor hold, RUN, a trip, a refused configuration. */
static uint16_t step_dirty(void)
{
    memset(&fx.cmd, 0xA5, sizeof fx.cmd);
    return step();
}

static void test_every_step_writes_the_relay(void **state)
{
    uint16_t k, hold_seen = 0U;
    (void)state;
    setup_topology(DTC_TOPO_FSTP);
    assert_true(fx.cfg.board.vmid_cal != 0U && fx.cfg.prot.i_hold_iq > 0);
    assert_int_equal(app_core_init(&fx.app, &fx.cfg), 0);
    for (k = 0; k < 4U * cal_len() && fx.app.st.state != APP_STATE_RUN; k++) {
        hold_seen = (uint16_t)(hold_seen | (step_dirty() == 0U));
        assert_int_equal(fx.cmd.relay, HAL_RELAY_OPEN);
    }
    assert_int_equal(hold_seen, 1U);
    assert_int_equal(fx.app.st.state, APP_STATE_RUN);
    assert_int_equal(step_dirty(), 0U);
    assert_int_equal(fx.cmd.enable, 1U);
    assert_int_equal(fx.cmd.relay, HAL_RELAY_OPEN);
    fx.m.trip = 1U;
    assert_int_equal(step_dirty(), 1U);
    assert_int_equal(fx.app.st.state, APP_STATE_FAULT);
    assert_int_equal(fx.cmd.relay, HAL_RELAY_OPEN);
    fx.cfg.version = 0U; /* refused at init */
    assert_int_not_equal(app_core_init(&fx.app, &fx.cfg), 0);
    assert_int_equal(step_dirty(), 1U);
    assert_int_equal(fx.cmd.relay, HAL_RELAY_OPEN);
}

UNIT_TEST_MAIN("app core", NULL,
               cmocka_unit_test(test_calibration_finds_offsets_then_runs),
               cmocka_unit_test(test_every_step_writes_the_relay),
               cmocka_unit_test(test_calibration_mean_is_rounded_with_noise),
               cmocka_unit_test(test_midpoint_calibration),
               cmocka_unit_test(test_rotor_hold),
               cmocka_unit_test(test_rotor_hold_only_at_rest),
               cmocka_unit_test(test_offset_too_far_is_a_fault),
               cmocka_unit_test(test_bad_config_latches_config_fault),
               cmocka_unit_test(test_conversion_matches_double_reference),
               cmocka_unit_test(test_overcurrent_trips_on_the_sample),
               cmocka_unit_test(test_dc_link_window),
               cmocka_unit_test(test_hw_trip_and_clear),
               cmocka_unit_test(test_encoder_plausibility),
               cmocka_unit_test(test_encoder_flux_check_counts_periods_in_a_row),
               cmocka_unit_test(test_encoder_jump_threshold_scales_with_ts_and_lines),
               cmocka_unit_test(test_stall_is_a_fault_and_acceleration_is_not),
               cmocka_unit_test(test_run_forwards_controller_decision),
               cmocka_unit_test(test_sfvc_writes_the_pwm_form),
               cmocka_unit_test(test_fault_names),
               cmocka_unit_test(test_command_arming),
               cmocka_unit_test(test_arming_refused_with_the_mid_point_off),
               cmocka_unit_test(test_comm_timeout),
               cmocka_unit_test(test_faultlog_and_capture_fed),
               cmocka_unit_test(test_desat_names_the_leg),
               cmocka_unit_test(test_current_sum_finds_a_stuck_sensor),
               cmocka_unit_test(test_current_sum_names_the_phase_that_stood_still),
               cmocka_unit_test(test_lost_encoder_at_speed_trips),
               cmocka_unit_test(test_open_phase_trips_or_reconfigures),
               cmocka_unit_test(test_open_device_keeps_one_direction),
               cmocka_unit_test(test_open_phase_shortcut_decides_as_the_squares),
               cmocka_unit_test(test_bad_post_fault_config_is_refused),
               cmocka_unit_test(test_reconfigure_turns_the_flux_into_the_new_frame))
