/*
 * app_plaus.h - plausibility of the measured phase currents against the current the control law
 * predicts from the voltage it applied: a stuck, lost or disconnected current sensor, found with
 * two sensors as with three.
 *
 * The law (law.h law_i_pred) predicts at step k the phase currents of sample k+1 from the
 * voltage vector committed for period [k, k+1] and the machine model, l_s di/dt = v - r_s i - e
 * (Hoang eqs. 6-9). Per measured channel x the block compares, over a window of
 * N = 2^APP_PLAUS_WIN_LOG2 periods, the measured change d_m = i_x(k+1) - i_x(k) with the
 * predicted change d_p = i1_x(k) - i_x(k):
 *  - the ratio sum(d_m d_p) / sum(d_p^2): a healthy sensor follows the prediction, the ratio is
 *    l_s(firmware) / l_s(machine) times the sensor's gain, about 1 (0.7 .. 1.4 for a 30 %
 *    inductance error); a sensor that no longer measures its current (stuck at any code, lost,
 *    reading noise) has d_m ~ 0 whatever the vector, the ratio is about 0. Below 1/4, over a window
 *    in which the predicted change was large enough (its mean square above APP_PLAUS_FLOOR_COUNTS
 *    ADC counts squared), the channel is suspect. This catches the dangerous case: a law misled by
 *    a stuck reading drives the true current one way, period after period, and the prediction is a
 *    steady ramp the reading never follows;
 *  - the regression slope cov(d_m, d_p) / var(d_p) with the window's means taken out: a model
 *    error the firmware makes slowly (a back-EMF or flux linkage a few per cent off, the
 *    resistance, the devices' drops: each a bias nearly constant over a window) shifts d_p but not
 *    its response to the switching. A suspect channel whose slope is 1/4 or more, over a window in
 *    which the predicted change varied (standard deviation above the same floor), does follow the
 *    switching: it is healthy and the model is off. A stuck one does not (slope ~0), nor can a
 *    steady ramp show it does (its variance is below the floor).
 * Before both, the prediction's bias is taken out: the mean of d_p - d_m, learnt with a leak of
 * 2^-APP_PLAUS_BIAS_LOG2 per period (3.2 ms). Within one window a steady model error looks exactly
 * like a stuck reading (the vector nearly balances the back-EMF, the true current stands still
 * while a back-EMF 10 % off predicts a ramp: SIL, current model, psi_m 10 % high); over the
 * milliseconds before it, a healthy sensor has shown what the bias is, and a sensor that sticks now
 * is judged against what it did until now.
 * A channel is reported when it is suspect and does not follow the switching. A drive at rest or
 * on null vectors only is never reported. Neither test depends on the machine's inductance, speed
 * or load, only on the sign and rough size of the model's response to the vectors.
 *
 * The window is 0.4 ms at 50 us: a stuck sensor is found before the law, misled by it, can drive
 * the true current far past the trip level (the over-current trip reads the stuck value too).
 *
 * Formats: currents IQ pu (dtc_base.h). Scaling and overflow: each change is a saturated
 * difference of two values below the trip level (<= 128 pu), shifted right by 8 (rounded) to IQ16
 * before the products, so |d| < 2^24 (the bias, a leaky mean of the difference of two such, within
 * 2^24 for bias_log2 >= 1, and the sums it enters below 2^26: plain 32-bit sums) and each product
 * < 2^50; N = 2^3 of them sum below 2^51, the
 * sums of changes below 2^27; N times a sum of products and a product of two sums stay below
 * 2^54 in int64_t, and 4 cov below 2^57, 16 s_mp below 2^55. The floor is formed the same way
 * at init. The window and the bias's leak are parameters (app_plaus_init): the PM law's
 * APP_PLAUS_WIN_LOG2 and APP_PLAUS_BIAS_LOG2, the IM laws' _IM values.
 */
#ifndef APP_PLAUS_H
#define APP_PLAUS_H

#include <stdint.h>

#include "fixmath.h"

/* Window: 2^3 = 8 control periods (the PM law; at most 3: the bounds above). */
#define APP_PLAUS_WIN_LOG2 3U
/* Least mean predicted change per period that makes a window count: 8 ADC counts (a few times
 * the sensors' noise and quantisation). */
#define APP_PLAUS_FLOOR_COUNTS 8
/* The prediction's bias is learnt over 2^6 = 64 periods (the PM law). */
#define APP_PLAUS_BIAS_LOG2 6U
/* The IM laws (im_dtc.h im_dtc_i_pred): a window of 2^2 = 4 periods and the bias over 2^4 = 16.
 * Their prediction takes the rotor's speed from the encoder's filtered speed, which lags the
 * machine's during a hard acceleration: the back-EMF it leaves out then grows by a few per cent
 * of the signal per period (measured: DFOC, the first torque on the default IM at 160 us), so the
 * bias must follow within some tens of periods; and their SVM and DSVM schemes run at 160 us,
 * where the first whole window after a stuck sensor's jump (the jump itself disturbs the window it
 * falls in) must end within 2 ms: at most 2 N - 1 periods, 7 at N = 4 (1.1 ms). A stuck sensor
 * still reads no change at all over the windows after its jump, whatever the bias has learnt. */
#define APP_PLAUS_WIN_LOG2_IM 2U
#define APP_PLAUS_BIAS_LOG2_IM 4U

typedef struct {
    int64_t floor_raw; /* N (APP_PLAUS_FLOOR_COUNTS counts in pu, IQ16)^2: least sum(d_p^2) */
    int64_t floor_var; /* N^2 (the same)^2: least N^2 var(d_p) */
    uint16_t win_log2;  /* N = 2^win_log2 periods a window (1..3) */
    uint16_t bias_log2; /* the bias's leak, 2^-bias_log2 per period */
} app_plaus_params_t;

/* app_plaus_t.judged: which windows the last app_plaus_step judged */
#define APP_PLAUS_JUDGED_HELD 1U /* the held window, at the start of the call */
#define APP_PLAUS_JUDGED_NOW 2U  /* the window that ended in the call, at its end */

typedef struct {
    iq_t i_prev[3];    /* measured phase currents of the previous sample (law's phase order; the
                        * measured channels only: a derived one's is neither kept nor read) */
    iq_t i1_prev[3];   /* the law's prediction made then for this sample (likewise) */
    uint16_t primed;   /* 1: i_prev and i1_prev hold a valid pair */
    uint16_t n;        /* periods in the current window */
    uint16_t pend;     /* the phases the last window failed when none of them stood still */
    uint16_t due;      /* 1: a window ended in a held period and waits for its judgement; 2: it
                        * waited through a second held period, whose sample is in wait_dm/wait_dp */
    uint16_t judged;   /* APP_PLAUS_JUDGED_ bits of the last call */
    int32_t bias[3];   /* the prediction's bias, mean of d_p - d_m, IQ16 pu per period */
    int32_t wait_dm[3]; /* due 2: that period's d_m and d_p, IQ16, the next window's first sample */
    int32_t wait_dp[3];
    int32_t s_m[3];    /* sum of d_m, IQ16 */
    int32_t s_p[3];    /* sum of d_p, IQ16 */
    int64_t s_mp[3];   /* sum of d_m d_p, IQ32 */
    int64_t s_pp[3];   /* sum of d_p^2, IQ32 */
} app_plaus_t;

/* adc_i_gain_iq: pu current per ADC count (board.adc_i_gain_iq); win_log2 (1..3) and bias_log2 (1..15):
 * APP_PLAUS_WIN_LOG2 and APP_PLAUS_BIAS_LOG2, or their _IM values for the IM laws. */
void app_plaus_init(app_plaus_params_t *p, iq_t adc_i_gain_iq, uint16_t win_log2, uint16_t bias_log2);
void app_plaus_reset(app_plaus_t *s);

/* One period, after the law's step. i: this sample's phase currents (law order); i1: the law's
 * prediction for the next sample, or NULL where the law has none (the block then rests and
 * restarts its window when a prediction comes back); measured: bit k set when phase k (law order)
 * is measured, not derived. Returns the set of measured phases (bit k: law phase k) that did not
 * follow the predicted current over the window that ended now, 0 when none (or no window ended).
 * Phases that failed and stood still (|sum(d_m d_p)| below sum(d_p^2)/16: a stuck sensor reads
 * no change at all) are returned at once, and only they when others failed too: the law's state
 * is formed from both sensors, so a stuck reading misleads the prediction of the healthy phase
 * as well (through the rotor flux x = phi_s - sigma l_s i of the IM laws' back-EMF), which still
 * moves with its current. Failed phases none of which stood still are returned only when the
 * next window fails too (a stuck sensor's jump to its code disturbs the window it falls in,
 * where the healthy phase may fail alone; the next window shows which one stands still).
 * hold != 0 (a period in which the law does its speed-loop work: app_core.h's slots 0 and 1): a
 * window that ends now is held and judged at the start of the first later call with hold = 0, at
 * the latest of the second later call, and its result returned there; a held call's sample meanwhile
 * waits (its d_m and d_p kept) and enters the next window first, after the judgement, so that the
 * windows and results are the same, one or two periods (Ts, 2 Ts) later, and the judgement never
 * adds to a held period but with hold set three periods in a row. */
uint16_t app_plaus_step(app_plaus_t *s, const app_plaus_params_t *p, const iq_t i[3], const iq_t *i1,
                        uint16_t measured, uint16_t hold);

#endif /* APP_PLAUS_H */
