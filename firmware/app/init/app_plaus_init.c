/*
 * app_plaus_init.c - the current-sensor plausibility's parameters (app_plaus.h app_plaus_init):
 * init only, in the application's init archive, which the F2812 image runs from flash.
 */
#include "app_plaus.h"

void app_plaus_init(app_plaus_params_t *p, iq_t adc_i_gain_iq, uint16_t win_log2, uint16_t bias_log2)
{
    const int64_t f = (int64_t)fix_rshift_rnd32(fix_sat32((int64_t)adc_i_gain_iq * APP_PLAUS_FLOOR_COUNTS), 8U); /* IQ16, as app_plaus.c */
    p->win_log2 = win_log2;
    p->bias_log2 = bias_log2;
    p->floor_raw = f * f * (int64_t)(1U << win_log2);
    p->floor_var = f * f * (int64_t)(1U << (2U * win_log2));
}

