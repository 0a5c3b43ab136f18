/*
 * app_ident_apply_run.c - app_ident_apply (app_ident.h): the identification's results into the
 * configuration in force, background only. The derivation is app_ident_apply.c's
 * (app_ident_derive); here the drive's state, the law's check and the restart on the new set
 * (app_reconfigure), as a disarmed parameter write (firmware/proto/app_params.c).
 */
#include "app_ident.h"

#include "app.h"
#include "dtc_params.h"
#include "law.h"

#include <stddef.h>

/* The background's copy of the configuration being changed (the identification's progress and
 * results are read into a local app_ident_view_t: the stack of a background call, as the IDENTIFY
 * command's). */
static dtc_config_t g_apply;

/* Configuration rows (the common part's and its law's) whose raw value differs between a and b. */
static uint16_t rows_changed(const dtc_config_t *a, const dtc_config_t *b)
{
    const dtc_param_list_t *l = dtc_param_law_list(a->law);
    const uint16_t n_law = l != NULL ? l->n : 0U;
    uint16_t k, n = 0U;
    for (k = 0U; k < dtc_params_common.n + n_law; k++) {
        const dtc_param_t *p = k < dtc_params_common.n ? &dtc_params_common.rows[k] : &l->rows[k - dtc_params_common.n];
        if (dtc_param_raw(a, p) != dtc_param_raw(b, p)) {
            n++;
        }
    }
    return n;
}

/* 1 when the drive is armed or identifying (its status copy off the derivation's stack) */
APP_NOINLINE static uint16_t busy(void)
{
    app_status_t s;
    app_get_status(&s);
    return s.state == APP_STATE_RUN || s.state == APP_STATE_IDENT ? 1U : 0U;
}

int16_t app_ident_apply(uint16_t *changed, int16_t *detail)
{
    const dtc_config_t *cfg = app_config();
    app_ident_view_t d;
    int16_t rc;
    *detail = 0;
    *changed = 0U;
    if (busy() != 0U) {
        return (int16_t)APP_IDENT_APPLY_ARMED;
    }
    if (cfg == NULL) {
        return (int16_t)APP_IDENT_APPLY_NOT_DONE;
    }
    app_get_ident_view(&d);
    rc = app_ident_derive(&d, cfg, &g_apply);
    if (rc != (int16_t)APP_IDENT_APPLY_OK) {
        return rc;
    }
    rc = law_check(&g_apply, NULL);
    if (rc != DTC_OK) {
        *detail = rc;
        return (int16_t)APP_IDENT_APPLY_CHECK;
    }
    *changed = rows_changed(&g_apply, cfg);
    rc = app_reconfigure(&g_apply);
    if (rc == APP_ERR_ARMED) {
        *changed = 0U;
        return (int16_t)APP_IDENT_APPLY_ARMED;
    }
    if (rc != 0) {
        *changed = 0U;
        *detail = rc;
        return (int16_t)APP_IDENT_APPLY_CHECK;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}
