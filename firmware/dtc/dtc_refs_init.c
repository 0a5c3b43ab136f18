/* dtc_refs_init.c - the init-time part of the reference sets (dtc_refs.h): the set a configuration
 * starts with and the start of every law's sets. Init-only code: its own file in the archive
 * dtc_config, which the F2812 image keeps in flash (firmware/CMakeLists.txt). */
#include "dtc_refs.h"

void dtc_shadow_init(dtc_shadow_t *s)
{
    s->seq = 0U;
    s->adopted = 0U;
}

void dtc_refs_from_config(dtc_refs_t *r, const dtc_config_t *cfg)
{
    r->speed_ref_iq = cfg->speed.speed_ref_iq;
    r->torque_ref_iq = cfg->speed.torque_ref_iq;
    r->flux_ref_iq = cfg->speed.flux_ref_iq;
    r->kp_iq = cfg->speed.kp_iq;
    r->ki_ts_iq = cfg->speed.ki_ts_iq;
    r->mode = cfg->speed.mode;
}

void dtc_refs_start(dtc_refs_t *act, dtc_shadow_t *sh, dtc_refs_t *r, const dtc_config_t *cfg)
{
    dtc_refs_from_config(r, cfg);
    act->mode = r->mode;
    dtc_shadow_init(sh);
}
