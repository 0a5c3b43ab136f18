/*
 * hal_null.h - a HAL binding with no hardware and no plant (hal_null.c), for the host programs that
 * drive the application's background on a drive at standstill: the protocol's fuzzer
 * (tests/fuzz/fuzz_proto.c) and its benchmark (tools/bench/bench_proto.c). It implements the
 * control half of hal.h: hal_read returns hal_null_meas with the tick hal_null_tick, hal_write
 * drops the command, the gates, trips, watchdog and interrupts do nothing. The serial line and the
 * parameter store stay the program's own (each models its own line).
 */
#ifndef HAL_NULL_H
#define HAL_NULL_H

#include <stdint.h>

#include "hal.h"

/* T1PR of the null binding's PWM: 3750 (50 us at 150 MHz / 2, up-down count). */
#define HAL_NULL_T1PR 3750U

extern hal_meas_t hal_null_meas; /* what hal_read returns */
extern uint32_t hal_null_tick;   /* its tick */

#endif /* HAL_NULL_H */
