/*
 * app_instance.h - the application's one instance (app.c): the controller the ISR owns, the
 * configuration in force (a RAM copy that parameter writes change) and the reference set the
 * background published last. Included by app.c and by the background operations that run from
 * flash on the F2812 (firmware/proto/app_ops.c: arming, reconfiguration); by nothing else.
 */
#ifndef APP_INSTANCE_H
#define APP_INSTANCE_H

#include "app_core.h"

typedef struct {
    app_core_t core;                  /* owned by the ISR; the background only through its requests */
    dtc_config_t cfg;                 /* the configuration in force (core.cfg points here) */
    const dtc_config_t *cfg_default;  /* the compiled-in configuration app_init was given */
    dtc_refs_t refs;                  /* the reference set published last (app_set_refs) */
} app_instance_t;

extern app_instance_t g_app_instance;

#endif /* APP_INSTANCE_H */
