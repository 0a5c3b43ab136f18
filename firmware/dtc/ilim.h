/*
 * ilim.h - current limit below the over-current trip (vector override of the switching table).
 *
 * With zero hysteresis bands the DTC loop lets the current ripple freely, and any flux-estimate
 * error adds a current error (a flux error dpsi is a current error dpsi / l_s in a surface PM
 * machine, Hoang eqs. 6-9). A drive must not trip on its own acceleration: when the current
 * predicted for the start of the next period exceeds the configured limit I_lim, the vector
 * chosen by the table is replaced by the one that reduces |i| fastest.
 *
 * Which vector: with psi = l_s i + psi_r (Hoang eqs. 6-9), d|i|^2/dt = 2 i . (v - r_s i - e) / l_s, and
 * r_s i and the back-EMF e are the same whichever vector is applied, so the vector minimising
 * v . i reduces |i| fastest (or raises it slowest). With the amplitude-invariant transform of
 * Hoang eqs. 1-5 and i_a + i_b + i_c = 0, v . i = (2/3) sum_x v_x0 i_x, v_x0 the leg voltages:
 *   SSTP: v_x0 = S_x V_dc, so minimise sum over the legs switched high of i_x (V_dc cancels),
 *         candidates the six active vectors (a null vector gives 0, never below the best active
 *         one, whose v . i <= -|v||i| cos 30 deg < 0);
 *   FSTP: leg A sits on the mid-point whatever the vector (its term is common to all four), so
 *         minimise S_b i_b + S_c i_c over Hoang Table I's four vectors (exact also with a mid-point
 *         off centre).
 * Only sums of currents: no products, no dependence on the link voltage.
 *
 * The limit itself (dtc_config.h i_lim_iq) is derived on the host from the trip level and the
 * machine (tools/config dtc_ilim_default_a): I_lim = I_trip - n dI, dI = T_s (V_max + w_max psi_m
 * + r_s I_trip) / L_s the largest current change over one period, n = 1 when the limit acts on the
 * current predicted for k+1 (delay compensation on), n = 2 on the sampled current (the vector
 * chosen at k acts from k+1 on). The phase currents are projections of the space vector
 * (amplitude-invariant Clarke), so |i| <= I_lim bounds every phase current as well.
 *
 * Formats: currents IQ pu; |i|^2 in unsigned Q48 (exact, iq_sumsq_q48); the sums are of halved
 * phase currents (cannot overflow). Pure functions, no state.
 */
#ifndef ILIM_H
#define ILIM_H

#include <stdint.h>

#include "clarke.h"
#include "fixmath.h"

typedef struct {
    iq_t i_lim_iq;  /* the limit I_lim, pu (prot.i_lim_iq); 0 = off */
    uint16_t fstp;  /* 1: four-switch inverter (Hoang Table I's four vectors), 0: six-switch */
} ilim_params_t;

/* vec: the table's vector (SSTP 0..7, FSTP 1..4). i: the current the limit acts on (all five
 * fields: phases and alpha/beta). Returns vec when |i| <= p->i_lim_iq (or the limit is off,
 * i_lim_iq = 0), else the vector of least v . i; *limited = 1 when the vector was replaced. */
uint16_t ilim_select(const ilim_params_t *p, const clarke_out_t *i, uint16_t vec, uint16_t *limited);

/* Internal to ilim_select: 1 when |i| > lim_iq (exact squares), else 0. */
uint16_t ilim_over(iq_t lim_iq, const clarke_out_t *i);

/* ilim_select's vector for a current over the limit (the vector of least v . i), for a law that
 * tests |i|^2 against its own I_lim^2 formed at init (dtc_step): ilim_select is ilim_over, then
 * this. Inline: the PM law's one call sits in its step (zero-wait RAM on the F2812). */
static inline uint16_t ilim_pick(const ilim_params_t *p, const clarke_out_t *i)
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

#endif /* ILIM_H */
