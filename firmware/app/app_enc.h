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
/* Encoder against the flux speed: consecutive speed-loop periods over the tolerance before the
 * trip (the sensorless speed's ripple never holds that long beyond it). */
#define APP_ENC_FLUX_PERIODS 4U
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
    uint16_t flux_n;      /* consecutive compared speed periods over the flux-speed tolerance */
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

/* The count as the drive uses it: with board.enc_reversed, m's counter and index capture read
 * enc_counts - 1 - count (a bijection of 0 .. enc_counts - 1 that keeps the index semantics: a
 * forward crossing latches 0), into out; a count outside the range is left as read (app_enc_check
 * names it). Subtractions only (the 50 us path). */
static inline void app_enc_reverse(const dtc_config_t *cfg, const hal_meas_t *m, hal_meas_t *out)
{
    const uint16_t last = (uint16_t)(cfg->board.enc_counts - 1U);
    *out = *m;
    if (m->qep_count <= last) {
        out->qep_count = (uint16_t)(last - m->qep_count);
    }
    if (m->qep_index_count <= last) {
        out->qep_index_count = (uint16_t)(last - m->qep_index_count);
    }
}

/* The largest plausible count change per period for cfg (app_enc.c); the checks restarted. */
void app_enc_init(app_enc_t *e, const dtc_config_t *cfg);

/* Restarts the checks: no previous count, no index seen, no still periods. */
static inline void app_enc_reset(app_enc_t *e)
{
    e->primed = 0U;
    e->index_known = 0U;
    e->still_n = 0U;
    e->flux_n = 0U;
}

/* Checks the sample m against the previous ones, at the last reported speed speed_iq.
 * Returns 0 or the encoder fault's detail (1 jump, 2 index, 3 lost signal: app_enc.c). */
int16_t app_enc_check(app_enc_t *e, const dtc_config_t *cfg, const hal_meas_t *m, iq_t speed_iq);

/* The encoder against the speed of the estimated flux (IM laws: law.h law_enc_plaus, im_dtc.h):
 * on each compared speed-loop period, err_iq the sensorless speed (the rotor-flux angular speed
 * less the slip of Casadei eq. 16) minus the encoder's speed through the same filter, tol_iq the
 * largest credible difference the host derived from the machine (the slip at the torque limit,
 * the speed period's delay at the largest acceleration). A difference beyond it for
 * APP_ENC_FLUX_PERIODS compared periods in a row is a failed encoder: lost during the
 * magnetisation (the count stands still at zero, where the freeze check cannot see it, while the
 * speed loop accelerates the rotor), slipping, or reading another shaft. Returns 0, or the sign of
 * err_iq (-1, 1) on a trip. Scaling: |err_iq| compared as a saturated int32. */
int16_t app_enc_flux_check(app_enc_t *e, iq_t err_iq, iq_t tol_iq);

#endif /* APP_ENC_H */
