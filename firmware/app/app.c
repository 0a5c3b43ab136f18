/*
 * app.c - the ISR translation unit: owns the one controller instance and binds the pure
 * application core (app_core.h) to the HAL. The same file runs on the F2812 (app_isr called from
 * the ADC interrupt by hal/f2812) and in SIL (called once per simulated period by hal/host).
 */
#include "app.h"

#include "app_core.h"
#include "hal.h"

#include <stddef.h>

/* The one global of the firmware (DESIGN.md section 4): the controller owned by the ISR. */
static app_core_t g_app;
/* Background-owned: the configuration in force (a RAM copy that parameter writes change) and
 * the reference set published last. */
static dtc_config_t g_cfg;
static const dtc_config_t *g_cfg_default; /* the compiled-in configuration app_init was given */
static dtc_refs_t g_refs;

int16_t app_init(const struct dtc_config *cfg)
{
    int16_t rc;
    hal_gates_off();
    g_cfg_default = cfg;
    if (cfg != NULL) {
        g_cfg = *cfg;
        cfg = &g_cfg;
    }
    rc = app_core_init(&g_app, cfg);
    if (rc != 0) {
        return rc;
    }
    dtc_refs_from_config(&g_refs, cfg);
    return app_core_set_pwm_period(&g_app, hal_pwm_period());
}

void app_set_arming(uint16_t mode)
{
    app_core_set_arming(&g_app, mode);
    if (mode == (uint16_t)APP_ARM_COMMAND && g_app.cfg != NULL) {
        dtc_refs_t r = g_refs; /* safe power-up: both references zero until the host sets them */
        r.speed_ref_iq = 0;
        r.torque_ref_iq = 0;
        (void)app_set_refs(&r);
    }
}

void app_attach(capture_t *cap, faultlog_t *flog)
{
    const uint16_t irq = hal_irq_save();
    app_core_attach(&g_app, cap, flog);
    hal_irq_restore(irq);
}

uint16_t app_arm(void)
{
    app_status_t s;
    uint16_t why;
    app_get_status(&s);
    why = app_core_arm_refusal(&g_app, &s, &g_refs);
    if (why == (uint16_t)APP_ARM_OK && s.state != APP_STATE_RUN) {
        app_core_request_arm(&g_app, APP_REQ_ARM);
    }
    return why;
}

void app_disarm(void)
{
    app_core_request_arm(&g_app, APP_REQ_DISARM);
}

void app_comm_seen(void)
{
    app_core_comm_seen(&g_app);
}

void app_set_comm_timeout(uint32_t periods)
{
    app_core_set_comm_timeout(&g_app, periods);
}

void app_get_refs(dtc_refs_t *r)
{
    *r = g_refs;
}

const dtc_config_t *app_config(void)
{
    return g_app.cfg;
}

const dtc_config_t *app_config_default(void)
{
    return g_cfg_default;
}

/* The references in force with cfg's gains and flux reference (the shadow set's other fields). */
static int16_t publish_with(const dtc_config_t *cfg)
{
    dtc_refs_t r;
    dtc_refs_from_config(&r, cfg);
    r.speed_ref_iq = g_refs.speed_ref_iq;
    r.torque_ref_iq = g_refs.torque_ref_iq;
    r.mode = g_refs.mode;
    return app_set_refs(&r);
}

int16_t app_config_live(const dtc_config_t *cfg)
{
    uint16_t irq;
    int16_t rc = law_check(cfg, NULL);
    if (rc != DTC_OK) {
        return rc;
    }
    irq = hal_irq_save(); /* a copy of a few hundred words: the ISR never sees half of it */
    g_cfg = *cfg;
    hal_irq_restore(irq);
    return publish_with(&g_cfg);
}

int16_t app_reconfigure(const dtc_config_t *cfg)
{
    int16_t rc;
    uint16_t irq;
    const uint16_t mode = g_app.arm_mode;
    const uint32_t timeout = g_app.comm_timeout_n;
    capture_t *const cap = g_app.cap;
    faultlog_t *const flog = g_app.flog;
    if (g_app.st.state == APP_STATE_RUN) {
        return APP_ERR_ARMED;
    }
    rc = law_check(cfg, NULL);
    if (rc != DTC_OK) {
        return rc;
    }
    /* Disarmed, gates off: the ISR is held off while the core restarts on the new set (it
     * calibrates again). */
    irq = hal_irq_save();
    g_cfg = *cfg;
    rc = app_core_init(&g_app, &g_cfg);
    app_core_attach(&g_app, cap, flog);
    app_core_set_arming(&g_app, mode);
    app_core_set_comm_timeout(&g_app, timeout);
    if (rc == 0) {
        rc = app_core_set_pwm_period(&g_app, hal_pwm_period());
    }
    hal_irq_restore(irq);
    if (rc == 0) {
        (void)publish_with(&g_cfg);
    }
    return rc;
}

int16_t app_set_reconfig(const struct dtc_config *post)
{
    return app_core_set_reconfig(&g_app, post);
}

void app_isr(void)
{
    hal_meas_t m;
    hal_cmd_t cmd;

    if (g_app.clear_request != 0U) {
        hal_trip_clear(); /* the core decides whether the fault may be left (app_core_step) */
    }
    hal_read(&m);
    if (app_core_step(&g_app, &m, &cmd) != 0U) {
        hal_gates_off(); /* a trip on this sample: off now, not at the next period boundary */
    }
    hal_write(&cmd);
}

void app_background(void)
{
    hal_watchdog_service();
}

void app_get_status(app_status_t *s)
{
    uint16_t irq = hal_irq_save();
    *s = g_app.st;
    hal_irq_restore(irq);
}

int16_t app_set_refs(const dtc_refs_t *r)
{
    int16_t rc;
    if (g_app.cfg == 0) {
        return DTC_ERR_NULL;
    }
    rc = law_shadow_write(&g_app.law, r);
    if (rc == DTC_OK) {
        g_refs = *r;
    }
    return rc;
}

void app_request_fault_clear(void)
{
    g_app.clear_request = 1U;
}
