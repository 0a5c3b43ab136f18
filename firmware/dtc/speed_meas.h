/*
 * speed_meas.h - rotor speed from quadrature encoder counts, division-free, usable from
 * standstill-near speeds to full speed.
 *
 * The problem: 2000 lines x 4 edges = 8000 counts/turn. Over one speed period (10 x 50 us =
 * 500 us) one count is 1/8000 turn / 500 us = 15 rpm: at 100 rpm the plain difference is
 * 6.7 counts, a 15 % quantisation step, and the PI would chatter on it.
 *
 * The fix (an adaptive-window M method): the unwrapped position is stored every speed period
 * in a ring of DTC_SPEED_RING entries, and the speed is the count difference over the SHORTEST
 * power-of-two window N = 2^m (m = 0..DTC_SPEED_WIN_LOG2_MAX) that holds at least
 * speed_min_counts counts:
 *     w = (pos[n] - pos[n - N]) * k_speed / N,   k_speed = pu speed per count per speed period,
 * where "/ N" is an exact arithmetic shift by m (no division). With speed_min_counts = 100:
 *     1500 rpm: 100 counts per 500 us, N = 1, resolution 15 rpm = 1.0 % of the speed;
 *     150 rpm:  10 counts per 500 us, N = 16, 160 counts, resolution 0.94 rpm = 0.6 %;
 *     100 rpm:  6.7 counts per 500 us, N = 16 (8 ms), 107 counts, resolution 0.94 rpm = 0.94 %.
 * The quantisation is below 1/min_counts of the speed everywhere the longest window suffices
 * (down to 94 rpm here); below that the 16-period window gives 0.94 rpm per count. The measured
 * speed is the mean over the window, i.e. delayed by (N-1)/2 speed periods: short at high speed
 * where the loop needs bandwidth, long only at low speed where the counts are scarce. Until the
 * ring has filled, only the windows it holds are used.
 *
 * Wrap handling: the raw counter runs 0 .. enc_counts-1; a per-period difference is folded into
 * (-enc_counts/2, enc_counts/2] (valid below enc_counts/2 counts per speed period, i.e. 60000 rpm
 * here) and accumulated in a uint16_t position that wraps modulo 2^16 by design; window
 * differences are taken modulo 2^16 and read as int16 (valid for |delta| < 32768 counts per
 * window: 4096 counts per speed period or 30000 rpm with N = 16).
 *
 * Formats: speed IQ pu; k_speed IQ. Scaling and overflow: delta * k_speed is formed in 64 bits
 * (< 2^47) and shifted with rounding (fix_rshift_rnd64_sat32), saturating at +-128 pu.
 */
#ifndef SPEED_MEAS_H
#define SPEED_MEAS_H

#include <stdint.h>

#include "dtc_config.h"
#include "fixmath.h"

typedef struct {
    uint16_t enc_counts;
    iq_t k_speed_iq;
    uint16_t min_counts;
} speed_meas_params_t;

typedef struct {
    const speed_meas_params_t *p;
    uint16_t ring[DTC_SPEED_RING]; /* unwrapped positions (mod 2^16) at the last speed periods */
    uint16_t head;                 /* index of the newest entry */
    uint16_t fill;                 /* entries written since reset (saturates at DTC_SPEED_RING) */
    uint16_t last_count;           /* raw counter at the last speed period */
    uint16_t pos;                  /* unwrapped position */
    uint16_t win_log2;             /* window used by the last estimate (for logging/tests) */
    iq_t speed_iq;
} speed_meas_t;

void speed_meas_init(speed_meas_t *s, const speed_meas_params_t *p, uint16_t count_now);
/* Forget the history; count_now becomes the reference position, the speed is 0. */
void speed_meas_reset(speed_meas_t *s, uint16_t count_now);
/* One speed period: returns the new speed estimate (also in s->speed_iq). */
iq_t speed_meas_step(speed_meas_t *s, uint16_t count_now);

/* The speed loop's divider, shared by every law: the loop runs in the first step of each group of
 * speed_div steps. speed_loop_due() is called once per step before the law's speed work: it returns
 * 1 in a speed-loop step (*div_cnt == 0) and 0 otherwise; the very first step after a reset
 * (*primed == 0) takes count_now as the encoder reference and returns 0. The law's reset clears
 * *primed and *div_cnt together, so *div_cnt != 0 (nine steps of ten) answers at once.
 * speed_loop_advance() is called once per step after it and counts *div_cnt modulo speed_div
 * (speed_div >= 1, checked at init). Inline: the 50 us path pays for no call. */
static inline uint16_t speed_loop_due(speed_meas_t *s, uint16_t *primed, uint16_t *div_cnt, uint16_t count_now)
{
    if (*div_cnt != 0U) {
        return 0U;
    }
    if (*primed == 0U) {
        speed_meas_reset(s, count_now);
        *primed = 1U;
        return 0U;
    }
    return 1U;
}

static inline void speed_loop_advance(uint16_t *div_cnt, uint16_t speed_div)
{
    *div_cnt = (uint16_t)(*div_cnt + 1U >= speed_div ? 0U : *div_cnt + 1U);
}

#endif /* SPEED_MEAS_H */
