/*
 * app.h - the application: drive state machine and the 50 us ISR body.
 *
 * The ISR body is hal_read() -> per-unit conversion and trip checks -> dtc_step() -> hal_write().
 * States: INIT -> CALIBRATE (ADC offsets, gates off) -> RUN -> FAULT (latched, gates off, reason).
 * The same code runs on the F2812 (called from the ADC interrupt, hal/f2812) and in SIL (called
 * once per simulated period by hal/host's harness).
 */
#ifndef APP_H
#define APP_H

#include <stdint.h>

struct dtc_config; /* firmware/dtc/dtc.h: typedef struct dtc_config dtc_config_t */

/* Validates the configuration and initialises the controller. Returns 0, or a negative error code
 * (the configuration's validation code); on error the drive stays in FAULT with gates off. */
int16_t app_init(const struct dtc_config *cfg);

/* The 50 us control ISR body. */
void app_isr(void);

/* Background loop work: watchdog service, shadow-parameter hand-over. */
void app_background(void);

#endif /* APP_H */
