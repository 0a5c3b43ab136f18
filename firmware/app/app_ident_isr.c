/*
 * app_ident_isr.c - the 50 us part of the PM machine's self-commissioning (app_ident.h,
 * docs/commissioning.md): each period it ramps the segment the background posted, regulates the
 * current or applies the open-loop voltage, accumulates the sums the background's fits read, and
 * encodes the voltage as one centred pulse per leg. The background part (the sequence of steps,
 * the fits and the bounds) is app_ident.c.
 */
#include "app_ident.h"
#include "app_ident_internal.h"

#include <stddef.h>

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
        /* a PM spin's references start from zero: a phase whose reference is below 1/16 of i_ref
         * gets none (all three at zero would put the whole drop on one axis and drive a current
         * through the low impedance of a machine at rest) */
        const iq_t thr = d->im_on != 0U ? 0 : fix_rshift_rnd32(fix_abs32(d->i_ref), 4U);
        for (x = 0U; x < 3U; x++) {
            if (d->im_on != 0U || fix_abs32(r[x]) > thr) {
                v[x] = r[x] >= 0 ? fix_add32(v[x], d->comp_iq) : fix_sub32(v[x], d->comp_iq);
            }
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
    /* the references: i_ref on the axis, i_perp_ref on its quadrature, and ia_ref_iq on alpha
     * (phase A: recentre) turned into the reference frame */
    const iq_t e[2] = {fix_sub32(fix_add32(d->i_ref, iq_mpy_q15(d->ia_ref_iq, c)), i_par),
                       fix_sub32(fix_sub32(d->i_perp_ref, iq_mpy_q15(d->ia_ref_iq, s)), i_perp)};
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

/* The mid-point hold of an FSTP dwell (slow regulator, the mid-point measured; dev: the measured
 * mid-point's deviation from V_dc / 2, pu). Phase A sits on the capacitors' mid-point, whose only
 * DC path it is: 2 C dv_mid/dt = -i_a, and on a beta-axis dwell i_a is the quadrature current
 * (Hoang eqs. 1-5 with phase A on the mid-point). The legs' duties follow the measured mid-point,
 * so anything that makes the applied phase-A voltage depend on the mid-point's position puts
 * k (v_mid - V_dc/2) on phase A: the two voltage sensors' ratio error (their consistency is
 * calibrated at V_dc/2 only, app_core.c vmid_cal) and the legs' threshold difference, which enters
 * as (V_D - V_CE)(d_b + d_c - 1)/2 with d_b + d_c - 1 = 2 (v_mid - V_dc/2)/V_dc (Hoang Table III);
 * k is about 1 % with datasheet tolerances. The swing's braking current moves the mid-point by
 * about 11 V on the Hoang Table VIII rig; with k of one sign the phase-A current that k drives
 * moves it further, growing as e^(k t / (2 C (R_s + kp))) (about 1/s), and the rotor follows the
 * current's angle without coming to rest. Once the swing is over (after the ramps, the count
 * within +-quiet_tol for ID_QUIET periods) the deviation is frozen and 2^-ID_MID_HOLD_LOG2 (1/32)
 * of its change since then is added to v_alpha: more than such a k, so the mid-point stays where
 * the swing left it and the phase-A current dies out. Holding it at V_dc/2 instead would send the
 * swing's charge back through phase A and pull the rotor (3.69 s instead of 2.80 s of standstill
 * steps on the rig); a larger gain adds a slower mode (docs/commissioning.md). Scaling:
 * |dev| <= 2 pu, the term <= 1/16 pu. */
static void mid_hold(app_ident_t *d, iq_t dev)
{
    if (d->mid_on == 0U) {
        const int32_t m = d->pos - d->quiet_ref;
        if (m > d->quiet_tol || m < -d->quiet_tol) {
            d->quiet_ref = d->pos;
            d->quiet_n = 0U;
        } else if (++d->quiet_n >= ID_QUIET) {
            d->mid_on = 1U;
        }
        d->mid_ref_iq = dev;
        return;
    }
    d->v_ab[0] = fix_add32(d->v_ab[0], fix_rshift_rnd32(fix_sub32(dev, d->mid_ref_iq), ID_MID_HOLD_LOG2));
}

/* The sign of section sec of the L_q square wave: + in the lead-in (0) and in the even halves,
 * - in the odd ones and in the lead-out (alt_m + 1, alt_m even). */
static int32_t alt_sign(uint16_t sec) { return (sec & 1U) != 0U ? -1 : 1; }

/* One period of SEG_ALT (app_ident.h), i_q the quadrature current of this sample. The command of
 * period k governs period k + 1 (hal.h): this sample lies at the start of the previous command's
 * interval, so it is judged by that command's section (alt_psec) and position (alt_pj). With
 * sigma_k the sign of half k (sections 1..alt_m) and its current running from i_s,k to i_e,k:
 *   sum_i = sum_k sigma_k (i_e,k - i_s,k)   (the swings, > 0): a boundary between halves k-1 and k
 *           enters twice (-2 sigma_k i), the first and the last once;
 *   sum_v = 2 sum_k sigma_k (trapezoid of i_q over half k), in samples: the interior samples of a
 *           half 2 sigma_k i, the first and last boundary sigma i, the others 0 (sigma alternates).
 * The background's L_q: (alt_m alt_n dv - R sum_v / 2) / sum_i (Hoang eq. 28 on the q axis; the
 * hold voltage and every constant drop cancel over the even number of equal halves). alt_moved
 * keeps the count's largest excursion from its start (counts, saturated at 0x7FFF). Scaling: |i_q| < 1.25 pu, at most 2^16 samples
 * of weight <= 2: the sums < 2^43. */
static void alt_step(app_ident_t *d, iq_t i_q, q15_t c, q15_t s)
{
    const uint16_t last = (uint16_t)(d->u.st.alt_m + 1U);
    const int32_t dp = d->pos - d->still_ref;
    const int32_t adp = dp < 0 ? -dp : dp;
    if (adp > (int32_t)d->u.st.alt_moved) {
        d->u.st.alt_moved = adp > 0x7FFF ? 0x7FFFU : (uint16_t)adp;
    }
    if (d->u.st.alt_psec != 0xFFFFU && d->u.st.alt_psec >= 1U) {
        const int64_t sg = (int64_t)alt_sign(d->u.st.alt_psec);
        if (d->u.st.alt_pj == 0U && d->u.st.alt_psec <= last) {
            const int64_t w = d->u.st.alt_psec == 1U || d->u.st.alt_psec == last ? 1 : 2;
            d->sum_i -= sg * w * (int64_t)i_q;
            if (d->u.st.alt_psec == 1U) {
                d->sum_v += sg * (int64_t)i_q;
            } else if (d->u.st.alt_psec == last) {
                d->sum_v -= sg * (int64_t)i_q;
            }
        } else if (d->u.st.alt_psec < last) {
            d->sum_v += 2 * sg * (int64_t)i_q;
        }
    }
    if (d->u.st.alt_sec > last) {
        /* the lead-out's last command governed the previous period: regulated again */
        d->v_ab[0] = d->v_hold;
        d->v_ab[1] = d->v_hold_b;
        d->phase = 4U;
        d->seg = (uint16_t)APP_IDENT_SEG_HOLD;
        d->done = 1U;
        return;
    }
    {
        const iq_t dv = alt_sign(d->u.st.alt_sec) > 0 ? d->dv_iq : fix_neg32(d->dv_iq);
        const uint16_t len = d->u.st.alt_sec == 0U || d->u.st.alt_sec == last ? (uint16_t)(d->u.st.alt_n >> 1U) : d->u.st.alt_n;
        /* along th + 90 degrees: (-sin th, cos th) */
        d->v_ab[0] = fix_sub32(d->v_hold, iq_mpy_q15(dv, s));
        d->v_ab[1] = fix_add32(d->v_hold_b, iq_mpy_q15(dv, c));
        d->u.st.alt_psec = d->u.st.alt_sec;
        d->u.st.alt_pj = d->u.st.alt_j;
        if (++d->u.st.alt_j >= len) {
            d->u.st.alt_j = 0U;
            d->u.st.alt_sec++;
        }
    }
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
    if (d->start_gap != 0U) {
        d->start_gap--; /* gates off: the hold's current decays (app_ident_start) */
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
        d->quiet_n = 0U;
        d->quiet_ref = d->pos;
        d->mid_on = 0U;
        d->ia_ref_iq = 0;
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
        if (d->seg == (uint16_t)APP_IDENT_SEG_PULSE || d->seg == (uint16_t)APP_IDENT_SEG_ALT) {
            d->v_hold = d->v_ab[0]; /* the regulated voltage before the step, both axes */
            d->v_hold_b = d->v_ab[1];
        }
        if (d->seg == (uint16_t)APP_IDENT_SEG_ALT) {
            d->phase = 2U;
            d->u.st.alt_sec = 0U;
            d->u.st.alt_j = 0U;
            d->u.st.alt_psec = 0xFFFFU;
            d->u.st.alt_pj = 0U;
            d->u.st.alt_moved = 0U;
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
    } else if (d->seg == (uint16_t)APP_IDENT_SEG_ALT) {
        alt_step(d, i_perp, c, s);
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
        const uint16_t mid = cfg->board.topology == (uint16_t)DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U ? 1U : 0U;
        const iq_t dev = fix_sub32(pu->vmid_iq, fix_rshift_rnd32(pu->vdc_iq, 1U));
        if (d->recentre != 0U) {
            /* the mid-point back to V_dc/2 (app_ident.c recentre): a phase-A current
             * 2^ID_RECENTRE_LOG2 pu per pu of deviation, at most ID_RECENTRE_I (2 C dv_mid/dt = -i_a) */
            d->ia_ref_iq = iq_sat(fix_sat32((int64_t)dev * ((int64_t)1 << ID_RECENTRE_LOG2)), fix_neg32(ID_RECENTRE_I),
                                  ID_RECENTRE_I);
        }
        regulate(d, i_par, i_perp, c, s);
        if (mid != 0U && d->slow != 0U && d->recentre == 0U) {
            if (d->phase == 0U) {
                /* the current and the vector still move: the swing has not begun */
                d->quiet_n = 0U;
                d->quiet_ref = d->pos;
            } else {
                mid_hold(d, dev);
            }
        }
        v_par = fix_add32(iq_mpy_q15(d->v_ab[0], c), iq_mpy_q15(d->v_ab[1], s));
        if (d->phase == 0U && moving == 0U) {
            d->phase = 1U;
            d->n = 0U;
        } else if (d->phase == 1U) {
            ++d->n;
            if (d->slow != 0U) {
                /* the encoder step: after n_settle, wait until the count stays within +-rest_tol
                 * of one value for ID_STILL periods; a rotor not at rest by ID_SETTLE_MAX is a coupled
                 * load, a blocked or a far too heavy rotor: named, not measured */
                const int32_t dev_c = d->pos - d->still_ref;
                if (dev_c > d->rest_tol || dev_c < -d->rest_tol) {
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
            if (d->recentre != 0U && fix_abs32(dev) < ID_RECENTRE_TOL && d->n < d->n_settle) {
                d->n = d->n_settle; /* recentred (the spin needs no rotor at rest) */
            }
            if (d->n >= d->n_settle && (d->slow == 0U || d->recentre != 0U || d->still_n >= ID_STILL)) {
                d->phase = 2U;
                d->wait_n = d->n;
                d->n = 0U;
            }
        } else if (d->phase == 2U && d->slow != 0U && d->recentre == 0U &&
                   (d->pos - d->still_ref > d->rest_tol || d->pos - d->still_ref < -d->rest_tol)) {
            /* a dwell's rotor that leaves its rest during the sums was at the turning point of a
             * slow creep, not at rest: the wait goes on (its time counted) and the sums start
             * again */
            d->phase = 1U;
            d->n = (uint16_t)(d->wait_n + d->n);
            d->still_n = 0U;
            d->still_ref = d->pos;
            d->sum_i = 0;
            d->sum_v = 0;
            d->sum_pos = 0;
            d->sum_q = 0;
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
