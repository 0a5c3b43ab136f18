/*
 * app_adc_defect16.c - firmware/app/app_adc.c with a deliberate defect, linked in its place into
 * the processor-in-the-loop images that prove the emulators catch it (tests/pil, docs/pil.md):
 * a 16 x 16-bit shortcut with the widening forgotten. A non-negative deviation of the 12-bit ADC
 * and a gain below 2^16 (the recorded boards' gains are 16-bit numbers: PM rig 37245 for the
 * currents, 5853 for V_dc) are multiplied as two uint16_t at int width, (iq_t)(du * gu) instead
 * of (iq_t)du * gu. Where int has 32 bits both promote to int and the product (< 4096 * 2^16 =
 * 2^28) is exact, the correct value; where it has 16 bits (C28x, AVR) they promote to unsigned
 * int and the product is taken modulo 2^16. Every other input takes app_adc.c's path.
 */
#include "app_adc.h"

iq_t app_adc_to_pu(uint16_t count, uint16_t offset, iq_t gain_iq)
{
    const int32_t d = (int32_t)count - (int32_t)offset;
    if (d >= 0 && d <= 4095 && gain_iq >= 0 && gain_iq <= 0xFFFF) {
        const uint16_t du = (uint16_t)d;
        const uint16_t gu = (uint16_t)gain_iq;
        return (iq_t)(du * gu);
    }
    return fix_sat32((int64_t)d * (int64_t)gain_iq);
}
