/*
 * hal_replay.h - the replay binding of hal.h (processor-in-the-loop, docs/pil.md): hal_read()
 * returns a recorded measurement, hal_write(), hal_gates_off() and hal_trip_clear() are observed
 * instead of driving hardware. Host, AVR and Cortex-M; no library calls.
 */
#ifndef HAL_REPLAY_H
#define HAL_REPLAY_H

#include "hal.h"
#include "pil_format.h"

/* What hal_pwm_period() returns (the recording's T1PR). */
void hal_replay_set_pwm_period(uint16_t t1pr);

/* Before an ISR: the measurement hal_read() returns, and the observation cleared. */
void hal_replay_begin_isr(const hal_meas_t *m);

/* After an ISR: what the firmware did to the HAL during it. */
const pil_hal_obs_t *hal_replay_obs(void);

#endif /* HAL_REPLAY_H */
