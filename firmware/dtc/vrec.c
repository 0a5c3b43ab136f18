#include "vrec.h"

void vrec_sstp(uint16_t sa, uint16_t sb, uint16_t sc, iq_t vdc_iq, iq_t *v_alpha_iq,
               iq_t *v_beta_iq)
{
    vrec_from_legs(sa != 0U ? vdc_iq : 0, sb != 0U ? vdc_iq : 0, sc != 0U ? vdc_iq : 0,
                   v_alpha_iq, v_beta_iq);
}

void vrec_fstp(uint16_t sb, uint16_t sc, iq_t vdc_iq, iq_t vmid_iq, uint16_t vmid_measured,
               iq_t *v_alpha_iq, iq_t *v_beta_iq)
{
    /* V_dc/2 exactly: 2*v_a0 = V_dc, so pass half through the "2 v_a0" of vrec_from_legs by
     * rounding once: fix_rshift_rnd32 keeps the shift of a negative value inside fixmath. */
    iq_t va0_iq = vmid_measured != 0U ? vmid_iq : fix_rshift_rnd32(vdc_iq, 1U);
    vrec_from_legs(va0_iq, sb != 0U ? vdc_iq : 0, sc != 0U ? vdc_iq : 0, v_alpha_iq, v_beta_iq);
}
