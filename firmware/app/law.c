#include "law.h"

#include <stddef.h>

#include "dsvm.h"
#include "flux_est.h"
#include "hal.h"
#include "svm.h"

/* The laws linked into this image (dtc_config.h: DTC_LAW_PM_LINKED, DTC_LAW_IM_LINKED from
 * DTC_LAWS): every law on the host and in SIL; one on the F2812, whose zero-wait RAM does not
 * hold both (hal/f2812/budget.sh). Only their tables exist below; a configuration of a law that
 * is not linked never gets past law_init (DTC_ERR_VARIANT). */

/* One table per law: its module's functions on the law's member of law_t.u, and its command's
 * form. law_init picks the table once from the configuration's law (the one switch on enum
 * dtc_law); every later call goes through it. */
struct law_ops {
    int16_t (*init)(law_t *l, const dtc_config_t *cfg);
    void (*reset)(law_t *l);
    void (*step)(law_t *l, const dtc_meas_t *m, dtc_out_t *o);
    int16_t (*shadow_write)(law_t *l, const dtc_refs_t *r);
    void (*refs_get)(const law_t *l, dtc_refs_t *r);
    iq_t (*speed_ref)(const law_t *l);
    uint16_t form; /* enum law_out_form */
};

#if DTC_LAW_PM_LINKED
static int16_t pm_init(law_t *l, const dtc_config_t *cfg) { return dtc_init(&l->u.pm, cfg); }
static void pm_reset(law_t *l) { dtc_reset(&l->u.pm); }
static void pm_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { dtc_step(&l->u.pm, m, o); }
static int16_t pm_shadow(law_t *l, const dtc_refs_t *r) { return dtc_shadow_write(&l->u.pm, r); }
static void pm_refs(const law_t *l, dtc_refs_t *r) { dtc_refs_get(&l->u.pm, r); }
static iq_t pm_speed_ref(const law_t *l) { return l->u.pm.act.speed_ref_iq; }
static const law_ops_t law_pm_dtc = {pm_init, pm_reset, pm_step, pm_shadow, pm_refs, pm_speed_ref, LAW_OUT_LEGS};
#endif

#if DTC_LAW_IM_LINKED
static int16_t im_init(law_t *l, const dtc_config_t *cfg) { return im_dtc_init(&l->u.im, cfg); }
static void im_reset(law_t *l) { im_dtc_reset(&l->u.im); }
static void im_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { im_dtc_step(&l->u.im, m, o); }
static void sfvc_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { im_sfvc_step(&l->u.im, m, o); }
static void dfoc_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { im_dfoc_step(&l->u.im, m, o); }
static void dsvm_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { im_dsvm_step(&l->u.im, m, o); }
static int16_t im_shadow(law_t *l, const dtc_refs_t *r) { return im_dtc_shadow_write(&l->u.im, r); }
static void im_refs(const law_t *l, dtc_refs_t *r) { im_dtc_refs_get(&l->u.im, r); }
static iq_t im_speed_ref(const law_t *l) { return l->u.im.act.speed_ref_iq; }
/* DTC and DSC share the step (im_dtc.c reads the law) */
static const law_ops_t law_im_dtc = {im_init, im_reset, im_step, im_shadow, im_refs, im_speed_ref, LAW_OUT_LEGS};
static const law_ops_t law_im_sfvc = {im_init, im_reset, sfvc_step, im_shadow, im_refs, im_speed_ref, LAW_OUT_DUTY};
static const law_ops_t law_im_dfoc = {im_init, im_reset, dfoc_step, im_shadow, im_refs, im_speed_ref, LAW_OUT_DUTY};
static const law_ops_t law_im_dsvm = {im_init, im_reset, dsvm_step, im_shadow, im_refs, im_speed_ref, LAW_OUT_THIRDS};
#endif

/* No law (a configuration refused at init): nothing runs. */
static int16_t none_init(law_t *l, const dtc_config_t *cfg)
{
    /* no law, or a law not linked: the common part's code if it has one, else the law's */
    const int16_t err = dtc_config_check_common(cfg, NULL);
    (void)l;
    return err != DTC_OK ? err : DTC_ERR_VARIANT;
}
static void none_reset(law_t *l) { (void)l; }
static void none_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o) { (void)l; (void)m; (void)o; }
static int16_t none_shadow(law_t *l, const dtc_refs_t *r) { (void)l; (void)r; return DTC_ERR_VARIANT; }
static void none_refs(const law_t *l, dtc_refs_t *r) { (void)l; (void)r; }
static iq_t none_speed_ref(const law_t *l) { (void)l; return 0; }
static const law_ops_t law_none = {none_init, none_reset, none_step, none_shadow, none_refs, none_speed_ref, LAW_OUT_LEGS};

/* The table of a law (the one switch on enum dtc_law): law_none for no law or one not linked. */
static const law_ops_t *law_ops_of(uint16_t law)
{
    switch (law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC: return &law_pm_dtc;
#endif
#if DTC_LAW_IM_LINKED
    case DTC_LAW_IM_DTC:
    case DTC_LAW_IM_DSC: return &law_im_dtc;
    case DTC_LAW_IM_SFVC: return &law_im_sfvc;
    case DTC_LAW_IM_DFOC: return &law_im_dfoc;
    case DTC_LAW_IM_DSVM: return &law_im_dsvm;
#endif
    default: return &law_none;
    }
}

int16_t law_init(law_t *l, const dtc_config_t *cfg)
{
    int16_t err;
    if (l == NULL || cfg == NULL) {
        return DTC_ERR_NULL;
    }
    l->law = cfg->law;
    l->ops = law_ops_of(cfg->law);
    err = l->ops->init(l, cfg);
    if (err != DTC_OK) {
        l->ops = &law_none;
    }
    return err;
}

void law_reset(law_t *l)
{
    l->ops->reset(l);
}

void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o)
{
    l->ops->step(l, m, o);
}

int16_t law_shadow_write(law_t *l, const dtc_refs_t *r)
{
    return l->ops->shadow_write(l, r);
}

void law_refs_get(const law_t *l, dtc_refs_t *r)
{
    l->ops->refs_get(l, r);
}

uint16_t law_i_pred(const law_t *l, iq_t i1[3])
{
#if DTC_LAW_PM_LINKED
    if (l->ops == &law_pm_dtc && l->u.pm.cfg->u.pm_dtc.est.delay_comp != 0U) {
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
    return l->ops->speed_ref(l);
}

uint16_t law_out_form(const law_t *l)
{
    return l->ops->form;
}

int16_t law_reconfigure(law_t *l, const dtc_config_t *post, uint16_t phase)
{
#if DTC_LAW_PM_LINKED
    if (l->law == (uint16_t)DTC_LAW_PM_DTC) {
        return dtc_reconfigure(&l->u.pm, post, phase);
    }
#else
    (void)post;
    (void)phase;
#endif
    (void)l;
    return DTC_ERR_RECONFIG;
}

int16_t law_check_reconfig(const dtc_config_t *post)
{
#if DTC_LAW_PM_LINKED
    return dtc_check(post, NULL);
#else
    (void)post;
    return DTC_ERR_RECONFIG;
#endif
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
