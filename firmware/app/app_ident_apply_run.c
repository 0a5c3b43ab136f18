/*
 * app_ident_apply_run.c - app_ident_apply (app_ident.h): the identification's results into the
 * configuration in force, background only. The derivation is app_ident_apply.c's
 * (app_ident_derive); here the drive's state, the law's check and the restart on the new set
 * (app_reconfigure), as a disarmed parameter write (firmware/proto/app_params.c).
 */
#include "app_ident.h"

#include "app.h"
#include "law.h"

#include <stddef.h>

/* The background's copies: the identification's state, the configuration being changed. */
static app_ident_t g_ident;
static dtc_config_t g_apply;

int16_t app_ident_apply(int16_t *detail)
{
    const dtc_config_t *cfg = app_config();
    app_status_t s;
    int16_t rc;
    *detail = 0;
    app_get_status(&s);
    if (s.state == APP_STATE_RUN || s.state == APP_STATE_IDENT) {
        return (int16_t)APP_IDENT_APPLY_ARMED;
    }
    if (cfg == NULL) {
        return (int16_t)APP_IDENT_APPLY_NOT_DONE;
    }
    app_get_ident(&g_ident);
    rc = app_ident_derive(&g_ident, cfg, &g_apply);
    if (rc != (int16_t)APP_IDENT_APPLY_OK) {
        return rc;
    }
    rc = law_check(&g_apply, NULL);
    if (rc != DTC_OK) {
        *detail = rc;
        return (int16_t)APP_IDENT_APPLY_CHECK;
    }
    rc = app_reconfigure(&g_apply);
    if (rc == APP_ERR_ARMED) {
        return (int16_t)APP_IDENT_APPLY_ARMED;
    }
    if (rc != 0) {
        *detail = rc;
        return (int16_t)APP_IDENT_APPLY_CHECK;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}
