/*
 * pil_console.c - the console image's drive and bench (pil_console.h): hal.h's measurement and
 * gate calls for a healthy drive at standstill; the serial line, the storage medium and the
 * interrupt mask are the binding's (pil_console_cm.c, tools/pil/pil_console_host.cpp).
 */
#include "pil_console.h"

#include "app.h"
#include "app_proto.h"
#include "hal.h"

#include <stddef.h>

/* The board's configuration (target/f2812/dtc_config_board.c, as the F2812 image links it). */
extern const struct dtc_config g_dtc_config;
extern const struct dtc_config *const g_dtc_config_post;

static hal_meas_t g_meas;
static volatile uint32_t g_tick;

/* ADC count of a per-unit value v_iq on a channel of gain gain_iq (pu per count, IQ24) and offset
 * counts: offset + v / gain, rounded (init only: the division runs once). */
static uint16_t adc_count(iq_t v_iq, iq_t gain_iq, uint16_t offset)
{
    const int32_t c = (int32_t)offset + (int32_t)((v_iq + gain_iq / 2) / gain_iq);
    return (uint16_t)(c < 0 ? 0 : (c > 4095 ? 4095 : c));
}

int16_t pil_console_init(void)
{
    const dtc_config_t *c = &g_dtc_config;
    int16_t rc;
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        g_meas.adc[k] = c->board.adc_i_offset[k];
    }
    g_meas.adc[HAL_ADC_VDC] = adc_count((iq_t)1 << FIX_IQ_Q, c->board.adc_vdc_gain_iq, c->board.adc_vdc_offset);
    g_meas.adc[HAL_ADC_VMID] = adc_count((iq_t)1 << (FIX_IQ_Q - 1), c->board.adc_vmid_gain_iq, c->board.adc_vmid_offset);
    g_meas.qep_count = 100U;
    g_tick = 0U;
    hal_init();
    rc = app_init(c);
    if (rc == 0) {
        (void)app_set_reconfig(g_dtc_config_post);
        app_set_arming(APP_ARM_COMMAND);
    }
    app_proto_start(APP_ISR_PERIOD_NS);
    return rc;
}

void pil_console_isr(void)
{
    app_isr();
}

void pil_console_background(void)
{
    app_background();
    app_proto_background();
}

uint32_t pil_console_ticks(void)
{
    return g_tick;
}

/* ---- hal.h: the bench ---------------------------------------------------------------------- */
void hal_init(void) {}

void hal_read(hal_meas_t *m)
{
    *m = g_meas;
    m->tick = g_tick;
    g_tick = g_tick + 1U;
}

void hal_write(const hal_cmd_t *cmd)
{
    (void)cmd;
}

uint16_t hal_pwm_period(void)
{
    return 3750U; /* 50 us at the F2812's 150 MHz, up-down count: T1PR = 150e6 * 50e-6 / 2 */
}

void hal_gates_off(void) {}
void hal_trip_clear(void) {}
void hal_watchdog_service(void) {}
