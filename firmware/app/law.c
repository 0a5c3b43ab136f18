#include "law.h"

#include <stddef.h>

/* The laws linked into this image (firmware/CMakeLists.txt, DTC_LAWS): every law on the host and
 * in SIL; one on the F2812, whose zero-wait RAM does not hold both (hal/f2812/budget.sh). A
 * configuration of a law that is not linked is refused at init (DTC_ERR_VARIANT). */
#ifndef DTC_LAW_PM_LINKED
#define DTC_LAW_PM_LINKED 1
#endif
#ifndef DTC_LAW_IM_LINKED
#define DTC_LAW_IM_LINKED 1
#endif
#if !DTC_LAW_PM_LINKED && !DTC_LAW_IM_LINKED
#error "DTC_LAWS links no control law"
#endif
#if DTC_LAW_PM_LINKED && DTC_LAW_IM_LINKED
#define LAW_IS_IM(l) ((l)->law == DTC_LAW_IM_DTC)
#elif DTC_LAW_IM_LINKED
#define LAW_IS_IM(l) 1
#else
#define LAW_IS_IM(l) 0
#endif

int16_t law_init(law_t *l, const dtc_config_t *cfg)
{
    if (l == NULL || cfg == NULL) {
        return DTC_ERR_NULL;
    }
    l->law = cfg->law;
#if DTC_LAW_IM_LINKED
    if (cfg->law == DTC_LAW_IM_DTC) {
        return im_dtc_init(&l->u.im, cfg);
    }
#endif
#if DTC_LAW_PM_LINKED
    return dtc_init(&l->u.pm, cfg); /* refuses an unknown law with DTC_ERR_VARIANT */
#else
    return DTC_ERR_VARIANT; /* the PM law is not linked into this image */
#endif
}

void law_reset(law_t *l)
{
#if DTC_LAW_IM_LINKED
    if (LAW_IS_IM(l)) {
        im_dtc_reset(&l->u.im);
        return;
    }
#endif
#if DTC_LAW_PM_LINKED
    dtc_reset(&l->u.pm);
#endif
}

void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o)
{
#if DTC_LAW_IM_LINKED
    if (LAW_IS_IM(l)) {
        if (l->u.im.pwm_law != 0U) {
            if (l->u.im.pwm_law == 1U) {
                im_sfvc_step(&l->u.im, m, o);
            } else if (l->u.im.pwm_law == 3U) {
                im_dsvm_step(&l->u.im, m, o);
            } else {
                im_dfoc_step(&l->u.im, m, o);
            }
        } else {
            im_dtc_step(&l->u.im, m, o);
        }
        return;
    }
#endif
#if DTC_LAW_PM_LINKED
    dtc_step(&l->u.pm, m, o);
#endif
}

int16_t law_shadow_write(law_t *l, const dtc_refs_t *r)
{
#if DTC_LAW_IM_LINKED
    if (LAW_IS_IM(l)) {
        return im_dtc_shadow_write(&l->u.im, r);
    }
#endif
#if DTC_LAW_PM_LINKED
    return dtc_shadow_write(&l->u.pm, r);
#endif
}

void law_refs_get(const law_t *l, dtc_refs_t *r)
{
#if DTC_LAW_IM_LINKED
    if (LAW_IS_IM(l)) {
        im_dtc_refs_get(&l->u.im, r);
        return;
    }
#endif
#if DTC_LAW_PM_LINKED
    dtc_refs_get(&l->u.pm, r);
#endif
}

int16_t law_reconfigure(law_t *l, const dtc_config_t *post, uint16_t phase)
{
    if (l->law != (uint16_t)DTC_LAW_PM_DTC) {
        return DTC_ERR_RECONFIG;
    }
    return dtc_reconfigure(&l->u.pm, post, phase);
}

uint16_t law_i_pred(const law_t *l, iq_t i1[3])
{
#if DTC_LAW_PM_LINKED
    if (!LAW_IS_IM(l) && l->u.pm.cfg->est.delay_comp != 0U) {
        i1[0] = l->u.pm.i1.ia_iq;
        i1[1] = l->u.pm.i1.ib_iq;
        i1[2] = l->u.pm.i1.ic_iq;
        return 1U;
    }
#else
    (void)l;
#endif
    (void)i1;
    return 0U;
}

iq_t law_speed_ref(const law_t *l)
{
    return LAW_IS_IM(l) ? l->u.im.act.speed_ref_iq : l->u.pm.act.speed_ref_iq;
}
