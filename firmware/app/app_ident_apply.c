/*
 * app_ident_apply.c - the identification's results into the drive's parameters (background only;
 * docs/commissioning.md "Applying the results").
 *
 * app_ident_derive writes a finished PM identification (app_ident_result_t) into a copy of the
 * configuration in force and derives there the rows that go with them; app_ident_apply checks the
 * copy with its law's check (law_check) and makes it the configuration in force as a parameter
 * write does (app_reconfigure: calibration, then READY; app_ident_apply_run.c, apart so that the
 * derivation links without the application). Nothing here runs in the 50 us path; the
 * divisions are app_ident_div64's (shift and subtract).
 *
 * Rows written (pu of the configuration's bases, dtc_base.h; res = app_ident_result_t):
 *   machine.rs_iq            = res.r_iq - board.r_on_iq: the R line's slope is R_s + R_on (Hoang
 *                              Table III: R_on is in series in every conduction state), R_on the
 *                              board's datasheet value; IQ, exact (a subtraction).
 *   u.pm_dtc.machine.ls_iq   = res.l_ts_iq x board.ts_pu_iq: L / (Z_b Ts) times Ts w_b is L / L_b;
 *                              IQ x IQ in 64 bits (< 2^55), rounded to nearest.
 *   u.pm_dtc.machine.inv_ls_iq = 2^48 / ls_iq rounded to nearest (1 / L_s, IQ); refused below
 *                              ls = 1/128 pu (1 / L_s above the IQ range).
 *   u.pm_dtc.machine.psi_m_iq = res.psi_iq (pu of V_b / w_b, the row's own base): exact.
 *   machine.pole_pairs       = res.pole_pairs.
 *   board.enc_gain_q16       = p 2^32 / enc_counts rounded to nearest (electrical angle_t LSB per
 *                              count, unsigned Q16).
 *   board.enc_reversed       = the configured direction exclusive-or res.enc_reversed (the
 *                              identification sees the count the configuration's direction gave it,
 *                              app_core_step).
 *   board.enc_offset         = res.enc_offset, plus one count's angle (enc_gain_q16 / 2^16 rounded)
 *                              when the identification found the count running down: the firmware
 *                              then reads N - 1 - count (app_enc_reverse), whose angle at raw count 0
 *                              is one count short of the identified one (angle_t, modulo a turn).
 *   board.td_ts_q15          = the dead time over the period from the R line's intercept
 *                              V_0 = g (V_CE + V_d + 2 V_dc T_d / T_s) (docs/commissioning.md
 *                              section 1; g = 2/3 on the alpha axis, 1/sqrt(3) on the beta axis):
 *                              T_d / T_s = (V_0 / g - V_CE - V_d) / (2 V_dc), V_CE and V_d the
 *                              board's datasheet values, V_dc the link the identification measured
 *                              last; Q15 rounded to nearest, a negative result written as 0, above
 *                              the row's range refused.
 * Not written: board.v_ce_iq, v_d_iq, r_on_iq, v_f_iq (no injection separates a device's threshold
 * and on-state resistance from R_s and the dead time: docs/commissioning.md); J and the friction
 * (no row: the speed PI's gains and the lost-encoder level derive from J in the host converter).
 */
#include "app_ident_internal.h"

/* 1 / g on the beta axis (g = 1 / sqrt(3)), IQ; on the alpha axis 1 / g = 3/2 is exact */
#define APPLY_IQ_SQRT3 29058990LL /* round(sqrt(3) 2^24) */

#if DTC_LAW_PM_LINKED
/* round(num / den) for den > 0 (background) */
static int64_t div_round(int64_t num, int64_t den)
{
    return num >= 0 ? app_ident_div64(num + den / 2, den) : -app_ident_div64(-num + den / 2, den);
}

int16_t app_ident_derive(const app_ident_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    int64_t ls, inv, gain, td;
    if (d->step != (uint16_t)APP_IDENT_DONE) {
        return (int16_t)APP_IDENT_APPLY_NOT_DONE;
    }
    if (in->law != (uint16_t)DTC_LAW_PM_DTC || d->im_on != 0U) {
        return (int16_t)APP_IDENT_APPLY_LAW;
    }
    *out = *in;
    /* R_s: the slope less the board's R_on */
    if (d->res.r_iq <= in->board.r_on_iq) {
        return (int16_t)APP_IDENT_APPLY_RS;
    }
    out->machine.rs_iq = d->res.r_iq - in->board.r_on_iq;
    /* L_s and 1 / L_s: IQ x IQ < 2^31 x 2^24 */
    ls = ((int64_t)d->res.l_ts_iq * (int64_t)in->board.ts_pu_iq + ((int64_t)1 << 23)) >> 24;
    if (ls < ((int64_t)1 << 17) || ls > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_LS;
    }
    inv = div_round((int64_t)1 << 48, ls);
    out->u.pm_dtc.machine.ls_iq = (iq_t)ls;
    out->u.pm_dtc.machine.inv_ls_iq = fix_sat32(inv);
    out->u.pm_dtc.machine.psi_m_iq = d->res.psi_iq;
    /* pole pairs and the encoder's gain, direction and offset */
    if (in->board.enc_counts == 0U || d->res.pole_pairs == 0U) {
        return (int16_t)APP_IDENT_APPLY_ENCODER;
    }
    gain = div_round((int64_t)d->res.pole_pairs << 32, (int64_t)in->board.enc_counts);
    if (gain > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_ENCODER;
    }
    out->machine.pole_pairs = d->res.pole_pairs;
    out->board.enc_gain_q16 = (uint32_t)gain;
    out->board.enc_reversed = (uint16_t)((in->board.enc_reversed != 0U) != (d->res.enc_reversed != 0U) ? 1U : 0U);
    out->board.enc_offset = (angle_t)(d->res.enc_offset +
                                      (d->res.enc_reversed != 0U ? (angle_t)((uint32_t)(gain + 32768) >> 16) : 0U));
    /* dead time: V_0 / g in IQ (|V_0| < 2 pu: x sqrt(3) < 2^51), less the thresholds, over 2 V_dc */
    if (d->vdc_iq <= 0) {
        return (int16_t)APP_IDENT_APPLY_DEADTIME;
    }
    {
        const int64_t v0g = d->res.axis == 0U ? ((int64_t)d->res.v0_iq * 3) / 2
                                               : ((int64_t)d->res.v0_iq * APPLY_IQ_SQRT3 + ((int64_t)1 << 23)) >> 24;
        const int64_t num = v0g - (int64_t)in->board.v_ce_iq - (int64_t)in->board.v_d_iq;
        td = num <= 0 ? 0 : div_round(num << 14, (int64_t)d->vdc_iq);
    }
    if (td > 16383) {
        return (int16_t)APP_IDENT_APPLY_DEADTIME;
    }
    out->board.td_ts_q15 = (q15_t)td;
    return (int16_t)APP_IDENT_APPLY_OK;
}
#else
/* An image without the PM DTC law (an IM image): nothing to apply. */
int16_t app_ident_derive(const app_ident_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    (void)in;
    (void)out;
    return d->step != (uint16_t)APP_IDENT_DONE ? (int16_t)APP_IDENT_APPLY_NOT_DONE : (int16_t)APP_IDENT_APPLY_LAW;
}
#endif
