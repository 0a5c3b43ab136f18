#include "app_plaus.h"

#include <stddef.h>

/* IQ24 -> IQ16, rounded (the change of two saturated values, |x| < 2^32). */
static int32_t to_q16(iq_t x)
{
    return fix_rshift_rnd32(x, 8U);
}

void app_plaus_init(app_plaus_params_t *p, iq_t adc_i_gain_iq)
{
    const int64_t f = (int64_t)to_q16(fix_sat32((int64_t)adc_i_gain_iq * APP_PLAUS_FLOOR_COUNTS));
    p->floor_q32 = (f * f) << APP_PLAUS_WIN_LOG2;
}

void app_plaus_reset(app_plaus_t *s)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        s->i_prev[k] = 0;
        s->i1_prev[k] = 0;
        s->s_mp[k] = 0;
        s->s_pp[k] = 0;
    }
    s->primed = 0U;
    s->n = 0U;
}

int16_t app_plaus_step(app_plaus_t *s, const app_plaus_params_t *p, const iq_t i[3], const iq_t *i1,
                       uint16_t measured)
{
    int16_t bad = -1;
    uint16_t k;

    if (s->primed != 0U) {
        for (k = 0U; k < 3U; k++) {
            const int64_t dm = (int64_t)to_q16(fix_sub32(i[k], s->i_prev[k]));
            const int64_t dp = (int64_t)to_q16(fix_sub32(s->i1_prev[k], s->i_prev[k]));
            s->s_mp[k] += dm * dp;
            s->s_pp[k] += dp * dp;
        }
        if (++s->n >= (uint16_t)(1U << APP_PLAUS_WIN_LOG2)) {
            for (k = 0U; k < 3U; k++) {
                if ((measured & (uint16_t)(1U << k)) != 0U && s->s_pp[k] > p->floor_q32 &&
                    4 * s->s_mp[k] < s->s_pp[k] && bad < 0) {
                    bad = (int16_t)k;
                }
                s->s_mp[k] = 0;
                s->s_pp[k] = 0;
            }
            s->n = 0U;
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
