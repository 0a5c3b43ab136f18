/*
 * app_core_internal.h - the two state changes of the application core (app_core.c) that its
 * init-time calls (init/app_core_init.c) make too, and the capture word they share. Included by
 * those two files only.
 */
#ifndef APP_CORE_INTERNAL_H
#define APP_CORE_INTERNAL_H

#include "app_core.h"

/* FAULT with this reason and detail and its tick, unless a fault is latched already (the first
 * one stays); an entry in the fault log if one is attached. */
void app_core_latch(app_core_t *a, uint16_t fault, int16_t detail);

/* CALIBRATE from the start: sums, the hold, every detector and the fault cleared. */
void app_core_enter_calibrate(app_core_t *a);

/* CAPTURE_OFF: the word app_core_t.cap_state points at without a capture (app_core.c, with the
 * ISR path, so that on the F2812 it sits in zero-wait RAM as the ISR's code does). */
extern const uint16_t app_core_cap_none;

#endif /* APP_CORE_INTERNAL_H */
