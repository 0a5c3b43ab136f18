#include "law.h"

#include <stddef.h>

int16_t law_init(law_t *l, const dtc_config_t *cfg)
{
    if (l == NULL || cfg == NULL) {
        return DTC_ERR_NULL;
    }
    l->law = cfg->law;
    if (cfg->law == DTC_LAW_IM_DTC) {
        return im_dtc_init(&l->u.im, cfg);
    }
    return dtc_init(&l->u.pm, cfg); /* refuses an unknown law with DTC_ERR_VARIANT */
}

void law_reset(law_t *l)
{
    if (l->law == DTC_LAW_IM_DTC) {
        im_dtc_reset(&l->u.im);
    } else {
        dtc_reset(&l->u.pm);
    }
}

void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o)
{
    if (l->law == DTC_LAW_IM_DTC) {
        im_dtc_step(&l->u.im, m, o);
    } else {
        dtc_step(&l->u.pm, m, o);
    }
}

int16_t law_shadow_write(law_t *l, const dtc_refs_t *r)
{
    return l->law == DTC_LAW_IM_DTC ? im_dtc_shadow_write(&l->u.im, r)
                                    : dtc_shadow_write(&l->u.pm, r);
}

void law_refs_get(const law_t *l, dtc_refs_t *r)
{
    if (l->law == DTC_LAW_IM_DTC) {
        im_dtc_refs_get(&l->u.im, r);
    } else {
        dtc_refs_get(&l->u.pm, r);
    }
}

iq_t law_speed_ref(const law_t *l)
{
    return l->law == DTC_LAW_IM_DTC ? l->u.im.act.speed_ref_iq : l->u.pm.act.speed_ref_iq;
}
