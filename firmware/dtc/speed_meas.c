#include "speed_meas.h"

void speed_meas_init(speed_meas_t *s, const speed_meas_params_t *p, uint16_t count_now)
{
    s->p = p;
    speed_meas_reset(s, count_now);
}

void speed_meas_reset(speed_meas_t *s, uint16_t count_now)
{
    uint16_t k;
    for (k = 0U; k < DTC_SPEED_RING; k++) {
        s->ring[k] = 0U;
    }
    s->head = 0U;
    s->fill = 1U;
    s->last_count = count_now;
    s->pos = 0U;
    s->win_log2 = 0U;
    s->speed_iq = 0;
}

iq_t speed_meas_step(speed_meas_t *s, uint16_t count_now)
{
    const speed_meas_params_t *p = s->p;
    int32_t d = (int32_t)count_now - (int32_t)s->last_count;
    int32_t half = (int32_t)(p->enc_counts >> 1);
    uint16_t m;
    int16_t diff = 0;

    /* Fold the raw difference across the counter's wrap at enc_counts. */
    if (d > half) {
        d -= (int32_t)p->enc_counts;
    } else if (d <= -half) {
        d += (int32_t)p->enc_counts;
    }
    s->last_count = count_now;
    s->pos = (uint16_t)(s->pos + (uint16_t)(uint32_t)d); /* modulo 2^16 by design */
    s->head = (uint16_t)((s->head + 1U) & (DTC_SPEED_RING - 1U));
    s->ring[s->head] = s->pos;
    if (s->fill < DTC_SPEED_RING) {
        s->fill++;
    }

    s->win_log2 = 0U;
    /* Shortest power-of-two window with at least min_counts counts (or the longest held). */
    for (m = 0U; m <= DTC_SPEED_WIN_LOG2_MAX; m++) {
        uint16_t n = (uint16_t)(1U << m);
        uint16_t old;
        if (n >= s->fill) {
            break; /* window longer than the history */
        }
        old = s->ring[(uint16_t)((s->head - n) & (DTC_SPEED_RING - 1U))];
        diff = (int16_t)(uint16_t)(s->pos - old); /* window difference modulo 2^16 */
        s->win_log2 = m;
        if ((diff >= 0 ? (int32_t)diff : -(int32_t)diff) >= (int32_t)p->min_counts) {
            break;
        }
    }
    /* diff * k_speed / 2^m; the rounding shift helper needs a shift >= 1, so the exact product
     * is doubled (< 2^48) and shifted by m + 1. */
    s->speed_iq = fix_rshift_rnd64_sat32((int64_t)diff * (int64_t)p->k_speed_iq * 2,
                                         (uint16_t)(s->win_log2 + 1U));
    return s->speed_iq;
}
