/*
 * law.h - the application's one entry to the control laws: the configuration's law (enum
 * dtc_law) chosen at init, one switch per call (DESIGN.md section 4). The application reaches a
 * law only through this header.
 *
 *   DTC_LAW_PM_DTC   PM brushless AC machine, DTC of Hoang et al. 2011   firmware/dtc/dtc.h
 *   DTC_LAW_IM_DTC   induction machine, Casadei et al. 2006: DTC          firmware/dtc/im_dtc.h
 *   DTC_LAW_IM_DSC   DSC (section 9)                                      im_dtc.c, dsc.h
 *   DTC_LAW_IM_SFVC  stator-flux vector control with SVM (10.3-10.5)      im_sfvc.c
 *   DTC_LAW_IM_DFOC  rotor-flux-oriented control (section 13)             im_dfoc.c
 *   DTC_LAW_IM_DSVM  DTC with discrete SVM (section 11)                   im_dsvm.c
 *   DTC_LAW_PM_ITC   PM indirect torque control (Hoang Figs. 5-8 (a))     firmware/dtc/itc.h
 *
 * Every law has the same shape: a check of its configuration part (error codes naming the field),
 * init, reset, step, and the form of its command (enum law_out_form), fixed by the law; each
 * keeps its reference set in force `act` and its shadow set `sh` (dtc_refs.h), which
 * law_shadow_write and law_refs_get reach; law.c dispatches each call with one switch on the law law_init accepted
 * (DESIGN.md section 4: at most a switch in the ISR path, no function pointers there). The laws share the
 * measurement and output structs (law_io.h) and the reference set (dtc_refs.h). Their states share storage (a union): only the configured one is used. Only
 * the laws linked into the image (firmware/CMakeLists.txt DTC_LAWS: DTC_LAW_PM_LINKED,
 * DTC_LAW_IM_LINKED, DTC_LAW_ITC_LINKED) exist here; a configuration of another is refused with
 * DTC_ERR_VARIANT.
 *
 * Adding a law: its value in enum dtc_law, its configuration part (a header like pm_dtc_cfg.h)
 * in dtc_config_t.u, its module with the functions above, its case in each switch of law.c; on
 * the host its converter part and scenario keys (docs/firmware-core.md, "Adding a control law").
 */
#ifndef LAW_H
#define LAW_H

#include <stdint.h>

#include "dtc_config.h"
#include "dtc_refs.h"
#include "law_io.h"
#if DTC_LAW_PM_LINKED
#include "dtc.h"
#endif
#if DTC_LAW_IM_LINKED
#include "im_dtc.h"
#endif
#if DTC_LAW_ITC_LINKED
#include "itc.h"
#endif

typedef struct {
    uint16_t law;          /* enum dtc_law, from the configuration once law_init accepted it
                            * (0xFFFF after a refused one: no law runs) */
    uint16_t step;         /* law_step's dispatch key: law, or the IM DTC's four-switch step
                            * (law.c), set with law */
    union {
#if DTC_LAW_PM_LINKED
        dtc_t pm;
#endif
#if DTC_LAW_IM_LINKED
        im_dtc_t im;
#endif
#if DTC_LAW_ITC_LINKED
        itc_t itc;
#endif
    } u;
} law_t;

/* The check of cfg by its law's module (the common part, then the law's part): DTC_OK or an enum
 * dtc_err code, *field (if not null) naming the field ("" on DTC_OK). DTC_ERR_VARIANT ("law")
 * for a law not linked into the image. Pure, init only. */
int16_t law_check(const dtc_config_t *cfg, const char **field);
/* Checks cfg and initialises its law. Returns DTC_OK or an enum dtc_err code; on error the
 * controller must not be stepped. */
int16_t law_init(law_t *l, const dtc_config_t *cfg);
void law_reset(law_t *l);
void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o);
int16_t law_shadow_write(law_t *l, const dtc_refs_t *r);
void law_refs_get(const law_t *l, dtc_refs_t *r);
/* The form of the law's command (enum law_out_form), the law's from law_init on. Inline: the
 * ISR asks it every period (app_core.c), one switch on the law and no call. */
static inline uint16_t law_out_form(const law_t *l)
{
    switch (l->law) {
    case DTC_LAW_IM_SFVC:
    case DTC_LAW_IM_DFOC:
    case DTC_LAW_PM_ITC: return LAW_OUT_DUTY;
    case DTC_LAW_IM_DSVM: return LAW_OUT_THIRDS;
    default: return LAW_OUT_LEGS;
    }
}
/* Live SSTP -> FSTP reconfiguration after leg `phase` failed: the PM law (dtc.h dtc_reconfigure)
 * and the IM switching-table DTC (im_dtc.h im_dtc_reconfigure, Hoang Table II on the FSTP);
 * DTC_ERR_RECONFIG for the other laws (DSC, DSVM and the SVM schemes are six-switch ones) and for
 * a post the law refuses. */
int16_t law_reconfigure(law_t *l, const dtc_config_t *post, uint16_t phase);
/* The phase currents (IQ pu, the law's phase order) the law predicts for the next sample from the
 * voltage it committed for the coming period (PM law with the actuation-delay compensation:
 * dtc.c dtc_predict; the IM laws: im_dtc.h im_dtc_i_pred, with vdc_iq the link voltage measured
 * at this sample). Returns 1 and fills i1[0..2], or 0 where the law makes no prediction (the
 * app's sensor plausibility, app_plaus.h, then rests). After law_step only. */
uint16_t law_i_pred(const law_t *l, iq_t vdc_iq, iq_t i1[3]);
/* The encoder plausibility's comparison of this step (IM laws with the encoder and
 * u.im.ref.enc_plaus_iq > 0, im_dtc.h): returns 1 on a speed-loop step where the rotor flux is
 * built, with *err_iq the sensorless speed (Casadei eqs. 16, 22) less the encoder's speed through
 * the same filter and *tol_iq the largest credible difference (pu electrical speed); 0 where the
 * law compares nothing (PM laws, sensorless, off, other steps). Inline: the ISR asks it every
 * period (app_core.c check_speed), a PM image then tests nothing. */
static inline uint16_t law_enc_plaus(const law_t *l, iq_t *err_iq, iq_t *tol_iq)
{
#if DTC_LAW_IM_LINKED
    if (dtc_law_is_im(l->law) != 0U) {
        *err_iq = l->u.im.plaus_err_iq;
        *tol_iq = l->u.im.cfg->u.im.ref.enc_plaus_iq;
        return l->u.im.plaus_on;
    }
#else
    (void)l;
#endif
    (void)err_iq;
    (void)tol_iq;
    return 0U;
}
/* The warnings the law raises now (bits APP_WARN_<id>, app_warn.h): the IM laws' model supervision
 * (im_sup.h: APP_WARN_IM_MODEL_MISMATCH); 0 for the PM laws. */
uint16_t law_warnings(const law_t *l);
/* The check of a post-fault configuration for law_reconfigure (its law's check: the PM DTC's or
 * the IM DTC's; DTC_ERR_RECONFIG for another law). */
int16_t law_check_reconfig(const dtc_config_t *post);
/* The speed reference in force (the app's stall check). */
iq_t law_speed_ref(const law_t *l);
/* Where the law holds it (the capture reads it there), NULL for a law not initialised. */
const iq_t *law_speed_ref_ptr(const law_t *l);
/* Encoder count -> electrical angle with the configuration's encoder gain and offset (flux_est.h
 * flux_est_angle), for the application's rotor hold. */
angle_t law_enc_angle(const dtc_config_t *cfg, uint16_t count);
/* The compare values and polarity of the three legs (hal.h HAL_CMD_PWM: cmpr_up, cmpr_dn, act)
 * for a command o of the PWM form `form` (LAW_OUT_DUTY: svm.h svm_cmpr; LAW_OUT_THIRDS: dsvm.h
 * dsvm_pwm) at the PWM period t1pr. */
void law_pwm(uint16_t form, const dtc_out_t *o, uint16_t t1pr, uint16_t cmpr_up[3], uint16_t cmpr_dn[3],
             uint16_t act[3]);

#endif /* LAW_H */
