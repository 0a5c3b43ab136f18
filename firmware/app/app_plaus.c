#include "app_plaus.h"

#include <stddef.h>

/* IQ24 -> IQ16, rounded (the change of two saturated values, |x| < 2^32). */
static int32_t to_q16(iq_t x)
{
    return fix_rshift_rnd32(x, 8U);
}

void app_plaus_reset(app_plaus_t *s)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        s->i_prev[k] = 0;
        s->i1_prev[k] = 0;
        s->sums[0].s_m[k] = 0;
        s->sums[0].s_p[k] = 0;
        s->sums[0].s_mp[k] = 0;
        s->sums[0].s_pp[k] = 0;
        s->sums[1].s_m[k] = 0;
        s->sums[1].s_p[k] = 0;
        s->sums[1].s_mp[k] = 0;
        s->sums[1].s_pp[k] = 0;
        s->bias[k] = 0;
    }
    s->acc = &s->sums[0];
    s->held = &s->sums[1];
    s->primed = 0U;
    s->n = 0U;
    s->pend = 0U;
    s->due = 0U;
    s->judged = 0U;
}

/* The judgement of the full window w (app_plaus.h app_plaus_step), its sums cleared for a later
 * window. */
static uint16_t plaus_judge(app_plaus_t *s, app_plaus_sums_t *w, const app_plaus_params_t *p, uint16_t measured)
{
    uint16_t bad = 0U, still = 0U, k;
    for (k = 0U; k < 3U; k++) {
        if ((measured & (uint16_t)(1U << k)) == 0U) {
            continue;
        }
        /* N^2 cov(d_m, d_p) and N^2 var(d_p), N = 2^win_log2 */
        const int64_t cov = w->s_mp[k] * (int64_t)(1U << p->win_log2) - (int64_t)w->s_m[k] * w->s_p[k];
        const int64_t var = w->s_pp[k] * (int64_t)(1U << p->win_log2) - (int64_t)w->s_p[k] * w->s_p[k];
        const uint16_t raw_bad = (uint16_t)(w->s_pp[k] > p->floor_raw && 4 * w->s_mp[k] < w->s_pp[k]);
        const uint16_t follows = (uint16_t)(var > p->floor_var && 4 * cov >= var);
        if (raw_bad != 0U && follows == 0U) {
            bad |= (uint16_t)(1U << k);
            if (16 * w->s_mp[k] < w->s_pp[k] && -16 * w->s_mp[k] < w->s_pp[k]) {
                still |= (uint16_t)(1U << k);
            }
        }
        /* cleared for a later window (an unmeasured channel's sums stay zero) */
        w->s_m[k] = 0;
        w->s_p[k] = 0;
        w->s_mp[k] = 0;
        w->s_pp[k] = 0;
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
    app_plaus_sums_t *const w = s->acc;

    s->judged = 0U;
    if (s->due != 0U) {
        if (hold == 0U || s->due >= 2U) {
            /* the held window, before this sample: at the first call out of the held periods, or
             * the second call after it ended */
            bad = plaus_judge(s, s->held, p, measured);
            s->due = 0U;
            s->judged = APP_PLAUS_JUDGED_HELD;
        } else {
            s->due++;
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
            w->s_m[k] += dm;
            w->s_p[k] += dp;
            w->s_mp[k] += (int64_t)dm * dp;
            w->s_pp[k] += (int64_t)dp * dp;
        }
        if (++s->n >= (uint16_t)(1U << p->win_log2)) {
            s->n = 0U;
            if (hold != 0U) {
                /* held (N >= 2: the window held before is judged by now, which cleared its
                 * sums): set aside for the judgement, the next window collects in the other */
                s->acc = s->held;
                s->held = w;
                s->due = 1U;
            } else {
                bad |= plaus_judge(s, w, p, measured);
                s->judged |= APP_PLAUS_JUDGED_NOW;
            }
        }
    }
    if (i1 == NULL) {
        app_plaus_reset(s);
        return bad;
    }
    for (k = 0U; k < 3U; k++) {
        s->i_prev[k] = i[k];
        s->i1_prev[k] = i1[k];
    }
    s->primed = 1U;
    return bad;
}
