#include "ilim.h"

/* |i| > limit, on the exact squares (unsigned Q48). External linkage on purpose: inlined, its
 * 64-bit temporaries would sit in ilim_select's frame on the deepest stack path. */
uint16_t ilim_over(iq_t lim_iq, const clarke_out_t *i)
{
    return iq_sumsq_q48(i->i_alpha_iq, i->i_beta_iq) > iq_sumsq_q48(lim_iq, 0) ? 1U : 0U;
}

uint16_t ilim_pick(const ilim_params_t *p, const clarke_out_t *i)
{
    /* Leg states of the candidates as bits a = 4, b = 2, c = 1 (swtab.h): SSTP V_1..V_6 = 100
     * 110 010 011 001 101; FSTP V_1..V_4 = 00 10 11 01 (legs b, c). */
    static const uint16_t sstp_legs[6] = {4U, 6U, 2U, 3U, 1U, 5U};
    /* Quartered phase currents: a sum of up to three quarters of int32 values stays within
     * +-3 * 2^29 < 2^31 (halves would not: two phases at the +128 pu rail of the saturated
     * conversion sum to 2^31), and quartering keeps the order of the sums (up to two LSB of
     * rounding). */
    const iq_t ha = fix_rshift_rnd32(i->ia_iq, 2U);
    const iq_t hb = fix_rshift_rnd32(i->ib_iq, 2U);
    const iq_t hc = fix_rshift_rnd32(i->ic_iq, 2U);
    uint16_t k, best = 1U;
    iq_t best_s = 0;

    if (p->fstp != 0U) {
        /* FSTP: the four candidates in order, sums 0 (V_1), b (V_2), b + c (V_3), c (V_4); the
         * first of least sum, as the SSTP loop below (written out: the PM law's 50 us path) */
        const iq_t sbc = hb + hc;
        if (hb < best_s) {
            best_s = hb;
            best = 2U;
        }
        if (sbc < best_s) {
            best_s = sbc;
            best = 3U;
        }
        return hc < best_s ? 4U : best;
    }
    for (k = 0U; k < 6U; k++) {
        const uint16_t legs = sstp_legs[k];
        iq_t s = (legs & 4U) != 0U ? ha : 0;
        s += (legs & 2U) != 0U ? hb : 0;
        s += (legs & 1U) != 0U ? hc : 0;
        if (k == 0U || s < best_s) {
            best_s = s;
            best = (uint16_t)(k + 1U);
        }
    }
    return best;
}

uint16_t ilim_select(const ilim_params_t *p, const clarke_out_t *i, uint16_t vec, uint16_t *limited)
{
    *limited = 0U;
    if (p->i_lim_iq <= 0 || ilim_over(p->i_lim_iq, i) == 0U) {
        return vec;
    }
    *limited = 1U;
    return ilim_pick(p, i);
}
