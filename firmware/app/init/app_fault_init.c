/*
 * app_fault_init.c - the fault detection's init-time check (app_fault.h app_fault_post_ok): its
 * own file in the application's init archive, which the F2812 image runs from flash, out of the
 * zero-wait RAM the ISR path needs.
 */
#include "app_fault.h"

#include "law.h"

uint16_t app_fault_post_ok(const dtc_config_t *c, const dtc_config_t *post)
{
    uint16_t k, same_adc = 1U;
    for (k = 0U; k < 3U; k++) {
        if (post->board.adc_i_offset[k] != c->board.adc_i_offset[k]) {
            same_adc = 0U;
        }
    }
    /* the same law before and after: the PM DTC, or the IM switching-table DTC (law.h
     * law_reconfigure) */
    return (uint16_t)!(law_check_reconfig(post) != DTC_OK || c->law != post->law ||
        (c->law != (uint16_t)DTC_LAW_PM_DTC && c->law != (uint16_t)DTC_LAW_IM_DTC) ||
        c->board.topology != (uint16_t)DTC_TOPO_SSTP || post->board.topology != (uint16_t)DTC_TOPO_FSTP ||
        c->board.i_sensors3 == 0U || post->board.i_sensors3 == 0U || c->prot.leg_i_min_iq <= 0 ||
        post->board.vmid_cal != 0U || post->prot.relay_periods == 0U ||
        post->est.estimator != c->est.estimator || same_adc == 0U ||
        post->board.enc_counts != c->board.enc_counts || post->board.enc_gain_q16 != c->board.enc_gain_q16 ||
        post->board.enc_offset != c->board.enc_offset || post->board.enc_reversed != c->board.enc_reversed || post->board.adc_i_gain_iq != c->board.adc_i_gain_iq ||
        post->board.adc_vdc_gain_iq != c->board.adc_vdc_gain_iq ||
        post->board.adc_vdc_offset != c->board.adc_vdc_offset || post->board.ts_pu_iq != c->board.ts_pu_iq ||
        post->speed.speed_div != c->speed.speed_div);
}
