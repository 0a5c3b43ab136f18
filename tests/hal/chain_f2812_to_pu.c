/*
 * chain_f2812_to_pu.c - from F2812 registers to per-unit quantities, through the real code path:
 * ADC result registers (left-justified 12 bits) -> hal_read (hal/f2812) -> offset calibration and
 * conversion (firmware/app) -> per-unit currents and voltages; QEP counter T2CNT -> hal_read ->
 * electrical angle (current model, Hoang eqs. 8-9) and measured speed (speed loop). Registers are
 * plain RAM on the host; the expected values are computed in double from the SI configuration.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "app_core.h"
#include "dtc_config_si.h"
#include "f2812_hal.h"
#include "f2812_regs.h"
#include "fixtest.h"
#include "speed_meas.h"

/* The ADC interrupt vector hal_init installs; these tests call hal_read themselves. */
F2812_INTERRUPT void f2812_adcint_isr(void) {}

static dtc_config_si_t si;
static dtc_config_t cfg;
static dtc_bases_t b;
static app_core_t app;

static void set_adc(uint16_t ia, uint16_t ib, uint16_t ic, uint16_t vdc, uint16_t vmid)
{
    const uint16_t c[HAL_ADC_COUNT] = {ia, ib, ic, vdc, vmid};
    for (unsigned n = 0; n < HAL_ADC_COUNT; n++) {
        f2812_adc.ADCRESULT[n] = (uint16_t)(c[n] << 4); /* left-justified, bits 15:4 */
    }
}

static int setup(void **state)
{
    char msg[200];
    (void)state;
    dtc_config_si_defaults(&si);
    si.topology = DTC_TOPO_SSTP;
    si.compensation = DTC_COMP_SSTP;
    if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
        fail_msg("%s", msg);
    }
    dtc_bases_from_si(&si, &b);
    hal_init();
    /* What RAM cannot do by itself: the flags hal_init cleared by writing 1s read 0, the
     * PDPINTA pin and the gate drivers' FAULT lines (GPIOB8..10, active low) read high (power
     * stage healthy). */
    f2812_gpiodata.B.DAT = 0xFFFFu;
    f2812_eva.EVAIFRA = 0u;
    f2812_eva.EVAIFRC = 0u;
    f2812_eva.COMCONA = (uint16_t)(f2812_eva.COMCONA | F2812_COMCONA_PDPINTASTATUS);
    assert_int_equal(app_core_init(&app, &cfg), 0);
    return 0;
}

/* Calibration with the gates off: the offsets the app adopts are the rounded mean of what the
 * registers held (here nominal + 9 on A, nominal - 5 on B), then a register value converts to
 * (count - calibrated offset) * A/count / I_base per unit. */
static void test_adc_registers_to_per_unit_with_calibration(void **state)
{
    const uint16_t vdc_counts = (uint16_t)lround(70.0 / si.adc_vdc_v_per_count);
    hal_meas_t m;
    hal_cmd_t cmd;
    dtc_meas_t pu;
    (void)state;
    for (unsigned k = 0; k < (1U << APP_CAL_LOG2); k++) {
        set_adc((uint16_t)(si.adc_i_offset[0] + 9), (uint16_t)(si.adc_i_offset[1] - 5), 0u, vdc_counts, 0u);
        hal_read(&m);
        assert_int_equal(app_core_step(&app, &m, &cmd), 1); /* gates off while calibrating */
    }
    if (app.st.state != APP_STATE_RUN) {
        fail_msg("state %u, fault %s (%d)", app.st.state, app_fault_name(app.st.fault), app.st.fault_detail);
    }
    assert_int_equal(app.offset[HAL_ADC_IA], si.adc_i_offset[0] + 9);
    assert_int_equal(app.offset[HAL_ADC_IB], si.adc_i_offset[1] - 5);

    for (int c = 0; c < 4096; c += 7) {
        set_adc((uint16_t)c, (uint16_t)(4095 - c), 0u, (uint16_t)c, 0u);
        hal_read(&m);
        app_core_convert(&app, &m, &pu);
        const double ia = (c - (si.adc_i_offset[0] + 9)) * si.adc_i_a_per_count / b.i_base_a;
        const double ib = ((4095 - c) - (si.adc_i_offset[1] - 5)) * si.adc_i_a_per_count / b.i_base_a;
        const double vdc = c * si.adc_vdc_v_per_count / b.v_base_v;
        const double lsb = ldexp(1.0, -FIX_IQ_Q);
        /* The Q24 gain is rounded to 0.5 LSB: the error grows by 0.5 LSB per count. */
        fixtest_assert_lsb(fixtest_iq_to_d(pu.ia_iq), ia, lsb, 0.5 * fabs(ia / fixtest_iq_to_d(cfg.board.adc_i_gain_iq)) + 0.5, "ia");
        fixtest_assert_lsb(fixtest_iq_to_d(pu.ib_iq), ib, lsb, 0.5 * fabs(ib / fixtest_iq_to_d(cfg.board.adc_i_gain_iq)) + 0.5, "ib");
        fixtest_assert_lsb(fixtest_iq_to_d(pu.vdc_iq), vdc, lsb, 0.5 * c + 0.5, "vdc");
    }
    /* Zero current at the calibrated offsets reads exactly zero. */
    set_adc((uint16_t)(si.adc_i_offset[0] + 9), (uint16_t)(si.adc_i_offset[1] - 5), 0u, vdc_counts, 0u);
    hal_read(&m);
    app_core_convert(&app, &m, &pu);
    assert_int_equal(pu.ia_iq, 0);
    assert_int_equal(pu.ib_iq, 0);
}

/* QEP: every counter value 0..7999 reads back and converts to the electrical angle
 * p * count / 8000 of a turn (+ the configured offset) within 1 angle LSB. */
static void test_qep_counts_to_electrical_angle(void **state)
{
    hal_meas_t m;
    (void)state;
    for (uint16_t c = 0; c < 8000u; c++) {
        f2812_eva.T2CNT = c;
        hal_read(&m);
        assert_int_equal(m.qep_count, c);
        const angle_t th = flux_est_angle(m.qep_count, cfg.board.enc_gain_q16, cfg.board.enc_offset);
        const double ref = fmod(65536.0 * si.pole_pairs * c / 8000.0 + cfg.board.enc_offset, 65536.0);
        double err = fabs((double)th - ref);
        err = fmin(err, 65536.0 - err); /* modulo one turn */
        if (err > 1.0) {
            fail_msg("count %u: angle %u vs %.3f LSB", c, th, ref);
        }
    }
}

/* QEP counter advancing 100 counts per speed period (500 us) = 1500 rpm, read through hal_read
 * and measured by the speed loop's estimator: 0.5 pu with w_base = p * 3000 rpm, within 1 %. */
static void test_qep_counts_to_speed(void **state)
{
    speed_meas_params_t p = {cfg.board.enc_counts, cfg.speed.speed_k_iq, cfg.speed.speed_min_counts};
    speed_meas_t s;
    hal_meas_t m;
    uint32_t pos = 1234u;
    (void)state;
    f2812_eva.T2CNT = (uint16_t)pos;
    hal_read(&m);
    speed_meas_init(&s, &p, m.qep_count);
    for (unsigned k = 0; k < 40u; k++) {
        pos += 100u;
        f2812_eva.T2CNT = (uint16_t)(pos % 8000u); /* the counter wraps at T2PR = 7999 */
        hal_read(&m);
        speed_meas_step(&s, m.qep_count);
    }
    const double rpm = fixtest_iq_to_d(s.speed_iq) * b.w_base_rad_s / si.pole_pairs * 30.0 / FIXTEST_PI;
    print_message("[ MEASURE  ] 100 counts per 500 us -> %.3f rpm\n", rpm);
    assert_true(fabs(rpm - 1500.0) < 15.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_adc_registers_to_per_unit_with_calibration, setup),
        cmocka_unit_test_setup(test_qep_counts_to_electrical_angle, setup),
        cmocka_unit_test_setup(test_qep_counts_to_speed, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
