/*
 * dtc_refs.h - the background-changeable reference set of every control law, and the shadow set
 * through which the background hands a new one to the ISR (DESIGN.md section 3). Shared by the
 * laws (dtc.h, im_dtc.h): each law adopts a set at the top of its step with its own limits.
 *
 * Protocol (a sequence lock for one writer that the ISR can preempt, on a single core): the
 * writer makes the sequence number odd, writes the fields, makes it even again; the ISR adopts
 * only an even sequence number it has not adopted yet, so it never sees half a set (if it
 * preempts a write it keeps the old set for one more period). All shared fields are volatile.
 */
#ifndef DTC_REFS_H
#define DTC_REFS_H

#include <stdint.h>

#include "dtc_config.h"
#include "fixmath.h"
#include "flux_est.h"
#include "speed_meas.h"
#include "speed_pi.h"
#include "vcomp.h"

/* The background-changeable parameter set. */
typedef struct {
    iq_t speed_ref_iq;  /* clamped to +-speed_limit on adoption */
    iq_t torque_ref_iq; /* torque mode; clamped to +-torque_limit on adoption */
    iq_t flux_ref_iq;   /* > 0 */
    iq_t kp_iq;         /* >= 0 */
    iq_t ki_ts_iq;      /* >= 0 */
    uint16_t mode;      /* enum dtc_mode */
} dtc_refs_t;

typedef struct {
    volatile uint16_t seq;  /* odd while the background writes */
    uint16_t adopted;       /* the sequence number the ISR adopted last */
    volatile iq_t speed_ref_iq, torque_ref_iq, flux_ref_iq, kp_iq, ki_ts_iq;
    volatile uint16_t mode;
} dtc_shadow_t;

/* DTC_OK, or DTC_ERR_VARIANT (mode), DTC_ERR_PI (negative gain), DTC_ERR_REFERENCE (flux <= 0). */
int16_t dtc_refs_check(const dtc_refs_t *r);

/* Nothing published, nothing adopted. Init only (dtc_refs_init.c). */
void dtc_shadow_init(dtc_shadow_t *s);

/* Background: publishes r (checked first; a refused set is not published). Returns DTC_OK or the
 * dtc_refs_check code. */
int16_t dtc_shadow_publish(dtc_shadow_t *s, const dtc_refs_t *r);

/* ISR: the sequence number of a complete set not adopted yet, or 0 when there is none (0 is
 * never such a number: it is the initial, adopted one). */
static inline uint16_t dtc_shadow_pending(const dtc_shadow_t *s)
{
    const uint16_t seq = s->seq;
    return (uint16_t)((seq & 1U) == 0U && seq != s->adopted ? seq : 0U);
}

/* ISR: copies the set of sequence number seq (from dtc_shadow_pending) into r and marks it
 * adopted. */
void dtc_shadow_take(dtc_shadow_t *s, uint16_t seq, dtc_refs_t *r);

/* Torque mode, every law: the mean-torque trim (dtc.c dtc_torque_trim explains why it exists).
 * trim += k (T* - T_est), limited to +-limit/4; returns T* + trim limited to +-limit.
 * Scaling and overflow: the error is IQ pu, times a Q15 gain < 1; the sums saturate and are
 * clamped (limit > 0, validated). */
iq_t dtc_trim_step(iq_t *trim_iq, iq_t ref_iq, iq_t te_iq, q15_t k_q15, iq_t limit_iq);

/* The reference set a configuration starts with (its initial references, gains and mode). Init
 * and background only (dtc_refs_init.c). */
void dtc_refs_from_config(dtc_refs_t *r, const dtc_config_t *cfg);

/* Every law's init: *r the configuration's set (dtc_refs_from_config) and act->mode its mode, so
 * that the law's adoption of *r that follows is no change of mode (no PI preload, the trim kept);
 * the shadow empty (dtc_shadow_init). Init only (dtc_refs_init.c). */
void dtc_refs_start(dtc_refs_t *act, dtc_shadow_t *sh, dtc_refs_t *r, const dtc_config_t *cfg);

/* Every law: makes r the set in force (*act): the speed and torque references clamped to the
 * configured limits, the speed-PI gains into *pi_p; a change to speed mode preloads the PI with
 * te_now_iq, the torque applied now (bumpless); any change of mode clears the mean-torque trim. */
/* (Inline: it runs in the ISR on the shadow-adoption path, the deepest stack chain of a step, so
 * it must not add a call frame there.) */
static inline void dtc_refs_adopt(dtc_refs_t *act, speed_pi_params_t *pi_p, speed_pi_t *pi, iq_t *trim_iq,
                    iq_t te_now_iq, const dtc_refs_t *r, const dtc_config_t *cfg)
{
    const uint16_t old_mode = act->mode;

    act->speed_ref_iq = iq_sat(r->speed_ref_iq, fix_neg32(cfg->speed.speed_limit_iq),
                               cfg->speed.speed_limit_iq);
    act->torque_ref_iq = iq_sat(r->torque_ref_iq, fix_neg32(cfg->speed.torque_limit_iq),
                                cfg->speed.torque_limit_iq);
    act->flux_ref_iq = r->flux_ref_iq;
    act->kp_iq = r->kp_iq;
    act->ki_ts_iq = r->ki_ts_iq;
    act->mode = r->mode;
    pi_p->kp_iq = r->kp_iq;
    pi_p->ki_ts_iq = r->ki_ts_iq;
    if (old_mode != DTC_MODE_SPEED && r->mode == DTC_MODE_SPEED) {
        speed_pi_reset(pi, te_now_iq, cfg->speed.torque_limit_iq); /* bumpless */
    }
    if (old_mode != r->mode) {
        *trim_iq = 0;
    }
}

/* Every law: the speed measurement's and the speed PI's parameters from the configuration. */
void dtc_speed_params_from_config(speed_meas_params_t *sm_p, speed_pi_params_t *pi_p,
                                  const dtc_config_t *cfg);

/* The PM laws (DTC, ITC): the stator-flux estimator's and the drop compensation's parameters from
 * the common part of cfg and the law's machine model mach (its part's l_s and psi_m). Defined in
 * dtc_init.c, a PM member of the init-only archive, so that an image without a PM law links none
 * of it and an image with one runs it from flash. */
void dtc_pm_est_params_from_config(flux_est_params_t *fe_p, vcomp_params_t *vc_p, const dtc_config_t *cfg,
                                   const dtc_pm_machine_cfg_t *mach);

#endif /* DTC_REFS_H */
