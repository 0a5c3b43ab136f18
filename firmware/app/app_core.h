/*
 * app_core.h - the drive's state machine and ISR body as a pure function of its state and one
 * raw measurement (no HAL calls, so unit tests drive it directly; app.c binds it to the HAL).
 *
 *   INIT --app_core_init ok--> CALIBRATE --64 periods (1024 with the FSTP mid-point
 *                                calibration), offsets and DC link sane--> RUN
 *     |                          |                                                  |
 *     +--bad configuration-------+---------------- any trip ------------------------+--> FAULT
 *   FAULT is latched with every gate off and a reason code; a clear request (background) takes
 *   the drive back to CALIBRATE, unless the fault is the configuration.
 *
 * Per period (app_core_step): raw ADC/encoder counts -> per-unit (calibrated offsets, config
 * gains) -> trip checks on THIS sample (phase over-current on all three currents, DC-link over-
 * and under-voltage, hardware trip input, encoder plausibility) -> the configured control law
 * (law_step: PM DTC or IM DTC/DSC) -> leg command. A
 * trip decided here turns the gates off in the same ISR that saw the sample.
 *
 * Formats: per-unit IQ (fixmath.h, dtc_base.h). Scaling and overflow: a count difference is at
 * most +-4095 and the gains are IQ pu per count; the product is formed in 64 bits and saturates
 * at +-128 pu, far beyond any trip level, so a saturated value still trips.
 */
#ifndef APP_CORE_H
#define APP_CORE_H

#include <stdint.h>

#include "dtc.h"
#include "hal.h"
#include "law.h"

enum app_state {
    APP_STATE_INIT = 0,
    APP_STATE_CALIBRATE = 1, /* gates off, measuring the current-sensor offsets; then, with the
                              * FSTP mid-point calibration and prot.i_hold_iq > 0, the rotor
                              * hold (gates on, phases B and C only) until it ends */
    APP_STATE_RUN = 2,
    APP_STATE_FAULT = 3      /* latched, gates off */
};

/* Stall (APP_FAULT_STALL): a drive at its torque limit whose speed error has not shrunk over
 * cfg->stall_speed_periods speed-loop periods (the host converts a time, 0.1 s by default) cannot
 * reach the reference (a locked rotor or a load above the limit): it is tripped, not left to run. */

/* Fault reasons (stable numbers; app_fault_name() gives the text). */
enum app_fault {
    APP_FAULT_NONE = 0,
    APP_FAULT_CONFIG = 1,         /* law_init refused the configuration (detail: enum dtc_err) */
    APP_FAULT_OVERCURRENT = 2,    /* |i| > i_trip on a phase (detail: phase 0=A, 1=B, 2=C) */
    APP_FAULT_DC_OVERVOLTAGE = 3, /* V_dc > vdc_max */
    APP_FAULT_DC_UNDERVOLTAGE = 4,/* V_dc < vdc_min */
    APP_FAULT_ENCODER = 5,        /* implausible count jump (detail 1) or index mismatch (2) */
    APP_FAULT_HW_TRIP = 6,        /* hardware protection input (PDPINTA) */
    APP_FAULT_ADC_OFFSET = 7,     /* calibrated offset too far from nominal (detail: channel) */
    APP_FAULT_STALL = 8,          /* speed mode: torque reference at its limit while the speed
                                   * error did not shrink for cfg->stall_speed_periods (detail:
                                   * the sign of the torque reference) */
    APP_FAULT_DESAT = 9,          /* gate-driver desaturation: a shorted device or shoot-through
                                   * (detail: leg 0=A, 1=B, 2=C) */
    APP_FAULT_CURRENT_SENSOR = 10,/* the three measured currents do not sum to zero (a stuck or
                                   * failed sensor; detail: the channel judged failed) */
    APP_FAULT_LEG = 11            /* a phase carries no current while the others do (an open
                                   * leg, phase or device) and no reconfiguration is possible
                                   * (detail: phase 0=A, 1=B, 2=C) */
};

/* Calibration: 2^APP_CAL_LOG2 samples averaged per current channel (and for the FSTP mid-point,
 * dtc_config.h vmid_cal). Largest accepted mid-point inconsistency: V_dc/2^APP_VMID_TOL_LOG2. */
#define APP_VMID_TOL_LOG2 4U
/* Mid-point calibration: 2^APP_VMID_CAL_LOG2 samples (51 ms at 50 us; the current offsets use the
 * first 2^APP_CAL_LOG2 of them). The low-pass of the voltage model turns a DC error E on v_alpha
 * into a current E / (w_c L_s): 1 mV is 0.04 A for Table VIII at 5 rad/s, so the mean must be
 * good to about a millivolt: 1024 samples divide the sensors' noise by 32. */
#define APP_VMID_CAL_LOG2 10U
#define APP_CAL_LOG2 6U
/* Rotor hold during the mid-point calibration (app_core.c hold_step): the hold current reaches
 * prot.i_hold_iq at a deviation of 2^APP_HOLD_ZONE_LOG2 encoder counts. One count is the
 * encoder's quantisation: a zone of two keeps the hold from chattering between full positive and
 * full negative current at rest, and any load the hold can carry moves the rotor by at most that
 * (plus the angle it needs to find |cos theta_e| large enough, below). */
#define APP_HOLD_ZONE_LOG2 1U
/* The hold's damping: the deviation it acts on is predicted 2^APP_HOLD_LEAD_LOG2 periods ahead
 * (0.8 ms at 50 us) with the speed low-passed over as many periods. Without it the relay-like
 * loop (current rise over ~8 periods, no friction) oscillates at full torque, and a rotor the
 * load pushed away from where the hold has torque (|cos theta_e| small) arrives at the start
 * still moving. A speed below one count per 2^APP_HOLD_LEAD_LOG2 periods counts as settled: the
 * hold goes on after the calibration until then, at most 2^APP_VMID_CAL_LOG2 periods more. */
#define APP_HOLD_LEAD_LOG2 4U
/* Fault detection (app_core.c; issue 16). A current sum above prot.i_sum_max_iq for this many
 * consecutive periods is a failed sensor (a few periods: noise and the sampling skew of the three
 * channels never last that long at that level). */
#define APP_ISUM_PERIODS 8U
/* Open phase: the electrical angle, IQ rad (pi/3), over which a phase must stay inside the zero
 * band (prot.leg_i_min_iq / 2^APP_LEG_ZERO_LOG2) while |i| is above prot.leg_i_min_iq to be taken
 * for open: 6.7 ms at 1500 rpm for Table VIII (p = 1; within the 20 ms of issue 16). A healthy
 * sinusoidal phase is within |i|/4 of zero for only 29 deg around a crossing, and its ripple
 * takes it out of the much narrower band within a period or two. */
#define APP_LEG_ANGLE_IQ ((iq_t)17568813) /* pi/3 * 2^24 */
#define APP_LEG_ZERO_LOG2 2U
/* Lost encoder signal: periods without a count change (prot.enc_freeze_speed_iq). */
#define APP_ENC_FREEZE_PERIODS 32U
/* Index check: accepted difference between latched index counts (edge jitter, direction). */
#define APP_INDEX_TOL_COUNTS 4

typedef struct {
    uint16_t state;       /* enum app_state */
    uint16_t fault;       /* enum app_fault */
    int16_t fault_detail; /* see enum app_fault */
    uint32_t tick;        /* tick of the last processed measurement */
    uint32_t fault_tick;  /* tick at which the fault latched */
    dtc_meas_t meas;      /* last per-unit measurement (third current derived) */
    dtc_out_t out;        /* last controller output (valid in RUN) */
    uint16_t reconfigured; /* enum hal_relay: the phase moved onto the mid-point after a leg
                            * failure (the drive runs as an FSTP since), 0 = none */
} app_status_t;

typedef struct app_core {
    const dtc_config_t *cfg;
    law_t law;             /* the configured control law (law.h) */
    app_status_t st;
    uint16_t offset[3];    /* current-sensor offsets in use, counts */
    uint32_t cal_sum[3];
    uint16_t cal_n;
    uint16_t hold_on;      /* 1: the rotor hold runs (CALIBRATE after the current offsets) */
    uint16_t hold_count0;  /* encoder count the hold keeps the rotor at */
    uint16_t hold_prev;    /* encoder count of the previous hold period */
    uint16_t hold_extra;   /* hold periods after the calibration, waiting for the rotor to settle */
    int32_t hold_v_q16;    /* rotor speed, counts per period, Q16, low-passed over 2^APP_HOLD_LEAD_LOG2 */
    int64_t vmid_cal_sum_iq; /* calibration: sum of (mid-point - V_dc/2), IQ pu (cfg->vmid_cal) */
    iq_t vmid_cal_iq;      /* the two voltage sensors' inconsistency, subtracted from vmid, pu */
    uint16_t meas_ch[2];   /* the two measured current channels (HAL_ADC_IA.. IC) */
    uint16_t enc_jump_counts; /* the largest plausible count change in one control period:
                               * twice the speed limit, and never below 1 count (quantisation) */
    uint16_t stall_n;      /* speed periods of the current stall window (0 = none open) */
    iq_t stall_err0_iq;    /* |speed error| at the start of the window */
    uint16_t enc_last;
    uint16_t enc_primed;
    uint16_t index_ref;    /* count latched by the first index pulse */
    uint16_t index_known;
    volatile uint16_t clear_request; /* set by the background, adopted by the ISR */
    uint16_t t1pr;         /* Timer 1 period of the PWM form (hal_pwm_period()), counts; 0 = none */
    /* Fault tolerance (issue 16; check_faults, reconfigure in app_core.c). */
    const dtc_config_t *post; /* the post-fault FSTP configuration (app_core_set_reconfig) or NULL */
    uint16_t perm;         /* the law's phase k is the physical phase (perm + k) mod 3: 0 before a
                            * reconfiguration, the failed phase after it */
    uint16_t relay_wait;   /* periods left until the relay is surely closed */
    uint16_t isum_n;       /* consecutive periods with |i_a + i_b + i_c| > prot.i_sum_max_iq */
    uint16_t enc_still_n;  /* consecutive periods without an encoder count change */
    iq_t leg_acc_iq[3];    /* electrical angle, IQ rad, over which phase k (law's order) looked open */
} app_core_t;

/* Validates the configuration (law_init) and enters CALIBRATE. Returns 0 or the dtc_err code;
 * on error the core is in FAULT with APP_FAULT_CONFIG. */
int16_t app_core_init(app_core_t *a, const dtc_config_t *cfg);

/* The HAL's PWM timer period T1PR (hal_pwm_period(), counts), for a law that commands the PWM
 * form (IM scheme SFVC: dtc_out_t.pwm). Such a law with t1pr = 0 (the control period is not a
 * whole number of timer counts; also DFOC) or t1pr = 0xFFFF (no 16-bit compare value above it, so
 * a duty of 0 or 1 cannot be written: hal.h, T1PR + 1) cannot be run: the core latches
 * APP_FAULT_CONFIG with DTC_ERR_SVM (in place of any fault latched before, which a clear request
 * would end) and returns that code; otherwise 0. */
int16_t app_core_set_pwm_period(app_core_t *a, uint16_t t1pr);

/* Fault tolerance (issue 16): post is the FSTP configuration of the same PM drive that the
 * application switches to when a leg fails (check_faults: a phase carries no current while the
 * others do), with the failed phase on the capacitor mid-point through the relay (hal_cmd_t
 * relay). It must pass dtc_config_validate, be the PM law on the FSTP, with the same encoder and
 * ADC scaling, three current sensors (board.i_sensors3: only the sum of three measured currents
 * tells a failed sensor from a failed leg), no mid-point calibration (the drive does not stop for
 * it), prot.relay_periods > 0; the running configuration must be the PM law on the SSTP with
 * three sensors and the open-phase check on. Otherwise the core latches APP_FAULT_CONFIG with
 * DTC_ERR_RECONFIG and returns it. post = NULL (the default): no relay fitted, a failed leg
 * trips (APP_FAULT_LEG). Call after app_core_init, before the first step; post must outlive the
 * core. */
int16_t app_core_set_reconfig(app_core_t *a, const dtc_config_t *post);

/* One control period: raw measurement in, leg command out. Returns 1 when the gates must be
 * turned off NOW (a trip decided on this sample, or any period outside RUN), else 0. */
uint16_t app_core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd);

/* Raw counts -> per-unit with the offsets in use (the derived third current included).
 * Pure; also used by the HAL register tests. */
void app_core_convert(const app_core_t *a, const hal_meas_t *m, dtc_meas_t *pu);

/* Short text of a fault reason (never NULL). */
const char *app_fault_name(uint16_t fault);

#endif /* APP_CORE_H */
