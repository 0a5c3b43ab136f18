/*
 * app_plaus.h - plausibility of the measured phase currents against the current the control law
 * predicts from the voltage it applied: a stuck, lost or disconnected current sensor, found with
 * two sensors as with three.
 *
 * The law (law.h law_i_pred) predicts at step k the phase currents of sample k+1 from the
 * voltage vector committed for period [k, k+1] and the machine model, l_s di/dt = v - r_s i - e
 * (Hoang eqs. 6-9). Per measured channel x the block correlates, over a window of
 * 2^APP_PLAUS_WIN_LOG2 periods, the measured change d_m = i_x(k+1) - i_x(k) with the predicted
 * change d_p = i1_x(k) - i_x(k):
 *     ratio = sum(d_m d_p) / sum(d_p^2).
 * A healthy sensor follows the model: the ratio is l_s(firmware) / l_s(machine) times the sensor's
 * gain, about 1 (0.7 .. 1.4 for a 30 % inductance error). A sensor that no longer measures its
 * current (stuck at any code, lost, reading noise) has d_m ~ 0 whatever the vector: the ratio is
 * about 0. The channel trips when the ratio is below 1/4 over a window in which the current was
 * predicted to move (sum(d_p^2) above the floor: APP_PLAUS_FLOOR_COUNTS ADC counts per period on
 * average), so a drive at rest or with null vectors only never trips on it. The criterion does not
 * depend on the machine's inductance, speed or load, only on the sign and rough size of the
 * model's prediction.
 *
 * The window is 0.8 ms at 50 us: a stuck sensor is found before the law, misled by it, can drive
 * the true current far past the trip level (the over-current trip reads the stuck value too).
 *
 * Formats: currents IQ pu (dtc_base.h). Scaling and overflow: each change is a saturated
 * difference of two values below the trip level (<= 128 pu), shifted right by 8 (rounded) to IQ16
 * before the products, so |d| < 2^24 and each product < 2^48; 2^4 of them sum below 2^52 in
 * int64_t. The floor is formed the same way at init.
 */
#ifndef APP_PLAUS_H
#define APP_PLAUS_H

#include <stdint.h>

#include "fixmath.h"

/* Window: 2^3 = 8 control periods. */
#define APP_PLAUS_WIN_LOG2 3U
/* Least mean predicted change per period that makes a window count: 8 ADC counts (a few times
 * the sensors' noise and quantisation). */
#define APP_PLAUS_FLOOR_COUNTS 8

typedef struct {
    int64_t floor_q32; /* 2^APP_PLAUS_WIN_LOG2 (8 counts in pu, IQ16)^2: least sum(d_p^2) */
} app_plaus_params_t;

typedef struct {
    iq_t i_prev[3];    /* measured phase currents of the previous sample (law's phase order) */
    iq_t i1_prev[3];   /* the law's prediction made then for this sample */
    uint16_t primed;   /* 1: i_prev and i1_prev hold a valid pair */
    uint16_t n;        /* periods in the current window */
    int64_t s_mp[3];   /* sum of d_m d_p, IQ32 */
    int64_t s_pp[3];   /* sum of d_p^2, IQ32 */
} app_plaus_t;

/* adc_i_gain_iq: pu current per ADC count (board.adc_i_gain_iq). */
void app_plaus_init(app_plaus_params_t *p, iq_t adc_i_gain_iq);
void app_plaus_reset(app_plaus_t *s);

/* One period, after the law's step. i: this sample's phase currents (law order); i1: the law's
 * prediction for the next sample, or NULL where the law has none (the block then rests and
 * restarts its window when a prediction comes back); measured: bit k set when phase k (law order)
 * is measured, not derived. Returns the phase (law order) 0..2 of a sensor that does not follow
 * the predicted current, or -1. */
int16_t app_plaus_step(app_plaus_t *s, const app_plaus_params_t *p, const iq_t i[3], const iq_t *i1,
                       uint16_t measured);

#endif /* APP_PLAUS_H */
