/*
 * law.h - the application's one control-law entry point: the configuration's law (enum dtc_law)
 * chosen at init, one switch per call in the ISR path (DESIGN.md section 4).
 *
 *   DTC_LAW_PM_DTC  PM brushless AC machine, Hoang et al. 2011     firmware/dtc/dtc.h
 *   DTC_LAW_IM_DTC  induction machine, Casadei et al. 2006 DTC/DSC firmware/dtc/im_dtc.h; its SVM
 *                   schemes SFVC (im_sfvc.c) and DFOC (im_dfoc.c) and the DTC with DSVM
 *                   (im_dsvm.c), chosen by im_dtc_t.pwm_law
 *
 * Every law has the same shape (init, reset, step, shadow write, refs get) and shares the
 * measurement and output structs (dtc_meas_t, dtc_out_t) and the reference set (dtc_refs.h).
 * The laws' states share storage (a union): only the configured one is ever used.
 */
#ifndef LAW_H
#define LAW_H

#include <stdint.h>

#include "dtc.h"
#include "im_dtc.h"

typedef struct {
    uint16_t law; /* enum dtc_law, from the configuration */
    union {
        dtc_t pm;
        im_dtc_t im;
    } u;
} law_t;

/* Validates cfg and initialises its law. Returns DTC_OK or an enum dtc_err code; on error the
 * controller must not be stepped. */
int16_t law_init(law_t *l, const dtc_config_t *cfg);
void law_reset(law_t *l);
void law_step(law_t *l, const dtc_meas_t *m, dtc_out_t *o);
int16_t law_shadow_write(law_t *l, const dtc_refs_t *r);
void law_refs_get(const law_t *l, dtc_refs_t *r);
/* Live SSTP -> FSTP reconfiguration after leg `phase` failed (dtc.h dtc_reconfigure): the PM
 * law only; DTC_ERR_RECONFIG for the IM law (Casadei's tables are six-switch ones) and for a
 * post that dtc_reconfigure refuses. */
int16_t law_reconfigure(law_t *l, const dtc_config_t *post, uint16_t phase);
/* The phase currents (IQ pu, the law's phase order) the law predicts for the next sample from the
 * voltage it committed for the coming period (PM law with the actuation-delay compensation:
 * dtc.c dtc_predict). Returns 1 and fills i1[0..2], or 0 where the law makes no prediction (the
 * app's sensor plausibility, app_plaus.h, then rests). */
uint16_t law_i_pred(const law_t *l, iq_t i1[3]);
/* The speed reference in force (the app's stall check). */
iq_t law_speed_ref(const law_t *l);

#endif /* LAW_H */
