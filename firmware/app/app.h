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

/* Background loop work: watchdog service. (A drive with a serial line runs the protocol's
 * pass beside it: app_proto_background, firmware/proto/app_proto.h.) */
void app_background(void);

/* The capture the ISR feeds after each step and the fault log it writes at each fault (either
 * NULL: none); after app_init (the serial protocol's start attaches its own, app_proto.h). */
void app_attach(capture_t *cap, faultlog_t *flog);

/* Arming (app_core.h enum app_arm_mode). APP_ARM_COMMAND (a drive operated over its serial
 * line; the board's main()): READY after the calibration, both references set to zero. After
 * app_init, before the ISR is enabled. */
void app_set_arming(uint16_t mode);

/* Background: arm (enum app_arm_refusal: APP_ARM_OK, the ISR then enters RUN at its next
 * period, or why not) and disarm (always; RUN -> READY at the next period; IDENT -> READY at
 * once, the identification stopped where it was, its results so far kept). */
uint16_t app_arm(void);
void app_disarm(void);

/* Background: the identification (app_ident.h) started from READY as an arm is, under the arm's
 * conditions (enum app_arm_refusal; APP_ARM_NOT_CALIBRATED when not READY): its fresh calibration
 * ends in APP_STATE_IDENT instead of RUN. Read the progress with app_get_ident; disarm ends it. */
uint16_t app_identify(void);

/* Background: a valid frame arrived (the command timeout restarts); the timeout in periods (0 = off). */
void app_comm_seen(void);
void app_set_comm_timeout(uint32_t periods);

/* Background: the reference set published last (app_set_refs). */
void app_get_refs(dtc_refs_t *r);

/* The configuration in force (the application's RAM copy), NULL before app_init accepted one. */
const dtc_config_t *app_config(void);

/* The compiled-in configuration (the one app_init was given). */
const dtc_config_t *app_config_default(void);

/* Background, armed: cfg (checked by law_check; it differs from the configuration in force only
 * in live parameters, those the ISR reads as it goes or takes from the shadow set) becomes the
 * configuration in force, copied with the ISR held off; of the shadow set (references, mode,
 * speed-PI gains, flux reference) the fields the change gave a new value are published, the
 * others stay as the background last set them. Returns 0 or the check's (or the shadow set's)
 * enum dtc_err code. */
int16_t app_config_live(const dtc_config_t *cfg);

/* Background, disarmed only: cfg (checked by its law's check, law_check) becomes the
 * configuration in force; the core restarts on it (calibration, then READY or RUN as the arming
 * mode says) with the command timeout kept and the shadow set as app_config_live publishes it. Returns 0, APP_ERR_ARMED while
 * armed, or the check's enum dtc_err code (nothing changed then). */
#define APP_ERR_ARMED 1
int16_t app_reconfigure(const dtc_config_t *cfg);

/* Background / host: a copy of the application status (state, fault reason, last per-unit
 * measurement and controller output), taken with interrupts masked. */
void app_get_status(app_status_t *s);

/* Background: new references / speed-PI gains through the controller's shadow set
 * (law_shadow_write). Returns 0 or an enum dtc_err code (nothing published then). */
int16_t app_set_refs(const dtc_refs_t *r);

/* Background: identify the machine (app_ident.h) at the end of the start-up calibration instead of
 * running; call after app_init, before the calibration ends. */
void app_request_ident(void);

/* Background / host: a copy of the identification's state and results, interrupts masked. */
void app_get_ident(app_ident_t *d);
/* The same, only its progress and results (app_ident_view_t): for the background's stack. */
void app_get_ident_view(app_ident_view_t *v);

/* Background: ask the ISR to leave FAULT (back to CALIBRATE). Ignored for a configuration fault. */
void app_request_fault_clear(void);

#endif /* APP_H */
