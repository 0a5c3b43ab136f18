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

#include "fixmath.h"

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

/* Nothing published, nothing adopted. */
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

#endif /* DTC_REFS_H */
