/*
 * app_fault.c - fault names and the application core's fault detection (see app_fault.h).
 */
#include "app_fault.h"

#include <stddef.h>

const char *app_fault_name(uint16_t fault)
{
    switch (fault) {
#define APP_FAULT_NAME_(id, num, name, detail, meaning)                                            \
    case APP_FAULT_##id: return name;
        APP_FAULT_LIST(APP_FAULT_NAME_)
#undef APP_FAULT_NAME_
    default: return "unknown";
    }
}

uint16_t app_fault_trips(app_fault_t *f, const dtc_config_t *c, const dtc_meas_t *pu, uint16_t perm,
                         int16_t *detail)
{
    const iq_t trip = c->prot.i_trip_iq;
    /* the first phase (law's order) above the trip level, 3 for none: three compares, no loop */
    const uint16_t k = fix_abs32(pu->ia_iq) > trip   ? 0U
                       : fix_abs32(pu->ib_iq) > trip ? 1U
                       : fix_abs32(pu->ic_iq) > trip ? 2U
                                                     : 3U;

    *detail = 0;
    if (k < 3U) {
        *detail = (int16_t)app_fault_phase(perm, k);
        return APP_FAULT_OVERCURRENT;
    }
    /* Failed current sensor (three sensors, prot.i_sum_max_iq): the star point is isolated, so
     * the three phase currents sum to zero; a sum above the level for APP_ISUM_PERIODS periods
     * is a sensor that does not measure its current (stuck, lost, wrong gain). The sum alone does
     * not say which; a stuck sensor reads one code whatever its current while the phases that
     * carry the machine's current move with the switching: the one phase whose reading stood
     * still (within APP_ISUM_STILL_COUNTS) over those periods while the other two moved is named
     * (APP_SENSOR_DETAIL_LIST 1), otherwise none (3): app_fault_isum, from flash on the F2812
     * (app_fault_isum.c), called only while the sum is off. Sums saturate. */
    if (c->prot.i_sum_max_iq > 0) {
        if (fix_abs32(fix_add32(fix_add32(pu->ia_iq, pu->ib_iq), pu->ic_iq)) > c->prot.i_sum_max_iq) {
            const iq_t i[3] = {pu->ia_iq, pu->ib_iq, pu->ic_iq};
            if (app_fault_isum(f, c, i, perm, detail) != 0U) {
                return APP_FAULT_CURRENT_SENSOR;
            }
        } else {
            f->isum_n = 0U;
        }
    }
    if (pu->vdc_iq > c->prot.vdc_max_iq) {
        return APP_FAULT_DC_OVERVOLTAGE;
    }
    if (pu->vdc_iq < c->prot.vdc_min_iq) {
        return APP_FAULT_DC_UNDERVOLTAGE;
    }
    return APP_FAULT_NONE;
}

/* 1 when phase k has not been seen in one direction for acc > APP_LEG_SIGN_ANGLE_IQ while both
 * other phases were seen in both directions since (their angles since either below acc). */
static uint16_t app_fault_one_way(const app_fault_t *f, uint16_t k, iq_t acc)
{
    const uint16_t j1 = app_fault_phase(k, 1U), j2 = app_fault_phase(k, 2U);
    return (uint16_t)(acc > APP_LEG_SIGN_ANGLE_IQ && f->pos_acc_iq[j1] < acc && f->neg_acc_iq[j1] < acc &&
                              f->pos_acc_iq[j2] < acc && f->neg_acc_iq[j2] < acc
                          ? 1U
                          : 0U);
}

/* Open phase (prot.leg_i_min_iq > 0): a leg that no longer switches its phase (leg or phase open)
 * leaves that phase's current at zero, and one open device leaves it at zero for every half-wave
 * the device should carry, while the other two phases carry the machine's current. Per phase k:
 * while |i_k| stays inside the zero band leg_i_min / 2^APP_LEG_ZERO_LOG2, the electrical angle
 * w Ts the machine turns is summed over the periods with |i| > leg_i_min (|i| the Clarke
 * magnitude, |i|^2 = (2/3) sum i_k^2 for an isolated star; below it the sum waits: the current
 * of the two remaining phases of an open one passes zero twice a turn), and a sum above
 * APP_LEG_ANGLE_IQ (60 deg) is an open phase (detection time pi / (3 w): 6.7 ms at 25 Hz, more
 * where the current dips). A healthy phase crosses the band: its
 * switching ripple alone moves it by several times the band every period or two (Hoang Table VIII,
 * 70 V: 0.1-0.5 A per period against 0.14 A), and even a phase current with a large DC part
 * (the uncompensated FSTP just after its hand-over: i_a ~ 4.5 A DC, phase B within |i|/4 for
 * 135 deg, SIL) keeps that ripple. A relative criterion (|i_k| < |i|/4) tripped there; the band
 * does not. A sum of the three measured currents of |i|/4 or more is a sensor, not a leg
 * (app_fault_trips names it once it lasts), and stops the sums. Found: the core reconfigures
 * when a post-fault configuration is set and the drive is not yet reconfigured, else trips
 * (APP_FAULT_LEG). At standstill no angle accumulates: a phase open at rest is found once the
 * machine turns. While relay_wait counts down (a reconfiguration's relay closing) the sums stay
 * at zero. PM laws, an open device: per phase the angle since it was last seen beyond the band in
 * each direction; a phase not seen in one direction over APP_LEG_SIGN_ANGLE_IQ (7 pi/3) while
 * both others were seen in both directions is open (app_fault.h: the voltage model keeps the
 * open device's phase outside the band). Scaling and overflow: currents are bounded by the trip level (app_fault_trips ran), at
 * most 128 pu (2^31 IQ); squares are formed in 64 bits and shifted right by 5 (<= 2^57), so 24 x^2 and the
 * sum of three stay below 2^63; 3 i_min^2 likewise; the angle sum saturates. */
uint16_t app_fault_open_phase(app_fault_t *f, const dtc_config_t *c, const dtc_meas_t *pu, iq_t speed_iq,
                              uint16_t perm, uint16_t hold, uint16_t *phase)
{
    const iq_t i[3] = {pu->ia_iq, pu->ib_iq, pu->ic_iq};
    iq_t s, zero;
    uint64_t sq[3], tot;
    iq_t dth;
    uint16_t k, sign, held, over = 0U;

    if (c->prot.leg_i_min_iq <= 0) {
        return 0U;
    }
    if (f->relay_wait > 0U) {
        f->relay_wait--;
        f->op_held = 0U;
        app_fault_leg_clear(f);
        return 0U;
    }
    /* a speed-loop period's sample is held over (app_fault.h), never two in a row */
    if (app_fault_open_phase_held(f, c, hold) != 0U) {
        return 0U;
    }
    held = f->op_held;
    f->op_held = 0U;
    s = fix_add32(fix_add32(i[0], i[1]), i[2]);
    if (f->imin_iq != c->prot.leg_i_min_iq) { /* a configuration constant: squared once per change */
        f->imin_iq = c->prot.leg_i_min_iq;
        f->imin2_3 = 3U * ((uint64_t)((int64_t)f->imin_iq * (int64_t)f->imin_iq) >> 5);
    }
    /* Both tests below pass without the squares when s = 0 (two sensors: the third current is
     * the other two's Kirchhoff sum) and a phase carries 1.5 i_min or more, the usual case:
     * with M = max |i_k| >= i_min + (i_min >> 1) >= 1.5 i_min - 1/2 (LSB), 2 tot >= 2 (M^2 / 32 - 1)
     * >= (2.25 i_min^2 - 1.5 i_min) / 16 - 2, which exceeds imin2_3 <= 3 i_min^2 / 32 for
     * i_min >= 8 LSB (1.5 i_min^2 > 3 i_min + 64); below 2^29, i_min + (i_min >> 1) cannot
     * overflow. Exact: the same decisions as with the squares, which are then not formed. */
    if (s != 0 || f->imin_iq < 8 || f->imin_iq >= ((iq_t)1 << 29) ||
        (fix_abs32(i[0]) < f->imin_iq + (f->imin_iq >> 1) && fix_abs32(i[1]) < f->imin_iq + (f->imin_iq >> 1) &&
         fix_abs32(i[2]) < f->imin_iq + (f->imin_iq >> 1))) {
        for (k = 0U; k < 3U; k++) {
            sq[k] = (uint64_t)((int64_t)i[k] * (int64_t)i[k]) >> 5;
        }
        tot = sq[0] + sq[1] + sq[2];
        if (2U * tot <= f->imin2_3) {
            return 0U; /* too little current to judge: the sums wait (a healthy phase leaves the
                        * band, which resets its sum, as soon as there is current again); the
                        * current sum is not judged either (near zero the sensors' noise alone
                        * reaches tot / 24) */
        }
        /* s is 0 whenever the third current is the other two's Kirchhoff sum (two sensors): then
         * 24 s^2 = 0 < tot (tot > imin2_3 / 2 >= 0 here) and no product is formed */
        if (s != 0 && 24U * ((uint64_t)((int64_t)s * (int64_t)s) >> 5) >= tot) {
            app_fault_leg_clear(f); /* the sum says a sensor is wrong: no phase is judged */
            return 0U;
        }
    }
    if (speed_iq != f->dth_w_iq || c->board.ts_pu_iq != f->dth_ts_iq) { /* the speed changes at the speed-loop rate */
        f->dth_w_iq = speed_iq;
        f->dth_ts_iq = c->board.ts_pu_iq;
        f->dth_iq = iq_mpy(fix_abs32(speed_iq), c->board.ts_pu_iq);
    }
    dth = held != 0U ? fix_add32(f->dth_iq, f->dth_iq) : f->dth_iq; /* the held period's angle too */
    zero = fix_rshift_rnd32(c->prot.leg_i_min_iq, APP_LEG_ZERO_LOG2);
    /* The angles since each direction was last seen (PM laws: an open device, one direction
     * only) and inside the band. Beyond it (|i| >= zero, the usual case) only the other
     * direction's angle grows; zero >= 0, so i > zero and i < -zero exclude each other and
     * |i| < zero holds only between them (|INT32_MIN| saturates, beyond -zero anyway). A sum
     * that grows past its level sets `over`; only then are the phases judged below (a sum that
     * did not grow in this period was judged, and passed, when it last did). */
    sign = dtc_law_is_im(c->law) == 0U ? 1U : 0U;
    for (k = 0U; k < 3U; k++) {
        if (i[k] > zero) {
            f->leg_acc_iq[k] = 0;
            if (sign != 0U) {
                f->pos_acc_iq[k] = 0;
                f->neg_acc_iq[k] = fix_add32(f->neg_acc_iq[k], dth);
                over |= (uint16_t)(f->neg_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ ? 1U : 0U);
            }
        } else if (i[k] < -zero) {
            f->leg_acc_iq[k] = 0;
            if (sign != 0U) {
                f->pos_acc_iq[k] = fix_add32(f->pos_acc_iq[k], dth);
                f->neg_acc_iq[k] = 0;
                over |= (uint16_t)(f->pos_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ ? 1U : 0U);
            }
        } else {
            f->leg_acc_iq[k] = fix_abs32(i[k]) < zero ? fix_add32(f->leg_acc_iq[k], dth) : 0;
            over |= (uint16_t)(f->leg_acc_iq[k] > APP_LEG_ANGLE_IQ ? 1U : 0U);
            if (sign != 0U) {
                f->pos_acc_iq[k] = fix_add32(f->pos_acc_iq[k], dth);
                f->neg_acc_iq[k] = fix_add32(f->neg_acc_iq[k], dth);
                over |= (uint16_t)(f->pos_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ || f->neg_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ
                                       ? 1U
                                       : 0U);
            }
        }
    }
    if (over == 0U) {
        return 0U; /* no sum past its level: none of the tests below can pass */
    }
    for (k = 0U; k < 3U; k++) {
        /* app_fault_one_way's own first test here, so that the call comes only past it */
        if (f->leg_acc_iq[k] > APP_LEG_ANGLE_IQ ||
            (sign != 0U && ((f->pos_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ && app_fault_one_way(f, k, f->pos_acc_iq[k]) != 0U) ||
                            (f->neg_acc_iq[k] > APP_LEG_SIGN_ANGLE_IQ && app_fault_one_way(f, k, f->neg_acc_iq[k]) != 0U)))) {
            *phase = app_fault_phase(perm, k);
            return 1U;
        }
    }
    return 0U;
}

/* Stall (speed mode): on each speed-loop period, with the torque reference at its limit, a window
 * of c->prot.stall_speed_periods is open; it trips when at its end the speed error has not shrunk
 * since its start. Any period below the limit closes the window. Torque mode has no speed error
 * to watch and is left alone. Scaling: |speed_ref - speed| saturated difference; compared. */
uint16_t app_fault_stall(app_fault_t *f, const dtc_config_t *c, const dtc_out_t *o, iq_t speed_ref_iq,
                         int16_t *detail)
{
    iq_t err;
    if (c->speed.mode != (uint16_t)DTC_MODE_SPEED || o->speed_tick == 0U) {
        return APP_FAULT_NONE;
    }
    if (fix_abs32(o->te_ref_iq) < c->speed.torque_limit_iq) {
        f->stall_n = 0U;
        return APP_FAULT_NONE;
    }
    err = fix_abs32(fix_sub32(speed_ref_iq, o->speed_iq));
    if (f->stall_n == 0U) {
        f->stall_err0_iq = err;
    }
    if (++f->stall_n < c->prot.stall_speed_periods) {
        return APP_FAULT_NONE;
    }
    f->stall_n = 0U;
    if (err >= f->stall_err0_iq) {
        *detail = (int16_t)(o->te_ref_iq < 0 ? -1 : 1);
        return APP_FAULT_STALL;
    }
    return APP_FAULT_NONE;
}
