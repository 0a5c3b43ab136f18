/*
 * app_init.c - the application's init-time and background calls (app.h): init, the post-fault
 * configuration, arming, the command timeout, the capture and fault-log attachment, the
 * configuration's replacement. In libdtc_app_init.a, which the F2812 image runs from flash (only
 * the ISR path, libdtc_app.a, is in zero-wait RAM); the instance is app.c's (app_instance.h).
 */
#include "app.h"
#include "app_instance.h"
#include "hal.h"

#include <stddef.h>

int16_t app_init(const struct dtc_config *cfg)
{
    int16_t rc;
    hal_gates_off();
    g_app_instance.cfg_default = cfg;
    if (cfg != NULL) {
        g_app_instance.cfg = *cfg;
        cfg = &g_app_instance.cfg;
    }
    rc = app_core_init(&g_app_instance.core, cfg);
    if (rc != 0) {
        return rc;
    }
    dtc_refs_from_config(&g_app_instance.refs, cfg);
    return app_core_set_pwm_period(&g_app_instance.core, hal_pwm_period());
}

int16_t app_set_reconfig(const struct dtc_config *post)
{
    return app_core_set_reconfig(&g_app_instance.core, post);
}

void app_set_arming(uint16_t mode)
{
    app_core_set_arming(&g_app_instance.core, mode);
    if (mode == (uint16_t)APP_ARM_COMMAND && g_app_instance.core.cfg != NULL) {
        dtc_refs_t r = g_app_instance.refs; /* safe power-up: both references zero until the host sets them */
        r.speed_ref_iq = 0;
        r.torque_ref_iq = 0;
        (void)app_set_refs(&r);
    }
}

void app_attach(capture_t *cap, faultlog_t *flog)
{
    const uint16_t irq = hal_irq_save();
    app_core_attach(&g_app_instance.core, cap, flog);
    hal_irq_restore(irq);
}

uint16_t app_arm(void)
{
    app_status_t s;
    uint16_t why;
    app_get_status(&s);
    why = app_core_arm_refusal(&g_app_instance.core, &s, &g_app_instance.refs);
    if (why == (uint16_t)APP_ARM_OK && s.state != APP_STATE_RUN) {
        app_core_request_arm(&g_app_instance.core, APP_REQ_ARM);
    }
    return why;
}

uint16_t app_identify(void)
{
    app_status_t s;
    uint16_t why;
    app_get_status(&s);
    if (s.state != APP_STATE_READY) {
        return (uint16_t)APP_ARM_NOT_CALIBRATED;
    }
    why = app_core_arm_refusal(&g_app_instance.core, &s, &g_app_instance.refs);
    if (why == (uint16_t)APP_ARM_OK) {
        /* the arm's fresh calibration ends in IDENT instead of RUN (calibrate_finish) */
        app_core_request_ident(&g_app_instance.core);
        app_core_request_arm(&g_app_instance.core, APP_REQ_ARM);
    }
    return why;
}

void app_disarm(void)
{
    app_core_t *const a = &g_app_instance.core;
    const uint16_t irq = hal_irq_save();
    if (a->st.state == APP_STATE_IDENT) {
        /* the identification stops where it is (its results so far kept); READY gates the legs
         * off from the next period */
        a->st.state = APP_STATE_READY;
        a->arm_mode = (uint16_t)APP_ARM_COMMAND;
    }
    hal_irq_restore(irq);
    app_core_request_arm(a, APP_REQ_DISARM);
}

void app_comm_seen(void)
{
    app_core_comm_seen(&g_app_instance.core);
}

void app_set_comm_timeout(uint32_t periods)
{
    app_core_set_comm_timeout(&g_app_instance.core, periods);
}

void app_get_refs(dtc_refs_t *r)
{
    *r = g_app_instance.refs;
}

const dtc_config_t *app_config(void)
{
    return g_app_instance.core.cfg;
}

const dtc_config_t *app_config_default(void)
{
    return g_app_instance.cfg_default;
}

/* cur, or now where the change of the configuration moved the field from was to now (a
 * selection in any format: no arithmetic, no overflow). */
static iq_t changed_iq(iq_t cur, iq_t was, iq_t now)
{
    return now != was ? now : cur;
}

/* The shadow set after a change of the configuration from one whose set was *was (its
 * dtc_refs_from_config, taken before the change: no copy of the old configuration is kept) to cfg:
 * the set published last, with each field that the change gave a new value (a gain, the flux
 * reference, a reference or the mode written by id) taken from cfg. */
static int16_t publish_with(const dtc_refs_t *was, const dtc_config_t *cfg)
{
    dtc_refs_t now;
    dtc_refs_t r = g_app_instance.refs;
    dtc_refs_from_config(&now, cfg);
    r.speed_ref_iq = changed_iq(r.speed_ref_iq, was->speed_ref_iq, now.speed_ref_iq);
    r.torque_ref_iq = changed_iq(r.torque_ref_iq, was->torque_ref_iq, now.torque_ref_iq);
    r.flux_ref_iq = changed_iq(r.flux_ref_iq, was->flux_ref_iq, now.flux_ref_iq);
    r.kp_iq = changed_iq(r.kp_iq, was->kp_iq, now.kp_iq);
    r.ki_ts_iq = changed_iq(r.ki_ts_iq, was->ki_ts_iq, now.ki_ts_iq);
    if (now.mode != was->mode) {
        r.mode = now.mode;
    }
    return app_set_refs(&r);
}

int16_t app_config_live(const dtc_config_t *cfg)
{
    uint16_t irq;
    dtc_refs_t was;
    int16_t rc = law_check(cfg, NULL);
    if (rc != DTC_OK) {
        return rc;
    }
    dtc_refs_from_config(&was, &g_app_instance.cfg); /* the background alone writes cfg */
    irq = hal_irq_save(); /* a copy of a few hundred words: the ISR never sees half of it */
    g_app_instance.cfg = *cfg;
    hal_irq_restore(irq);
    return publish_with(&was, &g_app_instance.cfg);
}

int16_t app_reconfigure(const dtc_config_t *cfg)
{
    int16_t rc;
    uint16_t irq;
    dtc_refs_t was;
    const uint16_t mode = g_app_instance.core.arm_mode;
    const uint32_t timeout = g_app_instance.core.comm_timeout_n;
    capture_t *const cap = g_app_instance.core.cap;
    faultlog_t *const flog = g_app_instance.core.flog;
    if (g_app_instance.core.st.state == APP_STATE_RUN) {
        return APP_ERR_ARMED;
    }
    rc = law_check(cfg, NULL);
    if (rc != DTC_OK) {
        return rc;
    }
    dtc_refs_from_config(&was, &g_app_instance.cfg);
    /* Disarmed, gates off: the ISR is held off while the core restarts on the new set (it
     * calibrates again). */
    irq = hal_irq_save();
    g_app_instance.cfg = *cfg;
    rc = app_core_init(&g_app_instance.core, &g_app_instance.cfg);
    app_core_attach(&g_app_instance.core, cap, flog);
    app_core_set_arming(&g_app_instance.core, mode);
    app_core_set_comm_timeout(&g_app_instance.core, timeout);
    if (rc == 0) {
        rc = app_core_set_pwm_period(&g_app_instance.core, hal_pwm_period());
    }
    hal_irq_restore(irq);
    if (rc == 0) {
        (void)publish_with(&was, &g_app_instance.cfg); /* the law starts from cfg's set */
    }
    return rc;
}

