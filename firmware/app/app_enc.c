/*
 * app_enc.c - encoder plausibility (see app_enc.h).
 */
#include "app_enc.h"

/* The largest count change in one control period that is still plausible: N with N * k <= 2 *
 * speed limit, k = pu speed of one count per control period (speed_k * speed_div), found by
 * bisection on products (no division), and never below 1: a single count step is quantisation
 * and cannot be told from a real speed however short the period or coarse the encoder.
 * Scaling: N < 2^15 counts, N * k formed in 64 bits. */
static uint16_t enc_jump_counts(const dtc_config_t *cfg)
{
    const int64_t k = (int64_t)cfg->speed.speed_k_iq * (int64_t)cfg->speed.speed_div;
    const int64_t jump = 2 * (int64_t)cfg->speed.speed_limit_iq;
    uint32_t lo = 0U, hi = (uint32_t)cfg->board.enc_counts / 2U + 1U; /* lo fits, hi does not (or is max) */
    while (hi - lo > 1U) {
        const uint32_t mid = (lo + hi) / 2U;
        if ((int64_t)mid * k <= jump) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return (uint16_t)(lo < 1U ? 1U : lo);
}

void app_enc_init(app_enc_t *e, const dtc_config_t *cfg)
{
    e->jump_counts = enc_jump_counts(cfg);
    e->last = 0U;
    e->index_ref = 0U;
    app_enc_reset(e);
}

/* Encoder plausibility:
 *  1. the count change of one period must stay within jump_counts (twice the speed limit,
 *     at least one count) (detail 1; a count outside 0 .. enc_counts-1 likewise);
 *  2. the counter value latched by each index pulse (hal_meas_t.qep_index_count, the capture unit)
 *     must equal the one latched by the first pulse within APP_INDEX_TOL_COUNTS: lost or extra
 *     counts show up as that difference, at whatever speed (detail 2);
 *  3. a lost signal (cable, supply: the counter stops) is a count that does not move for
 *     APP_ENC_FREEZE_PERIODS while the last measured speed is above prot.enc_freeze_speed_iq,
 *     which the host sets where the rotor turns several counts in that time even at the drive's
 *     largest deceleration: physically impossible, so the signal is gone (detail 3).
 * Scaling and overflow: |delta| <= counts/2 (<= 32768), compared as integers. */
int16_t app_enc_check(app_enc_t *e, const dtc_config_t *cfg, const hal_meas_t *m, iq_t speed_iq)
{
    const uint16_t counts = cfg->board.enc_counts;
    int32_t d;

    if (e->primed == 0U) {
        e->last = m->qep_count;
        e->primed = 1U;
        d = 0;
    } else {
        d = app_enc_fold((int32_t)m->qep_count - (int32_t)e->last, counts);
        e->last = m->qep_count;
        if (fix_abs32(d) > (int32_t)e->jump_counts) {
            return 1;
        }
        if (d != 0) {
            e->still_n = 0U;
        } else if (e->still_n < 0xFFFFU) {
            e->still_n++;
        }
        if (cfg->prot.enc_freeze_speed_iq > 0 && e->still_n >= APP_ENC_FREEZE_PERIODS &&
            fix_abs32(speed_iq) > cfg->prot.enc_freeze_speed_iq) {
            return 3;
        }
    }
    if (m->qep_count >= counts) {
        return 1;
    }
    if (m->qep_index_seen != 0U) {
        if (e->index_known == 0U) {
            e->index_ref = m->qep_index_count;
            e->index_known = 1U;
        } else {
            const int32_t x = app_enc_fold((int32_t)m->qep_index_count - (int32_t)e->index_ref, counts);
            if (fix_abs32(x) > (int32_t)APP_INDEX_TOL_COUNTS) {
                return 2;
            }
        }
    }
    return 0;
}

int16_t app_enc_flux_check(app_enc_t *e, iq_t err_iq, iq_t tol_iq)
{
    if (fix_abs32(err_iq) <= tol_iq) {
        e->flux_n = 0U;
        return 0;
    }
    if (++e->flux_n < APP_ENC_FLUX_PERIODS) {
        return 0;
    }
    return (int16_t)(err_iq < 0 ? -1 : 1);
}
