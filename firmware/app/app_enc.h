/*
 * app_enc.h - encoder plausibility for the application core (app_core.h): the current-model
 * estimator and the speed loop rely on the count, so a count that jumps, an index pulse at
 * another count or a count that stands still where the rotor cannot is a fault (APP_FAULT_ENCODER,
 * its detail APP_ENC_DETAIL_LIST in app_fault.h).
 *
 * State: app_enc_t, owned by the caller, no static state.
 */
#ifndef APP_ENC_H
#define APP_ENC_H

#include <stdint.h>

#include "hal.h"
#include "law.h"

/* Lost encoder signal: periods without a count change (prot.enc_freeze_speed_iq). */
#define APP_ENC_FREEZE_PERIODS 32U
/* Index check: accepted difference between latched index counts (edge jitter, direction). */
#define APP_INDEX_TOL_COUNTS 4

typedef struct {
    uint16_t jump_counts; /* the largest plausible count change in one control period:
                           * twice the speed limit, and never below 1 count (quantisation) */
    uint16_t last;        /* count of the previous period */
    uint16_t primed;      /* 0: no previous count yet */
    uint16_t index_ref;   /* count latched by the first index pulse */
    uint16_t index_known;
    uint16_t still_n;     /* consecutive periods without a count change */
} app_enc_t;

/* Folds a counter difference into (-counts/2, counts/2] (counter runs 0 .. counts-1).
 * Scaling: |d| < counts + counts/2 on entry, int32. */
static inline int32_t app_enc_fold(int32_t d, uint16_t counts)
{
    const int32_t half = (int32_t)(counts >> 1);
    if (d > half) {
        d -= (int32_t)counts;
    } else if (d <= -half) {
        d += (int32_t)counts;
    }
    return d;
}

/* The largest plausible count change per period for cfg (app_enc.c); the checks restarted. */
void app_enc_init(app_enc_t *e, const dtc_config_t *cfg);

/* Restarts the checks: no previous count, no index seen, no still periods. */
static inline void app_enc_reset(app_enc_t *e)
{
    e->primed = 0U;
    e->index_known = 0U;
    e->still_n = 0U;
}

/* Checks the sample m against the previous ones, at the last reported speed speed_iq.
 * Returns 0 or the encoder fault's detail (1 jump, 2 index, 3 lost signal: app_enc.c). */
int16_t app_enc_check(app_enc_t *e, const dtc_config_t *cfg, const hal_meas_t *m, iq_t speed_iq);

#endif /* APP_ENC_H */
