/*
 * app_ident.c - standstill self-commissioning of a PM machine (see app_ident.h,
 * docs/commissioning.md).
 */
#include "app_ident.h"

#include <stddef.h>

/* Segment timing, control periods (50 us: 2000 = 0.1 s). */
#define ID_ALIGN_RAMP 2000      /* first ramp to the aligning current: the rotor swings into alignment */
#define ID_ALIGN_SETTLE 2000U   /* alignment: the least settling before the wait for the rotor at rest */
#define ID_LEVEL_RAMP 400       /* later level changes: a full-rated change over 400 periods */
#define ID_LEVEL_SETTLE 800U    /* 40 ms: 6.5 time constants of the regulator's closed loop (163 1/s
                                 * for Hoang Table VIII, docs/commissioning.md), its error < 0.2 % */
#define ID_MEAS 1024U
#define ID_PULSE_GAP 600U       /* regulated hold between two voltage steps */
#define ID_PULSE_MAX 2000U      /* longest voltage step (100 ms) */
#define ID_PULSES 4U
#define ID_ENC_MOVE_SSTP 3000U  /* periods for one 120-degree move of the vector (SSTP) */
#define ID_ENC_MOVE_FSTP 3000U  /* one 180-degree move (FSTP) */
#define ID_ENC_LEVEL IQ(0.5)    /* the aligning and encoder current (see app_ident_start) */
#define ID_ENC_SETTLE 1500U     /* encoder dwell: the least settling before the wait for rest */
#define ID_ENC_MEAS 1024U
#define ID_OPEN_PERIODS 400U    /* regulator saturated with little current this long: open phase */
#define ID_STILL 1000U          /* dwell: periods with the count within +-1 before the sums (50 ms) */
#define ID_SETTLE_MAX 40000U    /* dwell: the longest wait for the rotor to come to rest (2 s) */
#define ID_IQ_2PI ((int64_t)105414357) /* 2 pi in IQ, round(2 pi 2^24) (an integer: the same on every target) */
#define ID_SPIN_I IQ(0.5)       /* spin: the q current of the acceleration (half rated) */
#define ID_SPIN_W IQ(0.25)      /* spin: the speed that ends the acceleration, pu electrical */
#define ID_SPIN_WIN 400U        /* spin: periods per speed window (20 ms) */
#define ID_SPIN_MAXW 100U       /* spin: the longest acceleration, windows (2 s) */
#define ID_COAST_MAXW 100U      /* spin: the longest coast, windows (2 s) */

/* The injection axis (res.axis). FSTP: beta (90 degrees), current from leg B into leg C, so that
 * phase A (the capacitor mid-point) carries none and the mid-point does not drift. SSTP: alpha
 * (0 degrees), i_a = I, i_b = i_c = -I/2: every phase carries current, so no leg sits in the
 * dead time's zero-current clamp, which would block the quadrature current that brakes the
 * rotor's swing (regulate). */
#define ID_TH0_FSTP ANGLE(0.25)
#define ID_TH0_SSTP ANGLE(0.0)

/* Background only: num / den rounded toward zero, for den > 0 and |num| < 2^63, by restoring
 * binary long division (64 shift-and-subtract steps): the firmware calls no division helper
 * (the C28x has no 64-bit divide; tests/rules checks the libraries for helpers). */
static int64_t div64(int64_t num, int64_t den)
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

static void fail(app_ident_t *d, uint16_t why, int16_t detail)
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

static void post_pulse(app_ident_t *d)
{
    d->seg = (uint16_t)APP_IDENT_SEG_PULSE;
    d->dv_iq = IQ(1.0 / 32.0);       /* 2.2 V on a 70 V link */
    d->di_stop_iq = IQ_FRAC(2, 5);        /* from the half-rated hold: at most 0.9 x rated */
    d->n_meas = ID_PULSE_MAX;
    d->done = 0U;
    d->go = 1U;
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
    d->v_lim_iq = IQ(0.25);
    d->fail = (uint16_t)APP_IDENT_OK;
    d->fail_step = 0U;
    d->fail_detail = 0;
    d->n_dwell = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 2U : 3U;
    d->u.st.pulse_num = 0;
    d->u.st.pulse_den = 0;
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
    /* 1 / V_dc (background: a division), for the duties. */
    d->inv_vdc_iq = vdc_iq > IQ(1.0 / 16.0) ? fix_sat32(div64((int64_t)1 << 48, (int64_t)vdc_iq)) : IQ(1.0);
    d->step = (uint16_t)APP_IDENT_RS;
    d->sub = 0U;
    /* The rotor swings onto the axis under the slow regulator (regulate), at half rated: the
     * braking quadrature current is at most the aligning current (the braking torque balances the
     * magnet's pull 1.5 p psi_m I sin(delta)), so |i| stays below 0.71 x rated. The alignment is the
     * encoder step's first dwell (it waits for the rotor at rest and sums the count). Then the
     * levels. */
    post_hold(d, 0U, 0U, ID_ENC_LEVEL, (iq_t)(ID_ENC_LEVEL / ID_ALIGN_RAMP), ID_ALIGN_SETTLE, ID_ENC_MEAS, 1U);
}

void app_ident_abort(app_ident_t *d) { fail(d, (uint16_t)APP_IDENT_FAIL_TRIP, 0); }

/* The voltage (v_alpha, v_beta) as one centred pulse per leg (app_ident.h: SSTP d_x = 1/2 +
 * v_x / V_dc; FSTP d_x = (v_mid + v_x - v_a) / V_dc, legs B and C). Inverse Clarke, amplitude
 * invariant: v_a = v_alpha, v_b,c = -v_alpha / 2 +- sqrt(3)/2 v_beta. Duties clamp to [1/16, 15/16];
 * compare value T1PR (1 - d) (hal.h: upper on from the up-count match to the down-count match).
 * Scaling: |v| <= v_lim = 0.25 pu, the sums stay below 2 pu; duty x T1PR < 2^40 in 64 bits. */
static void ident_pwm(const app_ident_t *d, const dtc_config_t *cfg, const dtc_meas_t *pu, uint16_t t1pr,
                      hal_cmd_t *cmd)
{
    const iq_t va = d->v_ab[0];
    const iq_t half_a = fix_neg32(fix_rshift_rnd32(va, 1U));
    const iq_t sb = fix_rshift_rnd64_sat32((int64_t)d->v_ab[1] * (int64_t)FIX_Q31_SQRT3_2, 31U);
    const iq_t v[3] = {va, fix_add32(half_a, sb), fix_sub32(half_a, sb)};
    iq_t base = fix_rshift_rnd32(d->vdc_iq, 1U);
    uint16_t x;
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
        cmd->cmpr_up[x] = (uint16_t)((uint32_t)t1pr -
                                     (uint32_t)(((int64_t)duty * (int64_t)t1pr + ((int64_t)1 << 23)) >> 24));
        cmd->cmpr_dn[x] = cmd->cmpr_up[x];
        cmd->act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
    }
    cmd->enable = 1U;
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
    const iq_t e[2] = {fix_sub32(d->i_ref, i_par), fix_neg32(i_perp)};
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

    d->tick++;
    d->vdc_iq = pu->vdc_iq;
    {
        /* unwrapped count: the per-period change folded into (-N/2, N/2] */
        const int32_t n_c = (int32_t)cfg->board.enc_counts;
        const int32_t half = (int32_t)(cfg->board.enc_counts >> 1U);
        int32_t dc = (int32_t)pu->enc_count - (int32_t)d->last_count;
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
            fail(d, (uint16_t)APP_IDENT_FAIL_OVERCURRENT, (int16_t)k);
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
        if (d->seg == (uint16_t)APP_IDENT_SEG_PULSE) {
            d->v_hold = d->v_ab[0]; /* the regulated voltage before the step, both axes */
            d->v_hold_b = d->v_ab[1];
        }
    }
    if (d->seg == (uint16_t)APP_IDENT_SEG_SPIN) {
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
                fail(d, (uint16_t)APP_IDENT_FAIL_VDC_LOW, 0);
                return 1U;
            }
        } else {
            d->sat_n = 0U;
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
                    fail(d, (uint16_t)APP_IDENT_FAIL_NOT_AT_REST, 0);
                    return 1U;
                }
            }
            if (d->n >= d->n_settle && (d->slow == 0U || d->still_n >= ID_STILL)) {
                d->phase = 2U;
                d->n = 0U;
            }
        } else if (d->phase == 2U) {
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
                fail(d, (uint16_t)APP_IDENT_FAIL_OPEN_PHASE, 0);
                return 1U;
            }
        } else {
            d->sat_n = 0U;
        }
    } else {
        return 1U;
    }
    ident_pwm(d, cfg, pu, t1pr, cmd);
    return 0U;
}

/* Least-squares line through the level means (background): R = S_xy / S_xx on deviations
 * from the means, V_0 = mean_v - R mean_i. Scaling: deviations |dx| < 2 pu (2^25), products
 * < 2^50, four of them < 2^52 in 64 bits; S_xx >> 24 is S_xx in IQ. */
static void fit_line(app_ident_t *d)
{
    int64_t mx = 0, my = 0, sxx = 0, sxy = 0;
    uint16_t k;
    for (k = 0U; k < APP_IDENT_R_LEVELS; k++) {
        mx += d->res.level_i_iq[k];
        my += d->res.level_v_iq[k];
    }
    mx = div64(mx, (int64_t)APP_IDENT_R_LEVELS);
    my = div64(my, (int64_t)APP_IDENT_R_LEVELS);
    for (k = 0U; k < APP_IDENT_R_LEVELS; k++) {
        const int64_t dx = (int64_t)d->res.level_i_iq[k] - mx;
        const int64_t dy = (int64_t)d->res.level_v_iq[k] - my;
        sxx += dx * dx;
        sxy += dx * dy;
    }
    sxx >>= 24;
    d->res.r_iq = sxx > 0 ? fix_sat32(div64(sxy, sxx)) : 0;
    d->res.v0_iq = fix_sub32(fix_sat32(my), iq_mpy(d->res.r_iq, fix_sat32(mx)));
}

/* One move of the encoder step: a turn over the dwells per turn, angle_t LSB (three: 21845, one
 * LSB short of a third, so the last dwell is 3 LSB = 0.02 degree short of a full turn). */
static uint32_t span_of(const app_ident_t *d) { return d->n_dwell == 2U ? 32768UL : 21845UL; }

/* Encoder results from the dwell positions (background; app_ident.h). */
static void encoder_results(app_ident_t *d, const dtc_config_t *cfg)
{
    const int64_t n_q8 = (int64_t)cfg->board.enc_counts << 8;
    const int64_t delta = (int64_t)d->u.st.dwell_pos_q8[d->n_dwell] - (int64_t)d->u.st.dwell_pos_q8[0];
    const int64_t ad = delta < 0 ? -delta : delta;
    int64_t p;
    int32_t acc = 0;
    angle_t off0 = 0U;
    uint16_t j;
    d->res.counts_per_turn = fix_sat32(div64(delta, 256));
    if (ad < (n_q8 >> 6)) {
        fail(d, (uint16_t)APP_IDENT_FAIL_ENC_NOT_COUNTING, (int16_t)d->res.counts_per_turn);
        return;
    }
    d->res.enc_reversed = delta < 0 ? 1U : 0U;
    p = div64(n_q8 + (ad >> 1), ad);
    if (p < 1 || p > 16) {
        fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_POLE_PAIRS);
        return;
    }
    {
        const int64_t err = p * ad - n_q8;
        if ((err < 0 ? -err : err) > div64(n_q8, 20)) {
            fail(d, (uint16_t)APP_IDENT_FAIL_ENC_LINES, (int16_t)d->res.counts_per_turn);
            return;
        }
    }
    d->res.pole_pairs = (uint16_t)p;
    for (j = 0U; j < d->n_dwell; j++) {
        /* the raw count at the dwell (Q8), in [0, N) */
        const int64_t raw = ((int64_t)d->count0 << 8) + (int64_t)d->u.st.dwell_pos_q8[j];
        int64_t cq8 = raw - div64(raw, n_q8) * n_q8;
        int64_t th;
        angle_t th_vec, off;
        if (cq8 < 0) {
            cq8 += n_q8;
        }
        if (d->res.enc_reversed != 0U) {
            cq8 = -cq8;
        }
        th = div64(cq8 * p * 65536, n_q8);       /* electrical angle of the count, angle_t units */
        th_vec = (angle_t)(d->res.axis + (angle_t)(span_of(d) * j) + (angle_t)d->u.st.dwell_ang[j]);
        off = (angle_t)((uint32_t)th_vec - (uint32_t)(uint16_t)(uint64_t)th); /* modulo one turn */
        if (j == 0U) {
            off0 = off;
        }
        acc += (int32_t)(int16_t)(uint16_t)(off - off0);
    }
    d->res.enc_offset = (angle_t)(off0 + (angle_t)(int16_t)div64(acc, (int64_t)d->n_dwell));
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
    d->u.st.dwell_pos_q8[j] = fix_sat32(div64(d->sum_pos * 256, (int64_t)d->n_meas));
    fix_polar(fix_sat32(div64(d->sum_i, (int64_t)d->n_meas)), fix_sat32(div64(d->sum_q, (int64_t)d->n_meas)), &a, &mag);
    d->u.st.dwell_ang[j] = (int16_t)a;
}

/* Background: the next move of the encoder step (one span forward), then a dwell at rest. */
static void post_move(app_ident_t *d)
{
    const uint32_t move = d->n_dwell == 2U ? ID_ENC_MOVE_FSTP : ID_ENC_MOVE_SSTP;
    const uint32_t span = span_of(d);
    post_hold(d, span << 16, (uint32_t)div64((int64_t)span << 16, (int64_t)move), ID_ENC_LEVEL,
              (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_ENC_SETTLE, ID_ENC_MEAS, 1U);
}

static void next_step(app_ident_t *d, uint16_t step)
{
    d->res.ticks[d->step] = d->tick - d->step_tick;
    d->step_tick = d->tick;
    d->step = step;
    d->sub = 0U;
}

/* Background: one spin window with the q current i (SEG_SPIN) or with the gates off (SEG_COAST). */
static void post_window(app_ident_t *d, uint16_t seg, iq_t i)
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
        fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_PSI);
        return;
    }
    {
        /* the q voltage's change less the resistive part of the q current's change (R of step RS) */
        const iq_t dv = fix_sub32(fix_sub32(d->u.sp.vq[1], d->u.sp.vq[0]), iq_mpy(d->res.r_iq, fix_sub32(d->u.sp.iq[1], d->u.sp.iq[0])));
        const int64_t t = div64((int64_t)dv * (int64_t)cfg->board.ts_pu_iq,
                                ddpos * (int64_t)d->res.pole_pairs);
        d->res.psi_iq = fix_sat32(div64(t * (int64_t)ID_SPIN_WIN * (int64_t)cfg->board.enc_counts, ID_IQ_2PI));
    }
    /* Bounds: psi_m from 1/64 to 4 pu (the back-EMF at rated speed 1/64 .. 4 x V_dc) */
    if (d->res.psi_iq < IQ(1.0 / 64.0) || d->res.psi_iq > IQ(4.0)) {
        fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_PSI);
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
        fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
        return;
    }
    {
        const int64_t beta = div64(x[1] * ((int64_t)1 << 30) * (x[0] < 0 ? -1 : 1), x[0] < 0 ? -x[0] : x[0]);
        const int64_t gamma = div64(x[2] * ((int64_t)1 << 30) * (x[0] < 0 ? -1 : 1), x[0] < 0 ? -x[0] : x[0]);
        /* the acceleration row: J (r0[0] + beta r0[1] + gamma r0[2]) = 2 N (torque integral from A's
         * centre to B's): the q current summed over the windows A..B less half of A's and B's sums
         * (IQ x periods); den in Q30 (r0 < 2^31, beta, gamma < 2^38: < 2^63 for the rig's spans) */
        const int64_t den = r0[0] * ((int64_t)1 << 30) + beta * r0[1] + gamma * r0[2];
        const int64_t rhs = 2 * (int64_t)ID_SPIN_WIN *
                            (d->u.sp.acc_i - (((int64_t)d->u.sp.iq[0] + (int64_t)d->u.sp.iq[1]) * (int64_t)ID_SPIN_WIN) / 2);
        if (den <= ((int64_t)1 << 12) || rhs <= 0) {
            fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
            return;
        }
        /* J in row units = rhs 2^30 / (den 2^24); Q12: rhs / (den >> 12) x 2^6 */
        d->res.j_q12 = fix_sat32(div64(rhs, den >> 12) * 64);
        d->res.b_iq = fix_sat32((beta * (int64_t)d->res.j_q12) >> 18);
        d->res.tc_iq = fix_sat32((gamma * (int64_t)d->res.j_q12) >> 18);
    }
    if (d->res.j_q12 <= 0) {
        fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_MECH);
    }
}

/* Background: the spin step. sub 0 accelerating at ID_SPIN_I on the q axis until ID_SPIN_W or the
 * voltage headroom (5/8 of the limit); 1 coasting (gates off) until two thirds of the coast's
 * first speed (window D); 2 until one third (window E); then the fits. Window 1 of each phase
 * (the current's ramp, its decay) is not used. */
static void spin_service(app_ident_t *d, const dtc_config_t *cfg)
{
    const int32_t dir = d->res.enc_reversed != 0U ? -1 : 1;
    app_ident_win_t rec;
    iq_t vq, iq;
    const int64_t dpos_t =
        div64((((int64_t)ID_SPIN_W * (int64_t)cfg->board.ts_pu_iq) >> 24) * (int64_t)ID_SPIN_WIN * (int64_t)cfg->board.enc_counts,
              ID_IQ_2PI * (int64_t)d->res.pole_pairs);
    rec.dpos = dir * d->win_dpos;
    rec.pos0 = dir * d->still_ref;
    rec.tick0 = d->win_tick;
    vq = fix_sat32(div64(d->sum_v, (int64_t)ID_SPIN_WIN));
    iq = fix_sat32(div64(d->sum_i, (int64_t)ID_SPIN_WIN));
    if (d->sub == 0U) {
        d->n_acc++;
        if (d->n_acc == 2U) {
            d->u.sp.w[0] = rec;
            d->u.sp.vq[0] = vq;
            d->u.sp.iq[0] = iq;
            d->u.sp.acc_i = 0;
        }
        if (d->n_acc >= 2U) {
            d->u.sp.acc_i += d->sum_i;
        }
        d->u.sp.w[1] = rec;
        d->u.sp.vq[1] = vq;
        d->u.sp.iq[1] = iq;
        if (d->n_acc >= 3U && ((int64_t)rec.dpos >= dpos_t || fix_abs32(vq) >= iq_mpy(d->v_lim_iq, IQ(0.625)) ||
                               d->n_acc >= ID_SPIN_MAXW)) {
            if ((int64_t)rec.dpos < (dpos_t >> 3)) {
                fail(d, fix_abs32(vq) >= iq_mpy(d->v_lim_iq, IQ(0.625)) ? (uint16_t)APP_IDENT_FAIL_VDC_LOW
                                                                            : (uint16_t)APP_IDENT_FAIL_BLOCKED,
                     (int16_t)(rec.dpos > 32767 ? 32767 : rec.dpos));
                return;
            }
            d->sub = 1U;
            post_window(d, (uint16_t)APP_IDENT_SEG_COAST, 0);
            return;
        }
        post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, ID_SPIN_I);
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
            next_step(d, (uint16_t)APP_IDENT_DONE);
            d->seg = (uint16_t)APP_IDENT_SEG_OFF;
            return;
        } else {
            /* between D and E, or before D */
        }
    }
    post_window(d, (uint16_t)APP_IDENT_SEG_COAST, 0);
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
    switch (d->step) {
    case APP_IDENT_RS:
        if (d->sub == 0U) { /* segment 0 aligned the rotor: the encoder's first dwell */
            store_dwell(d, 0U);
        } else { /* 1.. are the levels */
            d->res.level_i_iq[d->sub - 1U] = fix_sat32(div64(d->sum_i, (int64_t)d->n_meas));
            d->res.level_v_iq[d->sub - 1U] = fix_sat32(div64(d->sum_v, (int64_t)d->n_meas));
        }
        d->sub++;
        if (d->sub <= APP_IDENT_R_LEVELS) {
            post_hold(d, 0U, 0U, levels[d->sub - 1U], (iq_t)(IQ(1.0) / ID_LEVEL_RAMP), ID_LEVEL_SETTLE, ID_MEAS, 0U);
            return;
        }
        fit_line(d);
        /* Bounds: R between 1/4096 and 1/2 of Z_b; V_0 from -V_b/256 (a drop-free inverter's
         * measurement noise) to V_b/10 (7 V on 70 V). */
        if (d->res.r_iq < IQ(1.0 / 4096.0) || d->res.r_iq > IQ(0.5)) {
            fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_RS);
            return;
        }
        if (d->res.v0_iq < -IQ(1.0 / 256.0) || d->res.v0_iq > IQ(0.1)) {
            fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_V0);
            return;
        }
        next_step(d, (uint16_t)APP_IDENT_LS);
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
        d->res.l_ts_iq = d->u.st.pulse_den > 0 ? fix_sat32(div64(d->u.st.pulse_num * 16777216, d->u.st.pulse_den)) : 0;
        /* Bounds: L / (Z_b Ts) between 1/16 and 4096 (5 uH .. 6.5 H for Z_b = 31.8 ohm at 50 us). */
        if (d->res.l_ts_iq < IQ(1.0 / 16.0) || d->res.l_ts_iq > IQ(4096.0 - 1.0)) {
            fail(d, (uint16_t)APP_IDENT_FAIL_BOUNDS, (int16_t)APP_IDENT_Q_LS);
            return;
        }
        /* the first dwell was the alignment (step RS); the encoder step starts with a move */
        next_step(d, (uint16_t)APP_IDENT_ENCODER);
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
        encoder_results(d, cfg);
        if (d->step == (uint16_t)APP_IDENT_FAILED) {
            return;
        }
        /* electrical angle per count, Q16: p 2^32 / enc_counts */
        d->gain_q16 = (uint32_t)div64((int64_t)d->res.pole_pairs << 32, (int64_t)cfg->board.enc_counts);
        next_step(d, (uint16_t)APP_IDENT_SPIN);
        d->n_acc = 0U;
        d->n_coast = 0U;
        d->fresh = 1U;
        post_window(d, (uint16_t)APP_IDENT_SEG_SPIN, ID_SPIN_I);
        return;
    case APP_IDENT_SPIN:
        spin_service(d, cfg);
        return;
    default:
        return;
    }
}
