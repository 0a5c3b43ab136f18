/*
 * app_ident_im.c - self-commissioning of an induction machine (background only; the 50 us path is
 * app_ident.c's HOLD, PULSE and SPIN segments: sums, products, no division). docs/commissioning.md
 * "Induction machine". Steps 1-3 at standstill, 4-5 turning the rotor (file comment's end).
 *
 * The machine at standstill (Casadei eqs. A6-A9 with w = 0), eliminating the rotor current:
 *   v = R_s i + d psi_s / dt,  psi_s = sigma L_s i + psi_R,  d psi_R / dt = R_R i - psi_R / tau_r
 * (psi_R = (M / L_r) phi_r, R_R = R_r (M / L_r)^2, tau_r = L_r / R_r, L_M = M^2 / L_r = R_R tau_r,
 * L_s = sigma L_s + L_M). A DC current produces no torque, so the rotor stays at rest.
 *   1. R_s (step RS): the current is held at 1/4 of rated, stepped to 3/4 (the DC step of 3.),
 *      then held at 1 and 1/2; each level is held in windows until the axis voltage settles (the
 *      rotor flux settles with tau_r), its last window is the level's point, and the PM's line
 *      V = R I + V_0 is fitted through the four points (app_ident_fit_line). The voltage summed is
 *      the one the compare values apply (app_ident_im_quant).
 *   2. sigma L_s (step LS): on the settled half-rated hold, voltage steps of V_b/8 until the
 *      current rose by 0.4 pu: over a step much shorter than tau_r, psi_R moves by R_R times the
 *      rise's integral, so dv = (R + R_R) di + sigma L_s d(di)/dt and
 *      sigma L_s = (dv n Ts - (R + R_R) Ts sum_trapezoid(di)) / rise (the PM's L_s with R_R added).
 *   3. L_s, tau_r, R_r (from the DC step of step 1, once R, V_0 and sigma L_s are known), in
 *      deviations from the settled state before the step (di = i - i_0, ...):
 *      dpsi_s(t) = integral (v - R i - V_0) dt, L_s = dpsi_s(T) / di(T) at the settled end T;
 *      integrating d psi_R / dt = R_R i - psi_R / tau_r from 0 to T with dpsi_R(T) = L_M di(T)
 *      gives the area
 *        tau_r = integral_0^T (di / di(T) - dpsi_R / dpsi_R(T)) dt,  psi_R = psi_s - sigma L_s i,
 *      which needs no exponential fit and holds for any shape of the current's rise (the
 *      regulator's); the flux still moving at T is added as its tail (im_taur). Then
 *      R_R = L_M / tau_r and R_r = L_r / tau_r with L_r = L_s (L_lr = L_ls).
 * R_R needs sigma L_s and sigma L_s needs R_R: the background iterates the two (four passes; the
 * R_R term is about 4 % of a step's volt-seconds on the 4 kW machine, dv = V_b / 8 over 0.7 ms,
 * and a pass's error in R_R moves sigma L_s by that share of it).
 *   4. Pole pairs and direction (step ENCODER, im_pole_start / im_pole_service): a current vector
 *      of the magnetising current i_d (the configured stator flux over L_s) turned at w_b / 8
 *      electrical (SEG_SPIN with no encoder term); the unloaded rotor follows it at the slip of
 *      its friction, so the counts per electrical turn give p = enc_counts / (counts per turn).
 *      The current regulator takes gains from sigma L_s and R, and the legs' drops from V_0 are
 *      fed forward: with the board's gains and the drops left to the regulator the rotor hunts
 *      about the field (the current-fed rotor's swing is damped by 1 / (2 sqrt(K tau_r / J)) only).
 *   5. Spin (step SPIN, im_spin_start, then app_ident_results.c's spin and coast): indirect
 *      rotor-flux orientation on the encoder, the slip of Casadei eq. 16 in steady state,
 *      omega_sl = i_q / (tau_r i_d), i_d as in 4 and a small q current. In the rotor-flux frame at
 *      constant currents (Casadei eqs. A6-A9) v_q = R_s i_q + omega_e L_s i_d: the q voltage's
 *      slope over the electrical speed is L_s i_d (the PM's psi_m fit, res.psi_iq), L_s at the
 *      configured flux while turning; the torque is 1.5 p L_M i_d i_q, so the PM's J, B, T_c rows
 *      hold with k_t = 1.5 p L_M i_d (L_M = L_s - sigma L_s). A rotor that turned in 4 but stays
 *      below half the spin speed carries a load: coupled_load.
 */
#include "app_ident_internal.h"

/* IM timing, control periods. */
#define IM_WIN 512U              /* settling window (20.5 ms at 40 us) */
#define IM_WIN_MAX 200U          /* the longest wait for a level to settle (4.1 s at 40 us) */
#define IM_SETTLED_N 2U          /* consecutive windows that pass */
#define IM_WIN_RELAX 50U         /* ... a quarter of the LSB after this many windows */
#define IM_LSB_SHIFT 4U          /* ... and at least 1/2^IM_LSB_SHIFT of the duty's LSB */
#define IM_BASE 4U               /* the test compares the last IM_BASE windows with the IM_BASE before */
#define IM_SETTLE_SHIFT 13U      /* the test: a window's mean moved by less than 1/8192 of its value */
#define IM_PULSE_DV IQ_FRAC(1, 8) /* the voltage step, V_b / 8 */
#define IM_ITER 4U
#define IM_POLE_RAMP 16U         /* encoder step: windows of the field's speed ramp (0.26 s at 40 us) */
#define IM_POLE_SETTLE 24U       /* encoder step: windows before the sums (the ramp, then 8 to settle) */
#define IM_SPIN_A 4U             /* spin: the first window of the fits (the q current's step and the
                                  * regulator's settling before it) */
#define IM_POLE_MEAS 16U         /* encoder step: windows summed */
#define IM_SPIN_IQ IQ_FRAC(1, 8) /* spin: the q current at p = 2; small, so that the acceleration spans many
                                  * windows on a light rotor and the field orientation's error from
                                  * a tau_r off by 10 % stays below 1 % of the torque */

/* The DC levels: a quarter of rated first (the current leaves the dead time's zone around zero,
 * where the commanded voltage is not the applied one), then the step to 3/4 whose transient is
 * integrated (IM_STEP), then rated and half rated. */
static const iq_t im_levels[APP_IDENT_R_LEVELS] = {IQ(0.25), IQ(0.75), IQ(1.0), IQ(0.5)};
#define IM_STEP 1U

/* x r >> 24 for |x| < 2^62 and |r| < 2^31 without a 64 x 64 product: (hi 2^24 + lo) r >> 24 =
 * hi r + (lo r >> 24), hi r < 2^62 for |x| < 2^55. Rounds toward minus infinity in the low part. */
static int64_t mul_q24(int64_t x, int32_t r)
{
    const int64_t ax = x < 0 ? -x : x;
    const int64_t hi = ax >> 24;
    const int64_t lo = ax & (((int64_t)1 << 24) - 1);
    const int64_t p = hi * (int64_t)r + ((lo * (int64_t)r) >> 24);
    return x < 0 ? -p : p;
}

/* Background: a regulated window at level i (HOLD, reference axis res.axis). The first window of
 * a level ramps the current (step 0: a step, rate 0), later ones hold it. */
static void im_window(app_ident_t *d, iq_t i, iq_t rate)
{
    app_ident_post_hold(d, 0U, 0U, i, rate, 0U, IM_WIN, 0U);
}

/* Background: one voltage step of IM_PULSE_DV on the half-rated hold (PULSE, app_ident.h). */
static void im_pulse(app_ident_t *d)
{
    d->seg = (uint16_t)APP_IDENT_SEG_PULSE;
    d->dv_iq = IM_PULSE_DV;
    d->di_stop_iq = IQ_FRAC(2, 5); /* from the half-rated hold: at most 0.9 x rated */
    d->n_meas = ID_PULSE_MAX;
    d->done = 0U;
    d->go = 1U;
}

/* Background: the window just ended, into the DC step's integrals when the level is the step
 * from zero. The window's means stand for every period since the previous window's end (the ISR's
 * two unsummed periods per window and the background's lag included). Returns 1 once the level
 * has settled: its mean voltage and current moved by less than 1/2^IM_SETTLE_SHIFT of their
 * values over IM_SETTLED_N windows. */
static uint16_t im_settle(app_ident_t *d, iq_t *mv, iq_t *mi)
{
    app_ident_im_t *const m = &d->u.im;
    const uint32_t span = d->tick - m->tick_prev;
    m->tick_prev = d->tick;
    *mv = fix_sat32(app_ident_div64(d->sum_v, (int64_t)d->n_meas));
    *mi = fix_sat32(app_ident_div64(d->sum_i, (int64_t)d->n_meas));
    {
        /* An open leg on the SSTP's alpha axis: with leg B or C open the other two carry
         * i_a = -i_c (or -i_b), whose beta component i_a / sqrt(3) the regulator cannot null, so
         * the quadrature current stays; more than a quarter of the parallel one is named. (Leg A
         * open: no alpha current at all, app_ident.c's open-phase test.) */
        const int64_t mq = app_ident_div64(d->sum_q, (int64_t)d->n_meas);
        if (m->n_win > 0U && (mq < 0 ? -mq : mq) * 4 > (*mi < 0 ? -(int64_t)*mi : (int64_t)*mi)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_OPEN_PHASE, (int16_t)m->level);
            return 0U;
        }
    }
    if (m->level == IM_STEP) {
        const int64_t av0 = m->a_v, ai0 = m->a_i;
        m->a_v += (int64_t)*mv * (int64_t)span;
        m->a_i += (int64_t)*mi * (int64_t)span;
        /* the integrals of a_v, a_i: exact for means constant over the window (trapezoid) */
        m->b_v += app_ident_div64((av0 + m->a_v) * (int64_t)span, 2);
        m->b_i += app_ident_div64((ai0 + m->a_i) * (int64_t)span, 2);
        m->t += span;
    }
    {
        /* y = v - rho i: the regulator's current noise moves v along the resistance, so the test
         * follows y, rho the slope from the previous level's point (0 on the step from zero) */
        iq_t rho = 0;
        iq_t y;
        if (m->level > 0U) {
            const int64_t di = (int64_t)*mi - (int64_t)d->res.level_i_iq[m->level - 1U];
            const int64_t dv = (int64_t)*mv - (int64_t)d->res.level_v_iq[m->level - 1U];
            rho = (di > 0 ? di : -di) > (int64_t)IQ(1.0 / 16.0) ? fix_sat32(app_ident_div64(dv * 16777216, di)) : 0;
        }
        y = fix_sub32(*mv, iq_mpy(rho, *mi));
        m->y_hist[m->n_win % (2U * IM_BASE)] = y;
        if (m->n_win + 1U >= 2U * IM_BASE) {
            /* the last IM_BASE windows' sum against the IM_BASE before them; the threshold is
             * 1/2^IM_SETTLE_SHIFT of the voltage, at least a sixteenth of the duty's LSB (IM_LSB_SHIFT)
             * (3 quant_k: the regulator dithers between LSBs, app_ident_im_quant) */
            int64_t dy = 0;
            int64_t thr = (*mv < 0 ? -(int64_t)*mv : (int64_t)*mv) >> IM_SETTLE_SHIFT;
            uint16_t k;
            for (k = 0U; k < IM_BASE; k++) {
                dy += (int64_t)m->y_hist[(m->n_win - k) % (2U * IM_BASE)] -
                      (int64_t)m->y_hist[(m->n_win - k - IM_BASE) % (2U * IM_BASE)];
            }
            {
                /* after IM_WIN_RELAX windows a regulator dithering between LSBs is taken as
                 * settled at a quarter LSB (the flux's tail is added, im_taur) */
                const int64_t lsb = ((int64_t)m->quant_k * 3) >> (m->n_win < IM_WIN_RELAX ? IM_LSB_SHIFT : 2U);
                if (thr < lsb) {
                    thr = lsb;
                }
            }
            if ((dy < 0 ? -dy : dy) <= thr * (int64_t)IM_BASE) {
                m->n_ok++;
            } else {
                m->n_ok = 0U;
            }
        }
    }
    m->n_win++;
    if (m->n_ok >= IM_SETTLED_N) {
        return 1U;
    }
    if (m->n_win >= IM_WIN_MAX) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_NOT_SETTLED, (int16_t)m->level);
    }
    return 0U;
}

/* sigma L_s from the voltage steps' sums with the series resistance r (pu, IQ): L / (Z_b Ts) in IQ. */
static iq_t im_lsig(const app_ident_im_t *m, iq_t r)
{
    const int64_t num = (int64_t)IM_PULSE_DV * (int64_t)m->p_n - mul_q24(m->p_trap, r);
    return m->p_rise > 0 ? fix_sat32(app_ident_div64(num * 16777216, m->p_rise)) : 0;
}

/* tau_r (periods, Q4) from the DC step's integrals (file comment 3) with sigma L_s = lsig and the
 * previous pass's tau_r (taur, 0 on the first); L_s into d->res.im.ls_ts_iq. Returns 0 when the rotor
 * flux's change is not positive (no result). Baseline: the line v = R i + V_0 through the four
 * levels. The rotor flux still moving when a level was taken (its excess voltage e = v - R i - V_0,
 * decaying with tau_r) is added as its exponential tail: e tau_r of flux, e tau_r^2 of the area;
 * e_0 of the level before the step is flux that level still owed. Units: psi in IQ x periods,
 * areas in IQ x periods^2; L / (Z_b Ts) in IQ times a current integral (IQ x periods) >> 24 is
 * IQ x periods^2. Magnitudes: e < 2^22, tau_r Q4 < 2^20: e tau_r^2 < 2^54 before the shifts. */
static int32_t im_taur(app_ident_t *d, iq_t lsig, int32_t taur)
{
    app_ident_im_t *const m = &d->u.im;
    const int64_t t = (int64_t)m->t;
    const int64_t i0 = (int64_t)d->res.level_i_iq[IM_STEP - 1U];
    const int64_t di_end = (int64_t)m->i_end - i0;
    const int64_t v0 = (int64_t)d->res.v0_iq;
    const int64_t e_end = (int64_t)d->res.level_v_iq[IM_STEP] - (int64_t)iq_mpy(d->res.r_iq, m->i_end) - v0;
    const int64_t e_0 = (int64_t)d->res.level_v_iq[IM_STEP - 1U] - (int64_t)iq_mpy(d->res.r_iq, (iq_t)i0) - v0;
    const int64_t tail = app_ident_div64((e_end - e_0) * (int64_t)taur, 16);
    const int64_t tail2 = app_ident_div64(app_ident_div64(e_end * (int64_t)taur, 16) * (int64_t)taur, 16);
    /* deviations from the state before the step: psi_s - L_s i0, psi_R - L_M i0, i - i0 */
    const int64_t psi_s = m->a_v - mul_q24(m->a_i, d->res.r_iq) - v0 * t + tail;
    const int64_t int_di = m->a_i - i0 * t;
    const int64_t psi_r = psi_s - mul_q24(di_end, lsig);
    const int64_t int_psi_r = m->b_v - mul_q24(m->b_i, d->res.r_iq) - app_ident_div64(v0 * t * t, 2) -
                              mul_q24(int_di, lsig) - tail2;
    if (psi_r <= 0 || di_end <= 0) {
        return 0;
    }
    d->res.im.ls_ts_iq = fix_sat32(app_ident_div64(psi_s * 16777216, di_end));
    return fix_sat32(app_ident_div64(int_di * 16, di_end) - app_ident_div64(int_psi_r * 16, psi_r));
}

/* Background: sigma L_s, L_s, tau_r, R_r, R_R (file comment 2-3) and their bounds. */
static void im_results(app_ident_t *d)
{
    app_ident_im_t *const m = &d->u.im;
    iq_t rrg = 0, lsig = 0;
    int32_t taur = 0;
    uint16_t k;
    for (k = 0U; k < IM_ITER; k++) {
        lsig = im_lsig(m, fix_add32(d->res.r_iq, rrg));
        taur = im_taur(d, lsig, taur);
        if (taur <= 16) { /* below one period: nothing measured */
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_IM_TAUR);
            return;
        }
        rrg = fix_sat32(app_ident_div64((int64_t)fix_sub32(d->res.im.ls_ts_iq, lsig) * 16, (int64_t)taur));
    }
    d->res.im.lsig_ts_iq = lsig;
    d->res.im.taur_q4 = taur;
    d->res.im.rr_iq = fix_sat32(app_ident_div64((int64_t)d->res.im.ls_ts_iq * 16, (int64_t)taur));
    /* Bounds: L_s as the PM's L (1/16 .. 4096 x Z_b Ts); sigma L_s between 1/16 x Z_b Ts and half
     * of L_s (sigma < 1/2: a machine with a magnetising inductance); R_r as R_s (1/4096 .. 1/2 Z_b). */
    if (d->res.im.ls_ts_iq < IQ(1.0 / 16.0) || d->res.im.ls_ts_iq > IQ(4096.0 - 1.0)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LS);
        return;
    }
    if (lsig < IQ(1.0 / 16.0) || lsig > (d->res.im.ls_ts_iq >> 1)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_IM_LSIG);
        return;
    }
    if (d->res.im.rr_iq < IQ(1.0 / 4096.0) || d->res.im.rr_iq > IQ(0.5)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_IM_TAUR);
    }
}

/* Background: the encoder step of an induction machine (file comment 4): the field at w_b / 8
 * electrical, d axis on the standstill steps' axis (where the rotor flux is), the q axis (the
 * reference axis of SEG_SPIN) 90 degrees ahead; i_q = 0 and i_d the magnetising current of the
 * configured stator flux, i_d = phi_s* / L_s (L_s pu = L_s / (Z_b Ts) x Ts w_b), within 1/8 .. 3/4
 * of rated. The field's turn per period w_b Ts / 8 in angle_t Q16: ts_pu 2^32 / (8 2 pi) =
 * ts_pu_iq 2^29 / (2 pi 2^24) (ts_pu_iq < 2^24: < 2^53), reached by a ramp (im_pole_service). */
static void im_pole_start(app_ident_t *d, const dtc_config_t *cfg)
{
    app_ident_im_t *const m = &d->u.im;
    const iq_t ls_pu = iq_mpy(d->res.im.ls_ts_iq, cfg->board.ts_pu_iq);
    iq_t id = ls_pu > 0 ? fix_sat32(app_ident_div64((int64_t)cfg->speed.flux_ref_iq * 16777216, (int64_t)ls_pu)) : 0;
    id = iq_sat(id, IQ_FRAC(1, 8), IQ_FRAC(3, 4));
    d->res.im.id_iq = id;
    app_ident_next_step(d, (uint16_t)APP_IDENT_ENCODER);
    m->pole_rate_q16 = (uint32_t)app_ident_div64((int64_t)cfg->board.ts_pu_iq * ((int64_t)1 << 29), ID_IQ_2PI);
    d->im_rate_q16 = (uint32_t)app_ident_div64((int64_t)m->pole_rate_q16, (int64_t)IM_POLE_RAMP);
    d->gain_q16 = 0U;
    d->th_q16 = (uint32_t)(angle_t)(d->res.axis + ANGLE(0.25)) << 16;
    d->i_perp_ref = fix_neg32(id);
    /* the regulator's gains from the machine now known: a closed current loop of 1 / (32 Ts)
     * (781 rad/s at 40 us), kp = sigma L_s / (32 Ts), ki Ts = R Ts / (32 Ts). The board's gains
     * close it at about 70 rad/s on the 4 kW machine: too slow to impose the current, and a
     * machine half voltage-fed at the field's low frequency hunts about it (measured: the speed
     * swinging between 35 % and 140 % of the field's); and the spin's rising back-EMF would
     * leave the q current short. */
    d->kp_iq = fix_rshift_rnd32(d->res.im.lsig_ts_iq, 5U);
    d->ki_iq = fix_rshift_rnd32(d->res.r_iq, 5U);
    /* The inverter's drop from step RS as a feed-forward on each leg (app_ident.c ident_pwm): left
     * to the regulator, its square wave at six times the field's frequency, near the loop's
     * bandwidth, moves the q current by 15 % from window to window and the rotor hunts about
     * the field. V_0 on the alpha axis is 2/3 of two legs' drops: a leg's is 3/4 V_0. */
    d->comp_iq = iq_mpy(d->res.v0_iq, IQ(0.75));
    m->pole_win = 0U;
    m->pole_sum_v = 0;
    d->fresh = 1U;
    app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, 0);
}

static void im_spin_start(app_ident_t *d, const dtc_config_t *cfg);

/* Background: after each window of the encoder step. IM_POLE_SETTLE windows for the rotor's run-up
 * and the rotor flux's turn, then IM_POLE_MEAS windows summed: over P periods the field made
 * F = rate P / 2^32 electrical turns and the count moved dpos, so the counts per electrical turn
 * are dpos / F and p = enc_counts F / |dpos| = N rate P / (|dpos| 2^32), rounded (N rate P < 2^14
 * 2^24 2^14 for the rig's encoders). The rotor lags the field by the slip, which only raises
 * enc_counts F / |dpos| (no load: friction's slip, well below 1 %): accepted from 1/64 below to
 * 1/16 above a whole number; outside, the line count is wrong (encoder_lines). A count that moved
 * less than 1/64 of a turn per electrical turn: the field's q voltage tells a rotor that follows
 * the field (omega_e L_s i_d: the encoder does not count) from one that does not (about
 * omega_e sigma L_s i_d plus the rotor's share at full slip: blocked). */
static void im_pole_service(app_ident_t *d, const dtc_config_t *cfg)
{
    app_ident_im_t *const m = &d->u.im;
    m->pole_win++;
    if (m->pole_win < IM_POLE_RAMP) {
        /* the field's speed ramps up over IM_POLE_RAMP windows: the rotor follows it without
         * swinging (at a step of the field's speed the current-fed rotor swings about it, its
         * damping ratio 1 / (2 sqrt(K tau_r / J)), 0.08 on the 4 kW machine, K = dT / d omega) */
        d->im_rate_q16 = (uint32_t)app_ident_div64((int64_t)m->pole_rate_q16 * (int64_t)(m->pole_win + 1U), (int64_t)IM_POLE_RAMP);
    }
    if (m->pole_win == IM_POLE_SETTLE) {
        m->pole_pos0 = d->still_ref;
        m->pole_tick0 = d->win_tick;
        m->pole_sum_v = 0;
    }
    if (m->pole_win >= IM_POLE_SETTLE) {
        m->pole_sum_v += d->sum_v;
    }
    if (m->pole_win < IM_POLE_SETTLE + IM_POLE_MEAS) {
        app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, 0);
        return;
    }
    {
        const int64_t dpos = (int64_t)d->still_ref + (int64_t)d->win_dpos - (int64_t)m->pole_pos0;
        const int64_t per = (int64_t)(uint32_t)(d->win_tick + (uint32_t)ID_SPIN_WIN - 1U - m->pole_tick0);
        const int64_t num = (int64_t)cfg->board.enc_counts * (int64_t)d->im_rate_q16 * per;
        const int64_t ad = dpos < 0 ? -dpos : dpos;
        const int64_t den = ad * ((int64_t)1 << 32);
        int64_t p, err;
        d->res.im.vq_pole_iq = fix_sat32(app_ident_div64(m->pole_sum_v, (int64_t)IM_POLE_MEAS * (int64_t)ID_SPIN_WIN));
        d->res.counts_per_turn = d->im_rate_q16 != 0U ? fix_sat32(app_ident_div64(dpos * ((int64_t)1 << 32), (int64_t)d->im_rate_q16 * per)) : 0;
        if (den * 64 < num) {
            /* the expected q voltage omega_e L_s i_d: omega_e Ts = rate 2 pi / 2^32 (IQ rad per
             * period, < 2^24), times L / (Z_b Ts) and i_d (IQ) */
            const iq_t w_ts = fix_sat32(((int64_t)d->im_rate_q16 * ID_IQ_2PI) >> 32);
            const iq_t vq_free = iq_mpy(iq_mpy(w_ts, d->res.im.ls_ts_iq), d->res.im.id_iq);
            app_ident_fail(d,
                           d->res.im.vq_pole_iq * 2 >= vq_free ? (uint16_t)APP_IDENT_FAIL_ENC_NOT_COUNTING
                                                               : (uint16_t)APP_IDENT_FAIL_BLOCKED,
                           (int16_t)d->res.counts_per_turn);
            return;
        }
        p = app_ident_div64(num + (den >> 1), den);
        if (p < 1 || p > 16) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_POLE_PAIRS);
            return;
        }
        err = p * den - num; /* negative for a rotor lagging the field */
        if (err > (num >> 6) || -err > (num >> 4)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_ENC_LINES, (int16_t)d->res.counts_per_turn);
            return;
        }
        d->res.pole_pairs = (uint16_t)p;
        d->res.enc_reversed = dpos < 0 ? 1U : 0U;
        d->res.enc_offset = 0U;
        /* the field's speed as a count change per window: rate N_win enc_counts / (p 2^32) */
        d->ff_dpos0 = fix_sat32(app_ident_div64((int64_t)d->im_rate_q16 * (int64_t)ID_SPIN_WIN * (int64_t)cfg->board.enc_counts,
                                                 p * ((int64_t)1 << 32)));
    }
    im_spin_start(d, cfg);
}

/* Background: the spin (file comment 5): indirect field orientation on the encoder, the reference
 * axis turning with the rotor's electrical angle (gain p 2^32 / enc_counts per count) plus the
 * slip of Casadei eq. 16 in the steady state of constant i_d, i_q: omega_sl = i_q / (tau_r i_d).
 * In angle_t Q16 per period: omega_sl Ts 2^32 / (2 pi) = (i_q / i_d) 16 / taur_q4 x 2^32 / (2 pi)
 * = r 2^12 / (taur_q4 2 pi) with r = i_q / i_d in Q24: t = r 2^24 / taur_q4 (< 2^44 for
 * taur_q4 >= 16 and 0 <= i_q <= i_d), rate = t 2^12 / (2 pi 2^24) (< 2^56 before the division);
 * im_slip sets it for a q current (the reference at the start, then each window's measured mean). The acceleration ends
 * at the speed where the back-EMF omega_e L_s i_d = omega_e phi_s* is half the voltage limit,
 * omega_e = v_lim / (2 phi_s*), pu. */
static void im_slip(app_ident_t *d, iq_t iq)
{
    const int64_t r = app_ident_div64((int64_t)iq_sat(iq, 0, d->res.im.id_iq) * 16777216, (int64_t)d->res.im.id_iq);
    const int64_t t = app_ident_div64(r * 16777216, (int64_t)d->res.im.taur_q4);
    d->im_rate_q16 = (uint32_t)app_ident_div64(t * 4096, ID_IQ_2PI);
}

static void im_spin_start(app_ident_t *d, const dtc_config_t *cfg)
{
    const int64_t pp = (int64_t)d->res.pole_pairs;
    /* i_q = IM_SPIN_IQ (2 / p)^2: the torque grows with p and the target's mechanical speed falls
     * with it, so the acceleration's time would go as 1 / p^2 (one window for a four-pole-pair
     * 4 kW rotor, which then overshoots into the voltage limit); this keeps it that of p = 2
     * (1/2 rated at p = 1, 1/32 at p = 4) */
    const iq_t iq = fix_sat32(app_ident_div64((int64_t)IM_SPIN_IQ * 4, pp * pp));
    app_ident_next_step(d, (uint16_t)APP_IDENT_SPIN);
    d->gain_q16 = (uint32_t)app_ident_div64((int64_t)d->res.pole_pairs << 32, (int64_t)cfg->board.enc_counts);
    im_slip(d, iq);
    d->spin_i_iq = iq;
    d->spin_a = IM_SPIN_A;
    d->spin_w_iq = cfg->speed.flux_ref_iq > 0
                       ? fix_sat32(app_ident_div64((int64_t)d->v_lim_iq * 8388608, (int64_t)cfg->speed.flux_ref_iq))
                       : ID_SPIN_W;
    d->n_acc = 0U;
    d->n_coast = 0U;
    d->ff_w_k = app_ident_div64((int64_t)d->gain_q16 * ID_IQ_2PI, (int64_t)ID_SPIN_WIN);
    d->ff_psi_ts = iq_mpy(d->res.im.ls_ts_iq, d->res.im.id_iq);
    d->ff_prev = 0;
    d->v_ff_iq = 0;
    d->dv_ff_iq = 0;
    d->fresh = 0U; /* the field, its integrators and i_d go on from the encoder step */
    app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, iq);
}

/* Background: after an acceleration window of the spin, the q voltage's feed-forward for the next:
 * the back-EMF's rise omega_e L_s i_d since the encoder step (whose back-EMF the regulator's
 * integrators hold), from the window's count change x less the encoder step's:
 * omega_e Ts = x gain 2 pi / (2^32 N_win), in IQ x ff_w_k >> 32 (ff_w_k = gain 2 pi 2^24 / N_win),
 * times L_s i_d / (Z_b Ts).
 * The window's mean stands for its centre; the next window starts about half a window later: the
 * feed-forward starts at the mean plus half the last rise and rises by one rise per window. With
 * it, a PI of the board's gains (Z_b / 64, Z_b 4 rad/s) no longer trails the back-EMF's ramp (at
 * 0.46 pu/s on the 4 kW machine its error would be 0.11 pu of the 0.125 pu q current).
 * Scaling: |x| < 2^15, ff_w_k = gain 2^26.7 / 400 < 2^32 2^18: x ff_w_k < 2^63 for gain < 2^30. */
static void im_spin_ff(app_ident_t *d)
{
    const int64_t x = (int64_t)(d->res.enc_reversed != 0U ? -d->win_dpos : d->win_dpos) - (int64_t)d->ff_dpos0;
    const iq_t v = iq_mpy(fix_sat32((x * d->ff_w_k) >> 32), d->ff_psi_ts);
    const iq_t rise = fix_sub32(v, d->ff_prev);
    d->ff_prev = v;
    if (d->sub != 0U || d->n_acc == 0U) {
        d->v_ff_iq = d->sub != 0U ? 0 : d->v_ff_iq;
        d->dv_ff_iq = 0;
        return;
    }
    d->v_ff_iq = fix_add32(v, fix_rshift_rnd32(rise, 1U));
    d->dv_ff_iq = fix_sat32(app_ident_div64((int64_t)rise, (int64_t)ID_SPIN_WIN));
    /* the slip from the window's measured q current (Casadei eq. 16 with the current that flows,
     * not the reference) */
    im_slip(d, fix_sat32(app_ident_div64(d->sum_i, (int64_t)ID_SPIN_WIN)));
}

/* ISR: the sample just summed is the commanded voltage; the legs apply their compare values'
 * whole counts, alpha short by V_dc rq3 / (3 t1pr) (SSTP, the alpha injection axis of the IM): the
 * sum takes the applied voltage. The duty's LSB is V_dc / t1pr (0.1 V on the IM rig), and a
 * regulator resting between two LSBs would bias a level's mean by up to half of one: 1 % of R_s,
 * and over the DC step's seconds 15 % of its flux. Scaling: |rq3| <= 2^25, quant_k < 2^20:
 * product < 2^45; the result is IQ pu. */
void app_ident_im_quant(app_ident_t *d, int64_t rq3, uint16_t t1pr)
{
    d->u.im.t1pr = t1pr;
    d->sum_v -= (int64_t)fix_rshift_rnd64_sat32(rq3 * (int64_t)d->u.im.quant_k, 24U);
}

void app_ident_im_start(app_ident_t *d)
{
    app_ident_im_t *const m = &d->u.im;
    m->a_v = 0;
    m->a_i = 0;
    m->b_v = 0;
    m->b_i = 0;
    m->t = 0U;
    m->tick_prev = d->tick;
    m->i_end = 0;
    m->y_hist[0] = 0;
    m->n_win = 0U;
    m->n_ok = 0U;
    m->level = 0U;
    m->pulses = 0U;
    m->p_n = 0U;
    m->p_trap = 0;
    m->p_rise = 0;
    m->t1pr = 0U;
    m->quant_k = 0;
    m->pole_pos0 = 0;
    m->pole_tick0 = 0U;
    m->pole_sum_v = 0;
    m->pole_win = 0U;
    d->im_on = 1U;
    /* the step from zero: the reference steps (rate 0), the regulator limits the rise */
    im_window(d, im_levels[0], 0);
}

void app_ident_im_service(app_ident_t *d, const dtc_config_t *cfg)
{
    app_ident_im_t *const m = &d->u.im;
    iq_t mv, mi;
    if (d->step == (uint16_t)APP_IDENT_ENCODER) {
        im_pole_service(d, cfg);
        return;
    }
    if (d->step == (uint16_t)APP_IDENT_SPIN) {
        app_ident_spin_service(d, cfg);
        if (d->step == (uint16_t)APP_IDENT_SPIN) {
            im_spin_ff(d);
        }
        return;
    }
    if (m->quant_k == 0 && m->t1pr != 0U) {
        m->quant_k = fix_sat32(app_ident_div64((int64_t)d->vdc_iq, 3 * (int64_t)m->t1pr));
    }
    if (d->step == (uint16_t)APP_IDENT_RS) {
        if (im_settle(d, &mv, &mi) == 0U) {
            if (d->step == (uint16_t)APP_IDENT_RS) {
                im_window(d, im_levels[m->level], (iq_t)(IQ(1.0) / ID_LEVEL_RAMP));
            }
            return;
        }
        d->res.level_i_iq[m->level] = mi;
        d->res.level_v_iq[m->level] = mv;
        if (m->level == IM_STEP) {
            m->i_end = mi;
        }
        m->level++;
        m->n_win = 0U;
        m->n_ok = 0U;
        if (m->level < APP_IDENT_R_LEVELS) {
            /* the integrated step is a step of the reference (rate 0): the regulator shapes it */
            im_window(d, im_levels[m->level], m->level == IM_STEP ? 0 : (iq_t)(IQ(1.0) / ID_LEVEL_RAMP));
            return;
        }
        app_ident_fit_line(d);
        if (app_ident_rs_bounds(d) == 0U) {
            return;
        }
        app_ident_next_step(d, (uint16_t)APP_IDENT_LS);
        im_window(d, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP));
        return;
    }
    if (d->step != (uint16_t)APP_IDENT_LS) {
        return;
    }
    if (m->pulses == 0U && m->n_ok < IM_SETTLED_N + 1U) {
        /* the half-rated hold settling before the first step (n_ok IM_SETTLED_N + 1: settled) */
        if (im_settle(d, &mv, &mi) == 0U) {
            if (d->step == (uint16_t)APP_IDENT_LS) {
                im_window(d, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP));
            }
            return;
        }
        m->n_ok = IM_SETTLED_N + 1U;
        im_pulse(d);
        return;
    }
    if ((d->sub & 1U) == 0U) {
        /* a step ended (app_ident.c's PULSE: n step periods, the rise's samples summed in sum_i) */
        const iq_t rise = fix_sub32(d->i_last, d->i_first);
        m->p_n += d->n;
        m->p_trap += d->sum_i + (int64_t)fix_rshift_rnd32(rise, 1U);
        m->p_rise += (int64_t)rise;
        m->pulses++;
        d->sub = 1U;
        if (m->pulses < ID_PULSES) {
            app_ident_post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_PULSE_GAP, 16U, 0U);
            return;
        }
        im_results(d);
        if (d->step == (uint16_t)APP_IDENT_FAILED) {
            return;
        }
        im_pole_start(d, cfg);
        return;
    }
    /* the regulated gap ended: the next step */
    d->sub = 0U;
    im_pulse(d);
}
