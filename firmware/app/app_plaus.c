#include "app_plaus.h"

#include <stddef.h>

/* IQ24 -> IQ16, rounded (the change of two saturated values, |x| < 2^32). */
static int32_t to_q16(iq_t x)
{
    return fix_rshift_rnd32(x, 8U);
}

/* Channel k's window sums zeroed (a window judged, or the reset). */
static void plaus_sums_clear(app_plaus_t *s, uint16_t k)
{
    s->s_m[k] = 0;
    s->s_p[k] = 0;
    s->s_mp[k] = 0;
    s->s_pp[k] = 0;
}

void app_plaus_reset(app_plaus_t *s)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        s->i_prev[k] = 0;
        s->i1_prev[k] = 0;
        plaus_sums_clear(s, k);
        s->bias[k] = 0;
    }
    s->primed = 0U;
    s->n = 0U;
    s->pend = 0U;
    s->due = 0U;
    s->judged = 0U;
}

/* The judgement of a full window (app_plaus.h app_plaus_step), its sums cleared for the next. */
static uint16_t plaus_judge(app_plaus_t *s, const app_plaus_params_t *p, uint16_t measured)
{
    uint16_t bad = 0U, still = 0U, k;
    for (k = 0U; k < 3U; k++) {
        if ((measured & (uint16_t)(1U << k)) == 0U) {
            continue;
        }
        /* N^2 cov(d_m, d_p) and N^2 var(d_p), N = 2^win_log2 */
        const int64_t cov = s->s_mp[k] * (int64_t)(1U << p->win_log2) - (int64_t)s->s_m[k] * s->s_p[k];
        const int64_t var = s->s_pp[k] * (int64_t)(1U << p->win_log2) - (int64_t)s->s_p[k] * s->s_p[k];
        const uint16_t raw_bad = (uint16_t)(s->s_pp[k] > p->floor_raw && 4 * s->s_mp[k] < s->s_pp[k]);
        const uint16_t follows = (uint16_t)(var > p->floor_var && 4 * cov >= var);
        if (raw_bad != 0U && follows == 0U) {
            bad |= (uint16_t)(1U << k);
            if (16 * s->s_mp[k] < s->s_pp[k] && -16 * s->s_mp[k] < s->s_pp[k]) {
                still |= (uint16_t)(1U << k);
            }
        }
        plaus_sums_clear(s, k);
    }
    if (still != 0U) {
        s->pend = 0U;
        return still;
    }
    /* none stood still: reported only on a second failed window in a row */
    {
        const uint16_t first = (uint16_t)(s->pend == 0U ? 1U : 0U);
        s->pend = bad;
        return first != 0U ? 0U : bad;
    }
}

uint16_t app_plaus_step(app_plaus_t *s, const app_plaus_params_t *p, const iq_t i[3], const iq_t *i1,
                        uint16_t measured, uint16_t hold)
{
    uint16_t bad = 0U;
    uint16_t k;

    s->judged = 0U;
    if (s->due != 0U) {
        if (hold == 0U || s->due >= 2U) {
            /* the held window, before this sample: at the first call out of the held periods, or
             * the second call after it ended */
            bad = plaus_judge(s, p, measured);
            s->judged = APP_PLAUS_JUDGED_HELD;
            if (s->due >= 2U) {
                /* the sample that waited is the next window's first (the sums were just cleared;
                 * the same bounds as below) */
                for (k = 0U; k < 3U; k++) {
                    if ((measured & (uint16_t)(1U << k)) != 0U) {
                        s->s_m[k] += s->wait_dm[k];
                        s->s_p[k] += s->wait_dp[k];
                        s->s_mp[k] += (int64_t)s->wait_dm[k] * s->wait_dp[k];
                        s->s_pp[k] += (int64_t)s->wait_dp[k] * s->wait_dp[k];
                    }
                }
                s->n = 1U;
            }
            s->due = 0U;
        } else {
            s->due = 2U; /* this sample waits (below) */
        }
    }
    if (s->primed != 0U) {
        /* Only the measured channels are judged, so only they accumulate: an unmeasured channel's
         * sums stay zero (app_plaus_reset; a change of the mask comes with a reset). */
        for (k = 0U; k < 3U; k++) {
            if ((measured & (uint16_t)(1U << k)) == 0U) {
                continue;
            }
            const int32_t dm = to_q16(fix_sub32(i[k], s->i_prev[k]));
            /* the predicted change less the model's bias learnt so far (app_plaus.h). Plain 32-bit
             * sums: |dm|, |dp0| <= 2^23 (a saturated difference shifted by 8), so |dp0 - dm| <=
             * 2^24; the bias, each step moved towards dp0 - dm by a rounded 2^-bias_log2 of the
             * distance (bias_log2 >= 1), which never passes it, stays within 2^24; every sum
             * below stays within 2^26 and none could saturate. */
            const int32_t dp0 = to_q16(fix_sub32(s->i1_prev[k], s->i_prev[k]));
            const int32_t dp = dp0 - s->bias[k];
            s->bias[k] += fix_rshift_rnd32(dp0 - dm - s->bias[k], p->bias_log2);
            if (i1 != NULL) {
                /* the next call's pair, here where this channel's is read last (the unmeasured
                 * channels' are never read) */
                s->i_prev[k] = i[k];
                s->i1_prev[k] = i1[k];
            }
            if (s->due != 0U) {
                s->wait_dm[k] = dm; /* due 2: the held window is not judged yet */
                s->wait_dp[k] = dp;
                continue;
            }
            s->s_m[k] += dm;
            s->s_p[k] += dp;
            s->s_mp[k] += (int64_t)dm * dp;
            s->s_pp[k] += (int64_t)dp * dp;
        }
        if (s->due == 0U && ++s->n >= (uint16_t)(1U << p->win_log2)) {
            s->n = 0U;
            if (hold != 0U) {
                s->due = 1U; /* judged at the start of a later call (N >= 2: before the next ends) */
            } else {
                bad |= plaus_judge(s, p, measured);
                s->judged |= APP_PLAUS_JUDGED_NOW;
            }
        }
    }
    if (i1 == NULL) {
        app_plaus_reset(s);
        return bad;
    }
    if (s->primed == 0U) {
        /* the first pair (a primed call kept it above): the measured channels', the only ones read */
        for (k = 0U; k < 3U; k++) {
            if ((measured & (uint16_t)(1U << k)) != 0U) {
                s->i_prev[k] = i[k];
                s->i1_prev[k] = i1[k];
            }
        }
        s->primed = 1U;
    }
    return bad;
}
