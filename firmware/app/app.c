/*
 * app.c - the ISR translation unit: owns the one controller instance and binds the pure
 * application core (app_core.h) to the HAL. The same file runs on the F2812 (app_isr called from
 * the ADC interrupt by hal/f2812) and in SIL (called once per simulated period by hal/host).
 */
#include "app.h"

#include "app_core.h"
#include "app_instance.h"
#include "hal.h"

#include <stddef.h>

/* The one global of the firmware (DESIGN.md section 4): the controller owned by the ISR, with
 * the background's configuration copy and references (app_instance.h; the background operations
 * of firmware/proto/app_ops.c reach them there). */
app_instance_t g_app_instance;

void app_isr(void)
{
    hal_meas_t m;
    hal_cmd_t cmd;

    if (g_app_instance.core.clear_request != 0U) {
        hal_trip_clear(); /* the core decides whether the fault may be left (app_core_step) */
    }
    hal_read(&m);
    if (app_core_step(&g_app_instance.core, &m, &cmd) != 0U) {
        hal_gates_off(); /* a trip on this sample: off now, not at the next period boundary */
    }
    hal_write(&cmd);
}

void app_background(void)
{
    hal_watchdog_service();
    app_core_ident_service(&g_app_instance.core);
}

void app_request_ident(void) { app_core_request_ident(&g_app_instance.core); }

void app_get_ident(app_ident_t *d)
{
    uint16_t irq = hal_irq_save();
    *d = g_app_instance.core.ident;
    hal_irq_restore(irq);
}

void app_get_ident_view(app_ident_view_t *v)
{
    uint16_t irq = hal_irq_save();
    app_ident_view_of(&g_app_instance.core.ident, v);
    hal_irq_restore(irq);
}

void app_get_status(app_status_t *s)
{
    uint16_t irq = hal_irq_save();
    *s = g_app_instance.core.st;
    hal_irq_restore(irq);
}

int16_t app_set_refs(const dtc_refs_t *r)
{
    int16_t rc;
    if (g_app_instance.core.cfg == 0) {
        return DTC_ERR_NULL;
    }
    rc = law_shadow_write(&g_app_instance.core.law, r);
    if (rc == DTC_OK) {
        g_app_instance.refs = *r;
    }
    return rc;
}

void app_request_fault_clear(void)
{
    g_app_instance.core.clear_request = 1U;
}
