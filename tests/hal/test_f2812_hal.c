/*
 * test_f2812_hal.c - register-level tests of hal/f2812 on the host, registers in RAM.
 *
 * Expected register values are written out here from the fact sheet
 * (../shared/reference/f2812-facts.md, section numbers in the comments) and the physical
 * quantity they set, NOT taken from the binding's own macros, so a wrong bit in the binding
 * fails. Where the hardware does something RAM cannot (write-1-to-clear flags, read-only pin
 * status, shadow -> active loads), the test does it explicitly and says so.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "f2812_hal.h"
#include "f2812_regs.h"
#include "hal.h"

/* ---- test doubles and the emulated reset ------------------------------------------------- */

/* The real ADC ISR glue lives in target/f2812/f2812_main.c (image only); hal_init must install this one. */
static uint16_t g_adcint_calls;
F2812_INTERRUPT void f2812_adcint_isr(void) { g_adcint_calls++; }

#define PDPINTASTATUS 0x0100u /* COMCONA bit 8, read-only pin level (2.4) */
#define FCOMPOE 0x0200u       /* COMCONA bit 9 (2.4, item 8.2) */

static void reset_device(void)
{
    memset((void *)&f2812_flash, 0, sizeof f2812_flash);
    memset((void *)&f2812_piectrl, 0, sizeof f2812_piectrl);
    memset((void *)&f2812_pievect, 0, sizeof f2812_pievect);
    memset((void *)&f2812_sysctrl, 0, sizeof f2812_sysctrl);
    memset((void *)&f2812_gpiomux, 0, sizeof f2812_gpiomux);
    memset((void *)&f2812_gpiodata, 0, sizeof f2812_gpiodata);
    memset((void *)&f2812_adc, 0, sizeof f2812_adc);
    memset((void *)&f2812_eva, 0, sizeof f2812_eva);
    memset((void *)&f2812_spia, 0, sizeof f2812_spia);
    memset((void *)&f2812_scia, 0, sizeof f2812_scia);
    memset(&f2812_host_cpu, 0, sizeof f2812_host_cpu);
    f2812_host_cpu.intm = 1u; /* INTM is set after reset */
    g_adcint_calls = 0u;
}

/* The PDPINTA pin as the hardware reports it in COMCONA.PDPINTASTATUS. */
static void pdpinta_pin(int high)
{
    if (high) {
        f2812_eva.COMCONA = (uint16_t)(f2812_eva.COMCONA | PDPINTASTATUS);
    } else {
        f2812_eva.COMCONA = (uint16_t)(f2812_eva.COMCONA & ~PDPINTASTATUS);
    }
}

/* What RAM cannot do by itself: the flag registers hal_init cleared by writing 1s read 0. */
static void emulate_write_one_to_clear(void)
{
    f2812_eva.EVAIFRA = 0u;
    f2812_eva.EVAIFRB = 0u;
    f2812_eva.EVAIFRC = 0u;
    f2812_adc.ADCST = 0u;
}

static int setup_initialised(void **state)
{
    (void)state;
    reset_device();
    hal_init();
    emulate_write_one_to_clear();
    pdpinta_pin(1); /* no fault on the pin */
    return 0;
}

/* ---- a model of one EV-A leg (2.4, 2.5, f2812_hal.c "How legs are driven") --------------
 * Compare output in up/down mode is active from the up-count match to the down-count match:
 * CMPR = 0 -> active the whole period, CMPR > T1PR -> never active. ACTRA per output:
 * 00 forced low, 01 active low (= NOT compare), 10 active high (= compare), 11 forced high.
 * A leg's switch is ON when its output is high for the whole period. Dead band only delays
 * the edges, so it does not change the whole-period state. Returns 1 = on, 0 = off, -1 = PWM. */
static int output_level(uint16_t cmpr, uint16_t t1pr, uint16_t act)
{
    int cmp_active;
    if (cmpr == 0u) {
        cmp_active = 1;
    } else if (cmpr > t1pr) {
        cmp_active = 0;
    } else {
        return -1; /* a real PWM duty: never what a DTC switching state should produce */
    }
    switch (act & 3u) {
    case 0u: return 0;
    case 1u: return !cmp_active;
    case 2u: return cmp_active;
    default: return 1;
    }
}

typedef struct {
    int upper, lower;
} leg_t;

static leg_t leg_state(unsigned leg)
{
    const uint16_t cmpr[3] = {f2812_eva.CMPR1, f2812_eva.CMPR2, f2812_eva.CMPR3};
    const uint16_t actra = f2812_eva.ACTRA;
    leg_t s;
    s.upper = output_level(cmpr[leg], f2812_eva.T1PR, (uint16_t)(actra >> (4u * leg)));
    s.lower = output_level(cmpr[leg], f2812_eva.T1PR, (uint16_t)(actra >> (4u * leg + 2u)));
    return s;
}

static void assert_all_off_next_period(void)
{
    for (unsigned leg = 0; leg < 3; leg++) {
        leg_t s = leg_state(leg);
        assert_int_equal(s.upper, 0);
        assert_int_equal(s.lower, 0);
    }
    assert_int_equal(f2812_eva.ACTRA, 0x0000); /* every output forced low (2.5) */
}

/* One control period as the target runs it: (app_isr ->) hal_write, then the ISR epilogue. */
static void period(const hal_cmd_t *cmd)
{
    hal_write(cmd);
    f2812_adcint_done();
}

static void enable_outputs(void)
{
    const hal_cmd_t cmd = {0u, 0u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    period(&cmd); /* period k: all-off state to the shadows, outputs still Hi-Z */
    period(&cmd); /* period k+1: all-off is now active, FCOMPOE set, command to the shadows */
    assert_true(f2812_eva.COMCONA & FCOMPOE);
}

/* ---- start-up: system control, flash, watchdog ------------------------------------------ */
static void test_init_clocks_pll_and_peripheral_clocks(void **state)
{
    (void)state;
    /* 30 MHz crystal x 10 / 2 = 150 MHz: PLLCR.DIV = 10 (4.3, DS ✔). */
    assert_int_equal(f2812_sysctrl.PLLCR, 0x000A);
    assert_int_equal(30000000L * f2812_sysctrl.PLLCR / 2, 150000000L);
    /* HSPCLK = 150 MHz / (2 * 1) = 75 MHz, LSPCLK = 150 / (2 * 2) = 37.5 MHz (4.3). */
    assert_int_equal(f2812_sysctrl.HISPCP, 0x0001);
    assert_int_equal(f2812_sysctrl.LOSPCP, 0x0002);
    /* PCLKCR: EVAENCLK bit 0, ADCENCLK bit 3, SPIENCLK bit 8 (parameter EEPROM), SCIAENCLK
     * bit 10 (serial line), nothing else (4.3). */
    assert_int_equal(f2812_sysctrl.PCLKCR, 0x0509);
    /* Watchdog stays disabled through hal_init: 0x0068 = WDDIS | WDCHK 101b (4.4, HDR ✔). */
    assert_int_equal(f2812_sysctrl.WDCR, 0x0068);
    /* Every protected write happened under EALLOW, and EALLOW was closed again (4.2). */
    assert_int_equal(f2812_host_cpu.lost_writes, 0);
    assert_int_equal(f2812_host_cpu.eallow, 0);
}

static void test_init_waits_for_pll_lock_and_adc_power_up(void **state)
{
    (void)state;
    /* Busy waits, in SYSCLKOUT cycles at 150 MHz, must cover the datasheet maxima: PLL lock
     * 131072 OSCCLK cycles (4.3), bandgap 10 ms max, analog core 50 us max (3.2). */
    const double needed_s = 131072.0 / 30e6 + 10e-3 + 50e-6;
    assert_true((double)f2812_host_cpu.delay_cycles >= needed_s * 150e6 * 0.999);
}

static void test_init_skips_pll_relock_when_already_set(void **state)
{
    (void)state;
    reset_device();
    f2812_sysctrl.PLLCR = 0x000A; /* e.g. a debugger reload after a run */
    hal_init();
    assert_int_equal(f2812_sysctrl.PLLCR, 0x000A);
    assert_true((double)f2812_host_cpu.delay_cycles < (10e-3 + 50e-6) * 150e6 * 1.001);
}

static void test_init_flash_wait_states(void **state)
{
    (void)state;
    /* 150 MHz: PAGEWAIT = 5 (bits 11:8), RANDWAIT = 5 (3:0), OTPWAIT = 8, ENPIPE (4.7, WS ✔). */
    assert_int_equal(f2812_flash.FBANKWAIT, 0x0505);
    assert_int_equal(f2812_flash.FOTPWAIT, 0x0008);
    assert_int_equal(f2812_flash.FOPT, 0x0001);
    assert_true(f2812_host_cpu.pipeline_flushes >= 1);
}

static void test_eallow_emulation_drops_unprotected_writes(void **state)
{
    (void)state;
    /* The host accessor behaves like the silicon: without EALLOW the write is lost (4.2). */
    const uint16_t before = f2812_sysctrl.PLLCR;
    const uint16_t lost = f2812_host_cpu.lost_writes;
    f2812_wr_protected(&f2812_sysctrl.PLLCR, 0x0003);
    assert_int_equal(f2812_sysctrl.PLLCR, before);
    assert_int_equal(f2812_host_cpu.lost_writes, lost + 1);
}

static void test_watchdog_start_and_service(void **state)
{
    (void)state;
    f2812_watchdog_start();
    /* WDDIS = 0, WDCHK = 101b (0x0028), WDPS = 1 (/1): 0x0029 (4.4). */
    assert_int_equal(f2812_sysctrl.WDCR, 0x0029);
    /* Timeout: 256 counts of OSCCLK / 512 = 4.37 ms. */
    const double timeout_ms = 256.0 * 512.0 / 30e6 * 1e3;
    assert_true(timeout_ms > 4.3 && timeout_ms < 4.4);
    f2812_sysctrl.WDKEY = 0;
    hal_watchdog_service();
    assert_int_equal(f2812_sysctrl.WDKEY, 0x00AA); /* 0x55 then 0xAA, the last one stays */
    assert_int_equal(f2812_host_cpu.lost_writes, 0);
}

static void test_init_clears_stale_flags(void **state)
{
    (void)state;
    reset_device();
    hal_init();
    /* All EV-A flags written with 1s (write-1-to-clear, 2.8) and the SEQ1 interrupt flag cleared
     * through INT_SEQ1_CLR (3.1) before any interrupt source is enabled. */
    assert_int_equal(f2812_eva.EVAIFRA, 0xFFFF);
    assert_int_equal(f2812_eva.EVAIFRB, 0xFFFF);
    assert_int_equal(f2812_eva.EVAIFRC, 0xFFFF);
    assert_int_equal(f2812_adc.ADCST, 0x0010);
    assert_int_equal(f2812_piectrl.PIEACK, 0x0FFF); /* every PIE group re-armed */
}

/* ---- PIE --------------------------------------------------------------------------------- */
static void test_init_pie_vectors_and_enables(void **state)
{
    (void)state;
    /* ADCINT is PIE 1.6 at 0x0D4A, PDPINTA is 1.1 at 0x0D40; the table starts at 0x0D00 with
     * 2 words per entry (4.1). */
    const unsigned adcint = (0x0D4Au - 0x0D00u) / 2u;
    const unsigned pdpinta = (0x0D40u - 0x0D00u) / 2u;
    const unsigned t1pint = (0x0D56u - 0x0D00u) / 2u; /* PIE 2.4 (4.1 table) */
    for (unsigned v = 0; v < 128u; v++) {
        if (v == adcint) {
            assert_ptr_equal(f2812_pievect.vec[v], f2812_adcint_isr);
        } else if (v == t1pint) {
            assert_ptr_equal(f2812_pievect.vec[v], f2812_t1pint_isr);
        } else if (v == pdpinta) {
            assert_ptr_equal(f2812_pievect.vec[v], f2812_pdpint_isr);
        } else {
            assert_ptr_equal(f2812_pievect.vec[v], f2812_unexpected_isr);
        }
    }
    assert_int_equal(f2812_piectrl.PIECTRL & 1u, 1); /* ENPIE */
    /* PIEIER1: INT1.1 (bit 0) and INT1.6 (bit 5); PIEIER2: INT2.4 = T1PINT (bit 3), the PWM
     * form's period-match reload; every other group off. */
    assert_int_equal(f2812_piectrl.grp[0].IER, 0x0021);
    assert_int_equal(f2812_piectrl.grp[1].IER, 0x0008);
    for (unsigned g = 2; g < 12u; g++) {
        assert_int_equal(f2812_piectrl.grp[g].IER, 0);
    }
    assert_int_equal(f2812_host_cpu.ier, 0x0003); /* CPU INT1 = PIE group 1, INT2 = group 2 */
    assert_int_equal(f2812_host_cpu.intm, 1);     /* not enabled until main() says so */
    f2812_interrupts_enable();
    assert_int_equal(f2812_host_cpu.intm, 0);
}

/* ---- EV-A timer 1, compare, dead band ----------------------------------------------------- */
static void test_init_timer1_50us_up_down(void **state)
{
    (void)state;
    /* Continuous up/down: period = 2 * T1PR / HSPCLK = 2 * 1875 / 75 MHz = 50 us (2.3, EVG ✔). */
    assert_int_equal(f2812_eva.T1PR, 1875);
    assert_true(2.0 * f2812_eva.T1PR / 75e6 == 50e-6);
    /* T1CON: FREE+SOFT 0xC000, TMODE 01 (bits 12:11) 0x0800, TPS 0 (/1); TENABLE (0x0040) only
     * when main() starts operation: no conversion, no ISR before app_init has run. */
    assert_int_equal(f2812_eva.T1CON, 0xC800);
    f2812_adc.ADCTRL2 = 0;
    f2812_interrupts_enable();
    assert_int_equal(f2812_eva.T1CON, 0xC840);
    assert_int_equal(f2812_adc.ADCTRL2, 0x4900); /* SEQ1 reset to CONV00 before the first SOC */
    assert_int_equal(f2812_adc.ADCST, 0x0010);
    assert_int_equal(f2812_host_cpu.intm, 0);
    /* GPTCONA.T1TOADC (8:7) = 01: underflow starts the ADC, once per period (2.2, 2.10). */
    assert_int_equal(f2812_eva.GPTCONA, 0x0080);
}

static void test_init_compare_shadow_loads_at_period_start(void **state)
{
    (void)state;
    /* COMCONA: CENABLE (bit 15); CLD (14:13) = 00 and ACTRLD (11:10) = 00 load the CMPRx and
     * ACTRA shadows at T1CNT = 0, i.e. at the start of the next period; FCOMPOE = 0: outputs
     * high-impedance until the application enables them (2.4). */
    assert_int_equal(f2812_eva.COMCONA & ~PDPINTASTATUS, 0x8000);
    assert_int_equal(f2812_eva.EXTCONA, 0x0000); /* INDCOE = 0: FCOMPOE rules all six (2.7) */
    assert_all_off_next_period();
}

static void test_init_dead_band_every_leg(void **state)
{
    (void)state;
    const uint16_t db = f2812_eva.DBTCONA;
    /* EDBT1..3 (bits 5..7) all set: dead band on legs A, B, C (2.6). */
    assert_int_equal(db & 0x00E0u, 0x00E0u);
    /* Dead time = DBT * 2^DBTPS / HSPCLK: at least the 2 us asked for, and the smallest
     * prescaler that reaches it with DBT <= 15 (so at most one prescaled tick longer). */
    const unsigned dbt = (db >> 8) & 15u;
    const unsigned dbtps = (db >> 2) & 7u;
    const double dt = (double)dbt * (double)(1u << dbtps) / 75e6;
    assert_true(dt >= 2e-6);
    assert_true(dt < 2e-6 + (double)(1u << dbtps) / 75e6);
    assert_true(dbtps <= 5u && dbt >= 1u);
    assert_true(dbtps == 0u || 2e-6 * 75e6 / (double)(1u << (dbtps - 1u)) > 15.0);
    assert_int_equal(db, 0x0AF0); /* DBT = 10, DBTPS = 100b (/16): 160 / 75 MHz = 2.133 us */
}

static void test_init_pdpinta_enabled(void **state)
{
    (void)state;
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001); /* PDPINTA interrupt (2.8, 2.11) */
    assert_int_equal(f2812_gpiomux.GPDMUX & 1u, 1); /* GPIOD0 = T1CTRIP_PDPINTA (4.8) */
}

/* ---- ADC --------------------------------------------------------------------------------- */
static void test_init_adc_sequence_and_trigger(void **state)
{
    (void)state;
    /* ADCTRL3: ADCBGRFDN 11 (7:6), ADCPWDN (5), ADCCLKPS = 3 (4:1): 0x00C0|0x0020|0x0006. */
    assert_int_equal(f2812_adc.ADCTRL3, 0x00E6);
    /* ADCCLK = HSPCLK / (2 * ADCCLKPS) / (CPS + 1) = 12.5 MHz <= 25 MHz (3.2). */
    const unsigned clkps = (f2812_adc.ADCTRL3 >> 1) & 15u;
    const unsigned cps = (f2812_adc.ADCTRL1 >> 7) & 1u;
    const double adcclk = 75e6 / (2.0 * clkps) / (cps + 1.0);
    assert_true(adcclk == 12.5e6);
    /* ADCTRL1: ACQ_PS = 1 (11:8), CPS = 0, one cascaded sequencer SEQ_CASC (4): 0x0110. */
    assert_int_equal(f2812_adc.ADCTRL1, 0x0110);
    /* Five conversions: ia, ib, ic, Vdc, Vmid in hal.h order on ADCINA0..A4 (3.1). */
    assert_int_equal(f2812_adc.ADCMAXCONV, HAL_ADC_COUNT - 1);
    assert_int_equal(f2812_adc.ADCCHSELSEQ[0], 0x3210);
    assert_int_equal(f2812_adc.ADCCHSELSEQ[1], 0x0004);
    /* ADCTRL2: EVA_SOC_SEQ1 (8) + INT_ENA_SEQ1 (11), interrupt every EOS (INT_MOD_SEQ1 = 0). */
    assert_int_equal(f2812_adc.ADCTRL2, 0x0900);
    /* The sequence ends well inside the period: 4t + 4 * 3t at 80 ns = 1.28 us << 50 us. */
    const double t = 1.0 / adcclk;
    assert_true(4.0 * t + 4.0 * (2.0 + 1.0) * t < 2e-6);
}

/* ---- GPIO and QEP ------------------------------------------------------------------------ */
static void test_init_gpio_mux_keeps_other_pins(void **state)
{
    (void)state;
    reset_device();
    f2812_gpiomux.GPAMUX = 0x8000; /* some other pin already muxed by a boot loader */
    f2812_gpiomux.GPDMUX = 0x0040;
    hal_init();
    /* PWM1..6 (bits 0..5) and CAP1_QEP1, CAP2_QEP2, CAP3_QEPI1 (bits 8..10) (4.8). */
    assert_int_equal(f2812_gpiomux.GPAMUX, 0x873F);
    assert_int_equal(f2812_gpiomux.GPDMUX, 0x0041);
}

static void test_init_qep_timer2(void **state)
{
    (void)state;
    /* 2000 lines x 4 edges = 8000 counts per turn, T2 wraps in 0..T2PR (2.9). */
    assert_int_equal(f2812_eva.T2PR, 7999);
    assert_int_equal(f2812_eva.T2PR + 1, 4 * 2000);
    /* T2CON: FREE+SOFT, TMODE 11 directional up/down (0x1800), TCLKS 11 QEP (0x0030),
     * TENABLE, TPS = 0 (2.3; QEP forces /1). */
    assert_int_equal(f2812_eva.T2CON, 0xD870);
    /* CAPCONA: CAPRES=1 (no reset), CAP12EN = 11 QEP, CAP3EN, CAP3EDGE rising, CAP3 on T2. */
    assert_int_equal(f2812_eva.CAPCONA, 0xF004);
    assert_int_equal(f2812_eva.EVAIMRC, 0x0000); /* index flag polled, no interrupt */
}


/* ---- fault tolerance: relay outputs and desaturation inputs (f2812_board.h) ---------------
 * Relay coils on GPIOB0, B1, B2 (phase A, B, C), desaturation FAULT inputs on GPIOB8, B9, B10
 * (legs A, B, C, active low). Port B register addresses: fact sheet 4.8 (GPBMUX 0x70C4, GPBDIR
 * 0x70C5 [P]; GPBDAT/SET/CLEAR 0x70E4..0x70E6). RAM cannot emulate write-1-to-set/clear, so the
 * tests read what was written to SET and CLEAR. */
static void test_init_relay_and_desat_pins(void **state)
{
    (void)state;
    reset_device();
    f2812_gpiomux.GPBMUX = 0xFFFFu; /* every port-B pin muxed before: must become GPIO */
    f2812_gpiomux.GPBDIR = 0x0300u; /* B8, B9 outputs before: must become inputs */
    hal_init();
    /* Bits 0..2 and 8..10 cleared (GPIO), the others as they were. */
    assert_int_equal(f2812_gpiomux.GPBMUX, 0xF8F8u);
    /* B0..B2 outputs, B8..B10 inputs. */
    assert_int_equal(f2812_gpiomux.GPBDIR, 0x0007u);
    /* Coils off before the pins drive: B0..B2 latches cleared. */
    assert_int_equal(f2812_gpiodata.B.CLEAR, 0x0007u);
    assert_int_equal(f2812_gpiodata.B.SET, 0x0000u);
    /* GPAMUX, GPDMUX unchanged by this (the EV-A/QEP/PDPINTA pins, 4.8). */
    assert_int_equal(f2812_gpiomux.GPAMUX, 0x073Fu);
    assert_int_equal(f2812_gpiomux.GPDMUX, 0x0001u);
}

static void test_relay_phase_a_b_c_and_open(void **state)
{
    (void)state;
    enable_outputs();
    for (uint16_t r = 1u; r <= 3u; r++) {
        const hal_cmd_t cmd = {1u, 1u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, r};
        f2812_gpiodata.B.SET = 0u;
        f2812_gpiodata.B.CLEAR = 0u;
        hal_write(&cmd);
        /* The named phase's coil alone: B(r-1) set, the two others cleared. */
        assert_int_equal(f2812_gpiodata.B.SET, (uint16_t)(1u << (r - 1u)));
        assert_int_equal(f2812_gpiodata.B.CLEAR, (uint16_t)(0x0007u & ~(1u << (r - 1u))));
        /* That leg both switches off, the two others upper on as commanded. */
        for (uint16_t x = 0u; x < 3u; x++) {
            assert_int_equal(leg_state(x).upper, x == r - 1u ? 0 : 1);
            assert_int_equal(leg_state(x).lower, 0);
        }
    }
    const hal_cmd_t open = {0u, 1u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    f2812_gpiodata.B.SET = 0u;
    f2812_gpiodata.B.CLEAR = 0u;
    hal_write(&open);
    assert_int_equal(f2812_gpiodata.B.SET, 0x0000u);
    assert_int_equal(f2812_gpiodata.B.CLEAR, 0x0007u);
    assert_int_equal(leg_state(0).lower, 1); /* leg C's relay gone: every leg as commanded */
    assert_int_equal(leg_state(1).upper, 1);
    assert_int_equal(leg_state(2).lower, 1);
}

static void test_gates_off_and_disable_leave_the_relay(void **state)
{
    (void)state;
    enable_outputs();
    const hal_cmd_t b = {0u, 0u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 2u};
    hal_write(&b);
    assert_int_equal(f2812_gpiodata.B.SET, 0x0002u);
    f2812_gpiodata.B.SET = 0u;
    f2812_gpiodata.B.CLEAR = 0u;
    hal_gates_off();
    /* No port-B write: the coil stays on. */
    assert_int_equal(f2812_gpiodata.B.SET, 0u);
    assert_int_equal(f2812_gpiodata.B.CLEAR, 0u);
    /* A disabled command carrying the same relay writes nothing to it either. */
    const hal_cmd_t off = {0u, 0u, 0u, 0u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 2u};
    hal_write(&off);
    assert_int_equal(f2812_gpiodata.B.SET, 0u);
    assert_int_equal(f2812_gpiodata.B.CLEAR, 0u);
    /* A disabled command that opens it does open it (the relay is not a gate). */
    const hal_cmd_t off_open = {0u, 0u, 0u, 0u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    hal_write(&off_open);
    assert_int_equal(f2812_gpiodata.B.CLEAR, 0x0007u);
}

static void test_desat_inputs_active_low(void **state)
{
    (void)state;
    hal_meas_t m;
    f2812_gpiodata.B.DAT = 0xFFFFu; /* every FAULT line high (pulled up): no desaturation */
    hal_read(&m);
    assert_int_equal(m.desat, 0u);
    f2812_gpiodata.B.DAT = (uint16_t)(0xFFFFu & ~0x0200u); /* B9 low: leg B */
    hal_read(&m);
    assert_int_equal(m.desat, 2u);
    f2812_gpiodata.B.DAT = 0x08FFu; /* B8..B10 low, other port-B pins anything */
    hal_read(&m);
    assert_int_equal(m.desat, 7u);
    f2812_gpiodata.B.DAT = 0x0500u; /* B9 low only; B8, B10 high */
    hal_read(&m);
    assert_int_equal(m.desat, 2u);
}

/* ---- switching states -------------------------------------------------------------------- */
static void test_first_enable_takes_two_periods(void **state)
{
    (void)state;
    const hal_cmd_t cmd = {1u, 0u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    hal_write(&cmd);
    assert_false(f2812_eva.COMCONA & FCOMPOE); /* still high-impedance */
    assert_all_off_next_period();
    hal_write(&cmd); /* again in the SAME period: the all-off state is not active yet */
    assert_false(f2812_eva.COMCONA & FCOMPOE);
    assert_all_off_next_period();
    f2812_adcint_done(); /* end of period; its boundary loads the all-off shadows */
    hal_write(&cmd);
    assert_true(f2812_eva.COMCONA & FCOMPOE);
    assert_int_equal(leg_state(0).upper, 1);
    assert_int_equal(leg_state(1).upper, 0);
    assert_int_equal(leg_state(2).upper, 1);
}

static void test_sstp_all_eight_states(void **state)
{
    (void)state;
    enable_outputs();
    for (uint16_t k = 0; k < 8u; k++) {
        const hal_cmd_t cmd = {(uint16_t)((k >> 2) & 1u), (uint16_t)((k >> 1) & 1u),
                               (uint16_t)(k & 1u), 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
        const uint16_t comcona = f2812_eva.COMCONA;
        hal_write(&cmd);
        /* ACTRA: every pair upper active-high (10), lower active-low (01): 0x0666 (2.5, DMC). */
        assert_int_equal(f2812_eva.ACTRA, 0x0666);
        /* 100 % duty (CMPR = 0) for an upper switch on, 0 % (CMPR > T1PR) for lower on. */
        assert_int_equal(f2812_eva.CMPR1, cmd.sa ? 0 : 1876);
        assert_int_equal(f2812_eva.CMPR2, cmd.sb ? 0 : 1876);
        assert_int_equal(f2812_eva.CMPR3, cmd.sc ? 0 : 1876);
        const uint16_t s[3] = {cmd.sa, cmd.sb, cmd.sc};
        for (unsigned leg = 0; leg < 3; leg++) {
            leg_t l = leg_state(leg);
            assert_int_equal(l.upper, s[leg]);
            assert_int_equal(l.lower, !s[leg]); /* complementary, through the dead band */
        }
        /* Only shadows were written: the timer and compare control are untouched. */
        assert_int_equal(f2812_eva.COMCONA, comcona);
        assert_int_equal(f2812_eva.T1CON, 0xC800);
    }
}

static void test_fstp_all_four_states_leg_a_off(void **state)
{
    (void)state;
    f2812_set_fstp(1u);
    enable_outputs();
    for (uint16_t k = 0; k < 8u; k++) { /* 4 states x sa = 0/1, which must not matter */
        const hal_cmd_t cmd = {(uint16_t)((k >> 2) & 1u), (uint16_t)((k >> 1) & 1u),
                               (uint16_t)(k & 1u), 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
        hal_write(&cmd);
        /* Leg A (PWM1/2) forced low = both switches off; legs B, C as in SSTP: 0x0660. */
        assert_int_equal(f2812_eva.ACTRA, 0x0660);
        assert_int_equal(f2812_eva.CMPR1, 1876);
        assert_int_equal(leg_state(0).upper, 0);
        assert_int_equal(leg_state(0).lower, 0);
        assert_int_equal(leg_state(1).upper, cmd.sb);
        assert_int_equal(leg_state(1).lower, !cmd.sb);
        assert_int_equal(leg_state(2).upper, cmd.sc);
        assert_int_equal(leg_state(2).lower, !cmd.sc);
    }
}

static void test_enable_zero_is_all_off_next_period(void **state)
{
    (void)state;
    enable_outputs();
    const hal_cmd_t on = {1u, 1u, 0u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    hal_write(&on);
    const hal_cmd_t off = {1u, 1u, 0u, 0u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    hal_write(&off);
    assert_all_off_next_period();
    /* A re-enable from a driven all-off state needs no re-arm: outputs are still enabled. */
    hal_write(&on);
    assert_int_equal(leg_state(0).upper, 1);
}

static void test_gates_off_is_immediate_and_rearms_in_two_periods(void **state)
{
    (void)state;
    enable_outputs();
    const hal_cmd_t on = {1u, 0u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    hal_write(&on);
    hal_gates_off();
    assert_false(f2812_eva.COMCONA & FCOMPOE); /* Hi-Z now, not at the boundary */
    assert_all_off_next_period();
    f2812_adcint_done();
    period(&on);
    assert_false(f2812_eva.COMCONA & FCOMPOE);
    assert_all_off_next_period();
    hal_write(&on);
    assert_true(f2812_eva.COMCONA & FCOMPOE);
    assert_int_equal(leg_state(2).upper, 1);
}

/* ---- protection -------------------------------------------------------------------------- */
static void test_pdpinta_trip_latches_and_blocks_enable(void **state)
{
    (void)state;
    enable_outputs();
    hal_meas_t m;
    hal_read(&m);
    assert_int_equal(m.trip, 0);
    /* Hardware: pin low -> FCOMPOE cleared (Hi-Z), EVAIFRA.PDPINTA latched, interrupt. */
    pdpinta_pin(0);
    f2812_eva.COMCONA = (uint16_t)(f2812_eva.COMCONA & ~FCOMPOE);
    f2812_eva.EVAIFRA = (uint16_t)(f2812_eva.EVAIFRA | 0x0001u);
    f2812_piectrl.PIEACK = 0;
    f2812_pdpint_isr();
    assert_int_equal(f2812_piectrl.PIEACK, 0x0001);
    assert_false(f2812_eva.COMCONA & FCOMPOE);
    assert_all_off_next_period();
    assert_int_equal(f2812_eva.EVAIFRA & 1u, 1); /* the ISR leaves the fault latched */
    hal_read(&m);
    assert_int_equal(m.trip, 1);
    /* The pin comes back: still latched, enable refused. */
    pdpinta_pin(1);
    const hal_cmd_t on = {1u, 1u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    for (int i = 0; i < 3; i++) {
        period(&on);
        assert_false(f2812_eva.COMCONA & FCOMPOE);
        assert_all_off_next_period();
    }
    hal_read(&m);
    assert_int_equal(m.trip, 1);
    /* Clear: write 1 to bit 0 only (a read-modify-write would clear other pending flags). */
    f2812_eva.EVAIFRA = 0x0081; /* PDPINTA + T1PINT pending */
    hal_trip_clear();
    assert_int_equal(f2812_eva.EVAIFRA, 0x0001);
    f2812_eva.EVAIFRA = 0x0000; /* hardware: write-1-to-clear */
    hal_read(&m);
    assert_int_equal(m.trip, 0);
    period(&on);
    hal_write(&on);
    assert_true(f2812_eva.COMCONA & FCOMPOE);
}

static void test_pin_still_low_keeps_trip(void **state)
{
    (void)state;
    pdpinta_pin(0);
    hal_meas_t m;
    hal_read(&m);
    assert_int_equal(m.trip, 1);
    const hal_cmd_t on = {1u, 1u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    period(&on);
    period(&on);
    assert_false(f2812_eva.COMCONA & FCOMPOE);
}

/* ---- measurements ------------------------------------------------------------------------ */
static void test_adc_results_left_justified_to_hal_slots(void **state)
{
    (void)state;
    /* ADCRESULTn holds conversion n, 12 bits left-justified in 15:4 (3.1); conversion n is
     * hal.h channel n (ADCCHSELSEQ order tested above). */
    const uint16_t counts[HAL_ADC_COUNT] = {0u, 4095u, 2048u, 1234u, 3001u};
    for (unsigned n = 0; n < HAL_ADC_COUNT; n++) {
        f2812_adc.ADCRESULT[n] = (uint16_t)(counts[n] << 4);
    }
    f2812_adc.ADCRESULT[5] = 0xFFF0; /* unused results must not leak in */
    hal_meas_t m;
    memset(&m, 0xA5, sizeof m);
    hal_read(&m);
    assert_int_equal(m.adc[HAL_ADC_IA], 0);
    assert_int_equal(m.adc[HAL_ADC_IB], 4095);
    assert_int_equal(m.adc[HAL_ADC_IC], 2048);
    assert_int_equal(m.adc[HAL_ADC_VDC], 1234);
    assert_int_equal(m.adc[HAL_ADC_VMID], 3001);
    /* Every 12-bit code, on every slot. */
    for (uint16_t c = 0; c < 4096u; c++) {
        for (unsigned n = 0; n < HAL_ADC_COUNT; n++) {
            f2812_adc.ADCRESULT[n] = (uint16_t)(((c + 97u * n) & 0x0FFFu) << 4);
        }
        hal_read(&m);
        for (unsigned n = 0; n < HAL_ADC_COUNT; n++) {
            assert_int_equal(m.adc[n], (c + 97u * n) & 0x0FFFu);
        }
    }
}

static void test_qep_count_index_and_direction(void **state)
{
    (void)state;
    hal_meas_t m;
    const uint16_t counts[] = {0u, 1u, 4000u, 7998u, 7999u};
    for (unsigned i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        f2812_eva.T2CNT = counts[i];
        hal_read(&m);
        assert_int_equal(m.qep_count, counts[i]);
        assert_int_equal(m.qep_index_seen, 0);
    }
    /* Index: CAP3 captured T2 on QEPI1 and flagged EVAIFRC.CAP3INT (bit 2); CAP1INT also
     * pending. hal_read reports it once and clears only that flag (write 1, 2.8). */
    f2812_eva.EVAIFRC = 0x0005;
    f2812_eva.CAP3FIFO = 7991u; /* T2 value latched at the pulse */
    hal_read(&m);
    assert_int_equal(m.qep_index_seen, 1);
    assert_int_equal(m.qep_index_count, 7991u);
    assert_int_equal(f2812_eva.EVAIFRC, 0x0004);
    f2812_eva.EVAIFRC = 0x0000; /* hardware: write-1-to-clear */
    hal_read(&m);
    assert_int_equal(m.qep_index_seen, 0);
    /* Direction: GPTCONA.T2STAT (bit 14) = 1 counting up (2.2). */
    f2812_eva.GPTCONA = (uint16_t)(f2812_eva.GPTCONA | 0x4000u);
    assert_int_equal(f2812_qep_direction(), 1);
    f2812_eva.GPTCONA = (uint16_t)(f2812_eva.GPTCONA & ~0x4000u);
    assert_int_equal(f2812_qep_direction(), -1);
}

static void test_adc_isr_exit_and_tick(void **state)
{
    (void)state;
    hal_meas_t m;
    hal_read(&m);
    assert_int_equal(m.tick, 0);
    for (uint32_t k = 1; k <= 3u; k++) {
        f2812_piectrl.PIEACK = 0;
        f2812_adc.ADCST = 0;
        f2812_adcint_done();
        /* RST_SEQ1 (bit 14) with the run configuration kept, INT_SEQ1_CLR (ADCST bit 4),
         * PIEACK group 1 (3.3 step 7, 4.1). */
        assert_int_equal(f2812_adc.ADCTRL2, 0x4900);
        assert_int_equal(f2812_adc.ADCST, 0x0010);
        assert_int_equal(f2812_piectrl.PIEACK, 0x0001);
        hal_read(&m);
        assert_int_equal(m.tick, k);
    }
}

static void test_isr_load_figure(void **state)
{
    (void)state;
    assert_int_equal(f2812_isr_ticks_max(), 0);
    /* ISR ends while T1 still counts up at 1000: 1000 ticks (13.3 us) into the period. */
    f2812_eva.GPTCONA = (uint16_t)(f2812_eva.GPTCONA | 0x2000u); /* T1STAT = up (2.2) */
    f2812_eva.T1CNT = 1000;
    f2812_adcint_done();
    assert_int_equal(f2812_isr_ticks_max(), 1000);
    /* Counting down at 1000: 2 * 1875 - 1000 = 2750 ticks (36.7 us) into the period. */
    f2812_eva.GPTCONA = (uint16_t)(f2812_eva.GPTCONA & ~0x2000u);
    f2812_adcint_done();
    assert_int_equal(f2812_isr_ticks_max(), 2750);
    /* A shorter one does not lower the worst case. */
    f2812_eva.GPTCONA = (uint16_t)(f2812_eva.GPTCONA | 0x2000u);
    f2812_eva.T1CNT = 10;
    f2812_adcint_done();
    assert_int_equal(f2812_isr_ticks_max(), 2750);
}

/* ---- helpers ----------------------------------------------------------------------------- */
static void test_memcopy_copies_exactly_the_range(void **state)
{
    (void)state;
    uint16_t src[6] = {1u, 2u, 3u, 4u, 5u, 6u};
    uint16_t dst[6] = {0u, 0u, 0u, 0u, 0u, 0u};
    f2812_memcopy(&dst[1], &src[1], &src[4]);
    const uint16_t expect[6] = {0u, 2u, 3u, 4u, 0u, 0u};
    assert_memory_equal(dst, expect, sizeof dst);
    f2812_memcopy(dst, &src[2], &src[2]); /* empty section: nothing */
    assert_memory_equal(dst, expect, sizeof dst);
}

static void test_irq_save_restore_nests(void **state)
{
    (void)state;
    f2812_interrupts_enable();
    uint16_t outer = hal_irq_save();
    assert_int_equal(f2812_host_cpu.intm, 1);
    uint16_t inner = hal_irq_save();
    hal_irq_restore(inner);
    assert_int_equal(f2812_host_cpu.intm, 1); /* still inside the outer section */
    hal_irq_restore(outer);
    assert_int_equal(f2812_host_cpu.intm, 0);
}

/* ---- PWM form (hal.h): compare values, polarity, reload points ----------------------------
 * Expected values from the fact sheet: T1PR = 1875 (2.3: 50 us up/down at HSPCLK 75 MHz);
 * ACTRA pair of a leg, upper output active high (10b) and lower active low (01b) = 0x6, the
 * swapped pair 0x9, fields of leg x at bit 4x (2.5); COMCONA.CLD bits 14:13, 00 = reload at
 * underflow, 01 = at underflow and period match (2.4); EVAIMRA bit 7 = T1PINT (2.8). */
#define T1PR_50US 1875u
#define CLD_BITS 0x6000u
#define CLD_UF_AND_PERIOD 0x2000u
#define EVAIMRA_T1PINT 0x0080u

static hal_cmd_t pwm_cmd(uint16_t up_a, uint16_t dn_a, uint16_t up_b, uint16_t dn_b, uint16_t up_c,
                         uint16_t dn_c)
{
    hal_cmd_t c;
    memset(&c, 0, sizeof c);
    c.enable = 1u;
    c.form = HAL_CMD_PWM;
    c.cmpr_up[0] = up_a;
    c.cmpr_dn[0] = dn_a;
    c.cmpr_up[1] = up_b;
    c.cmpr_dn[1] = dn_b;
    c.cmpr_up[2] = up_c;
    c.cmpr_dn[2] = dn_c;
    return c;
}

static void assert_cmpr(uint16_t a, uint16_t b, uint16_t c)
{
    assert_int_equal(f2812_eva.CMPR1, a);
    assert_int_equal(f2812_eva.CMPR2, b);
    assert_int_equal(f2812_eva.CMPR3, c);
}

/* Duty 0 (never matched: T1PR + 1 = 1876, and any larger value is written as 1876), duty 1
 * (CMPR = 0) and mid (CMPR = T1PR / 2 = 937 on both halves: 50 % centred); centred pulses reload
 * at underflow only (CLD = 00) and need no period-match interrupt. */
static void test_pwm_duty_zero_one_mid_centred(void **state)
{
    (void)state;
    enable_outputs();
    hal_cmd_t c = pwm_cmd(T1PR_50US + 1u, T1PR_50US + 1u, 0u, 0u, 937u, 937u);
    period(&c);
    assert_cmpr(1876u, 0u, 937u);
    assert_int_equal(f2812_eva.ACTRA, 0x0666);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001);
    c = pwm_cmd(60000u, 60000u, T1PR_50US, T1PR_50US, 1u, 1u);
    period(&c);
    assert_cmpr(1876u, T1PR_50US, 1u);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    /* The leg-state form is the same registers at 0 / 100 %. */
    const hal_cmd_t legs = {1u, 0u, 1u, 1u, HAL_CMD_LEGS, {0u, 0u, 0u}, {0u, 0u, 0u}, {0u, 0u, 0u}, 0u};
    period(&legs);
    assert_cmpr(0u, 1876u, 0u);
    assert_int_equal(f2812_eva.ACTRA, 0x0666);
}

/* Upper active low on leg B: the pair's polarities swap (PWM3 active low 01b, PWM4 active high
 * 10b: field 0x9 at bit 4). */
static void test_pwm_polarity_per_leg(void **state)
{
    (void)state;
    enable_outputs();
    hal_cmd_t c = pwm_cmd(400u, 400u, 400u, 400u, 400u, 400u);
    c.act[1] = HAL_PWM_UPPER_ACTIVE_LOW;
    period(&c);
    assert_int_equal(f2812_eva.ACTRA, 0x0696);
}

/* Asymmetric pulses: the command of period k governs period k+1, its up-count values from the
 * underflow, its down-count values from the period match (hal.h). The test calls f2812_t1pint()
 * where the period match would raise T1PINT, and reads the shadows (RAM) after each write. */
static void test_pwm_asymmetric_reload_points(void **state)
{
    (void)state;
    enable_outputs();
    /* Period k: first asymmetric command (up 500 / down 1200 on leg A). CLD is still 00, so the
     * up values go to the shadows now (loaded at the underflow that starts k+1) and T1PINT is
     * armed to switch CLD to 01 at the match of k. */
    hal_cmd_t c1 = pwm_cmd(500u, 1200u, 937u, 937u, 0u, 1876u);
    hal_write(&c1);
    assert_cmpr(500u, 937u, 0u);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001 | EVAIMRA_T1PINT);
    f2812_adcint_done();
    f2812_t1pint(); /* match of k */
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, CLD_UF_AND_PERIOD);
    assert_cmpr(500u, 937u, 0u); /* unchanged: loads at the underflow of k+1 */
    assert_true(f2812_eva.COMCONA & FCOMPOE);
    /* Period k+1: hal_write first puts c1's down values in the shadows (they load at the match
     * of k+1), then keeps c2 for the match. */
    hal_cmd_t c2 = pwm_cmd(300u, 1500u, 100u, 100u, 1876u, 0u);
    hal_write(&c2);
    assert_cmpr(1200u, 937u, 1876u);
    f2812_adcint_done();
    f2812_t1pint(); /* match of k+1: c2's up values, loaded at the underflow of k+2 */
    assert_cmpr(300u, 100u, 1876u);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, CLD_UF_AND_PERIOD);
    /* Period k+2: a centred command. c2's down values go first; at the match the centred values
     * follow and CLD returns to 00 (underflow only), the interrupt is disarmed. */
    hal_cmd_t c3 = pwm_cmd(900u, 900u, 900u, 900u, 900u, 900u);
    hal_write(&c3);
    assert_cmpr(1500u, 100u, 0u);
    f2812_adcint_done();
    f2812_t1pint();
    assert_cmpr(900u, 900u, 900u);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001);
    assert_true(f2812_eva.COMCONA & FCOMPOE);
}

/* enable = 0 while the period-match reload is in force: all-off goes to the shadows at once (it
 * loads at the match: the pulse ends half-way, hal.h), and the match returns CLD to 00. */
static void test_pwm_asymmetric_then_disable(void **state)
{
    (void)state;
    enable_outputs();
    hal_cmd_t c1 = pwm_cmd(500u, 1200u, 500u, 1200u, 500u, 1200u);
    period(&c1);
    f2812_t1pint();
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, CLD_UF_AND_PERIOD);
    hal_cmd_t off = c1;
    off.enable = 0u;
    hal_write(&off);
    assert_cmpr(1876u, 1876u, 1876u);
    assert_int_equal(f2812_eva.ACTRA, 0x0000);
    f2812_adcint_done();
    f2812_t1pint();
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    assert_cmpr(1876u, 1876u, 1876u);
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001);
    /* hal_gates_off in split mode: outputs Hi-Z and CLD 00 at once. */
    enable_outputs();
    period(&c1);
    f2812_t1pint();
    hal_gates_off();
    assert_false(f2812_eva.COMCONA & FCOMPOE);
    assert_int_equal(f2812_eva.COMCONA & CLD_BITS, 0);
    assert_int_equal(f2812_eva.EVAIMRA, 0x0001);
}

/* FSTP: leg A has no devices, its compare values are ignored (CMPR1 parked, PWM1/2 forced low). */
static void test_pwm_fstp_leg_a_ignored(void **state)
{
    (void)state;
    f2812_set_fstp(1u);
    enable_outputs();
    hal_cmd_t c = pwm_cmd(0u, 0u, 937u, 937u, 100u, 100u);
    period(&c);
    assert_cmpr(1876u, 937u, 100u);
    assert_int_equal(f2812_eva.ACTRA, 0x0660);
    f2812_set_fstp(0u);
}

static void test_pwm_period_register(void **state)
{
    (void)state;
    assert_int_equal(hal_pwm_period(), T1PR_50US);
    assert_int_equal(f2812_eva.T1PR, T1PR_50US);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_init_clocks_pll_and_peripheral_clocks, setup_initialised),
        cmocka_unit_test_setup(test_init_waits_for_pll_lock_and_adc_power_up, setup_initialised),
        cmocka_unit_test(test_init_skips_pll_relock_when_already_set),
        cmocka_unit_test_setup(test_init_flash_wait_states, setup_initialised),
        cmocka_unit_test_setup(test_eallow_emulation_drops_unprotected_writes, setup_initialised),
        cmocka_unit_test_setup(test_watchdog_start_and_service, setup_initialised),
        cmocka_unit_test(test_init_clears_stale_flags),
        cmocka_unit_test_setup(test_init_pie_vectors_and_enables, setup_initialised),
        cmocka_unit_test_setup(test_init_timer1_50us_up_down, setup_initialised),
        cmocka_unit_test_setup(test_init_compare_shadow_loads_at_period_start, setup_initialised),
        cmocka_unit_test_setup(test_init_dead_band_every_leg, setup_initialised),
        cmocka_unit_test_setup(test_init_pdpinta_enabled, setup_initialised),
        cmocka_unit_test_setup(test_init_adc_sequence_and_trigger, setup_initialised),
        cmocka_unit_test(test_init_gpio_mux_keeps_other_pins),
        cmocka_unit_test_setup(test_init_qep_timer2, setup_initialised),
        cmocka_unit_test_setup(test_first_enable_takes_two_periods, setup_initialised),
        cmocka_unit_test_setup(test_sstp_all_eight_states, setup_initialised),
        cmocka_unit_test_setup(test_fstp_all_four_states_leg_a_off, setup_initialised),
        cmocka_unit_test_setup(test_enable_zero_is_all_off_next_period, setup_initialised),
        cmocka_unit_test_setup(test_gates_off_is_immediate_and_rearms_in_two_periods,
                               setup_initialised),
        cmocka_unit_test_setup(test_pdpinta_trip_latches_and_blocks_enable, setup_initialised),
        cmocka_unit_test_setup(test_pin_still_low_keeps_trip, setup_initialised),
        cmocka_unit_test_setup(test_adc_results_left_justified_to_hal_slots, setup_initialised),
        cmocka_unit_test_setup(test_qep_count_index_and_direction, setup_initialised),
        cmocka_unit_test_setup(test_adc_isr_exit_and_tick, setup_initialised),
        cmocka_unit_test_setup(test_isr_load_figure, setup_initialised),
        cmocka_unit_test(test_memcopy_copies_exactly_the_range),
        cmocka_unit_test_setup(test_irq_save_restore_nests, setup_initialised),
        cmocka_unit_test_setup(test_pwm_duty_zero_one_mid_centred, setup_initialised),
        cmocka_unit_test_setup(test_pwm_polarity_per_leg, setup_initialised),
        cmocka_unit_test_setup(test_pwm_asymmetric_reload_points, setup_initialised),
        cmocka_unit_test_setup(test_pwm_asymmetric_then_disable, setup_initialised),
        cmocka_unit_test_setup(test_pwm_fstp_leg_a_ignored, setup_initialised),
        cmocka_unit_test_setup(test_pwm_period_register, setup_initialised),
        cmocka_unit_test(test_init_relay_and_desat_pins),
        cmocka_unit_test_setup(test_relay_phase_a_b_c_and_open, setup_initialised),
        cmocka_unit_test_setup(test_gates_off_and_disable_leave_the_relay, setup_initialised),
        cmocka_unit_test_setup(test_desat_inputs_active_low, setup_initialised),
    };
    return cmocka_run_group_tests_name("f2812_hal", tests, NULL, NULL);
}
