#include "dsc.h"

/* SSTP vector number of the leg states S_A S_B S_C (swtab.h): index = 4 S_A + 2 S_B + S_C. */
static const uint16_t dsc_vector_of_legs[8] = {0U, 5U, 3U, 4U, 1U, 6U, 2U, 7U};

void dsc_components(iq_t psi_alpha_iq, iq_t psi_beta_iq, uint16_t ccw, iq_t c[3])
{
    const int64_t half_q31 = 1073741824; /* 1/2 */
    const int64_t s32_q31 = 1859775393;  /* sqrt(3)/2 */
    const int64_t a = (int64_t)psi_alpha_iq * s32_q31;
    const int64_t b = (int64_t)psi_beta_iq * half_q31;
    if (ccw != 0U) {
        c[0] = fix_rshift_rnd64_sat32(a + b, 31U);  /* axis 30 deg */
        c[1] = fix_rshift_rnd64_sat32(-a + b, 31U); /* axis 150 deg */
        c[2] = fix_neg32(psi_beta_iq);               /* axis 270 deg */
    } else {
        c[0] = fix_rshift_rnd64_sat32(a - b, 31U);  /* axis 330 deg */
        c[1] = psi_beta_iq;                          /* axis 90 deg */
        c[2] = fix_rshift_rnd64_sat32(-a - b, 31U); /* axis 210 deg */
    }
}

void dsc_reset(dsc_t *s, uint16_t ccw, iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    iq_t c[3];
    uint16_t x;
    s->ccw = ccw != 0U ? 1U : 0U;
    dsc_components(psi_alpha_iq, psi_beta_iq, s->ccw, c);
    /* Each leg takes the state it has on the hexagon at the flux's angle (dsc.h): counter-
     * clockwise S_A = [c_c > 0], S_B = [c_a > 0], S_C = [c_b > 0]; clockwise S_A = [c_b > 0],
     * S_B = [c_c > 0], S_C = [c_a > 0]. */
    for (x = 0U; x < 3U; ++x) {
        const uint16_t src = s->ccw != 0U ? (uint16_t)(x == 0U ? 2U : x - 1U) : (uint16_t)(x == 2U ? 0U : x + 1U);
        s->s[x] = (uint16_t)(c[src] > 0 ? 1U : 0U);
    }
}

uint16_t dsc_step(dsc_t *s, iq_t psi_alpha_iq, iq_t psi_beta_iq, iq_t psi_ref_iq)
{
    iq_t c[3];
    const iq_t lo = fix_neg32(psi_ref_iq);
    uint16_t x;
    dsc_components(psi_alpha_iq, psi_beta_iq, s->ccw, c);
    for (x = 0U; x < 3U; ++x) {
        /* Casadei section 9: upper limit -> S = 0, lower limit -> S = 1. */
        if (c[x] > psi_ref_iq) {
            s->s[x] = 0U;
        } else if (c[x] < lo) {
            s->s[x] = 1U;
        }
    }
    return dsc_vector_of_legs[(uint16_t)(4U * s->s[0] + 2U * s->s[1] + s->s[2])];
}
