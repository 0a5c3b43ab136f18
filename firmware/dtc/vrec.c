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

/* Dead-time error of one leg over one period, in units of e = V_dc T_d/T_s: the leg changed state
 * at the period's start (prev -> cur) and for T_d both devices were off, so the phase current's
 * free-wheeling diode set the leg voltage: turning on the upper device with the current leaving the
 * leg (i > 0), the lower diode kept the leg at 0 for T_d: -e on the period's mean; turning it off
 * with the current entering (i < 0), the upper diode kept it at V_dc: +e. Otherwise the current
 * commutates at once and there is no error (0). The sign of the sampled current decides. */
static int32_t deadtime_leg(uint16_t prev, uint16_t cur, iq_t i)
{
    if (prev == 0U && cur != 0U && i > 0) {
        return -1;
    }
    if (prev != 0U && cur == 0U && i < 0) {
        return 1;
    }
    return 0;
}

/* Dead-time compensation (Casadei sec. 10.5; deadtime_code, then vrec.h deadtime_apply): the leg
 * errors of deadtime_leg through the same
 * leg-to-alpha/beta transform as the reconstruction (vrec_from_legs, Hoang eqs. 1-5; FSTP: leg A
 * is the mid-point and never switches). Phase currents at the switching instant, all three
 * (clarke_out_t: the two measured, the third by Kirchhoff).
 * Scaling and overflow: e = V_dc * T_d/T_s (IQ x Q15, rounded) with T_d/T_s < 1/2 (validated), so
 * |e| < 2^30 and the leg errors k_x e (k_x in {-1, 0, 1}) give 2 k_a e and (k_b + k_c) e exactly in
 * 32 bits: vrec_from_legs' sums 2 v_a and v_b + v_c cannot saturate, and its saturating
 * difference and rounded Q31 products are taken here the same way on the integer multiples of e
 * (bit for bit vrec_from_legs of the three leg errors, with no 64-bit sum but the last). */
uint16_t deadtime_code(const deadtime_params_t *p, const clarke_out_t *i, const swtab_legs_t *prev,
                       const swtab_legs_t *cur)
{
    int32_t ka, kb, kc;
    if (prev->sa == cur->sa && prev->sb == cur->sb && prev->sc == cur->sc) {
        return DEADTIME_CODE_ZERO; /* no leg changed: no dead-time error (most periods) */
    }
    ka = p->fstp != 0U ? 0 : deadtime_leg(prev->sa, cur->sa, i->ia_iq);
    kb = deadtime_leg(prev->sb, cur->sb, i->ib_iq);
    kc = deadtime_leg(prev->sc, cur->sc, i->ic_iq);
    return (uint16_t)((uint32_t)(ka + 1) | ((uint32_t)(kb + 1) << 2) | ((uint32_t)(kc + 1) << 4));
}

void deadtime_error(const deadtime_params_t *p, iq_t vdc_iq, const clarke_out_t *i, const swtab_legs_t *prev,
                    const swtab_legs_t *cur, iq_t *dva, iq_t *dvb)
{
    deadtime_apply(p, vdc_iq, deadtime_code(p, i, prev, cur), dva, dvb);
}
