#include "law.h"

#include <stddef.h>

#include "dsvm.h"
#include "app_warn.h"
#include "flux_est.h"
#include "hal.h"
#include "svm.h"

/* The laws linked into this image (dtc_config.h: DTC_LAW_PM_LINKED, DTC_LAW_IM_LINKED,
 * DTC_LAW_ITC_LINKED, from DTC_LAWS): every law on the host and in SIL; one on the F2812, whose
 * zero-wait RAM does not hold both (hal/f2812/budget.sh). Only their tables exist below; a configuration of a law that
 * is not linked never gets past law_init (DTC_ERR_VARIANT). */

/* The dispatch: one switch on the law chosen at init per call (DESIGN.md section 4: a variant
 * costs at most a switch in the ISR path; no function pointers there). l->law is the
 * configuration's law after a successful law_init, LAW_NONE after a refused one: nothing runs. */
#define LAW_NONE 0xFFFFU
/* law_t.step: the law's value, or this one for DTC_LAW_IM_DTC on the four-switch inverter
 * (im_dtc_step_fstp), so that the topology is chosen with the law, at init or at a
 * reconfiguration, and costs the six-switch step nothing. */
#define LAW_STEP_IM_DTC_FSTP 0xFFFEU

/* The dispatch key of law_step for the configuration cfg of law `law` (LAW_NONE for none). */
static uint16_t law_step_key(uint16_t law, const dtc_config_t *cfg)
{
    return law == (uint16_t)DTC_LAW_IM_DTC && cfg->board.topology == (uint16_t)DTC_TOPO_FSTP
               ? (uint16_t)LAW_STEP_IM_DTC_FSTP
               : law;
}

/* No law, or a law not linked: the common part's code if it has one, else DTC_ERR_VARIANT. */
static int16_t none_init(const dtc_config_t *cfg)
{
    const int16_t err = dtc_config_check_common(cfg, NULL);
    return err != DTC_OK ? err : DTC_ERR_VARIANT;
}

int16_t law_init(law_t *l, const dtc_config_t *cfg)
{
    int16_t err;
    if (l == NULL || cfg == NULL) {
        return DTC_ERR_NULL;
    }
    switch (cfg->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: err = dtc_init(&l->u.pm, cfg); break;
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES: err = im_dtc_init(&l->u.im, cfg); break;
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: err = itc_init(&l->u.itc, cfg); break;
#endif
    default: err = none_init(cfg); break;
    }
    l->law = err == DTC_OK ? cfg->law : (uint16_t)LAW_NONE;
    l->step = law_step_key(l->law, cfg);
    return err;
}

void law_reset(law_t *l)
{
    switch (l->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: dtc_reset(&l->u.pm); break;
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES: im_dtc_reset(&l->u.im); break;
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: itc_reset(&l->u.itc); break;
#endif
    default: break;
    }
}

void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o)
{
    switch (l->step) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: dtc_step(&l->u.pm, m, o); break;
#endif
#if DTC_LAW_IM_LINKED
    case DTC_LAW_IM_DTC:
    case DTC_LAW_IM_DSC: im_dtc_step(&l->u.im, m, o); break; /* im_dtc.c reads the law */
    case DTC_LAW_IM_SFVC: im_sfvc_step(&l->u.im, m, o); break;
    case DTC_LAW_IM_DFOC: im_dfoc_step(&l->u.im, m, o); break;
    case DTC_LAW_IM_DSVM: im_dsvm_step(&l->u.im, m, o); break;
    case LAW_STEP_IM_DTC_FSTP: im_dtc_step_fstp(&l->u.im, m, o); break;
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: itc_step(&l->u.itc, m, o); break;
#endif
    default: break;
    }
}

int16_t law_shadow_write(law_t *l, const dtc_refs_t *r)
{
    switch (l->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: return dtc_shadow_publish(&l->u.pm.sh, r);
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES: return dtc_shadow_publish(&l->u.im.sh, r);
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: return dtc_shadow_publish(&l->u.itc.sh, r);
#endif
    default: (void)r; return DTC_ERR_VARIANT;
    }
}

void law_refs_get(const law_t *l, dtc_refs_t *r)
{
    switch (l->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: *r = l->u.pm.act; break;
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES: *r = l->u.im.act; break;
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: *r = l->u.itc.act; break;
#endif
    default: (void)r; break;
    }
}

uint16_t law_i_pred(const law_t *l, iq_t vdc_iq, iq_t i1[3])
{
#if DTC_LAW_PM_LINKED
    if (l->law == (uint16_t)DTC_LAW_PM_DTC && l->u.pm.cfg->u.pm_dtc.est.delay_comp != 0U) {
        i1[0] = l->u.pm.i1.ia_iq;
        i1[1] = l->u.pm.i1.ib_iq;
        i1[2] = l->u.pm.i1.ic_iq;
        return 1U;
    }
#endif
#if DTC_LAW_IM_LINKED
    if (dtc_law_is_im(l->law) != 0U) {
        im_dtc_i_pred(&l->u.im, vdc_iq, i1);
        return 1U;
    }
#endif
#if DTC_LAW_ITC_LINKED
    if (l->law == (uint16_t)DTC_LAW_PM_ITC) {
        itc_i_pred(&l->u.itc, i1);
        return 1U;
    }
#endif
    (void)l;
    (void)vdc_iq;
    (void)i1;
    return 0U;
}

uint16_t law_warnings(const law_t *l)
{
#if DTC_LAW_IM_LINKED
    if (dtc_law_is_im(l->law) != 0U) {
        return (uint16_t)(l->u.im.sup.warn != 0U ? 1U << APP_WARN_IM_MODEL_MISMATCH : 0U);
    }
#else
    (void)l;
#endif
    return 0U;
}

const iq_t *law_speed_ref_ptr(const law_t *l)
{
    switch (l->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: return &l->u.pm.act.speed_ref_iq;
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES: return &l->u.im.act.speed_ref_iq;
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC: return &l->u.itc.act.speed_ref_iq;
#endif
    default: return NULL;
    }
}

iq_t law_speed_ref(const law_t *l)
{
    const iq_t *const p = law_speed_ref_ptr(l);
    return p != NULL ? *p : 0;
}

int16_t law_reconfigure(law_t *l, const dtc_config_t *post, uint16_t phase)
{
    int16_t err = DTC_ERR_RECONFIG;
    switch (l->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: err = dtc_reconfigure(&l->u.pm, post, phase); break;
#endif
#if DTC_LAW_IM_LINKED
    case DTC_LAW_IM_DTC: err = im_dtc_reconfigure(&l->u.im, post, phase); break;
#endif
    default: (void)post; (void)phase; break;
    }
    if (err == DTC_OK) {
        l->step = law_step_key(l->law, post);
    }
    return err;
}

int16_t law_check_reconfig(const dtc_config_t *post)
{
    switch (post->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: return dtc_check(post, NULL);
#endif
#if DTC_LAW_IM_LINKED
    case DTC_LAW_IM_DTC: return im_dtc_check(post, NULL);
#endif
    default: return DTC_ERR_RECONFIG;
    }
}

angle_t law_enc_angle(const dtc_config_t *cfg, uint16_t count)
{
    return flux_est_angle(count, cfg->board.enc_gain_q16, cfg->board.enc_offset);
}

void law_pwm(uint16_t form, const dtc_out_t *o, uint16_t t1pr, uint16_t cmpr_up[3], uint16_t cmpr_dn[3],
             uint16_t act[3])
{
    uint16_t x;
    if (form == LAW_OUT_THIRDS) {
        /* DSVM: one pulse per leg holding the three sub-interval states (dsvm.h, hal.h) */
        const uint16_t c23 = dsvm_c23(t1pr);
        for (x = 0U; x < 3U; x++) {
            dsvm_pwm(o->thirds[x], t1pr, c23, &cmpr_up[x], &cmpr_dn[x], &act[x]);
        }
    } else {
        /* one centred pulse per leg (hal.h): compare values of the law's duties */
        for (x = 0U; x < 3U; x++) {
            const uint16_t c = svm_cmpr(o->duty_iq[x], t1pr);
            cmpr_up[x] = c;
            cmpr_dn[x] = c;
            act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
        }
    }
}
