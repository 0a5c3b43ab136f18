/*
 * app_adc.h - a raw ADC count in per-unit: (count - offset) * gain, for the application core's
 * measurement conversion and calibration (app_core.h). Stateless.
 */
#ifndef APP_ADC_H
#define APP_ADC_H

#include <stdint.h>

#include "fixmath.h"

/* (count - offset) * gain_iq, IQ pu. Scaling and overflow: |count - offset| <= 4095 for the
 * 12-bit ADC (any 16-bit count fits the int32 difference); the product with an IQ gain (pu per
 * count) is formed in 64 bits and saturates at +-128 pu, far beyond any trip level. */
iq_t app_adc_to_pu(uint16_t count, uint16_t offset, iq_t gain_iq);

#endif /* APP_ADC_H */
