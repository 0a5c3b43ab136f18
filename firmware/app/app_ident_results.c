/*
 * app_ident_results.c - the self-commissioning's evaluations in the background (flash on the
 * F2812; the 50 us path only sums, app_ident.c app_ident_isr): the R_s line through the DC
 * levels, the encoder's lines, pole pairs and offset from the dwells, and the spin step
 * (app_ident.h APP_IDENT_SPIN: the rotor accelerated on half-rated q current, then coasting with
 * the gates off; psi_m, J and the friction from the windows' sums).
 */
#include "app_ident_internal.h"

/* Least-squares line through the level means (background): R = S_xy / S_xx on deviations
 * from the means, V_0 = mean_v - R mean_i. Scaling: deviations |dx| < 2 pu (2^25), products
 * < 2^50, four of them < 2^52 in 64 bits; S_xx >> 24 is S_xx in IQ. */
void app_ident_fit_line(app_ident_t *d)
{
    int64_t mx = 0, my = 0, sxx = 0, sxy = 0;
    uint16_t k;
    for (k = 0U; k < APP_IDENT_R_LEVELS; k++) {
        mx += d->res.level_i_iq[k];
        my += d->res.level_v_iq[k];
    }
    mx = app_ident_div64(mx, (int64_t)APP_IDENT_R_LEVELS);
    my = app_ident_div64(my, (int64_t)APP_IDENT_R_LEVELS);
    for (k = 0U; k < APP_IDENT_R_LEVELS; k++) {
        const int64_t dx = (int64_t)d->res.level_i_iq[k] - mx;
        const int64_t dy = (int64_t)d->res.level_v_iq[k] - my;
        sxx += dx * dx;
        sxy += dx * dy;
    }
    sxx >>= 24;
    d->res.r_iq = sxx > 0 ? fix_sat32(app_ident_div64(sxy, sxx)) : 0;
    d->res.v0_iq = fix_sub32(fix_sat32(my), iq_mpy(d->res.r_iq, fix_sat32(mx)));
}

/* One move of the encoder step: a turn over the dwells per turn, angle_t LSB (three: 21845, one
 * LSB short of a third, so the last dwell is 3 LSB = 0.02 degree short of a full turn). */
uint32_t app_ident_span_of(const app_ident_t *d) { return d->n_dwell == 2U ? 32768UL : 21845UL; }

/* Encoder results from the dwell positions (background; app_ident.h). */
void app_ident_encoder_results(app_ident_t *d, const dtc_config_t *cfg)
{
    const int64_t n_q8 = (int64_t)cfg->board.enc_counts << 8;
    const int64_t delta = (int64_t)d->u.st.dwell_pos_q8[d->n_dwell] - (int64_t)d->u.st.dwell_pos_q8[0];
    const int64_t ad = delta < 0 ? -delta : delta;
    int64_t p;
    int32_t acc = 0;
    angle_t off0 = 0U;
    uint16_t j;
    d->res.counts_per_turn = fix_sat32(app_ident_div64(delta, 256));
    if (ad < (n_q8 >> 6)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_ENC_NOT_COUNTING, (int16_t)d->res.counts_per_turn);
        return;
    }
    d->res.enc_reversed = delta < 0 ? 1U : 0U;
    /* The rotor rests on the current actually flowing (store_dwell), so between the first and the
     * last dwell it turned one electrical turn plus the change of the current's angle from the
     * reference (on the FSTP the mid-point moves with the vector and a mid-point sensor's error
     * turns the current by a few degrees): travel = 2^16 + ang_n - ang_0, angle_t units (< 2^17).
     * p = enc_counts travel / (2^16 |delta|), rounded; n_q8 travel < 2^24 2^17 in 64 bits. */
    {
        const int64_t travel = 65536 + (int64_t)(int16_t)(uint16_t)((uint16_t)d->u.st.dwell_ang[d->n_dwell] -
                                                                     (uint16_t)d->u.st.dwell_ang[0]);
        const int64_t den = ad * 65536;
        int64_t err;
        p = app_ident_div64(n_q8 * travel + (den >> 1), den);
        if (p < 1 || p > 16) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_POLE_PAIRS);
            return;
        }
        err = p * den - n_q8 * travel;
        /* within 1/64 (1.6 %, 5.6 degrees electrical over the turn): the usual line-count mix-ups
         * (500 for 1024, 1000 for 512 or 1024) are 2.3 % or more off a whole pole-pair number */
        if ((err < 0 ? -err : err) > (n_q8 << 10)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_ENC_LINES, (int16_t)d->res.counts_per_turn);
            return;
        }
    }
    d->res.pole_pairs = (uint16_t)p;
    for (j = 0U; j < d->n_dwell; j++) {
        /* the raw count at the dwell (Q8), in [0, N) */
        const int64_t raw = ((int64_t)d->count0 << 8) + (int64_t)d->u.st.dwell_pos_q8[j];
        int64_t cq8 = raw - app_ident_div64(raw, n_q8) * n_q8;
        int64_t th;
        angle_t th_vec, off;
        if (cq8 < 0) {
            cq8 += n_q8;
        }
        if (d->res.enc_reversed != 0U) {
            cq8 = -cq8;
        }
        th = app_ident_div64(cq8 * p * 65536, n_q8);       /* electrical angle of the count, angle_t units */
        th_vec = (angle_t)(d->res.axis + (angle_t)(app_ident_span_of(d) * j) + (angle_t)d->u.st.dwell_ang[j]);
        off = (angle_t)((uint32_t)th_vec - (uint32_t)(uint16_t)(uint64_t)th); /* modulo one turn */
        if (j == 0U) {
            off0 = off;
        }
        acc += (int32_t)(int16_t)(uint16_t)(off - off0);
    }
    d->res.enc_offset = (angle_t)(off0 + (angle_t)(int16_t)app_ident_div64(acc, (int64_t)d->n_dwell));
}


/* Background: one spin window with the q current i (SEG_SPIN) or with the gates off (SEG_COAST). */
void app_ident_post_window(app_ident_t *d, uint16_t seg, iq_t i)
{
    d->seg = seg;
    d->slow = 0U;
    d->th_left_q16 = 0U;
    d->i_target = i;
    d->i_rate = (iq_t)(IQ(1.0) / ID_LEVEL_RAMP);
    d->n_meas = ID_SPIN_WIN;
    d->done = 0U;
    d->go = 1U;
}

/* Background: the row of the spin's integrated equation of motion between the centres of windows
 * x and y (app_ident.h units: speed in counts per period, torque in pu q current):
 *   J (w_y - w_x) + B (pos_y - pos_x) + T_c (t_y - t_x) = mean torque x (t_y - t_x),
 * times 2 N (N = ID_SPIN_WIN, w = dpos / N, pos at the centre pos0 + dpos / 2):
 *   r[0] = 2 (dpos_y - dpos_x), r[1] = N (2 pos0_y + dpos_y - 2 pos0_x - dpos_x), r[2] = 2 N (t_y - t_x).
 * Magnitudes: counts and periods below 2^26 over a spin: each element < 2^37. */
static void motion_row(const app_ident_win_t *x, const app_ident_win_t *y, int64_t r[3])
{
    r[0] = 2 * ((int64_t)y->dpos - (int64_t)x->dpos);
    r[1] = (int64_t)ID_SPIN_WIN * (2 * (int64_t)y->pos0 + (int64_t)y->dpos - 2 * (int64_t)x->pos0 - (int64_t)x->dpos);
    r[2] = 2 * (int64_t)ID_SPIN_WIN * (int64_t)(uint32_t)(y->tick0 - x->tick0);
}

/* Background: psi_m and the mechanics from the spin's windows (app_ident.h).
 * psi_m (Hoang eqs. 6-9, v = R i + d psi / dt, psi = L i + psi_m e^{j theta}, in the rotor frame at
 * constant current, i_d = 0: v_q = R i_q + w_e psi_m + the inverter's
 * threshold and dead-time drop along the current, constant for a current of one sign): the q
 * voltage's change less R (step RS's slope) times the q current's change, over the electrical
 * speed's change between windows A and B, w_e = dpos p 2 pi / (enc_counts N Ts):
 *   psi_pu = dv_q enc_counts N ts_pu / (ddpos p 2 pi).
 * Mechanics (J dw/dt + B w + T_c = T_e, T_e = k_t i_q): the two coast rows (no torque) fix
 * (J, B, T_c) up to a factor, their cross product (a, b, c): B / J = b / a, T_c / J = c / a; the
 * acceleration row (the measured q current's integral) gives J. Scaling as commented below. */
static void spin_results(app_ident_t *d, const dtc_config_t *cfg)
{
    const app_ident_win_t *const a_w = &d->u.sp.w[0];
    const app_ident_win_t *const b_w = &d->u.sp.w[1];
    const int64_t ddpos = (int64_t)b_w->dpos - (int64_t)a_w->dpos;
    int64_t r0[3], r1[3], r2[3], x[3];
    uint16_t k;
    if (ddpos <= 0) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_PSI);
        return;
    }
    {
        /* the slope of (v_q - R i_q) over the count change per window, least squares over every
         * window from A to B (not A and B alone: the windows are short against an electrical turn,
         * and what ripples at the electrical frequency, the FSTP's mid-point above all, would bias
         * a two-point slope by several per cent): slope = (n Sxy - Sx Sy) / (n Sxx - Sx^2), IQ per
         * count in Q8 (the products < 2^47 x 2^7 windows, num x 2^8 < 2^63) */
        const int64_t *const f = d->u.sp.fit;
        const int64_t n = (int64_t)d->n_acc - (int64_t)d->spin_a + 1; /* the windows spin_a .. n_acc */
        const int64_t num = n * f[3] - f[0] * f[1];
        const int64_t den = n * f[2] - f[0] * f[0];
        int64_t slope_q8, t;
        if (den <= 0 || n < 2) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_PSI);
            return;
        }
        slope_q8 = app_ident_div64(num * 256, den);
        t = app_ident_div64(slope_q8 * (int64_t)cfg->board.ts_pu_iq, 256 * (int64_t)d->res.pole_pairs);
        d->res.psi_iq = fix_sat32(app_ident_div64(t * (int64_t)ID_SPIN_WIN * (int64_t)cfg->board.enc_counts, ID_IQ_2PI));
    }
    /* Bounds: psi_m from 1/64 to 4 pu (the back-EMF at rated speed 1/64 .. 4 x V_dc) */
    if (d->res.psi_iq < IQ(1.0 / 64.0) || d->res.psi_iq > IQ(4.0)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_PSI);
        return;
    }
    motion_row(a_w, b_w, r0);
    motion_row(&d->u.sp.w[2], &d->u.sp.w[3], r1);
    motion_row(&d->u.sp.w[3], &d->u.sp.w[4], r2);
    /* (a, b, c) = r1 x r2, halved together below 2^32 (elements of r below 2^31: products < 2^62) */
    x[0] = r1[1] * r2[2] - r1[2] * r2[1];
    x[1] = r1[2] * r2[0] - r1[0] * r2[2];
    x[2] = r1[0] * r2[1] - r1[1] * r2[0];
    while ((x[0] < 0 ? -x[0] : x[0]) >= ((int64_t)1 << 32) || (x[1] < 0 ? -x[1] : x[1]) >= ((int64_t)1 << 32) ||
           (x[2] < 0 ? -x[2] : x[2]) >= ((int64_t)1 << 32)) {
        for (k = 0U; k < 3U; k++) {
            x[k] /= 2;
        }
    }
    /* B / J and T_c / J as x_1 / x_0, x_2 / x_0 in Q30; J must be positive and dominate (a coast
     * that decelerates) */
    if (x[0] == 0 || (x[1] < 0 ? -x[1] : x[1]) > (x[0] < 0 ? -x[0] : x[0]) * 256 ||
        (x[2] < 0 ? -x[2] : x[2]) > (x[0] < 0 ? -x[0] : x[0]) * 256) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
        return;
    }
    {
        const int64_t beta = app_ident_div64(x[1] * ((int64_t)1 << 30) * (x[0] < 0 ? -1 : 1), x[0] < 0 ? -x[0] : x[0]);
        const int64_t gamma = app_ident_div64(x[2] * ((int64_t)1 << 30) * (x[0] < 0 ? -1 : 1), x[0] < 0 ? -x[0] : x[0]);
        /* the acceleration row: J (r0[0] + beta r0[1] + gamma r0[2]) = 2 N (torque integral from A's
         * centre to B's): the q current summed over the windows A..B less half of A's and B's sums
         * (IQ x periods); den in Q30 (r0 < 2^31, beta, gamma < 2^38: < 2^63 for the rig's spans) */
        const int64_t den = r0[0] * ((int64_t)1 << 30) + beta * r0[1] + gamma * r0[2];
        const int64_t rhs = 2 * (int64_t)ID_SPIN_WIN *
                            (d->u.sp.acc_i - (((int64_t)d->u.sp.iq[0] + (int64_t)d->u.sp.iq[1]) * (int64_t)ID_SPIN_WIN) / 2);
        if (den <= ((int64_t)1 << 12) || rhs <= 0) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
            return;
        }
        /* J in row units = rhs 2^30 / (den 2^24); Q12: rhs / (den >> 12) x 2^6 */
        d->res.j_q12 = fix_sat32(app_ident_div64(rhs, den >> 12) * 64);
        d->res.b_iq = fix_sat32((beta * (int64_t)d->res.j_q12) >> 18);
        d->res.tc_iq = fix_sat32((gamma * (int64_t)d->res.j_q12) >> 18);
    }
    if (d->res.j_q12 <= 0) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
    }
}

/* Background: the spin step. sub 0 accelerating at ID_SPIN_I on the q axis until ID_SPIN_W or the
 * voltage headroom (5/8 of the limit); 1 coasting (gates off) until two thirds of the coast's
 * first speed (window D); 2 until one third (window E); then the fits. Window 1 of each phase
 * (the current's ramp, its decay) is not used. */
void app_ident_spin_service(app_ident_t *d, const dtc_config_t *cfg)
{
    const int32_t dir = d->res.enc_reversed != 0U ? -1 : 1;
    app_ident_win_t rec;
    iq_t vq, iq;
    const int64_t dpos_t =
        app_ident_div64((((int64_t)d->spin_w_iq * (int64_t)cfg->board.ts_pu_iq) >> 24) * (int64_t)ID_SPIN_WIN * (int64_t)cfg->board.enc_counts,
              ID_IQ_2PI * (int64_t)d->res.pole_pairs);
    rec.dpos = dir * d->win_dpos;
    rec.pos0 = dir * d->still_ref;
    rec.tick0 = d->win_tick;
    vq = fix_sat32(app_ident_div64(d->sum_v, (int64_t)ID_SPIN_WIN));
    iq = fix_sat32(app_ident_div64(d->sum_i, (int64_t)ID_SPIN_WIN));
    if (d->sub == 0U) {
        d->n_acc++;
        if (d->n_acc == d->spin_a) {
            uint16_t f;
            d->u.sp.w[0] = rec;
            d->u.sp.vq[0] = vq;
            d->u.sp.iq[0] = iq;
            d->u.sp.acc_i = 0;
            for (f = 0U; f < 4U; f++) {
                d->u.sp.fit[f] = 0;
            }
        }
        if (d->n_acc >= d->spin_a) {
            /* |x| < 2^15 counts per window, |y| < 2^25: x y < 2^40, over <= 100 windows < 2^47 */
            const int64_t x = (int64_t)rec.dpos;
            const int64_t y = (int64_t)fix_sub32(vq, iq_mpy(d->res.r_iq, iq));
            d->u.sp.acc_i += d->sum_i;
            d->u.sp.fit[0] += x;
            d->u.sp.fit[1] += y;
            d->u.sp.fit[2] += x * x;
            d->u.sp.fit[3] += x * y;
        }
        d->u.sp.w[1] = rec;
        d->u.sp.vq[1] = vq;
        d->u.sp.iq[1] = iq;
        if (d->n_acc > d->spin_a && ((int64_t)rec.dpos >= dpos_t || fix_abs32(vq) >= iq_mpy(d->v_lim_iq, IQ(0.625)) ||
                               d->n_acc >= ID_SPIN_MAXW)) {
            /* An induction machine already turned freely in its encoder step (app_ident_im.c): a
             * rotor that stays below half the spin speed carries a load (the PM's spin starts at
             * rest, so there a rotor below an eighth of it may be blocked as well). */
            const uint16_t vlow = fix_abs32(vq) >= iq_mpy(d->v_lim_iq, IQ(0.625)) ? 1U : 0U;
            if ((int64_t)rec.dpos < (dpos_t >> (d->im_on != 0U ? 1U : 3U))) {
                app_ident_fail(d, vlow != 0U ? (uint16_t)APP_IDENT_FAIL_VDC_LOW
                                             : (d->im_on != 0U ? (uint16_t)APP_IDENT_FAIL_COUPLED_LOAD
                                                               : (uint16_t)APP_IDENT_FAIL_BLOCKED),
                               (int16_t)(rec.dpos > 32767 ? 32767 : rec.dpos));
                return;
            }
            d->sub = 1U;
            app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_COAST, 0);
            return;
        }
        app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, d->spin_i_iq);
        return;
    }
    d->n_coast++;
    if (d->n_coast == 2U) {
        d->u.sp.w[2] = rec;
    } else if (d->n_coast > 2U) {
        if (d->sub == 1U && ((int64_t)rec.dpos * 3 <= 2 * (int64_t)d->u.sp.w[2].dpos || d->n_coast >= ID_COAST_MAXW / 2U)) {
            d->u.sp.w[3] = rec;
            d->sub = 2U;
        } else if (d->sub == 2U && ((int64_t)rec.dpos * 3 <= (int64_t)d->u.sp.w[2].dpos || d->n_coast >= ID_COAST_MAXW)) {
            d->u.sp.w[4] = rec;
            spin_results(d, cfg);
            if (d->step == (uint16_t)APP_IDENT_FAILED) {
                return;
            }
            app_ident_next_step(d, (uint16_t)APP_IDENT_DONE);
            d->seg = (uint16_t)APP_IDENT_SEG_OFF;
            return;
        } else {
            /* between D and E, or before D */
        }
    }
    app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_COAST, 0);
}
