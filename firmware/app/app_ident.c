/*
 * app_ident.c - standstill self-commissioning of a PM machine (see app_ident.h,
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

/* Background: hands the ISR a regulated-current segment. */
static void post_hold(app_ident_t *d, uint32_t th_move_q16, uint32_t th_rate_q16, iq_t i_target, iq_t i_rate,
                      uint16_t n_settle, uint16_t n_meas, uint16_t slow)
{
    d->seg = (uint16_t)APP_IDENT_SEG_HOLD;
    d->slow = slow != 0U ? 1U : 0U;
    d->th_left_q16 = th_move_q16;
    d->th_rate_q16 = th_rate_q16;
    d->i_target = i_target;
    d->i_rate = i_rate;
    d->n_settle = n_settle;
    d->n_meas = n_meas;
    d->done = 0U;
    d->go = 1U;
}

void app_ident_post_hold(app_ident_t *d, uint32_t th_move_q16, uint32_t th_rate_q16, iq_t i_target, iq_t i_rate,
                         uint16_t n_settle, uint16_t n_meas, uint16_t slow)
{
    post_hold(d, th_move_q16, th_rate_q16, i_target, i_rate, n_settle, n_meas, slow);
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
    d->seg = seg;
    d->dv_iq = dv;
    d->di_stop_iq = di_stop;
    d->n_meas = n_meas;
    d->done = 0U;
    d->go = 1U;
}

/* The L step's voltage pulse: 2.2 V on a 70 V link, until the current rose by 0.4 pu (from the
 * half-rated hold: at most 0.9 x rated). */
static void post_pulse(app_ident_t *d)
{
    post_open_loop(d, (uint16_t)APP_IDENT_SEG_PULSE, IQ(1.0 / 32.0), IQ_FRAC(2, 5), ID_PULSE_MAX);
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
    post_hold(d, 0U, 0U, ID_ENC_LEVEL, (iq_t)(ID_ENC_LEVEL / ID_ALIGN_RAMP), ID_ALIGN_SETTLE, ID_ENC_MEAS, 1U);
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

/* The voltage (v_alpha, v_beta) as one centred pulse per leg (app_ident.h: SSTP d_x = 1/2 +
 * v_x / V_dc; FSTP d_x = (v_mid + v_x - v_a) / V_dc, legs B and C). Inverse Clarke, amplitude
 * invariant: v_a = v_alpha, v_b,c = -v_alpha / 2 +- sqrt(3)/2 v_beta. Duties clamp to [1/16, 15/16];
 * compare value T1PR (1 - d) (hal.h: upper on from the up-count match to the down-count match).
 * Scaling: |v| <= v_lim = 0.25 pu, the sums stay below 2 pu; duty x T1PR < 2^40 in 64 bits. */
static int64_t ident_pwm(const app_ident_t *d, const dtc_config_t *cfg, const dtc_meas_t *pu, uint16_t t1pr,
                         hal_cmd_t *cmd)
{
    int64_t rq[3];
    const iq_t va = d->v_ab[0];
    const iq_t half_a = fix_neg32(fix_rshift_rnd32(va, 1U));
    const iq_t sb = fix_rshift_rnd64_sat32((int64_t)d->v_ab[1] * (int64_t)FIX_Q31_SQRT3_2, 31U);
    iq_t v[3] = {va, fix_add32(half_a, sb), fix_sub32(half_a, sb)};
    iq_t base = fix_rshift_rnd32(d->vdc_iq, 1U);
    uint16_t x;
    if (d->comp_iq != 0) {
        /* the legs' drop (thresholds and dead time, comp_iq = 3/4 V_0 of step RS: V_0 is 2/3 of
         * two legs' drops on the alpha axis) added along the sign of each phase's reference
         * current (the reference: no sign noise at the crossings); reference (i_ref on th,
         * i_perp_ref on th + 90 degrees) to phases by the inverse Clarke transform */
        const q15_t cc = fix_cos((angle_t)(d->th_q16 >> 16));
        const q15_t ss = fix_sin((angle_t)(d->th_q16 >> 16));
        const iq_t ra = fix_sub32(iq_mpy_q15(d->i_ref, cc), iq_mpy_q15(d->i_perp_ref, ss));
        const iq_t rb = fix_add32(iq_mpy_q15(d->i_ref, ss), iq_mpy_q15(d->i_perp_ref, cc));
        const iq_t hra = fix_neg32(fix_rshift_rnd32(ra, 1U));
        const iq_t srb = fix_rshift_rnd64_sat32((int64_t)rb * (int64_t)FIX_Q31_SQRT3_2, 31U);
        const iq_t r[3] = {ra, fix_add32(hra, srb), fix_sub32(hra, srb)};
        for (x = 0U; x < 3U; x++) {
            v[x] = r[x] >= 0 ? fix_add32(v[x], d->comp_iq) : fix_sub32(v[x], d->comp_iq);
        }
    }
    const uint16_t fstp = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 1U : 0U;
    if (fstp != 0U && cfg->board.fstp_vmid_measured != 0U) {
        base = pu->vmid_iq;
    }
    cmd->form = (uint16_t)HAL_CMD_PWM;
    for (x = 0U; x < 3U; x++) {
        iq_t u = fix_add32(base, v[x]);
        iq_t duty;
        if (fstp != 0U) {
            u = fix_sub32(u, va); /* leg voltage to the negative rail: v_mid + v_x - v_a */
        }
        duty = iq_sat(iq_mpy(u, d->inv_vdc_iq), IQ(1.0 / 16.0), IQ(15.0 / 16.0));
        {
            const int64_t prod = (int64_t)duty * (int64_t)t1pr; /* counts, Q24 (< 2^40) */
            const int64_t counts = (prod + ((int64_t)1 << 23)) >> 24;
            rq[x] = prod - (counts << 24); /* the rounding's residual, counts Q24, |rq| <= 2^23 */
            cmd->cmpr_up[x] = (uint16_t)((uint32_t)t1pr - (uint32_t)counts);
        }
        cmd->cmpr_dn[x] = cmd->cmpr_up[x];
        cmd->act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
    }
    cmd->enable = 1U;
    /* The compare register's whole counts apply duty - rq / t1pr per leg: the SSTP's
     * phase-to-neutral alpha voltage is short by V_dc (2 rq_a - rq_b - rq_c) / (3 t1pr) (Hoang
     * eqs. 1-4), in counts Q24 x 3 here; the caller scales it (app_ident_im.c). */
    return 2 * rq[0] - rq[1] - rq[2];
}

/* The angle and current ramps of a HOLD segment; returns 1 while either is moving. The angle
 * only moves forward (the encoder step turns the vector in the positive direction); th_q16 wraps
 * modulo one turn by design (angle_t in its upper 16 bits). */
static uint16_t ramps(app_ident_t *d)
{
    uint16_t moving = 0U;
    if (d->th_left_q16 != 0U) {
        const uint32_t st = d->th_left_q16 < d->th_rate_q16 || d->th_rate_q16 == 0U ? d->th_left_q16 : d->th_rate_q16;
        d->th_q16 += st;
        d->th_left_q16 -= st;
        moving = 1U;
    }
    if (d->i_ref != d->i_target) {
        const iq_t diff = fix_sub32(d->i_target, d->i_ref);
        if (fix_abs32(diff) <= d->i_rate || d->i_rate <= 0) {
            d->i_ref = d->i_target;
        } else {
            d->i_ref = diff > 0 ? fix_add32(d->i_ref, d->i_rate) : fix_sub32(d->i_ref, d->i_rate);
            moving = 1U;
        }
    }
    return moving;
}

/* PI in the reference frame (the axis at th and its quadrature): the parallel current to i_ref,
 * the quadrature current to zero; v_alpha,beta = the two outputs turned by th. Integrators and
 * outputs clamped to +-v_lim. In the reference frame a turning th needs no integrator to follow
 * it. d->slow: no integral action on the quadrature axis, only kp: there the machine is
 * voltage-fed through R_s + kp, so a swing of the rotor about the axis (whose back-EMF is in
 * quadrature to the current once aligned) drives a quadrature current that brakes it, about
 * 1.5 p^2 psi_m^2 / (R_s + kp) of damping (0.012 N.m.s/rad for Hoang Table VIII: damping ratio
 * 0.8 at half rated current, where the friction alone takes seconds). A static quadrature voltage
 * error (the FSTP mid-point sensor's, the dead time's) leaves a quadrature current at rest, so the
 * rotor rests on the current actually flowing: its angle is measured (store_dwell), not regulated
 * away (an integral would pull the rotor slowly after every swing). */
static void regulate(app_ident_t *d, iq_t i_par, iq_t i_perp, q15_t c, q15_t s)
{
    const iq_t e[2] = {fix_sub32(d->i_ref, i_par), fix_sub32(d->i_perp_ref, i_perp)};
    const iq_t ki[2] = {d->ki_iq, d->slow == 0U ? d->ki_iq : 0};
    iq_t v[2];
    uint16_t k;
    for (k = 0U; k < 2U; k++) {
        d->integ[k] = iq_sat(fix_add32(d->integ[k], iq_mpy(ki[k], e[k])), fix_neg32(d->v_lim_iq), d->v_lim_iq);
        v[k] = iq_sat(fix_add32(d->integ[k], iq_mpy(d->kp_iq, e[k])), fix_neg32(d->v_lim_iq), d->v_lim_iq);
    }
    d->v_ab[0] = fix_sub32(iq_mpy_q15(v[0], c), iq_mpy_q15(v[1], s));
    d->v_ab[1] = fix_add32(iq_mpy_q15(v[0], s), iq_mpy_q15(v[1], c));
}

uint16_t app_ident_isr(app_ident_t *d, const dtc_config_t *cfg, const dtc_meas_t *pu, uint16_t t1pr,
                       hal_cmd_t *cmd)
{
    const iq_t iph[3] = {pu->ia_iq, pu->ib_iq, pu->ic_iq};
    iq_t i_ab[2];
    iq_t i_par, i_perp, v_par;
    q15_t c, s;
    uint16_t k;

    int32_t dc;
    d->tick++;
    d->summed = 0U;
    d->vdc_iq = pu->vdc_iq;
    {
        /* unwrapped count: the per-period change folded into (-N/2, N/2] */
        const int32_t n_c = (int32_t)cfg->board.enc_counts;
        const int32_t half = (int32_t)(cfg->board.enc_counts >> 1U);
        dc = (int32_t)pu->enc_count - (int32_t)d->last_count;
        if (dc > half) {
            dc -= n_c;
        } else if (dc <= -half) {
            dc += n_c;
        }
        d->pos += dc;
        d->last_count = pu->enc_count;
    }
    if (d->step == (uint16_t)APP_IDENT_DONE || d->step == (uint16_t)APP_IDENT_FAILED ||
        d->step == (uint16_t)APP_IDENT_IDLE) {
        return 1U;
    }
    for (k = 0U; k < 3U; k++) {
        if (fix_abs32(iph[k]) > IQ(1.25)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_OVERCURRENT, (int16_t)k);
            return 1U;
        }
    }
    /* Clarke, amplitude invariant: i_beta = (i_b - i_c) / sqrt(3) */
    i_ab[0] = iph[0];
    i_ab[1] = fix_rshift_rnd64_sat32((int64_t)fix_sub32(iph[1], iph[2]) * (int64_t)FIX_Q31_INV_SQRT3, 31U);
    if (d->go != 0U) {
        d->go = 0U;
        d->n = 0U;
        d->sum_i = 0;
        d->sum_v = 0;
        d->sum_pos = 0;
        d->sum_q = 0;
        d->sat_n = 0U;
        d->still_n = 0U;
        d->still_ref = d->pos;
        d->phase = d->seg == (uint16_t)APP_IDENT_SEG_PULSE ? 6U : 0U;
        d->win_tick = d->tick;
        if (d->seg == (uint16_t)APP_IDENT_SEG_SPIN || d->seg == (uint16_t)APP_IDENT_SEG_COAST) {
            d->phase = 2U; /* a window: sums from its first period */
            if (d->fresh != 0U) {
                d->fresh = 0U;
                d->integ[0] = 0;
                d->integ[1] = 0;
                d->i_ref = 0;
            }
        }
        if (d->seg == (uint16_t)APP_IDENT_SEG_SIGN) {
            d->phase = 2U;
            d->v_hold = 0;
        }
        if (d->seg == (uint16_t)APP_IDENT_SEG_PULSE) {
            d->v_hold = d->v_ab[0]; /* the regulated voltage before the step, both axes */
            d->v_hold_b = d->v_ab[1];
        }
    }
    if (d->seg == (uint16_t)APP_IDENT_SEG_SPIN && d->im_on != 0U) {
        /* induction machine: the reference axis (the rotor flux's q axis) turns by the rotor's
         * electrical angle, this period's count change times gain (direction applied), plus
         * im_rate (the slip of indirect field orientation; the whole field in the encoder step,
         * gain 0); |dc| gain < 2^31 in 64 bits, modulo one turn */
        const int64_t de = (int64_t)(d->res.enc_reversed != 0U ? -dc : dc) * (int64_t)d->gain_q16;
        d->th_q16 += d->im_rate_q16 + (uint32_t)(uint64_t)de;
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_SPIN) {
        /* the reference axis on the rotor's q axis: theta_e = offset + count x gain (direction
         * applied), + 90 degrees; the count's product < 2^31 x 2^32 in 64 bits, modulo one turn */
        const int64_t e = (((int64_t)d->count0 + (int64_t)d->pos) * (int64_t)d->gain_q16) >> 16;
        const uint16_t el = (uint16_t)(uint64_t)e;
        const angle_t th_e = (angle_t)(d->res.enc_offset + (d->res.enc_reversed != 0U ? (angle_t)(0U - el) : (angle_t)el));
        d->th_q16 = (uint32_t)(angle_t)(th_e + ANGLE(0.25)) << 16;
    }
    {
        const angle_t th = (angle_t)(d->th_q16 >> 16);
        c = fix_cos(th);
        s = fix_sin(th);
    }
    i_par = fix_add32(iq_mpy_q15(i_ab[0], c), iq_mpy_q15(i_ab[1], s));
    i_perp = fix_sub32(iq_mpy_q15(i_ab[1], c), iq_mpy_q15(i_ab[0], s));

    if (d->seg == (uint16_t)APP_IDENT_SEG_PULSE) {
        const iq_t dva = iq_mpy_q15(d->dv_iq, c);
        const iq_t dvb = iq_mpy_q15(d->dv_iq, s);
        /* n counts the step commands written; the command of period k governs period k + 1
         * (hal.h), so the step acts from the sample after the first command to the sample
         * after the last one: those two samples are its start and end current. */
        uint16_t on = 1U;
        if (d->phase == 6U) {
            d->phase = 5U;
            d->n = 1U;
        } else if (d->phase == 5U) { /* the step's start sample */
            d->i_first = i_par;
            d->phase = 2U;
            d->n = 2U;
        } else if (d->phase == 2U) {
            const iq_t rise = fix_sub32(i_par, d->i_first);
            d->sum_i += (int64_t)rise;
            if (rise >= d->di_stop_iq || d->n >= d->n_meas) {
                on = 0U;
                d->phase = 3U; /* the next sample is the step's end */
            } else {
                d->n++;
            }
        } else if (d->phase == 3U) {
            d->i_last = i_par;
            on = 0U;
            d->phase = 4U;
            d->seg = (uint16_t)APP_IDENT_SEG_HOLD; /* regulated again, integrators as before */
            d->done = 1U;
        } else {
            on = 0U;
        }
        if (on != 0U) {
            d->v_ab[0] = fix_add32(d->v_hold, dva);
            d->v_ab[1] = fix_add32(d->v_hold_b, dvb);
        } else {
            d->v_ab[0] = d->v_hold;
            d->v_ab[1] = d->v_hold_b;
        }
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_SPIN) {
        (void)ramps(d);
        regulate(d, i_par, i_perp, c, s);
        if (d->im_on != 0U) {
            /* the back-EMF's rise as a feed-forward on the q axis (the regulator's integral alone
             * would trail the rising speed by a large share of i_q, app_ident_im.c im_spin_ff) */
            d->v_ff_iq = fix_add32(d->v_ff_iq, d->dv_ff_iq);
            d->v_ab[0] = fix_add32(d->v_ab[0], iq_mpy_q15(d->v_ff_iq, c));
            d->v_ab[1] = fix_add32(d->v_ab[1], iq_mpy_q15(d->v_ff_iq, s));
        }
        v_par = fix_add32(iq_mpy_q15(d->v_ab[0], c), iq_mpy_q15(d->v_ab[1], s));
        if (d->phase == 2U) {
            d->sum_i += (int64_t)i_par;
            d->sum_v += (int64_t)v_par;
            if (++d->n >= d->n_meas) {
                d->phase = 4U;
                d->win_dpos = d->pos - d->still_ref;
                d->done = 1U;
            }
        }
        /* the regulator at its voltage limit: the back-EMF and drops exceed what the link gives */
        if (fix_abs32(v_par) >= fix_sub32(d->v_lim_iq, IQ(1.0 / 256.0))) {
            if (++d->sat_n >= ID_OPEN_PERIODS) {
                app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_VDC_LOW, 0);
                return 1U;
            }
        } else {
            d->sat_n = 0U;
        }
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_SIGN) {
        /* open loop (a reversed sensor would make any regulator run away): the voltage rises along
         * th until a phase current reaches di_stop or the pulse its longest, then the gates off */
        if (d->phase == 2U) {
            const iq_t mx = fix_abs32(iph[0]) > fix_abs32(iph[1]) ? fix_abs32(iph[0]) : fix_abs32(iph[1]);
            if ((mx > fix_abs32(iph[2]) ? mx : fix_abs32(iph[2])) >= d->di_stop_iq || d->n >= d->n_meas) {
                for (k = 0U; k < 3U; k++) {
                    d->u.sg.i[k] = iph[k];
                }
                d->phase = 3U;
                d->n = 0U;
                return 1U;
            }
            d->n++;
            d->v_hold = fix_add32(d->v_hold, d->dv_iq);
            d->v_ab[0] = iq_mpy_q15(d->v_hold, c);
            d->v_ab[1] = iq_mpy_q15(d->v_hold, s);
        } else {
            if (d->phase == 3U && ++d->n >= ID_SIGN_GAP) {
                d->phase = 4U;
                d->done = 1U;
            }
            return 1U;
        }
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_COAST) {
        if (d->phase == 2U && ++d->n >= d->n_meas) {
            d->phase = 4U;
            d->win_dpos = d->pos - d->still_ref;
            d->done = 1U;
        }
        return 1U;
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_HOLD) {
        const uint16_t moving = ramps(d);
        regulate(d, i_par, i_perp, c, s);
        v_par = fix_add32(iq_mpy_q15(d->v_ab[0], c), iq_mpy_q15(d->v_ab[1], s));
        if (d->phase == 0U && moving == 0U) {
            d->phase = 1U;
            d->n = 0U;
        } else if (d->phase == 1U) {
            ++d->n;
            if (d->slow != 0U) {
                /* the encoder step: after n_settle, wait until the count stays within +-1 of one
                 * value for ID_STILL periods; a rotor not at rest by ID_SETTLE_MAX is a coupled
                 * load, a blocked or a far too heavy rotor: named, not measured */
                const int32_t dev = d->pos - d->still_ref;
                if (dev > 1 || dev < -1) {
                    d->still_ref = d->pos;
                    d->still_n = 0U;
                } else if (d->still_n < ID_STILL) {
                    d->still_n++;
                }

                if (d->n >= ID_SETTLE_MAX) {
                    app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_NOT_AT_REST, 0);
                    return 1U;
                }
            }
            if (d->n >= d->n_settle && (d->slow == 0U || d->still_n >= ID_STILL)) {
                d->phase = 2U;
                d->n = 0U;
            }
        } else if (d->phase == 2U) {
            /* a sum with the regulator at its limit measures the limit, not the machine: the link
             * is too low for this step's current (link_update) */
            if (fix_abs32(v_par) >= fix_sub32(d->v_lim_iq, IQ(1.0 / 256.0))) {
                app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_VDC_LOW, (int16_t)d->step);
                return 1U;
            }
            d->summed = 1U;
            d->sum_i += (int64_t)i_par;
            d->sum_v += (int64_t)v_par;
            d->sum_pos += (int64_t)d->pos;
            d->sum_q += (int64_t)i_perp;
            if (++d->n >= d->n_meas) {
                d->phase = 4U;
                d->done = 1U;
            }
        } else {
            /* 4: done, regulating until the next segment */
        }
        /* Open phase: the regulator at its limit while the current stays below a quarter of a
         * reference of at least a quarter of rated. */
        if (fix_abs32(v_par) >= fix_sub32(d->v_lim_iq, IQ(1.0 / 256.0)) && d->i_ref >= IQ(0.25) &&
            fix_abs32(i_par) < fix_rshift_rnd32(d->i_ref, 2U)) {
            if (++d->sat_n >= ID_OPEN_PERIODS) {
                app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_OPEN_PHASE, 0);
                return 1U;
            }
        } else {
            d->sat_n = 0U;
        }
    } else {
        return 1U;
    }
    {
        const int64_t rq3 = ident_pwm(d, cfg, pu, t1pr, cmd);
        if (d->im_on != 0U && d->summed != 0U) {
            app_ident_im_quant(d, rq3, t1pr); /* summed this period: the applied voltage's share */
        }
    }
    return 0U;
}

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
    post_hold(d, span << 16, (uint32_t)app_ident_div64((int64_t)span << 16, (int64_t)move), ID_ENC_LEVEL,
              (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_ENC_SETTLE, ID_ENC_MEAS, 1U);
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
            post_hold(d, 0U, 0U, levels[d->sub - 1U], (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_LEVEL_SETTLE, ID_MEAS, 0U);
            return;
        }
        app_ident_fit_line(d);
        if (app_ident_rs_bounds(d) == 0U) {
            return;
        }
        app_ident_next_step(d, (uint16_t)APP_IDENT_LS);
        post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_LEVEL_SETTLE, 16U, 0U);
        return;
    case APP_IDENT_LS:
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
                post_hold(d, 0U, 0U, IQ(0.5), (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_PULSE_GAP, 16U, 0U);
            }
            return;
        }
        d->res.l_ts_iq = d->u.st.pulse_den > 0 ? fix_sat32(app_ident_div64(d->u.st.pulse_num * 16777216, d->u.st.pulse_den)) : 0;
        /* Bounds: L / (Z_b Ts) between 1/16 and 4096 (5 uH .. 6.5 H for Z_b = 31.8 ohm at 50 us). */
        if (d->res.l_ts_iq < IQ(1.0 / 16.0) || d->res.l_ts_iq > IQ(4096.0 - 1.0)) {
            app_ident_fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LS);
            return;
        }
        /* the first dwell was the alignment (step RS); the encoder step starts with a move */
        app_ident_next_step(d, (uint16_t)APP_IDENT_ENCODER);
        d->sub = 1U;
        post_move(d);
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
        app_ident_post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, ID_SPIN_I);
        return;
    case APP_IDENT_SPIN:
        app_ident_spin_service(d, cfg);
        return;
    default:
        return;
    }
}
