/*
 * app_ident_apply.c - the identification's results into the drive's parameters (background only;
 * docs/commissioning.md "Applying the results").
 *
 * app_ident_derive writes a finished identification (app_ident_result_t), a PM's or an induction
 * machine's, into a copy of the configuration in force and derives there the rows that go with
 * them; app_ident_apply checks the
 * copy with its law's check (law_check) and makes it the configuration in force as a parameter
 * write does (app_reconfigure: calibration, then READY; app_ident_apply_run.c, apart so that the
 * derivation links without the application). Nothing here runs in the 50 us path; the
 * divisions are app_ident_div64's (shift and subtract).
 *
 * Rows written (pu of the configuration's bases, dtc_base.h; res = app_ident_result_t), on both
 * machines (derive_common): machine.rs_iq, machine.pole_pairs, board.enc_gain_q16,
 * board.enc_reversed, board.td_ts_q15; on a PM also L_s, 1/L_s, psi_m and the encoder's offset:
 *   machine.rs_iq            = res.r_iq - board.r_on_iq: the R line's slope is R_s + R_on (Hoang
 *                              Table III: R_on is in series in every conduction state), R_on the
 *                              board's datasheet value; IQ, exact (a subtraction).
 *   u.pm_dtc.machine.ls_iq   = res.l_ts_iq x board.ts_pu_iq: L / (Z_b Ts) times Ts w_b is L / L_b;
 *                              IQ x IQ in 64 bits (< 2^55), rounded to nearest.
 *   u.pm_dtc.machine.inv_ls_iq = 2^48 / ls_iq rounded to nearest (1 / L_s, IQ); refused below
 *                              ls = 1/128 pu (1 / L_s above the IQ range).
 *   u.pm_dtc.machine.lq_iq   = ls_iq x res.lq_q12 / 2^12 rounded to nearest (L_q = L_d times the
 *                              identified L_q / L_d) when res.salient, else ls_iq (L_q within the
 *                              measurement's accuracy of L_d: a surface PM, the laws' surface path);
 *                              refused (APP_IDENT_APPLY_LS) as L_s.
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
 * An induction machine (derive_im; docs/commissioning.md "Induction machine": the terminals show
 * R_s, sigma L_s, L_s and tau_r, the inverse-Gamma model, not the T model's split of the leakage,
 * which is taken equal, L_ls = L_lr, so L_r = L_s, as dtc-sil identify writes identified.toml):
 *   sls = res.im.lsig_ts_iq x ts_pu (as L_s above); ls = res.psi_iq / res.im.id_iq (the spin's
 *   L_s i_d over i_d: L_s at the configured flux, turning), or res.im.ls_ts_iq x ts_pu (standing)
 *   when that is not above sls; lm = ls - sls (L_M, the inverse-Gamma magnetising inductance);
 *   all IQ rounded to nearest. Then, each rounded to nearest from exact integer operands:
 *   u.im.machine.rr_iq       = res.im.rr_iq (R_r = L_r / tau_r with L_r = L_s standing), exact.
 *   u.im.machine.sigma_ls_iq = u.im.machine.sigma_lr_iq = sls (sigma L_r = sigma L_s when L_r = L_s).
 *   u.im.machine.m_iq        = sqrt(ls lm) (M^2 = L_s L_r - sigma L_s L_r = L_s L_M): the root of a
 *                              Q48 product (< 2^62).
 *   u.im.machine.kr_iq = ks_iq = sqrt(ls 2^48 / lm) (L_r / M = L_s / M = sqrt(L_s / L_M)): the
 *                              quotient floored in Q48 (its error < 2^-24 LSB), then the root.
 *   u.im.machine.inv_ks_iq   = sqrt(lm 2^48 / ls) (M / L_s).
 *   u.im.fw.kt_iq            = lm 2^47 / (sls ls) (Casadei eq. 34's k_T = (1 - sigma) / (2 sigma l_s)).
 *   u.im.ref.magn_k_q31      = ts_pu rr 2^7 / ls (T_s / tau_r, tau_r = l_r / r_r; Q31).
 *   u.im.ref.inv_psir_sq_iq  = ls 2^72 / (phi_s*^2 lm) (1 / phi_r*^2 with phi_r* = (M / L_s) phi_s*,
 *                              written only when psir_ref_iq = 0: the rotor-flux reference derived
 *                              from speed.flux_ref_iq; in two quotients, error < 1/64 LSB).
 *   u.im.ref.magn_ramp_iq    = (1 - phi_r* / M) rr ts_pu (the start-up's flux ramp, the converter's
 *                              (I_n - I_m) L_s / tau_r T_s with I_n the rated current = I_b, the
 *                              identification's current base; refused unless I_m < I_n).
 *   u.im.dfoc.id_ref_iq      = phi_r* / M, u.im.dfoc.iq_per_t_iq = sqrt(ls / (lm phi_r*^2))
 *                              (l_r / (m phi_r*)): the DFOC law only.
 *   Then the rows the converter designs from the settings it holds in u.im.design (derive_im_design):
 *   the current limit prot.i_lim_iq and the torque limit speed.torque_limit_iq it allows,
 *   u.im.ref.magn_periods, u.im.dsvm.torque_band2_iq, u.im.dfoc.kp_iq and ki_ts_iq, and
 *   u.im.ref.enc_plaus_iq (from the identified J).
 * On both machines, from the identified J, when the configuration holds the speed loop's design
 * bandwidth (speed.speed_bw_iq > 0): speed.kp_iq, speed.ki_ts_iq and prot.enc_freeze_speed_iq as
 * the host converter designs them (derive_speed).
 * Not written: board.v_ce_iq, v_d_iq, r_on_iq, v_f_iq (no injection separates a device's threshold
 * and on-state resistance from R_s and the dead time: docs/commissioning.md); J, the friction (no
 * row holds them: only what is designed from J).
 */
#include "app_ident_internal.h"
#include "app_enc.h"

/* 1 / g on the beta axis (g = 1 / sqrt(3)), IQ; on the alpha axis 1 / g = 3/2 is exact */
#define APPLY_IQ_SQRT3 29058990LL /* round(sqrt(3) 2^24) */

#if DTC_LAW_PM_LINKED || DTC_LAW_IM_LINKED
/* round(num / den) for den > 0 (background) */
static int64_t div_round(int64_t num, int64_t den)
{
    return num >= 0 ? app_ident_div64(num + den / 2, den) : -app_ident_div64(-num + den / 2, den);
}

/* floor(num 2^sh / den) for num >= 0 and 0 < den < 2^62, by restoring long division over the bits
 * of num followed by sh zeros (the shifted numerator never formed: any sh); -1 when the quotient
 * reaches 2^62 (the caller refuses). Background. */
static int64_t div_shl(int64_t num, uint16_t sh, int64_t den)
{
    const uint64_t n = (uint64_t)num, dd = (uint64_t)den;
    uint64_t q = 0U, r = 0U;
    int16_t b;
    for (b = (int16_t)(63 + (int16_t)sh); b >= 0; b--) {
        const uint64_t bit = b >= (int16_t)sh ? (n >> (uint16_t)(b - (int16_t)sh)) & 1U : 0U;
        r = (r << 1) | bit;
        if (q >= ((uint64_t)1 << 61)) {
            return -1;
        }
        q <<= 1;
        if (r >= dd) {
            r -= dd;
            q |= 1U;
        }
    }
    return (int64_t)q;
}

/* The common rows of a PM's and an IM's identification: R_s, the dead time, the pole pairs and
 * the encoder's gain and direction (the file comment). *gain: the encoder gain written. */
APP_NOINLINE static int16_t derive_common(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out, int64_t *gain)
{
    int64_t td;
    /* R_s: the slope less the board's R_on */
    if (d->res.r_iq <= in->board.r_on_iq) {
        return (int16_t)APP_IDENT_APPLY_RS;
    }
    out->machine.rs_iq = d->res.r_iq - in->board.r_on_iq;
    /* pole pairs and the encoder's gain and direction */
    if (in->board.enc_counts == 0U || d->res.pole_pairs == 0U) {
        return (int16_t)APP_IDENT_APPLY_ENCODER;
    }
    *gain = div_round((int64_t)d->res.pole_pairs << 32, (int64_t)in->board.enc_counts);
    if (*gain > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_ENCODER;
    }
    out->machine.pole_pairs = d->res.pole_pairs;
    out->board.enc_gain_q16 = (uint32_t)*gain;
    out->board.enc_reversed = (uint16_t)((in->board.enc_reversed != 0U) != (d->res.enc_reversed != 0U) ? 1U : 0U);
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

/* A product chain in floating form, m 2^e with 2^30 <= m < 2^31 after fx_of (m = 0 for zero;
 * each step's rounding costs at most 2^-30 of the value; background). */
typedef struct {
    uint32_t m; /* below 2^31 (fx_of); widened to 64 bits before every shift and product */
    int16_t e;
} apply_fx_t;

static apply_fx_t fx_of(uint64_t m, int16_t e)
{
    apply_fx_t r;
    uint16_t k = 0U;
    while (m != 0U && m < ((uint64_t)1 << 30)) {
        m <<= 1;
        e--;
    }
    while ((m >> k) >= ((uint64_t)1 << 31)) {
        k++;
    }
    if (k > 0U) {
        m = (m + ((uint64_t)1 << (k - 1U))) >> k;
        if (m >= ((uint64_t)1 << 31)) {
            m >>= 1;
            k++;
        }
    }
    r.m = (uint32_t)m; /* < 2^31 here */
    r.e = (int16_t)(e + (int16_t)k);
    return r;
}

static apply_fx_t fx_mul(apply_fx_t a, apply_fx_t b)
{
    return fx_of((uint64_t)a.m * (uint64_t)b.m, (int16_t)(a.e + b.e));
}

/* a / b for b.m > 0: the quotient with 31 more bits (below 2^62) */
static apply_fx_t fx_div(apply_fx_t a, apply_fx_t b)
{
    return fx_of((uint64_t)div_shl((int64_t)a.m, 31U, (int64_t)b.m), (int16_t)(a.e - b.e - 31));
}

/* An IQ value (>= 0) in fx form: exact. */
static apply_fx_t fx_iq(int64_t x)
{
    return fx_of((uint64_t)x, -24);
}

/* round(a 2^frac) as an int32 row; -1 beyond 2^31 - 1 (the caller refuses) */
static int64_t fx_row(apply_fx_t a, int16_t frac)
{
    const int16_t sh = (int16_t)(a.e + frac);
    if (sh >= 0) {
        return sh > 31 || ((uint64_t)a.m << (uint16_t)sh) > (uint64_t)0x7FFFFFFF ? -1 : (int64_t)((uint64_t)a.m << (uint16_t)sh);
    }
    if (sh < -40) {
        return 0;
    }
    {
        const uint64_t r = ((uint64_t)a.m + ((uint64_t)1 << (uint16_t)(-sh - 1))) >> (uint16_t)(-sh);
        return r > (uint64_t)0x7FFFFFFF ? -1 : (int64_t)r;
    }
}

/* The rows designed from the inertia, again on the identified J (when the configuration holds
 * the speed loop's design bandwidth, speed.speed_bw_iq > 0, and the spin measured J > 0). kt_iq:
 * the torque per pu current of the spin's fit, pu (PM: psi_m; IM: L_M i_d). With
 * Jn = J w_b^2 / (p T_b) (the inertia in pu; T_b = 3/2 p psi_b I_b) and res.j_q12 = J / k_t in pu
 * current x Ts^2 per count (Q12; a count = 2 pi / counts mechanical rad, k_t I_b = T_b kt):
 *     Jn = (j_q12 / 2^12) kt counts ts_pu^2 / (2 pi p)
 *     speed.kp_iq       = Jn bw                 (the converter's kp = J bw, in pu w_b / (p T_b))
 *     speed.ki_ts_iq    = Jn bw^2 ts_pu speed_div / 4   (ki = kp bw / 4, times the speed period)
 *     prot.enc_freeze_speed_iq (when the configuration has it, > 0) = the larger of
 *         2 pi 8 p / (counts N ts_pu)          (8 counts in N = APP_ENC_FREEZE_PERIODS periods)
 *         8 T_lim N ts_pu / Jn                 (4 times the speed 2 T_lim / J takes in N periods)
 *       the second as the level in force times (kp_old p_old) / (Jn bw p): T_lim is the
 *       converter's torque_limit_nm, which the image does not hold (speed.torque_limit_iq may be the
 *       current limit's, smaller), and the level in force is 8 (T_lim / T_b_old) N ts / Jn_old with
 *       Jn_old bw = kp_old and T_b proportional to the pole pairs (a kp changed by hand since
 *       scales it likewise);
 * each a chain of fx products (relative error < 2^-28), rounded to nearest at the end. */
/* Jn = (j_q12 / 2^12) kt counts ts_pu^2 / (2 pi p) (derive_speed's comment), kt_iq > 0 */
static apply_fx_t jn_of(const app_ident_view_t *d, const dtc_config_t *in, const dtc_config_t *out, iq_t kt_iq)
{
    const apply_fx_t ts = fx_iq(in->board.ts_pu_iq);
    apply_fx_t jn = fx_mul(fx_of((uint64_t)d->res.j_q12, -12), fx_iq(kt_iq));
    jn = fx_mul(fx_mul(jn, fx_of((uint64_t)in->board.enc_counts, 0)), fx_mul(ts, ts));
    return fx_div(jn, fx_of((uint64_t)ID_IQ_2PI * out->machine.pole_pairs, -24));
}

APP_NOINLINE static int16_t derive_speed(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out, iq_t kt_iq)
{
    apply_fx_t jn, bw, ts, x;
    int64_t kp, ki, fr;
    const uint16_t p = out->machine.pole_pairs;
    if (in->speed.speed_bw_iq <= 0 || d->res.j_q12 <= 0) {
        return (int16_t)APP_IDENT_APPLY_OK;
    }
    if (kt_iq <= 0) {
        return (int16_t)APP_IDENT_APPLY_J;
    }
    ts = fx_iq(in->board.ts_pu_iq);
    bw = fx_iq(in->speed.speed_bw_iq);
    jn = jn_of(d, in, out, kt_iq);
    kp = fx_row(fx_mul(jn, bw), 24);
    ki = fx_row(fx_mul(fx_mul(fx_mul(jn, bw), fx_mul(bw, ts)), fx_of((uint64_t)in->speed.speed_div, 0)), 22);
    if (kp < 1 || ki < 0) {
        return (int16_t)APP_IDENT_APPLY_J;
    }
    out->speed.kp_iq = (iq_t)kp;
    out->speed.ki_ts_iq = (iq_t)ki;
    if (in->prot.enc_freeze_speed_iq > 0) {
        /* the deceleration's term scales with 1 / J: the level in force times kp in force over the
         * new kp (both Jn bw), when that term was the larger (the torque limit it was designed
         * with, the converter's torque_limit_nm, is not held: the one in force may be the current
         * limit's, smaller) */
        const apply_fx_t nts = fx_mul(fx_of(APP_ENC_FREEZE_PERIODS, 0), ts);
        const apply_fx_t w_counts = fx_div(fx_of((uint64_t)ID_IQ_2PI * 8U * p, -24),
                                           fx_mul(fx_of((uint64_t)in->board.enc_counts, 0), nts));
        const int64_t counts_iq = fx_row(w_counts, 24);
        x = w_counts;
        if (counts_iq >= 0 && (int64_t)in->prot.enc_freeze_speed_iq > counts_iq + 1 && in->speed.kp_iq > 0) {
            x = fx_div(fx_mul(fx_mul(fx_of((uint64_t)in->prot.enc_freeze_speed_iq, -24), fx_of((uint64_t)in->speed.kp_iq, -24)),
                              fx_of(in->machine.pole_pairs, 0)),
                       fx_mul(fx_mul(jn, bw), fx_of(p, 0)));
        }
        fr = fx_row(x, 24);
        if (fr < 1) {
            return (int16_t)APP_IDENT_APPLY_J;
        }
        out->prot.enc_freeze_speed_iq = (iq_t)fr;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* An inductance identified as L / (Z_b Ts) (IQ) in pu of L_b: x board.ts_pu_iq (Ts w_b), IQ x IQ
 * in 64 bits (< 2^55), rounded to nearest. */
static int64_t l_pu(iq_t l_ts_iq, const dtc_config_t *in)
{
    return ((int64_t)l_ts_iq * (int64_t)in->board.ts_pu_iq + ((int64_t)1 << 23)) >> 24;
}
#endif

#if DTC_LAW_PM_LINKED
/* The PM's rows (the file comment). */
static int16_t derive_pm(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    int64_t ls, inv, lq, gain = 0;
    const int16_t rc = derive_common(d, in, out, &gain);
    if (rc != (int16_t)APP_IDENT_APPLY_OK) {
        return rc;
    }
    /* L_s and 1 / L_s */
    ls = l_pu(d->res.l_ts_iq, in);
    if (ls < ((int64_t)1 << 17) || ls > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_LS;
    }
    inv = div_round((int64_t)1 << 48, ls);
    out->u.pm_dtc.machine.ls_iq = (iq_t)ls;
    out->u.pm_dtc.machine.inv_ls_iq = fix_sat32(inv);
    /* L_q (ls < 2^31, lq_q12 < 2^16: the product within 47 bits); the law forms 1 / L_q at init */
    lq = d->res.salient != 0U ? (ls * (int64_t)d->res.lq_q12 + 2048) >> 12 : ls;
    if (lq < ((int64_t)1 << 17) || lq > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_LS;
    }
    out->u.pm_dtc.machine.lq_iq = (iq_t)lq;
    out->u.pm_dtc.machine.psi_m_iq = d->res.psi_iq;
    /* the encoder's offset: read as N - 1 - count when the count was found running down */
    out->board.enc_offset = (angle_t)(d->res.enc_offset +
                                      (d->res.enc_reversed != 0U ? (angle_t)((uint32_t)(gain + 32768) >> 16) : 0U));
    return derive_speed(d, in, out, d->res.psi_iq);
}
#endif

#if DTC_LAW_IM_LINKED
/* round(num 2^sh / den) (div_shl's range; -1 beyond it) */
static int64_t div_shl_round(int64_t num, uint16_t sh, int64_t den)
{
    const int64_t q = div_shl(num, (uint16_t)(sh + 1U), den);
    return q < 0 ? -1 : (q + 1) >> 1;
}

/* round(sqrt(x)) for 0 <= x < 2^62 (fix_isqrt_rnd; below 2^31; background) */
static int64_t isqrt_round(int64_t x)
{
    uint32_t fl;
    return (int64_t)fix_isqrt_rnd((uint64_t)x, &fl);
}

/* ls / (lm x^2) in 2^sh units for IQ inputs, floor within one unit: floor(ls 2^(sh1) / (lm x))
 * then that 2^16 / x (the first quotient's floor costs less than 2^16 / x < 1 unit for x > 2^16);
 * -1 beyond range. */
static int64_t ls_over_lm_x2(int64_t ls, int64_t lm, int64_t x, uint16_t sh)
{
    const int64_t a = div_shl(ls, (uint16_t)(sh - 16U), lm * x);
    return a < 0 ? -1 : div_shl(a, 16U, x);
}

/* a.m 2^31 on the exponent e >= a.e, rounded to nearest (< 2^62; 0 below half a unit) */
static uint64_t fx_align(apply_fx_t a, int16_t e)
{
    const int16_t sh = (int16_t)(e - a.e);
    if (sh > 62) {
        return 0U;
    }
    if (sh == 0) {
        return (uint64_t)a.m << 31;
    }
    return (((uint64_t)a.m << 31) + ((uint64_t)1 << (uint16_t)(sh - 1))) >> (uint16_t)sh;
}

/* a + b (sub = 0), or a - b (sub = 1; 0 when a <= b), of two values >= 0: both on the larger
 * exponent with 31 more bits (each < 2^62, the sum < 2^63), the smaller rounded there (2^-61 of
 * the larger), then fx_of's rounding. */
static apply_fx_t fx_addsub(apply_fx_t a, apply_fx_t b, uint16_t sub)
{
    int16_t e;
    uint64_t ma, mb;
    if (b.m == 0U) {
        return a;
    }
    if (a.m == 0U) {
        return sub != 0U ? a : b;
    }
    e = a.e > b.e ? a.e : b.e;
    ma = fx_align(a, e);
    mb = fx_align(b, e);
    return fx_of(sub != 0U ? (ma > mb ? ma - mb : 0U) : ma + mb, (int16_t)(e - 31));
}

/* 1 when a < b (both >= 0) */
static uint16_t fx_lt(apply_fx_t a, apply_fx_t b)
{
    return fx_addsub(b, a, 1U).m != 0U ? 1U : 0U;
}

/* sqrt(a) for a >= 0: the mantissa on an even exponent in [2^60, 2^62), its root rounded to
 * nearest (fix_isqrt_rnd: 2^30..2^31, half a unit, 2^-31 of the value) */
static apply_fx_t fx_sqrt(apply_fx_t a)
{
    uint32_t fl;
    uint64_t m = a.m;
    int16_t e = a.e;
    if (m == 0U) {
        return a;
    }
    if ((e & 1) != 0) {
        m <<= 1;
        e--;
    }
    m <<= 30;
    e = (int16_t)(e - 30);
    return fx_of(fix_isqrt_rnd(m, &fl), (int16_t)(e / 2));
}

/* ceil(a) for a >= 0 (below 2^31; -1 beyond it) */
static int64_t fx_ceil(apply_fx_t a)
{
    if (a.e >= 0) {
        return a.e > 31 || ((uint64_t)a.m << (uint16_t)a.e) > (uint64_t)0x7FFFFFFF ? -1 : (int64_t)((uint64_t)a.m << (uint16_t)a.e);
    }
    if (a.e < -40) {
        return a.m != 0U ? 1 : 0;
    }
    return (int64_t)(((uint64_t)a.m + ((uint64_t)1 << (uint16_t)(-a.e)) - 1U) >> (uint16_t)(-a.e));
}

/* The identified machine for derive_im_design, fx (pu; L_r = L_s, the equal leakage split) */
typedef struct {
    apply_fx_t ls, sls, lm, m, rs, rr, ts;
    apply_fx_t psir;   /* the rotor-flux reference phi_r*: the configured, or (M / L_s) phi_s* */
    apply_fx_t t_lim;  /* the configured torque limit, pu of the identified pole pairs' T_b */
} apply_im_t;

/* The steady-state torque at the stator current i (pu; the converter's
 * dtc_im_torque_at_current_nm, law_im_si.c, with L_r = L_s): T = (3/2) p (M^2 / L_r) i_d i_q
 * (Casadei eq. 16's torque in the rotor-flux frame), in pu L_M i_d sqrt(i^2 - i_d^2), with
 * i_d = phi_r* / M on a rotor-flux reference, or on the stator-flux reference phi_s* the i_d that
 * gives |phi_s| = phi_s* in steady state (phi_s = L_s i_d + j sigma L_s i_q, Casadei eq. 19 at
 * constant rotor flux): i_d^2 = (phi_s*^2 - (sigma L_s i)^2) / (L_s^2 - (sigma L_s)^2). 0 when
 * i <= i_d; *any = 1 when phi_s* <= sigma L_s i (no such i_d: the converter's HUGE_VAL, no clamp). */
static apply_fx_t im_torque_at(const dtc_config_t *in, const apply_im_t *q, apply_fx_t i, uint16_t *any)
{
    apply_fx_t id2, i2 = fx_mul(i, i);
    *any = 0U;
    if (in->u.im.ref.psir_ref_iq > 0) {
        const apply_fx_t id = fx_div(q->psir, q->m);
        id2 = fx_mul(id, id);
    } else {
        const apply_fx_t phi = fx_iq(in->speed.flux_ref_iq), sli = fx_mul(q->sls, i);
        if (!fx_lt(sli, phi)) {
            *any = 1U;
            return fx_of(0U, 0);
        }
        id2 = fx_div(fx_addsub(fx_mul(phi, phi), fx_mul(sli, sli), 1U),
                     fx_addsub(fx_mul(q->ls, q->ls), fx_mul(q->sls, q->sls), 1U));
    }
    if (!fx_lt(id2, i2)) {
        return fx_of(0U, 0);
    }
    return fx_mul(fx_mul(q->lm, fx_sqrt(id2)), fx_sqrt(fx_addsub(i2, id2, 1U)));
}

/* 1 when the configuration's DFOC current PIs are the converter's zeta = 0 design (the zero on the
 * stator transient pole: K_i T_s = R_s w_c T_s with w_c = K_p / sigma L_s, within 1e-5 of K_i T_s
 * and one LSB), whose first-order loops do not overshoot (dtc_im_hold_margin_a); the crossover in
 * *wc. */
static uint16_t dfoc_zeta0(const dtc_config_t *in, const apply_im_t *q, apply_fx_t *wc)
{
    const apply_fx_t kp_in = fx_iq(in->u.im.dfoc.kp_iq), sls_in = fx_iq(in->u.im.machine.sigma_ls_iq);
    const apply_fx_t rs_in = fx_iq(in->machine.rs_iq), ki_in = fx_iq(in->u.im.dfoc.ki_ts_iq);
    const apply_fx_t ki0 = fx_mul(fx_mul(rs_in, fx_div(kp_in, sls_in)), q->ts); /* K_i' T_s of the zeta = 0 design */
    const apply_fx_t dev = fx_lt(ki0, ki_in) != 0U ? fx_addsub(ki_in, ki0, 1U) : fx_addsub(ki0, ki_in, 1U);
    const apply_fx_t tol = fx_addsub(fx_iq(1), fx_div(ki_in, fx_of(100000U, 0)), 0U);
    *wc = fx_div(kp_in, sls_in);
    return (uint16_t)(fx_lt(tol, dev) == 0U ? 1U : 0U);
}

/* derive_im_design's parts, each its own function (APP_NOINLINE), so that the fx temporaries
 * (apply_fx_t, returned through the stack) of one are not on the stack beside the others'. Each returns APP_IDENT_APPLY_OK or APP_IDENT_APPLY_IM. */
/* design_limits' current step dI and current limit I_lim (written when derived), with V_max */
typedef struct {
    apply_fx_t vmax, di, ilim;
} apply_step_t;

/* the current step and the current limit (design.vdc_iq > 0) */
APP_NOINLINE static int16_t limit_step(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q,
                                       apply_step_t *st)
{
    const dtc_im_design_cfg_t *g = &in->u.im.design;
    const uint16_t p = out->machine.pole_pairs, p_in = in->machine.pole_pairs;
    const uint16_t ilim_n = (uint16_t)(g->derived & DTC_IM_DESIGN_ILIM_N);
    const uint16_t modulated = in->law == (uint16_t)DTC_LAW_IM_SFVC || in->law == (uint16_t)DTC_LAW_IM_DFOC ||
                               in->law == (uint16_t)DTC_LAW_IM_DSVM ? 1U : 0U;
    const apply_fx_t vdc = fx_iq(g->vdc_iq);
    const apply_fx_t vmax = in->board.topology == (uint16_t)DTC_TOPO_SSTP
                                ? fx_div(fx_mul(vdc, fx_of(2U, 0)), fx_of(3U, 0))
                                : fx_div(vdc, fx_sqrt(fx_of(3U, 0)));
    const apply_fx_t itrip = fx_iq(in->prot.i_trip_iq);
    apply_fx_t num = fx_addsub(vmax, fx_mul(q->rs, itrip), 0U);
    int64_t row;
    if (modulated == 0U) {
        const apply_fx_t wmax = fx_div(fx_mul(fx_iq(in->speed.speed_limit_iq), fx_of(p, 0)), fx_of(p_in, 0));
        const apply_fx_t e = fx_mul(wmax, fx_mul(q->psir, fx_div(q->m, q->ls)));
        num = fx_addsub(num, fx_lt(e, vmax) != 0U ? e : vmax, 0U);
    }
    st->vmax = vmax;
    st->di = fx_div(fx_mul(q->ts, num), q->sls);
    if (ilim_n > 0U) {
        st->ilim = fx_addsub(itrip, fx_mul(fx_of(ilim_n, 0), st->di), 1U);
        row = fx_row(st->ilim, 24);
        if (row < 0) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->prot.i_lim_iq = (iq_t)(row >= (int64_t)in->prot.i_trip_iq ? (int64_t)in->prot.i_trip_iq - 1 : row);
    } else {
        st->ilim = fx_iq(in->prot.i_lim_iq);
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* the torque the current limit st->ilim allows: *t_lim the smaller of it and *t_lim; the current
 * limit switched off (0) when it allows no torque */
APP_NOINLINE static void limit_torque(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q,
                                      const apply_step_t *st, apply_fx_t *t_lim)
{
    /* the excursion above the held current (the converter's dtc_im_hold_margin_a): dI, or
     * on SFVC and on the DFOC's zeta = 0 design its SVM ripple V_max T_s / (4 sigma L_s) */
    apply_fx_t wc;
    const apply_fx_t h = in->law == (uint16_t)DTC_LAW_IM_SFVC ||
                                 (in->law == (uint16_t)DTC_LAW_IM_DFOC && in->u.im.dfoc.kp_iq > 0 &&
                                  in->machine.rs_iq > 0 && dfoc_zeta0(in, q, &wc) != 0U)
                             ? fx_div(fx_mul(q->ts, st->vmax), fx_mul(q->sls, fx_of(4U, 0))) : st->di;
    uint16_t any;
    const apply_fx_t t_i = im_torque_at(in, q, fx_addsub(st->ilim, h, 1U), &any);
    if (any == 0U && t_i.m == 0U) {
        out->prot.i_lim_iq = 0; /* no torque below the limit: the trip alone protects */
    } else if (any == 0U && fx_lt(t_i, *t_lim) != 0U) {
        *t_lim = t_i;
    }
}

/* the current step, the current limit and the torque it allows */
APP_NOINLINE static int16_t design_limits(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q)
{
    const dtc_im_design_cfg_t *g = &in->u.im.design;
    if (g->vdc_iq > 0 && g->torque_limit_iq > 0) {
        apply_step_t st;
        apply_fx_t t_lim = q->t_lim;
        int64_t row;
        if (limit_step(in, out, q, &st) != (int16_t)APP_IDENT_APPLY_OK) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        if (st.ilim.m != 0U) {
            limit_torque(in, out, q, &st, &t_lim);
        }
        row = fx_row(t_lim, 24);
        if (row < 1) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->speed.torque_limit_iq = (iq_t)row;
        out->speed.torque_ref_iq = fix_clamp32(out->speed.torque_ref_iq, -out->speed.torque_limit_iq,
                                               out->speed.torque_limit_iq);
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* DSVM's outer torque band */
APP_NOINLINE static int16_t design_band2(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q)
{
    const dtc_im_design_cfg_t *g = &in->u.im.design;
    const apply_fx_t vdc = fx_iq(g->vdc_iq);
    int64_t row;
    if (in->law == (uint16_t)DTC_LAW_IM_DSVM && (g->derived & DTC_IM_DESIGN_BAND2) != 0U && g->vdc_iq > 0) {
        /* Casadei eqs. 12, 15: dT = M (2/3 V_dc) phi_r* T_s / (sigma L_s L_r), L_r = L_s */
        const apply_fx_t dt = fx_div(fx_mul(fx_mul(q->m, fx_div(fx_mul(vdc, fx_of(2U, 0)), fx_of(3U, 0))),
                                            fx_mul(q->psir, q->ts)),
                                     fx_mul(q->sls, q->ls));
        const apply_fx_t b2 = fx_mul(dt, fx_of(2U, 0)), b1 = fx_iq(in->u.im.sw.torque_band_iq);
        row = fx_row(fx_lt(b2, b1) != 0U ? b1 : b2, 24);
        if (row < 0) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->u.im.dsvm.torque_band2_iq = (iq_t)row;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* the magnetisation's periods */
APP_NOINLINE static int16_t design_magn(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q)
{
    const dtc_im_design_cfg_t *g = &in->u.im.design;
    if (g->magn_wait_iq > 0) {
        const apply_fx_t ramp = fx_mul(fx_mul(fx_addsub(fx_of(1U, 0), fx_div(q->psir, q->m), 1U), q->rr), q->ts);
        const apply_fx_t psis = in->u.im.ref.psir_ref_iq > 0 ? fx_div(fx_mul(q->psir, q->ls), q->m)
                                                            : fx_iq(in->speed.flux_ref_iq);
        const int64_t n1 = ramp.m != 0U ? fx_ceil(fx_div(psis, ramp)) : -1;
        const int64_t n2 = fx_ceil(fx_div(fx_mul(q->ls, fx_iq(g->magn_wait_iq)), fx_mul(q->rr, q->ts)));
        if (n1 < 0 || n2 < 0 || n1 + n2 < 1 || n1 + n2 > 65535) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->u.im.ref.magn_periods = (uint16_t)(n1 + n2);
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* the DFOC current PIs */
APP_NOINLINE static int16_t design_dfoc(const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q)
{
    if (in->law == (uint16_t)DTC_LAW_IM_DFOC && in->u.im.dfoc.kp_iq > 0 && in->machine.rs_iq > 0) {
        const apply_fx_t kp_in = fx_iq(in->u.im.dfoc.kp_iq), sls_in = fx_iq(in->u.im.machine.sigma_ls_iq);
        const apply_fx_t rs_in = fx_iq(in->machine.rs_iq), ki_in = fx_iq(in->u.im.dfoc.ki_ts_iq);
        apply_fx_t wc;
        int64_t kp, ki;
        if (dfoc_zeta0(in, q, &wc) != 0U) {
            kp = fx_row(fx_mul(q->sls, wc), 24);
            ki = fx_row(fx_mul(fx_mul(q->rs, wc), q->ts), 24);
        } else {
            const apply_fx_t k = fx_div(q->sls, sls_in);
            kp = fx_row(fx_addsub(fx_mul(fx_addsub(kp_in, rs_in, 0U), k), q->rs, 1U), 24);
            ki = fx_row(fx_mul(ki_in, k), 24);
        }
        if (kp < 1 || ki < 0) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->u.im.dfoc.kp_iq = (iq_t)kp;
        out->u.im.dfoc.ki_ts_iq = (iq_t)ki;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* the encoder plausibility */
APP_NOINLINE static int16_t design_enc_plaus(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out,
                                           const apply_im_t *q, iq_t kt_iq)
{
    const dtc_im_design_cfg_t *g = &in->u.im.design;
    int64_t row;
    if (in->u.im.ref.enc_plaus_iq > 0 && g->torque_limit_iq > 0 && d->res.j_q12 > 0 && kt_iq > 0) {
        apply_fx_t slip = fx_div(fx_mul(q->rr, q->t_lim), fx_mul(q->psir, q->psir));
        const apply_fx_t acc = fx_div(fx_mul(fx_mul(q->t_lim, q->ts), fx_of(in->speed.speed_div, 0)),
                                      jn_of(d, in, out, kt_iq));
        if (in->u.im.fw.on != 0U && in->u.im.fw.psi_min_iq > 0) {
            const apply_fx_t psi_min = fx_iq(in->u.im.fw.psi_min_iq);
            const apply_fx_t kt = fx_div(q->lm, fx_mul(fx_mul(q->sls, q->ls), fx_of(2U, 0)));
            const apply_fx_t psir_min = fx_mul(psi_min, fx_sqrt(fx_div(q->lm, q->ls)));
            apply_fx_t t2 = fx_mul(kt, fx_mul(psi_min, psi_min)), s2;
            t2 = fx_lt(q->t_lim, t2) != 0U ? q->t_lim : t2;
            s2 = fx_div(fx_mul(q->rr, t2), fx_mul(psir_min, psir_min));
            slip = fx_lt(slip, s2) != 0U ? s2 : slip;
        }
        row = fx_row(fx_addsub(fx_div(fx_mul(slip, fx_of(3U, 0)), fx_of(2U, 0)), acc, 0U), 24);
        if (row < 1) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        out->u.im.ref.enc_plaus_iq = (iq_t)row;
    }
    return (int16_t)APP_IDENT_APPLY_OK;
}

/* The rows the converter designs from the machine and the settings it holds in u.im.design, again
 * on the identified machine (each only where the converter wrote what it needs, else the row in
 * force stays). pu of the configuration's bases; every quantity a chain of at most 16 fx
 * operations (each within 2^-30 relative, the chain within 2^-26, before the row's rounding to
 * nearest; a ceiling can differ by one only within that of an integer). The SI settings are kept: the torque limit as N.m (its pu
 * value times p_in / p, T_b being proportional to p), the speed limit as mechanical speed (the
 * electrical row times p / p_in), p_in the pole pairs of the configuration in force. Overflow:
 * fx mantissas stay below 2^31 (products below 2^62, sums below 2^63) and the exponents within
 * +-200 for rows of IQ range; a row beyond its format (fx_row's -1) or below its least value is
 * refused with APP_IDENT_APPLY_IM (the configuration in force unchanged).
 *  - The current step dI over one period (the converter's dtc_ilim_step_a): on DTC and DSC
 *    T_s (V_max + min(w_max (M / L_r) phi_r*, V_max) + R_s i_trip) / sigma L_s, on SFVC, DFOC and
 *    DSVM T_s (V_max + R_s i_trip) / sigma L_s; V_max = 2/3 V_dc (SSTP) or V_dc / sqrt(3) (FSTP),
 *    V_dc the nominal link (design.vdc_iq). With n = design.derived's bits 0-1 > 0 the current limit
 *    prot.i_lim_iq = i_trip - n dI (dtc_ilim_default_a; 0 when not positive; below i_trip_iq).
 *  - The torque limit (dtc_si_im_convert): the smaller of design.torque_limit_iq and the torque at
 *    I_lim - h (im_torque_at), h = dI, on SFVC and the DFOC's zeta = 0 design V_max T_s / (4 sigma L_s)
 *    (dtc_im_hold_margin_a); a current limit that allows no torque is switched off (0), as the
 *    converter does; the torque reference clamped to the limit.
 *  - DSVM, design.derived's bit 2: the outer band 2 dT with dT = (3/2) p M / (sigma L_s L_r)
 *    (2/3 V_dc) |phi_r*| T_s (Casadei eqs. 12, 15: a whole vector across the flux at standstill),
 *    at least the inner band.
 *  - The magnetisation's periods (design.magn_wait_iq = ln(1 / (1 - magn_frac)) > 0):
 *    ceil(phi_s,final / (rho T_s)) + ceil(tau_r ln(1 / (1 - magn_frac)) / T_s), rho T_s the ramp
 *    (1 - phi_r* / M) r_r T_s (derive_im), phi_s,final = phi_r* L_s / M on a rotor-flux reference,
 *    else phi_s*; tau_r / T_s = l_r / (r_r ts_pu) (the converter's start-up, Casadei eq. 20 at DC).
 *  - DFOC (Casadei sec. 13; the converter's design for the crossover w_c and damping zeta, which
 *    the gains in force, K_p' and K_i' T_s on the machine in force, sigma L_s' and R_s', hold):
 *    with zeta = 0 the converter makes K_p' = sigma L_s' w_c, K_i' T_s = R_s' w_c T_s, so
 *    K_i' T_s = R_s' (K_p' / sigma L_s') T_s, which the gains in force meet within 1 LSB plus 1e-5;
 *    then w_c = K_p' / sigma L_s' and K_p = sigma L_s w_c, K_i T_s = R_s w_c T_s. Otherwise they are
 *    zeta > 0's K_p' = 2 zeta w_c sigma L_s' - R_s', K_i' T_s = sigma L_s' w_c^2 T_s, and with the same
 *    w_c and zeta K_p = (K_p' + R_s') sigma L_s / sigma L_s' - R_s (> 0, else refused),
 *    K_i T_s = K_i' T_s sigma L_s / sigma L_s'. Gains set by hand since are taken for such a
 *    design. Nothing is written while K_p' = 0.
 *  - The encoder plausibility (u.im.ref.enc_plaus_iq > 0 in force, J identified; kt_iq the spin's
 *    torque constant): 1.5 w_slip + (p T_lim / J) T_s speed_div, w_slip = r_r T_lim / phi_r*^2
 *    (Casadei eq. 16), with the flux weakening (Casadei sec. 12) the larger of that and
 *    r_r min(T_lim, k_T psi_min^2) / ((M / L_s) psi_min)^2 (k_T of Casadei eq. 31,
 *    L_M / (2 sigma L_s L_s)); in pu the acceleration term is T_lim ts_pu speed_div / Jn. */
APP_NOINLINE static int16_t derive_im_design(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out, const apply_im_t *q,
                                iq_t kt_iq)
{
    int16_t rc = design_limits(in, out, q);
    if (rc == (int16_t)APP_IDENT_APPLY_OK) {
        rc = design_band2(in, out, q);
    }
    if (rc == (int16_t)APP_IDENT_APPLY_OK) {
        rc = design_magn(in, out, q);
    }
    if (rc == (int16_t)APP_IDENT_APPLY_OK) {
        rc = design_dfoc(in, out, q);
    }
    if (rc == (int16_t)APP_IDENT_APPLY_OK) {
        rc = design_enc_plaus(d, in, out, q, kt_iq);
    }
    return rc;
}

/* derive_im's machine for derive_im_design (apply_im_t), from L_s, sigma L_s and L_M (pu, IQ) */
APP_NOINLINE static void im_q_of(const app_ident_view_t *d, const dtc_config_t *in, const dtc_config_t *out,
                                 int64_t ls, int64_t sls, int64_t lm, apply_im_t *q)
{
    const dtc_im_cfg_t *im = &out->u.im;
    q->ls = fx_iq(ls);
    q->sls = fx_iq(sls);
    q->lm = fx_iq(lm);
    q->m = fx_sqrt(fx_mul(q->ls, q->lm));
    q->rs = fx_iq(out->machine.rs_iq);
    q->rr = fx_iq(d->res.im.rr_iq);
    q->ts = fx_iq(in->board.ts_pu_iq);
    q->psir = im->ref.psir_ref_iq > 0 ? fx_iq(im->ref.psir_ref_iq)
                                      : fx_mul(fx_iq(in->speed.flux_ref_iq), fx_sqrt(fx_div(q->lm, q->ls)));
    q->t_lim = fx_div(fx_mul(fx_iq(in->u.im.design.torque_limit_iq), fx_of(in->machine.pole_pairs, 0)),
                      fx_of(out->machine.pole_pairs, 0));
}

/* The induction machine's rows (the file comment). */
static int16_t derive_im(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    dtc_im_cfg_t *im = &out->u.im;
    int64_t ls, sls, lm, m, kr, inv_ks, kt, mk, psir, i_m, ramp, gain = 0;
    iq_t kt_spin;
    const int16_t rc = derive_common(d, in, out, &gain);
    if (rc != (int16_t)APP_IDENT_APPLY_OK) {
        return rc;
    }
    /* sigma L_s (the voltage steps), L_s (turning: psi / i_d; standing when that is not above
     * sigma L_s, a spin that measured no flux), L_M = L_s - sigma L_s */
    sls = l_pu(d->res.im.lsig_ts_iq, in);
    ls = d->res.im.id_iq > 0 && d->res.psi_iq > 0 ? div_shl_round(d->res.psi_iq, 24U, d->res.im.id_iq) : 0;
    if (!(ls > sls)) {
        ls = l_pu(d->res.im.ls_ts_iq, in);
    }
    if (sls < 1 || ls > (int64_t)0x7FFFFFFF || !(ls > sls) || d->res.im.rr_iq <= 0) {
        return (int16_t)APP_IDENT_APPLY_IM;
    }
    lm = ls - sls;
    /* T model with L_ls = L_lr (L_r = L_s): M = sqrt(L_s L_M), L_r / M = L_s / M = sqrt(L_s / L_M),
     * M / L_s = sqrt(L_M / L_s), sigma L_s = sigma L_r = the identified sigma L_s */
    m = isqrt_round(ls * lm);
    kr = div_shl(ls, 48U, lm);
    if (kr < 0) {
        return (int16_t)APP_IDENT_APPLY_IM;
    }
    kr = isqrt_round(kr);
    inv_ks = isqrt_round(div_shl(lm, 48U, ls)); /* lm < ls: below 2^48 */
    /* Casadei eq. 34's k_T = (1 - sigma) / (2 sigma l_s) = L_M / (2 sigma L_s L_s) */
    kt = div_shl_round(lm, 47U, sls * ls);
    /* T_s / tau_r = T_s w_b r_r / l_r (Q31) */
    mk = div_shl_round((int64_t)in->board.ts_pu_iq * (int64_t)d->res.im.rr_iq, 7U, ls);
    if (kr > (int64_t)0x7FFFFFFF || kt < 1 || kt > (int64_t)0x7FFFFFFF || mk < 1 || mk > (int64_t)0x7FFFFFFF) {
        return (int16_t)APP_IDENT_APPLY_IM;
    }
    im->machine.rr_iq = d->res.im.rr_iq;
    im->machine.sigma_ls_iq = (iq_t)sls;
    im->machine.sigma_lr_iq = (iq_t)sls;
    im->machine.kr_iq = (iq_t)kr;
    im->machine.ks_iq = (iq_t)kr;
    im->machine.inv_ks_iq = (iq_t)inv_ks;
    im->machine.m_iq = (iq_t)m;
    im->fw.kt_iq = (iq_t)kt;
    im->ref.magn_k_q31 = (q31_t)mk;
    /* the rotor-flux reference: the configured one, or the stator flux's at no load, (M / L_s)
     * phi_s*; 1 / its square when it is derived: L_s / (phi_s*^2 L_M) */
    if (im->ref.psir_ref_iq > 0) {
        psir = im->ref.psir_ref_iq;
    } else {
        const int64_t inv_sq = ls_over_lm_x2(ls, lm, (int64_t)in->speed.flux_ref_iq, 72U);
        if (inv_sq < 1 || inv_sq > (int64_t)0x7FFFFFFF) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        im->ref.inv_psir_sq_iq = (iq_t)inv_sq;
        psir = ((int64_t)in->speed.flux_ref_iq * inv_ks + ((int64_t)1 << 23)) >> 24;
    }
    /* the start-up's flux ramp: (I_n - phi_r* / M) r_r T_s, I_n the rated current = the current
     * base (the identification's), refused when the magnetising current is not below it */
    i_m = div_shl_round(psir, 24U, m);
    if (i_m < 0 || i_m >= ((int64_t)1 << 24)) {
        return (int16_t)APP_IDENT_APPLY_IM;
    }
    ramp = (((((int64_t)1 << 24) - i_m) * (int64_t)d->res.im.rr_iq + ((int64_t)1 << 23)) >> 24) * in->board.ts_pu_iq;
    ramp = (ramp + ((int64_t)1 << 23)) >> 24;
    if (ramp < 1) {
        return (int16_t)APP_IDENT_APPLY_IM;
    }
    im->ref.magn_ramp_iq = (iq_t)ramp;
    if (out->law == (uint16_t)DTC_LAW_IM_DFOC) {
        /* i_d* = phi_r* / M, i_q per torque l_r / (m phi_r*) = sqrt(L_s / (L_M phi_r*^2)) */
        const int64_t q2 = ls_over_lm_x2(ls, lm, psir, 96U);
        const int64_t q = q2 < 0 ? -1 : isqrt_round(q2);
        if (q < 1 || q > (int64_t)0x7FFFFFFF) {
            return (int16_t)APP_IDENT_APPLY_IM;
        }
        im->dfoc.id_ref_iq = (iq_t)i_m;
        im->dfoc.iq_per_t_iq = (iq_t)q;
    }
    /* the spin's fit is over k_t = 3/2 p L_M i_d: kt = L_M i_d in pu (app_ident_im.c) */
    kt_spin = (iq_t)((lm * (int64_t)d->res.im.id_iq + ((int64_t)1 << 23)) >> 24);
    {
        apply_im_t q;
        int16_t rc2;
        im_q_of(d, in, out, ls, sls, lm, &q);
        rc2 = derive_im_design(d, in, out, &q, d->res.j_q12 > 0 ? kt_spin : 0);
        if (rc2 != (int16_t)APP_IDENT_APPLY_OK) {
            return rc2;
        }
    }
    return derive_speed(d, in, out, kt_spin);
}
#endif

void app_ident_view_of(const app_ident_t *d, app_ident_view_t *v)
{
    v->step = d->step;
    v->fail = d->fail;
    v->fail_step = d->fail_step;
    v->fail_detail = d->fail_detail;
    v->im_on = d->im_on;
    v->vdc_iq = d->vdc_iq;
    v->res = d->res;
}

int16_t app_ident_derive(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out)
{
    if (d->step != (uint16_t)APP_IDENT_DONE) {
        return (int16_t)APP_IDENT_APPLY_NOT_DONE;
    }
#if DTC_LAW_PM_LINKED
    if (in->law == (uint16_t)DTC_LAW_PM_DTC && d->im_on == 0U) {
        *out = *in;
        return derive_pm(d, in, out);
    }
#endif
#if DTC_LAW_IM_LINKED
    if (dtc_law_is_im(in->law) != 0U && d->im_on != 0U) {
        *out = *in;
        return derive_im(d, in, out);
    }
#endif
    (void)in;
    (void)out;
    return (int16_t)APP_IDENT_APPLY_LAW;
}
