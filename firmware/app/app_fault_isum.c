/*
 * app_fault_isum.c - the three-sensor sum check's count and the phase it names (app_fault.h
 * app_fault_isum). Called only on the periods the sum is off, so the F2812 image runs it from
 * flash (libdtc_app_flash.a), out of the zero-wait RAM the ISR path needs.
 */
#include "app_fault.h"

uint16_t app_fault_isum(app_fault_t *f, const dtc_config_t *c, const iq_t i[3], uint16_t perm, int16_t *detail)
{
    uint16_t k;
    if (f->isum_n == 0U) {
        f->isum_moved = 0U;
        for (k = 0U; k < 3U; k++) {
            f->isum_i0_iq[k] = i[k];
        }
    } else {
        /* APP_ISUM_STILL_COUNTS in pu: a saturated product of the gain and a small count */
        const iq_t still = fix_sat32((int64_t)c->board.adc_i_gain_iq * APP_ISUM_STILL_COUNTS);
        for (k = 0U; k < 3U; k++) {
            if (fix_abs32(fix_sub32(i[k], f->isum_i0_iq[k])) > still) {
                f->isum_moved |= (uint16_t)(1U << k);
            }
        }
    }
    if (++f->isum_n < APP_ISUM_PERIODS) {
        return 0U;
    }
    /* the one phase that did not move: 6, 5, 3 are the masks of the other two moved */
    {
        const uint16_t m = f->isum_moved;
        *detail = m == 6U   ? (int16_t)(3U + app_fault_phase(perm, 0U))
                  : m == 5U ? (int16_t)(3U + app_fault_phase(perm, 1U))
                  : m == 3U ? (int16_t)(3U + app_fault_phase(perm, 2U))
                            : (int16_t)9; /* APP_SENSOR_DETAIL_LIST 3: cannot tell */
    }
    return 1U;
}
