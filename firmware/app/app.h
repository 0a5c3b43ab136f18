/*
 * app.h - the application: drive state machine and the 50 us ISR body.
 *
 * The ISR body is hal_read() -> per-unit conversion and trip checks -> dtc_step() -> hal_write().
 * States: INIT -> CALIBRATE (ADC offsets, gates off) -> RUN -> FAULT (latched, gates off, reason).
 * The same code runs on the F2812 (called from the ADC interrupt, hal/f2812) and in SIL (called
 * once per simulated period by hal/host's harness). The logic lives in app_core.h (pure, unit
 * tested); app.c owns the one controller instance and calls the HAL.
 */
#ifndef APP_H
#define APP_H

#include <stdint.h>

#include "app_core.h"

/* Validates the configuration and initialises the controller. Returns 0, or a negative error code
 * (enum dtc_err); on error the drive stays in FAULT (APP_FAULT_CONFIG) with gates off. */
int16_t app_init(const struct dtc_config *cfg);

/* The 50 us control ISR body. */
void app_isr(void);

/* The post-fault FSTP configuration (app_core_set_reconfig) of a drive with reconfiguration
 * relays; after app_init, before the ISR is enabled. Returns 0 or DTC_ERR_RECONFIG (the drive is
 * then in its configuration fault). */
int16_t app_set_reconfig(const struct dtc_config *post);

/* Background loop work: watchdog service. */
void app_background(void);

/* Background / host: a copy of the application status (state, fault reason, last per-unit
 * measurement and controller output), taken with interrupts masked. */
void app_get_status(app_status_t *s);

/* Background: new references / speed-PI gains through the controller's shadow set
 * (dtc_shadow_write). Returns 0 or an enum dtc_err code (nothing published then). */
int16_t app_set_refs(const dtc_refs_t *r);

/* Background: identify the machine (app_ident.h) at the end of the start-up calibration instead of
 * running; call after app_init, before the calibration ends. */
void app_request_ident(void);

/* Background / host: a copy of the identification's state and results, interrupts masked. */
void app_get_ident(app_ident_t *d);

/* Background: ask the ISR to leave FAULT (back to CALIBRATE). Ignored for a configuration fault. */
void app_request_fault_clear(void);

#endif /* APP_H */
