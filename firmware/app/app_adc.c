/*
 * app_adc.c - ADC counts in per-unit (see app_adc.h). One function in its own file: the
 * processor-in-the-loop images link a deliberately defective copy of it in its place
 * (tests/pil/app_adc_defect16.c, docs/pil.md).
 */
#include "app_adc.h"

iq_t app_adc_to_pu(uint16_t count, uint16_t offset, iq_t gain_iq)
{
    const int32_t d = (int32_t)count - (int32_t)offset;
    return fix_sat32((int64_t)d * (int64_t)gain_iq);
}
