/*
 * dtc_init.c - initialisation of the PM law (dtc.h dtc_init). Runs once, from app_init in the
 * background before the control interrupt starts: built into the init-only archive dtc_init,
 * which the F2812 image keeps in flash (firmware/CMakeLists.txt), so it costs no zero-wait RAM.
 */
#include "dtc.h"
#include "dtc_internal.h"

#include <stddef.h>

int16_t dtc_init(dtc_t *c, const dtc_config_t *cfg)
{
    int16_t err;
    dtc_refs_t r;

    if (c == NULL) {
        return DTC_ERR_NULL;
    }
    c->cfg = NULL;
    err = dtc_check(cfg, NULL);
    if (err != DTC_OK) {
        return err;
    }
    c->cfg = cfg;

    dtc_pm_est_params_from_config(&c->fe_p, &c->vc_p, cfg, &cfg->u.pm_dtc.machine);
    dtc_block_params(c, cfg);
    dtc_speed_params_from_config(&c->sm_p, &c->pi_p, cfg);

    dtc_refs_from_config(&r, cfg);
    c->act.mode = cfg->speed.mode;
    c->te_ref_iq = 0;
    dtc_refs_adopt(&c->act, &c->pi_p, &c->pi, &c->te_trim_iq, c->te_ref_iq, &r, cfg);
    dtc_shadow_init(&c->sh);

    flux_est_init(&c->fe, &c->fe_p);
    speed_meas_init(&c->sm, &c->sm_p, 0U);
    dtc_reset(c);
    return DTC_OK;
}
