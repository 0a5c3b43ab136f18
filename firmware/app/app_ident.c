/*
 * app_ident.c - self-commissioning of a PM machine, its background part: the sequence of steps,
 * the fits and the bounds (app_ident_isr.c is its 50 us part; see app_ident.h,
 * docs/commissioning.md).
 */
#include "app_ident.h"
#include "app_ident_internal.h"

#include <stddef.h>

/* Background only: num / den rounded toward zero, for den > 0 and |num| < 2^63, by restoring
 * binary long division (64 shift-and-subtract steps): the firmware calls no division helper
 * (the C28x has no 64-bit divide; tests/rules checks the libraries for helpers). */
int64_t app_ident_div64(int64_t num, int64_t den)
{
    const uint64_t n = num < 0 ? (uint64_t)0 - (uint64_t)num : (uint64_t)num;
    const uint64_t dd = (uint64_t)den;
    uint64_t q = 0U, r = 0U;
    int16_t b;
    for (b = 63; b >= 0; b--) {
        r = (r << 1) | ((n >> (uint16_t)b) & 1U);
        if (r >= dd) {
            r -= dd;
            q |= (uint64_t)1 << (uint16_t)b;
        }
    }
    return num < 0 ? -(int64_t)q : (int64_t)q;
}

void app_ident_fail(app_ident_t *d, uint16_t why, int16_t detail)
{
    if (d->step != (uint16_t)APP_IDENT_FAILED && d->step != (uint16_t)APP_IDENT_DONE) {
        d->fail = why;
        d->fail_step = d->step;
        d->fail_detail = detail;
        d->step = (uint16_t)APP_IDENT_FAILED;
        d->seg = (uint16_t)APP_IDENT_SEG_OFF;
    }
}

/* Background: hands the ISR segment seg for n_meas periods, its parameters already written: go is
 * written last, and the ISR starts the segment in its next period. */
static void post_go(app_ident_t *d, uint16_t seg, uint16_t n_meas)
{
    d->seg = seg;
    d->n_meas = n_meas;
    d->done = 0U;
    d->go = 1U;
}

/* Background: hands the ISR a regulated-current segment. */
void app_ident_post_hold(app_ident_t *d, uint32_t th_move_q16, uint32_t th_rate_q16, iq_t i_target, iq_t i_rate,
                         uint16_t n_settle, uint16_t n_meas, uint16_t slow)
{
    d->slow = slow != 0U ? 1U : 0U;
    d->th_left_q16 = th_move_q16;
    d->th_rate_q16 = th_rate_q16;
    d->i_target = i_target;
    d->i_rate = i_rate;
    d->n_settle = n_settle;
    post_go(d, (uint16_t)APP_IDENT_SEG_HOLD, n_meas);
}

/* Bounds: R between 1/4096 and 1/2 of Z_b; V_0 from -V_b/256 (a drop-free inverter's
 * measurement noise) to V_b/10 (7 V on 70 V). */
uint16_t app_ident_rs_bounds(app_ident_t *d)
{
    if (d->res.r_iq < IQ(1.0 / 4096.0) || d->res.r_iq > IQ(0.5)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_RS);
        return 0U;
    }
    if (d->res.v0_iq < -IQ(1.0 / 256.0) || d->res.v0_iq > IQ(0.1)) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_V0);
        return 0U;
    }
    return 1U;
}

/* Background: hands the ISR an open-loop segment (SEG_PULSE: a step of dv on the hold voltage;
 * SEG_SIGN: a voltage rising by dv per period), ended at di_stop (PULSE: the current's rise; SIGN: a
 * phase current) or after n_meas periods. */
static void post_open_loop(app_ident_t *d, uint16_t seg, iq_t dv, iq_t di_stop, uint16_t n_meas)
{
    d->dv_iq = dv;
    d->di_stop_iq = di_stop;
    post_go(d, seg, n_meas);
}

/* The L step's voltage pulse: 2.2 V on a 70 V link, until the current rose by 0.4 pu (from the
 * half-rated hold: at most 0.9 x rated). */
static void post_pulse(app_ident_t *d)
{
    post_open_loop(d, (uint16_t)APP_IDENT_SEG_PULSE, IQ(1.0 / 32.0), IQ_FRAC(2, 5), ID_PULSE_MAX);
}

static void post_move(app_ident_t *d);

/* Step LS's L_q part, its sub-steps (after the L_d pulses' 2 ID_PULSES). */
#define ID_LQ_GAP ((uint16_t)(2U * ID_PULSES + 1U))  /* the regulated hold before the square wave */
#define ID_LQ_ALT ((uint16_t)(2U * ID_PULSES + 2U))  /* the square wave */
#define ID_MOVED_TOLS 4          /* rotor_moved: the wave's excursion limit in quiet_tol (1/256 turn) */

/* Background: the L_q square wave (SEG_ALT) on the half-rated hold along the axis (the rotor
 * aligned on it: the axis is d, the wave's axis q). Sized from the L_d just measured and the rated
 * current, nothing else: the voltage the L_d steps use (V_b / 32), a half period alt_n of
 * ID_ALT_PP L_d / dv (the swing a fifth of rated with L_q = L_d; 13 periods, 0.65 ms, on Hoang
 * Table VIII), rounded to an even count in [ID_ALT_NMIN, ID_ALT_NMAX], and an even number alt_m
 * of halves spanning at least ID_ALT_MEAS periods. The swing's torque 1.5 p psi_m i_q alternates
 * with zero mean: the rotor swings by about (1.5 p psi_m / J) (i_pp / 2) (alt_n Ts / pi)^2 (a few
 * microradians on the rig, far below a count) and its back-EMF biases L_q by about
 * -1.5 p^2 psi_m^2 (alt_n Ts / pi)^2 / J relative to L_q (docs/commissioning.md). The hold's d
 * current keeps every phase current's sign through the swing on both topologies (the legs' drops
 * stay constant and cancel over the even number of halves). */
static void post_alt(app_ident_t *d)
{
    const int64_t dv = (int64_t)IQ(1.0 / 32.0);
    int64_t n = app_ident_div64((int64_t)d->res.l_ts_iq * (int64_t)ID_ALT_PP + (dv << 23), dv << 24);
    n = n < (int64_t)ID_ALT_NMIN ? (int64_t)ID_ALT_NMIN : (n > (int64_t)ID_ALT_NMAX ? (int64_t)ID_ALT_NMAX : n);
    n = (n + 1) & ~(int64_t)1;
    d->u.st.alt_n = (uint16_t)n;
    d->u.st.alt_m = (uint16_t)(2 * app_ident_div64((int64_t)ID_ALT_MEAS + 2 * n - 1, 2 * n));
    d->sub = ID_LQ_ALT;
    d->dv_iq = (iq_t)dv;
    post_go(d, (uint16_t)APP_IDENT_SEG_ALT, 0U);
}

/* Background: step LS's L_q part after each of its segments. L_q / (Z_b Ts) =
 * (alt_m alt_n dv - R sum_v / 2) / sum_i (alt_step's sums), in the L_d bounds and within [1/4, 8]
 * of L_d (beyond that an interior PM is implausible: a wiring or sensing fault), kept as L_q / L_d
 * in Q12 (res.lq_q12, rounded to nearest: 1/4096 of L_d); res.salient when it departs from L_d by
 * more than a sixteenth (the two measurements' accuracy, docs/commissioning.md). Then the encoder
 * step. */
static void lq_service(app_ident_t *d)
{
    int64_t num;
    iq_t lq, ld;
    if (d->sub == ID_LQ_GAP) {
        post_alt(d);
        return;
    }
    /* the swing the wave drives is microradians (post_alt), below a count: the check names a rotor
     * that turns (a load driving it), beyond ID_MOVED_TOLS x quiet_tol (about 1/64 turn). Below it
     * the rotor may still swing about the hold's axis, left from its alignment in step RS (on the
     * rig +-0.025 rad at about 3 Hz, friction its only damping: up to 2 x 32 counts of 8000 from
     * the wave's start, by when the wave starts); that swing's back-EMF is a slow ramp that cancels
     * over each pair of halves but for e1 T / (2 dv), about 1e-4 of L_q, and its axis error biases
     * L_q by sin^2(delta) (L_d - L_q) / L_q (docs/commissioning.md). A slow creep (the FSTP's rotor
     * following its hold's angle, about a count per 3 ms on the rig) adds a constant back-EMF that
     * cancels over the even number of halves. */
    if ((int32_t)d->u.st.alt_moved > ID_MOVED_TOLS * d->quiet_tol) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_MOVED, (int16_t)d->u.st.alt_moved);
        return;
    }
    /* R sum_v / 2 in IQ periods, rounded (|R| < 2^23, |sum_v| < 2^43: the product within 64 bits) */
    num = (int64_t)d->dv_iq * (int64_t)d->u.st.alt_n * (int64_t)d->u.st.alt_m -
          (((int64_t)d->res.r_iq * d->sum_v + ((int64_t)1 << 24)) >> 25);
    lq = d->sum_i > 0 ? fix_sat32(app_ident_div64(num * 16777216, d->sum_i)) : 0;
    ld = d->res.l_ts_iq;
    d->lq_periods = (uint16_t)(d->tick - d->u.st.lq_tick0); /* < 2^16: 416 + (alt_m + 1) alt_n */
    if (lq < IQ(1.0 / 16.0) || lq > IQ(4096.0 - 1.0) || (int64_t)lq * 4 < (int64_t)ld || (int64_t)lq > (int64_t)ld * 8) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LQ);
        return;
    }
    /* ld >= IQ(1/16) (the L_d bounds), lq < 2^36: the Q12 ratio <= 8 x 4096 fits 16 bits */
    d->res.lq_q12 = (uint16_t)app_ident_div64(((int64_t)lq << 12) + ((int64_t)ld >> 1), (int64_t)ld);
    d->res.salient = ((int64_t)lq - (int64_t)ld) * 16 > (int64_t)ld || ((int64_t)ld - (int64_t)lq) * 16 > (int64_t)ld ? 1U : 0U;
    /* the first dwell was the alignment (step RS); the encoder step starts with a move */
    app_ident_next_step(d, (uint16_t)APP_IDENT_ENCODER);
    d->sub = 1U;
    post_move(d);
}

/* Background: the duties' 1 / V_dc and the regulator's voltage limit from the last measured link
 * (a division: background only), before each segment, so a link that sags (a weak supply pulled
 * down through its resistance) is followed. The limit is a quarter of the board's base
 * V_b and of the measured V_dc: what both topologies apply without the duties' clamp (the FSTP's
 * largest vector is V_dc 7/16 / sqrt(3) = 0.25 V_dc with the duties in [1/16, 15/16]), so a link
 * too low for the step saturates the regulator (open_phase, dc_link_low) instead of the duties,
 * which would leave the commanded voltage, and every result from it, silently wrong. */
static void link_update(app_ident_t *d)
{
    const iq_t vdc = d->vdc_iq;
    const iq_t q = fix_rshift_rnd32(vdc, 2U);
    d->inv_vdc_iq = vdc > IQ(1.0 / 16.0) ? fix_sat32(app_ident_div64((int64_t)1 << 48, (int64_t)vdc)) : IQ(16.0);
    d->v_lim_iq = q < IQ(0.25) ? q : IQ(0.25);
}

/* Background: the sign pulse along phase k's axis (0, 120, 240 degrees). */
static void post_sign(app_ident_t *d, uint16_t k)
{
    d->seg = (uint16_t)APP_IDENT_SEG_SIGN;
    d->th_q16 = (uint32_t)(angle_t)(k == 0U ? 0U : (k == 1U ? 21845U : 43691U)) << 16;
    post_open_loop(d, (uint16_t)APP_IDENT_SEG_SIGN, ID_SIGN_RATE, ID_SIGN_STOP, ID_SIGN_MAX);
}

/* Background: the alignment, step RS's first regulated segment. The rotor swings onto the axis
 * under the slow regulator (regulate), at half rated: the braking quadrature current is at most the
 * aligning current (the braking torque balances the magnet's pull 1.5 p psi_m I sin(delta)), so
 * |i| stays below 0.71 x rated. The alignment is the encoder step's first dwell (it waits for the
 * rotor at rest and sums the count). Then the levels. */
static void post_align(app_ident_t *d)
{
    d->u.st.pulse_num = 0; /* the sign pulses' scratch (u.sg) ends here */
    d->u.st.pulse_den = 0;
    d->th_q16 = (uint32_t)d->res.axis << 16;
    d->i_ref = 0;
    d->integ[0] = 0;
    d->integ[1] = 0;
    app_ident_post_hold(d, 0U, 0U, ID_ENC_LEVEL, (iq_t)(ID_ENC_LEVEL / ID_ALIGN_RAMP),
                        ID_ALIGN_SETTLE, ID_ENC_MEAS, 1U);
}

/* Background: one sign pulse ended (phase k pulsed). A pulse that reached no current within the
 * regulator's voltage limit is an open phase. Otherwise each measured phase (the derived one,
 * -(sum of the others), is never the culprit) that read the clearly wrong sign (+ expected for k,
 * - for the others; wrong by more than a quarter of the stop level) is marked: bit 0 on its own
 * pulse (it carries the whole current there), bit 1 on another's (a non-pulsed phase can sit near
 * zero: on the FSTP the leg at the mid-point's potential is in the dead time's clamp). After the
 * third pulse: a phase wrong on its own pulse is a sensor mounted the wrong way round (named);
 * any other mark is named without a phase. */
static void sign_result(app_ident_t *d, const dtc_config_t *cfg, uint16_t k)
{
    const iq_t lo = fix_rshift_rnd32(ID_SIGN_STOP, 2U);
    /* the phase the firmware derives: none with three sensors, A on the FSTP, C on the SSTP */
    const uint16_t derived = cfg->board.i_sensors3 != 0U ? 3U : (cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 0U : 2U);
    iq_t mx = 0;
    uint16_t x, bad = 0U;
    for (x = 0U; x < 3U; x++) {
        const iq_t a = fix_abs32(d->u.sg.i[x]);
        const iq_t want = x == k ? d->u.sg.i[x] : fix_neg32(d->u.sg.i[x]);
        mx = a > mx ? a : mx;
        if (x != derived && want < fix_neg32(lo)) {
            d->u.sg.bad[x] |= x == k ? 1U : 2U;
        }
    }
    if (mx < fix_sub32(ID_SIGN_STOP, IQ(1.0 / 64.0))) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_OPEN_PHASE, (int16_t)(k + 1U));
        return;
    }
    if (k < 2U) {
        return;
    }
    for (x = 0U; x < 3U; x++) {
        if ((d->u.sg.bad[x] & 1U) != 0U) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_SENSOR_SIGN, (int16_t)(x + 1U));
            return;
        }
        bad |= d->u.sg.bad[x];
    }
    if (bad != 0U) {
        app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_SENSOR_SIGN, 0);
    }
}

void app_ident_start(app_ident_t *d, const dtc_config_t *cfg, uint16_t qep_count, iq_t vdc_iq)
{
    uint16_t k;
    d->go = 0U;
    d->done = 0U;
    d->res.axis = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? ID_TH0_FSTP : ID_TH0_SSTP;
    d->th_q16 = (uint32_t)d->res.axis << 16;
    d->i_ref = 0;
    d->integ[0] = 0;
    d->integ[1] = 0;
    d->v_ab[0] = 0;
    d->v_ab[1] = 0;
    d->phase = 0U;
    d->n = 0U;
    d->sat_n = 0U;
    d->sum_i = 0;
    d->sum_v = 0;
    d->sum_pos = 0;
    d->last_count = qep_count;
    d->count0 = qep_count;
    d->pos = 0;
    d->vdc_iq = vdc_iq;
    /* Regulator gains from the base impedance Z_b = V_b / I_b = 1 pu (app_ident.h). */
    d->kp_iq = IQ(1.0 / 64.0);
    d->ki_iq = IQ(1.0 / 4096.0);     /* per period: Z_b * 4.9 rad/s at 50 us */
    d->fail = (uint16_t)APP_IDENT_OK;
    d->fail_step = 0U;
    d->fail_detail = 0;
    d->n_dwell = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 2U : 3U;
    d->tick = 0U;
    d->step_tick = 0U;
    for (k = 0U; k < 7U; k++) {
        d->res.ticks[k] = 0U;
    }
    d->res.pole_pairs = 0U;
    d->res.enc_reversed = 0U;
    d->res.enc_offset = 0U;
    d->res.r_iq = 0;
    d->res.v0_iq = 0;
    d->res.l_ts_iq = 0;
    d->res.lq_q12 = 0U;
    d->res.salient = 0U;
    d->lq_periods = 0U;
    d->res.counts_per_turn = 0;
    d->res.psi_iq = 0;
    d->res.j_q12 = 0;
    d->res.b_iq = 0;
    d->res.tc_iq = 0;
    d->fresh = 0U;
    d->i_perp_ref = 0;
    d->comp_iq = 0;
    d->v_ff_iq = 0;
    d->dv_ff_iq = 0;
    d->im_rate_q16 = 0U;
    d->spin_i_iq = ID_SPIN_I;
    d->spin_w_iq = ID_SPIN_W;
    d->spin_a = 2U; /* the first window holds the current's ramp */
    d->gain_q16 = 0U;
    d->res.im.ls_ts_iq = 0;
    d->res.im.lsig_ts_iq = 0;
    d->res.im.taur_q4 = 0;
    d->res.im.rr_iq = 0;
    d->res.im.id_iq = 0;
    d->res.im.vq_pole_iq = 0;
    d->sign_k = 0U;
    /* The calibration's rotor hold (app_hold.h) ends with its current still in the windings (up to
     * its limit, several amperes); gates off for a sign pulse's gap first, so that neither the
     * first sign pulse nor the over-current check below reads it (app_ident_isr). */
    d->start_gap = ID_SIGN_GAP;
    /* a dwell at rest: the count within a quarter degree (3 counts of 4096, at least 1); its swing
     * over (the mid-point hold, app_ident_isr.c mid_hold): within 1/256 turn */
    d->rest_tol = (int32_t)((3U * (uint32_t)cfg->board.enc_counts + 2048U) >> 12);
    d->rest_tol = d->rest_tol < 1 ? 1 : d->rest_tol;
    d->quiet_tol = (int32_t)(cfg->board.enc_counts >> 8);
    d->quiet_tol = d->quiet_tol < 1 ? 1 : d->quiet_tol;
    d->quiet_ref = 0;
    d->quiet_n = 0U;
    d->mid_on = 0U;
    d->mid_ref_iq = 0;
    d->recentre = 0U;
    d->ia_ref_iq = 0;
    for (k = 0U; k < 3U; k++) {
        d->u.sg.bad[k] = 0U;
        d->u.sg.i[k] = 0;
    }
    link_update(d);
    d->step = (uint16_t)APP_IDENT_RS;
    d->sub = 0U;
    d->im_on = 0U;
    if (dtc_law_is_im(cfg->law) != 0U) {
        app_ident_im_start(d); /* no alignment: a DC current gives an induction machine no torque */
        return;
    }
    /* first the sensors' signs, then the alignment (service) */
    post_sign(d, 0U);
}

void app_ident_abort(app_ident_t *d) { app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_TRIP, 0); }

/* Background: the mean count and the measured current's angle of the dwell just ended (index j).
 * The rotor at rest lies on the current actually flowing, the reference axis turned by
 * atan2(mean quadrature, mean parallel current): the slow regulator has no quadrature integral,
 * so a static quadrature voltage error (the FSTP mid-point sensor's, the dead time's) leaves a
 * quadrature current; its angle is measured instead of regulated away. */
static void store_dwell(app_ident_t *d, uint16_t j)
{
    angle_t a;
    iq_t mag;
    d->u.st.dwell_pos_q8[j] = fix_sat32(app_ident_div64(d->sum_pos * 256, (int64_t)d->n_meas));
    fix_polar(fix_sat32(app_ident_div64(d->sum_i, (int64_t)d->n_meas)), fix_sat32(app_ident_div64(d->sum_q, (int64_t)d->n_meas)), &a, &mag);
    d->u.st.dwell_ang[j] = (int16_t)a;
}

/* Background: the next move of the encoder step (one span forward), then a dwell at rest. */
static void post_move(app_ident_t *d)
{
    const uint32_t move = d->n_dwell == 2U ? ID_ENC_MOVE_FSTP : ID_ENC_MOVE_SSTP;
    const uint32_t span = app_ident_span_of(d);
    app_ident_post_hold(d, span << 16, (uint32_t)app_ident_div64((int64_t)span << 16, (int64_t)move), ID_ENC_LEVEL,
              (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_ENC_SETTLE, ID_ENC_MEAS, 1U);
}

/* Background, FSTP with the mid-point measured: before the spin, the mid-point back to V_dc/2
 * (the ISR's phase-A current reference, app_ident_isr.c) on the last dwell's vector, slow
 * regulator, until within ID_RECENTRE_TOL or ID_RECENTRE_MAX. The standstill steps leave it where
 * the swings' braking currents and the moves put it (15 V off on the rig's p = 4 machines): the
 * legs then reach the duties' clamp below the regulator's limit (the B and C legs span
 * v_mid - V_dc/16 .. 15 V_dc/16 - v_mid about the mid-point, sqrt(3) |v| needed), and the spin's
 * q voltage, psi_m and J are wrong (psi_m +18 % on such a machine, 0.3 % with a stiff link). The
 * spin needs no rotor at rest: the recentring's pull on the rotor ends with it. */
static void recentre(app_ident_t *d)
{
    d->sub = ID_SPIN_RECENTRE;
    d->recentre = 1U;
    app_ident_post_hold(d, 0U, 0U, ID_ENC_LEVEL, (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_RECENTRE_MAX, 16U, 1U);
}

/* Background: the spin's first window. On the FSTP the legs' drop (thresholds and dead time) is
 * compensated during the spin, each leg's sqrt(3)/2 V_0 (step RS's intercept on the beta axis,
 * where legs B and C carry +-I: V_0 = 2 d / sqrt(3) for a leg's drop d) along its reference
 * current's sign (ident_pwm): with two switching legs the drop has a negative-sequence part,
 * which in the rotor frame ripples the q voltage at twice the electrical frequency, a large share
 * of a spin's back-EMF that a few 20 ms windows do not average (psi_m +5 % on the rig's p = 2
 * machines without it, +0.3 % with it; the SSTP's three legs give no such part). */
static void spin_start(app_ident_t *d, const dtc_config_t *cfg)
{
    if (cfg->board.topology == (uint16_t)DTC_TOPO_FSTP) {
        d->comp_iq = fix_rshift_rnd64_sat32((int64_t)d->res.v0_iq * (int64_t)FIX_Q31_SQRT3_2, 31U);
    }
    app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, ID_SPIN_I);
}

void app_ident_next_step(app_ident_t *d, uint16_t step)
{
    d->res.ticks[d->step] = d->tick - d->step_tick;
    d->step_tick = d->tick;
    d->step = step;
    d->sub = 0U;
}

void app_ident_service(app_ident_t *d, const dtc_config_t *cfg)
{
    static const iq_t levels[APP_IDENT_R_LEVELS] = {IQ(1.0), IQ(0.75), IQ(0.5), IQ(0.25)};
    if (d->step != (uint16_t)APP_IDENT_RS && d->step != (uint16_t)APP_IDENT_LS &&
        d->step != (uint16_t)APP_IDENT_ENCODER && d->step != (uint16_t)APP_IDENT_SPIN) {
        return;
    }
    if (d->go != 0U || d->done == 0U) {
        return; /* the ISR is in a segment */
    }
    link_update(d);
    if (d->im_on != 0U) {
        app_ident_im_service(d, cfg);
        return;
    }
    switch (d->step) {
    case APP_IDENT_RS:
        if (d->sign_k < 3U) {
            sign_result(d, cfg, d->sign_k);
            d->sign_k++;
            if (d->step == (uint16_t)APP_IDENT_FAILED) {
                return;
            }
            if (d->sign_k < 3U) {
                post_sign(d, d->sign_k);
            } else {
                post_align(d);
            }
            return;
        }
        if (d->sub == 0U) { /* segment 0 aligned the rotor: the encoder's first dwell */
            store_dwell(d, 0U);
        } else { /* 1.. are the levels */
            d->res.level_i_iq[d->sub - 1U] = fix_sat32(app_ident_div64(d->sum_i, (int64_t)d->n_meas));
            d->res.level_v_iq[d->sub - 1U] = fix_sat32(app_ident_div64(d->sum_v, (int64_t)d->n_meas));
        }
        d->sub++;
        if (d->sub <= APP_IDENT_R_LEVELS) {
            app_ident_post_hold(d, 0U, 0U, levels[d->sub - 1U], (iq_t)(IQ(1.0) / ID_LEVEL_RAMP),
                                ID_LEVEL_SETTLE, ID_MEAS, 0U);
            return;
        }
        app_ident_fit_line(d);
        if (app_ident_rs_bounds(d) == 0U) {
            return;
        }
        app_ident_next_step(d, (uint16_t)APP_IDENT_LS);
        app_ident_post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_LEVEL_SETTLE, 16U, 0U);
        return;
    case APP_IDENT_LS:
        if (d->sub > 2U * ID_PULSES) {
            lq_service(d);
            return;
        }
        if ((d->sub & 1U) != 0U) {
            /* a step ended: its volt-periods less the resistive part (trapezoid of the rise)
             * over its current rise, Hoang eq. 28's L di/dt = v - R i on the step axis */
            const iq_t rise = fix_sub32(d->i_last, d->i_first);
            const int64_t trap = d->sum_i + (int64_t)fix_rshift_rnd32(rise, 1U);
            d->u.st.pulse_num += (int64_t)d->dv_iq * (int64_t)d->n -
                            (int64_t)fix_rshift_rnd64_sat32((int64_t)d->res.r_iq * trap, 24U);
            d->u.st.pulse_den += (int64_t)rise;
        }
        d->sub++;
        if (d->sub < 2U * ID_PULSES) {
            if ((d->sub & 1U) != 0U) {
                post_pulse(d);
            } else {
                app_ident_post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP),
                                    ID_PULSE_GAP, 16U, 0U);
            }
            return;
        }
        d->res.l_ts_iq = d->u.st.pulse_den > 0 ? fix_sat32(app_ident_div64(d->u.st.pulse_num * 16777216, d->u.st.pulse_den)) : 0;
        /* Bounds: L / (Z_b Ts) between 1/16 and 4096 (5 uH .. 6.5 H for Z_b = 31.8 ohm at 50 us). */
        if (d->res.l_ts_iq < IQ(1.0 / 16.0) || d->res.l_ts_iq > IQ(4096.0 - 1.0)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LS);
            return;
        }
        /* then L_q: the square wave after a regulated hold (lq_service) */
        d->u.st.lq_tick0 = d->tick;
        d->sub = ID_LQ_GAP;
        app_ident_post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_ALT_GAP, 16U, 0U);
        return;
    case APP_IDENT_ENCODER:
        store_dwell(d, d->sub);
        if (d->sub < d->n_dwell) {
            d->sub++;
            post_move(d);
            return;
        }
        app_ident_encoder_results(d, cfg);
        if (d->step == (uint16_t)APP_IDENT_FAILED) {
            return;
        }
        /* electrical angle per count, Q16: p 2^32 / enc_counts */
        d->gain_q16 = (uint32_t)app_ident_div64((int64_t)d->res.pole_pairs << 32, (int64_t)cfg->board.enc_counts);
        app_ident_next_step(d, (uint16_t)APP_IDENT_SPIN);
        d->n_acc = 0U;
        d->n_coast = 0U;
        d->fresh = 1U;
        if (cfg->board.topology == (uint16_t)DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U) {
            recentre(d);
            return;
        }
        spin_start(d, cfg);
        return;
    case APP_IDENT_SPIN:
        if (d->sub == ID_SPIN_RECENTRE) {
            d->recentre = 0U;
            d->sub = 0U;
            spin_start(d, cfg);
            return;
        }
        app_ident_spin_service(d, cfg);
        return;
    default:
        return;
    }
}
