/*
 * app_core_internal.h - the two state changes of the application core (app_core.c) that its
 * init-time calls (init/app_core_init.c) make too. Included by those two files only.
 */
#ifndef APP_CORE_INTERNAL_H
#define APP_CORE_INTERNAL_H

#include "app_core.h"

/* FAULT with this reason and detail and its tick, unless a fault is latched already (the first
 * one stays); an entry in the fault log if one is attached. */
void app_core_latch(app_core_t *a, uint16_t fault, int16_t detail);

/* CALIBRATE from the start: sums, the hold, every detector and the fault cleared. */
void app_core_enter_calibrate(app_core_t *a);

#endif /* APP_CORE_INTERNAL_H */
