/*
 * app_ident_im.c - self-commissioning of an induction machine at standstill (background only;
 * the 50 us path is app_ident.c's HOLD and PULSE segments: sums, no division). docs/commissioning.md
 * "Induction machine".
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
 * previous pass's tau_r (taur, 0 on the first); L_s into m->res.ls_ts_iq. Returns 0 when the rotor
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
    m->res.ls_ts_iq = fix_sat32(app_ident_div64(psi_s * 16777216, di_end));
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
        rrg = fix_sat32(app_ident_div64((int64_t)fix_sub32(m->res.ls_ts_iq, lsig) * 16, (int64_t)taur));
    }
    m->res.lsig_ts_iq = lsig;
    m->res.taur_q4 = taur;
    m->res.rr_iq = fix_sat32(app_ident_div64((int64_t)m->res.ls_ts_iq * 16, (int64_t)taur));
    /* Bounds: L_s as the PM's L (1/16 .. 4096 x Z_b Ts); sigma L_s between 1/16 x Z_b Ts and half
     * of L_s (sigma < 1/2: a machine with a magnetising inductance); R_r as R_s (1/4096 .. 1/2 Z_b). */
    if (m->res.ls_ts_iq < IQ(1.0 / 16.0) || m->res.ls_ts_iq > IQ(4096.0 - 1.0)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LS);
        return;
    }
    if (lsig < IQ(1.0 / 16.0) || lsig > (m->res.ls_ts_iq >> 1)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_IM_LSIG);
        return;
    }
    if (m->res.rr_iq < IQ(1.0 / 4096.0) || m->res.rr_iq > IQ(0.5)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_IM_TAUR);
    }
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
    m->res.ls_ts_iq = 0;
    m->res.lsig_ts_iq = 0;
    m->res.taur_q4 = 0;
    m->res.rr_iq = 0;
    d->im_on = 1U;
    /* the step from zero: the reference steps (rate 0), the regulator limits the rise */
    im_window(d, im_levels[0], 0);
}

void app_ident_im_service(app_ident_t *d)
{
    app_ident_im_t *const m = &d->u.im;
    iq_t mv, mi;
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
        app_ident_next_step(d, (uint16_t)APP_IDENT_DONE);
        d->seg = (uint16_t)APP_IDENT_SEG_OFF;
        return;
    }
    /* the regulated gap ended: the next step */
    d->sub = 0U;
    im_pulse(d);
}
