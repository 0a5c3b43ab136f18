/*
 * app_fault.h - the drive's fault reasons (one table: number, name, what the detail means) and
 * the fault detection of the application core (app_core.h) on the per-unit sample: phase
 * over-current, the current sum of three sensors, DC-link over- and under-voltage, the hardware
 * trip and desaturation inputs, an open phase, a stall; and the check of a post-fault
 * configuration. The functions only detect: each returns the fault found (enum app_fault) with
 * its detail, and the core latches it. The encoder's checks are app_enc.h.
 *
 * State: app_fault_t, owned by the caller (the core), no static state.
 */
#ifndef APP_FAULT_H
#define APP_FAULT_H

#include <stdint.h>

#include "hal.h"
#include "law.h"

/* What a fault's detail (app_status_t.fault_detail) means. */
enum app_fault_detail {
    APP_DETAIL_NONE = 0,    /* 0 */
    APP_DETAIL_DTC_ERR = 1, /* enum dtc_err */
    APP_DETAIL_PHASE = 2,   /* physical phase or leg 0 = A, 1 = B, 2 = C */
    APP_DETAIL_CHANNEL = 3, /* ADC channel (enum hal_adc_channel) */
    APP_DETAIL_ENCODER = 4, /* the encoder check that failed (APP_ENC_DETAIL_LIST) */
    APP_DETAIL_SIGN = 5,    /* the sign of the torque reference (or speed), -1 or 1 */
    APP_DETAIL_SENSOR = 6   /* current sensor: 3 * (the check that found it, APP_SENSOR_DETAIL_LIST)
                             * + the physical phase 0 = A, 1 = B, 2 = C */
};

/* The fault reasons: X(ID, number, name, detail, meaning). The number is stable (it is the
 * status's fault code), the name is the text app_fault_name() gives and the host reports; the
 * meaning is the host's one-line description of a latched fault, "%c" standing for the phase
 * letter of an APP_DETAIL_PHASE detail ("" where the name says it all). Only the host expands
 * the meaning: the firmware image carries the names.
 *  - CONFIG: law_init (or app_core_set_pwm_period, app_core_set_reconfig) refused the configuration.
 *  - OVERCURRENT: |i| > prot.i_trip_iq on a phase.
 *  - DC_OVERVOLTAGE, DC_UNDERVOLTAGE: V_dc above prot.vdc_max_iq, below prot.vdc_min_iq.
 *  - ENCODER: app_enc.h.
 *  - HW_TRIP: the hardware protection input (PDPINTA).
 *  - ADC_OFFSET: a calibrated offset too far from nominal.
 *  - STALL: speed mode, the torque reference at its limit while the speed error did not shrink
 *    for prot.stall_speed_periods speed-loop periods (the host converts a time, 0.1 s by
 *    default): a locked rotor or a load above the limit cannot reach the reference; it is
 *    tripped, not left to run.
 *  - DESAT: a gate driver's desaturation output: a shorted device or shoot-through.
 *  - CURRENT_SENSOR: a stuck or failed current sensor (APP_SENSOR_DETAIL_LIST).
 *  - LEG: a phase carries no current while the others do (an open leg, phase or device) and no
 *    reconfiguration is possible.
 *  - OVERSPEED: app_fault_overspeed.
 *  - ENCODER_SPEED: the IM laws with the encoder: the encoder's speed against the estimated flux's
 *    (app_enc.h app_enc_flux_check); detail the sign of (flux speed - encoder speed).
 *  - COMM_TIMEOUT: command arming (app_core.h APP_ARM_COMMAND) with a command timeout set: the
 *    drive was armed and the host sent no valid frame for that long. */
#define APP_FAULT_LIST(X)                                                                          \
    X(NONE, 0, "none", APP_DETAIL_NONE, "")                                                        \
    X(CONFIG, 1, "config", APP_DETAIL_DTC_ERR, "")                                                 \
    X(OVERCURRENT, 2, "overcurrent", APP_DETAIL_PHASE,                                             \
      "phase %c current above protection.overcurrent_a")                                           \
    X(DC_OVERVOLTAGE, 3, "dc_overvoltage", APP_DETAIL_NONE, "")                                    \
    X(DC_UNDERVOLTAGE, 4, "dc_undervoltage", APP_DETAIL_NONE, "")                                  \
    X(ENCODER, 5, "encoder", APP_DETAIL_ENCODER, "encoder")                                        \
    X(HW_TRIP, 6, "hw_trip", APP_DETAIL_NONE, "")                                                  \
    X(ADC_OFFSET, 7, "adc_offset", APP_DETAIL_CHANNEL, "")                                         \
    X(STALL, 8, "stall", APP_DETAIL_SIGN,                                                          \
      "torque reference at its limit while the speed error did not shrink")                        \
    X(DESAT, 9, "desat", APP_DETAIL_PHASE,                                                         \
      "gate-driver desaturation on leg %c (a shorted device or shoot-through): every gate off")    \
    X(CURRENT_SENSOR, 10, "current_sensor", APP_DETAIL_SENSOR, "current sensor")                   \
    X(LEG, 11, "leg", APP_DETAIL_PHASE,                                                            \
      "phase %c carries no current while the others do (an open leg, phase or device) and the "    \
      "drive cannot be reconfigured (no relay fitted, a second failure, or a law without it)")    \
    X(OVERSPEED, 12, "overspeed", APP_DETAIL_SIGN,                                                 \
      "measured speed beyond protection.overspeed_rpm")                                            \
    X(ENCODER_SPEED, 13, "encoder_speed", APP_DETAIL_SIGN,                                         \
      "the encoder's speed disagrees with the speed of the estimated rotor flux less its slip "     \
      "(Casadei eqs. 16, 22) by more than the slip at the torque limit allows: encoder lost, "     \
      "slipping or wired to another shaft")                                   \
    X(COMM_TIMEOUT, 14, "comm_timeout", APP_DETAIL_NONE,                                           \
      "armed and no valid frame from the host for comm_timeout_s: torque to zero, disarmed")

/* The current-sensor fault's details: X(check, meaning); the detail is 3 * check + the physical
 * phase, "%c" its letter.
 *  0: two sensors, the channel does not follow the current the law predicts from the voltage it
 *     applied (app_plaus.h);
 *  1: three sensors whose sum is not zero, one reading standing still while the others moved
 *     (APP_ISUM_STILL_COUNTS): that phase is named;
 *  2: two sensors, the channel reads zero while the law drives current into it: its sensor stuck
 *     at zero or the phase open, which two sensors cannot tell apart. */
#define APP_SENSOR_DETAIL_LIST(X)                                                                  \
    X(0, "phase %c's current sensor does not follow the current the law predicts from the voltage " \
         "it applied: a stuck or failed sensor")                                                   \
    X(1, "the three measured phase currents do not sum to zero and phase %c's reading stood still " \
         "while the others moved: its current sensor stuck")                                       \
    X(2, "phase %c reads zero while the law drives current into it: its current sensor stuck at "  \
         "zero, or the phase open (two sensors cannot tell which; a third sensor can)")           \
    X(3, "the three measured phase currents do not sum to zero: a failed current sensor; which one " \
         "the sum cannot tell (no single reading stood still while the others moved)")

/* The encoder fault's details: X(number, meaning) (app_enc.h). */
#define APP_ENC_DETAIL_LIST(X)                                                                     \
    X(1, "implausible encoder count change")                                                       \
    X(2, "encoder index pulse at another count (lost or extra counts)")                            \
    X(3, "encoder signal lost: the count stood still at a speed where that is impossible")

#define APP_FAULT_ENUM_(id, num, name, detail, meaning) APP_FAULT_##id = num,
enum app_fault { APP_FAULT_LIST(APP_FAULT_ENUM_) APP_FAULT_COUNT_ };
#undef APP_FAULT_ENUM_

/* Short text of a fault reason, APP_FAULT_LIST's name (never NULL; "unknown" for any other number). */
const char *app_fault_name(uint16_t fault);

/* Fault detection: a current sum above prot.i_sum_max_iq for this many consecutive periods is a
 * failed sensor (a few periods: noise and the sampling skew of the three channels never last
 * that long at that level). */
#define APP_ISUM_PERIODS 8U
/* The phase the sum check names: the one reading that stood still, within this many ADC counts
 * (the sensors' noise), over those periods while the other two moved (a stuck sensor reads one
 * code whatever its current; a phase carrying the machine's current moves by the switching
 * ripple every period). */
#define APP_ISUM_STILL_COUNTS 2
/* Open phase: the electrical angle, IQ rad (pi/3), over which a phase must stay inside the zero
 * band (prot.leg_i_min_iq / 2^APP_LEG_ZERO_LOG2) while |i| is above prot.leg_i_min_iq to be taken
 * for open: 6.7 ms at 1500 rpm for Hoang Table VIII (p = 1; within 20 ms). A healthy sinusoidal phase
 * is within |i|/4 of zero for only 29 deg around a crossing, and its ripple takes it out of the
 * much narrower band within a period or two. */
#define APP_LEG_ANGLE_IQ ((iq_t)17568813) /* pi/3 * 2^24 */
#define APP_LEG_ZERO_LOG2 2U
/* Open device, PM laws: the electrical angle, IQ rad (7 pi/3), over which a phase must never read
 * beyond the zero band in one direction while the machine carries current (|i| above
 * prot.leg_i_min_iq), and both other phases have read beyond it in both directions, to be taken
 * for open.
 * One open device of a leg (the other and both diodes still conduct) lets its phase carry current
 * in one direction only: a half-wave that sits inside the zero band for the other half-period
 * where the law's flux follows the machine (the current model), but with the voltage model's
 * flux integrating the voltage the open leg did not apply, the law keeps that phase's current
 * small in the one direction and leaves the band every few periods (measured: -0.2 .. -0.4 A
 * where the band is 0.07 A), so the band alone never lasts pi/3. A synchronous machine's phase
 * current changes sign every half electrical turn; a torque reversal that lands on a zero
 * crossing extends one sign to at most a whole turn (2 pi), hence 2 pi plus the band's pi/3. The
 * other phases' alternation tells the open phase from a healthy one that the voltage model's wrong
 * flux holds at a current of one sign for as long (measured: -4 A on A and +4 A on C while
 * the open B upper device kept B at -2.8 .. 0 A; elsewhere B at -5 .. 0 A, the largest current,
 * while A and C alternated). Not for
 * the IM laws, whose stator frequency is not the rotor's electrical speed (at a large slip the
 * phase current keeps its sign for more rotor angle). */
#define APP_LEG_SIGN_ANGLE_IQ ((iq_t)122981693) /* 7 pi/3 * 2^24 */

typedef struct {
    uint16_t isum_n;       /* consecutive periods with |i_a + i_b + i_c| > prot.i_sum_max_iq */
    uint16_t isum_moved;   /* bit k: phase k (law's order) moved beyond APP_ISUM_STILL_COUNTS from
                            * isum_i0_iq during those periods */
    iq_t isum_i0_iq[3];    /* the phase currents of the first of those periods */
    iq_t leg_acc_iq[3];    /* electrical angle, IQ rad, over which phase k (law's order) looked open */
    iq_t pos_acc_iq[3];    /* electrical angle, IQ rad, since phase k last read above the zero band */
    iq_t neg_acc_iq[3];    /* electrical angle, IQ rad, since phase k last read below the zero band */
    uint16_t relay_wait;   /* periods left until the relay is surely closed */
    uint16_t stall_n;      /* speed periods of the current stall window (0 = none open) */
    iq_t stall_err0_iq;    /* |speed error| at the start of the window */
    iq_t imin_iq;          /* open phase: the leg_i_min_iq that imin2_3 was formed from */
    uint64_t imin2_3;      /* 3 ((imin_iq^2) >> 5), IQ pu^2 / 2^5 (app_fault_open_phase): formed when
                            * the configuration's leg_i_min_iq differs from imin_iq, not per period */
    iq_t dth_w_iq, dth_ts_iq; /* open phase: the speed and period that dth_iq was formed from */
    iq_t dth_iq;           /* |w| Ts, IQ rad per period: formed when the speed (a speed-loop rate
                            * quantity) or the period differs from the last, not per period */
    uint16_t op_held;      /* open phase: 1 when the last period's sample was not judged (a
                            * speed-loop period, app_fault_open_phase's hold), 0 else */
} app_fault_t;

/* (p + k) mod 3 for p + k in 0..5, without a division: the physical phase of the law's phase k
 * when the law's phase 0 is the physical phase p (app_core_t.perm). */
static inline uint16_t app_fault_phase(uint16_t p, uint16_t k)
{
    const uint16_t s = (uint16_t)(p + k);
    return s >= 3U ? (uint16_t)(s - 3U) : s;
}

/* Zeroes the open-phase angles. */
static inline void app_fault_leg_clear(app_fault_t *f)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        f->leg_acc_iq[k] = 0;
        f->pos_acc_iq[k] = 0;
        f->neg_acc_iq[k] = 0;
    }
}

/* Zeroes the current-sum count and the open-phase angles (entering the calibration). */
static inline void app_fault_reset(app_fault_t *f)
{
    f->isum_n = 0U;
    f->op_held = 0U;
    app_fault_leg_clear(f);
}

/* Every counter zero, the relay settled and no stall window open (init). */
static inline void app_fault_init(app_fault_t *f)
{
    f->relay_wait = 0U;
    f->stall_n = 0U;
    f->stall_err0_iq = 0;
    f->imin_iq = 0;
    f->imin2_3 = 0U; /* 3 ((0^2) >> 5) */
    f->dth_w_iq = 0;
    f->dth_ts_iq = 0;
    f->dth_iq = 0; /* |0| 0 */
    app_fault_reset(f);
}

/* After a reconfiguration: the open-phase check waits relay_periods periods for the relay to
 * close, with its angles and the stall window cleared. */
static inline void app_fault_reconfigured(app_fault_t *f, uint16_t relay_periods)
{
    f->relay_wait = relay_periods;
    f->stall_n = 0U;
    app_fault_leg_clear(f);
}

/* 1 while a phase has looked open (inside the zero band, app_fault_open_phase) over more than an
 * eighth of APP_LEG_ANGLE_IQ (7.5 deg electrical): the open-phase check is judging it. An open
 * phase makes the law's voltage reconstruction wrong (the open leg's voltage is not what its
 * state says), so the flux angle's speed (Casadei eqs. 16, 22) leaves the encoder's before the
 * open phase is found (SIL, IM on im_second_machine at 1000 rpm, leg B: the encoder plausibility
 * latched 3.4 ms after the leg opened, the open-phase check needs 60 deg, 5 ms): the
 * encoder plausibility (app_enc_flux_check) rests meanwhile. A healthy phase leaves the band
 * within a period or two (app_fault_open_phase). */
static inline uint16_t app_fault_phase_suspect(const app_fault_t *f)
{
    const iq_t lim = APP_LEG_ANGLE_IQ >> 3;
    return (uint16_t)(f->leg_acc_iq[0] > lim || f->leg_acc_iq[1] > lim || f->leg_acc_iq[2] > lim ? 1U : 0U);
}

/* The hardware protection input (PDPINTA) and the gate drivers' desaturation outputs that pull
 * it: a desaturation is named with its leg (the lowest one flagged), any other trip as the
 * hardware trip. Returns the fault (APP_FAULT_NONE: none) and sets *detail. */
static inline uint16_t app_fault_hw(const hal_meas_t *m, int16_t *detail)
{
    uint16_t x;
    if ((m->desat & 7U) == 0U && m->trip == 0U) {
        return APP_FAULT_NONE; /* the usual period: one test */
    }
    for (x = 0U; x < 3U; x++) {
        if ((m->desat & (uint16_t)(1U << x)) != 0U) {
            *detail = (int16_t)x;
            return APP_FAULT_DESAT;
        }
    }
    if (m->trip != 0U) {
        *detail = 0;
        return APP_FAULT_HW_TRIP;
    }
    return APP_FAULT_NONE;
}

/* Trip checks on one per-unit sample pu (law's phase order; its phase k is the physical phase
 * app_fault_phase(perm, k)) after app_fault_hw: over-current, the current sum, the DC link.
 * Returns the fault (APP_FAULT_NONE: none) and sets *detail. */
uint16_t app_fault_trips(app_fault_t *f, const dtc_config_t *c, const dtc_meas_t *pu, uint16_t perm,
                         int16_t *detail);

/* Open phase (prot.leg_i_min_iq > 0) on the sample pu at the reported speed speed_iq (app_fault.c):
 * a phase inside the zero band over APP_LEG_ANGLE_IQ, or (PM laws) never beyond it in one
 * direction over APP_LEG_SIGN_ANGLE_IQ while the other two alternate. Returns 1 with *phase the physical phase found open, else 0.
 * hold = 1 (the law ran its speed loop in this period, its longest step): the sample is not judged
 * unless the last one was not either; the next judged sample then counts the angle of both
 * periods. So the check never adds to a speed-loop period but with a speed loop every period,
 * and an open phase is found at most one period (Ts) later than when every sample is judged. */
uint16_t app_fault_open_phase(app_fault_t *f, const dtc_config_t *c, const dtc_meas_t *pu, iq_t speed_iq,
                              uint16_t perm, uint16_t hold, uint16_t *phase);

/* The hold of app_fault_open_phase: 1 when this period's sample is held over (hold set, the last
 * sample judged, the check on and no relay closing), with the hold noted (op_held), else 0.
 * Inline: the core asks it before the call (app_core.c), so that a speed-loop period pays no
 * call for the check. */
static inline uint16_t app_fault_open_phase_held(app_fault_t *f, const dtc_config_t *c, uint16_t hold)
{
    if (hold != 0U && f->op_held == 0U && f->relay_wait == 0U && c->prot.leg_i_min_iq > 0) {
        f->op_held = 1U;
        return 1U;
    }
    return 0U;
}

/* Stall (speed mode) on the law's output o with the speed reference speed_ref_iq (app_fault.c).
 * Returns APP_FAULT_STALL (detail: the sign of the torque reference) or APP_FAULT_NONE. */
uint16_t app_fault_stall(app_fault_t *f, const dtc_config_t *c, const dtc_out_t *o, iq_t speed_ref_iq,
                         int16_t *detail);

/* Overspeed (prot.overspeed_iq > 0): on a speed-loop period of the law's output o, the measured
 * speed above the level the host derives from the rated speed and the speed limit, either
 * direction (torque mode with no load, an active load driving the machine). Returns
 * APP_FAULT_OVERSPEED (detail: the speed's sign) or APP_FAULT_NONE. */
static inline uint16_t app_fault_overspeed(const dtc_config_t *c, const dtc_out_t *o, int16_t *detail)
{
    if (c->prot.overspeed_iq > 0 && o->speed_tick != 0U && fix_abs32(o->speed_iq) > c->prot.overspeed_iq) {
        *detail = (int16_t)(o->speed_iq < 0 ? -1 : 1);
        return APP_FAULT_OVERSPEED;
    }
    return APP_FAULT_NONE;
}

/* 1 when post may be the post-fault configuration of the running configuration c
 * (app_core_set_reconfig, app_core.h), else 0. */
uint16_t app_fault_post_ok(const dtc_config_t *c, const dtc_config_t *post);

/* The three-sensor sum check on a period its sum is off (app_fault_trips; app_fault_isum.c, from
 * flash on the F2812): counts the period and follows which readings moved (APP_ISUM_STILL_COUNTS);
 * on the APP_ISUM_PERIODS-th in a row returns 1 with *detail the APP_SENSOR_DETAIL_LIST code
 * (1: the one reading that stood still, the physical phase through perm; 3: none to name). */
uint16_t app_fault_isum(app_fault_t *f, const dtc_config_t *c, const iq_t i[3], uint16_t perm, int16_t *detail);

#endif /* APP_FAULT_H */
