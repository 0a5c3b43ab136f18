#include "hyst.h"

/* Half band: the band is validated non-negative, so the halving shift is of a non-negative
 * value; it still goes through the fixmath helper by rule. Rounded; a band of 1 LSB gives a
 * half band of 1 LSB. */
void hyst2_init(hyst2_t *h, iq_t band_iq, uint16_t out_init)
{
    h->half_band_iq = fix_rshift_rnd32(band_iq, 1U);
    h->out = out_init != 0U ? 1U : 0U;
}

void hyst3_init(hyst3_t *h, iq_t band_iq)
{
    h->half_band_iq = fix_rshift_rnd32(band_iq, 1U);
    h->out = 0;
}

void hyst5_init(hyst5_t *h, iq_t band_iq, iq_t band2_iq)
{
    h->half_band_iq = fix_rshift_rnd32(band_iq, 1U);
    h->half_band2_iq = fix_rshift_rnd32(band2_iq > band_iq ? band2_iq : band_iq, 1U);
    h->out = 0;
}
