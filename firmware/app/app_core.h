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
 * Arming (app_core_set_arming). APP_ARM_AUTO (the default: a SIL scenario without a serial line,
 * the unit tests): the end of the calibration enters RUN as above. APP_ARM_COMMAND (a drive
 * operated over its serial line, docs/operate.md): the end of the calibration enters READY, gates
 * off, and only an arm request (app_core_arm_refusal passed, then app_core_request_arm) leads to
 * RUN, through a calibration of its own (fresh offsets, the DC link checked at its end); a disarm
 * request takes RUN back to READY; a fault clear ends in READY too, never in RUN.
 * With a command timeout set (app_core_set_comm_timeout), RUN without a valid frame from the host
 * (app_core_comm_seen) for that many periods latches APP_FAULT_COMM_TIMEOUT: gates off, so no
 * torque, and disarmed.
 *
 * Per period (app_core_step): raw ADC/encoder counts -> per-unit (calibrated offsets, config
 * gains) -> trip checks on THIS sample (phase over-current on all three currents, DC-link over-
 * and under-voltage, hardware trip input, encoder plausibility) -> the configured control law
 * (law_step: PM DTC or IM DTC/DSC) -> leg command (the PWM form: app_pwm.h). A
 * trip decided here turns the gates off in the same ISR that saw the sample.
 *
 * The core is the state machine; its parts are modules of their own, each with its state in
 * app_core_t: the ADC conversion (app_adc.h), fault detection (app_fault.h, with the fault
 * table), encoder plausibility (app_enc.h), the rotor hold (app_hold.h) and the PWM form
 * (app_pwm.h).
 *
 * Formats: per-unit IQ (fixmath.h, dtc_base.h). Scaling and overflow: a count difference is at
 * most +-4095 and the gains are IQ pu per count; the product is formed in 64 bits and saturates
 * at +-128 pu, far beyond any trip level, so a saturated value still trips.
 */
#ifndef APP_CORE_H
#define APP_CORE_H

#include <stdint.h>

#include "app_enc.h"
#include "app_fault.h"
#include "app_hold.h"
#include "app_ident.h"
#include "app_plaus.h"
#include "capture.h"
#include "faultlog.h"
#include "hal.h"
#include "law.h"

enum app_state {
    APP_STATE_INIT = 0,
    APP_STATE_CALIBRATE = 1, /* gates off, measuring the current-sensor offsets; then, with the
                              * FSTP mid-point calibration and prot.i_hold_iq > 0, the rotor
                              * hold (gates on, phases B and C only) until it ends */
    APP_STATE_RUN = 2,
    APP_STATE_FAULT = 3,     /* latched, gates off */
    APP_STATE_READY = 4,     /* APP_ARM_COMMAND: calibrated and disarmed, gates off, waiting
                              * for an arm request */
    APP_STATE_IDENT = 5      /* self-commissioning (app_ident.h), entered from CALIBRATE instead
                              * of RUN when requested (app_core_request_ident); stays there with
                              * the gates off once it ended (ident.step DONE or FAILED) */
};

/* How the drive enters RUN after its calibration (app_core_set_arming). */
enum app_arm_mode {
    APP_ARM_AUTO = 0,   /* by itself */
    APP_ARM_COMMAND = 1 /* only on an arm request (READY until then) */
};

/* Background -> ISR requests (app_core_t.arm_request). */
enum app_arm_request {
    APP_REQ_NONE = 0,
    APP_REQ_ARM = 1,
    APP_REQ_DISARM = 2
};

/* Why an arm request is refused (app_core_arm_refusal); the values are proto.h's enum
 * proto_refusal, the serial protocol's detail. */
enum app_arm_refusal {
    APP_ARM_OK = 0,
    APP_ARM_NOT_CALIBRATED = 1, /* not READY: calibrating (or not command arming) */
    APP_ARM_VDC_RANGE = 2,      /* the last V_dc sample outside [prot.vdc_min_iq, prot.vdc_max_iq] */
    APP_ARM_FAULT = 3,          /* a fault is latched */
    APP_ARM_REF_NONZERO = 4,    /* the speed or torque reference is not zero */
    APP_ARM_VMID_RANGE = 7      /* FSTP with the mid-point measured: the last sample's mid-point more
                                 * than V_dc / 2^APP_VMID_TOL_LOG2 off V_dc / 2 (the calibration
                                 * would take that imbalance for a sensor offset) */
};

/* Calibration: 2^APP_CAL_LOG2 samples averaged per current channel (and for the FSTP mid-point,
 * dtc_config.h vmid_cal). Largest accepted mid-point inconsistency: V_dc/2^APP_VMID_TOL_LOG2. */
#define APP_VMID_TOL_LOG2 4U
/* Mid-point calibration: 2^APP_VMID_CAL_LOG2 samples (51 ms at 50 us; the current offsets use the
 * first 2^APP_CAL_LOG2 of them). The low-pass of the voltage model turns a DC error E on v_alpha
 * into a current E / (w_c L_s): 1 mV is 0.04 A for Hoang Table VIII at 5 rad/s, so the mean must be
 * good to about a millivolt: 1024 samples divide the sensors' noise by 32. */
#define APP_VMID_CAL_LOG2 10U
#define APP_CAL_LOG2 6U

/* The speed-loop cycle's slots (app_core_t.speed_slots, RUN): the laws run their speed-rate work
 * in fixed periods of the cycle of speed_div periods, and the application keeps its own
 * occasional work out of them, so that the worst ISR is an ordinary period plus the largest one
 * slot adds, not a sum of them:
 *  - slot 0, the law's speed-loop period: the speed measurement, the speed PI and the hand-over
 *    (PM dtc_step), the application's speed checks (check_speed: overspeed, stall, encoder
 *    against the flux speed) and the laws' warnings; the open-phase check holds this period's
 *    sample over to slot 1 (app_fault_open_phase's hold);
 *  - slot 1: the PM law's speed-dependent gains (dtc_step forms them at the start of the step
 *    after its speed loop), the IM law's stator-flux reference (im_dtc_refs) and the open-phase
 *    check's held sample;
 *  - the later slots: the current-sensor plausibility's judgement of a window that ended in slot
 *    0 or 1 (app_plaus_step's hold: one or two periods later); the IM laws' encoder plausibility
 *    (slot 3) and model supervision (slot 4, im_dtc_internal.h).
 * With a speed_div of 1 or 2 every period is slot 0 or 1: app_plaus_step holds a window at most
 * two periods. */
#define APP_SLOTS_HELD 3U /* app_core_t.speed_slots: the bits of slots 0 and 1 */

typedef struct {
    uint16_t state;       /* enum app_state */
    uint16_t fault;       /* enum app_fault (app_fault.h) */
    int16_t fault_detail; /* its detail (APP_FAULT_LIST, app_fault.h) */
    uint32_t tick;        /* tick of the last processed measurement */
    uint32_t fault_tick;  /* tick at which the fault latched */
    dtc_meas_t meas;      /* last per-unit measurement (third current derived) */
    dtc_out_t out;        /* last controller output (valid in RUN) */
    uint16_t reconfigured; /* enum hal_relay: the phase moved onto the mid-point after a leg
                            * failure (the drive runs as an FSTP since), 0 = none */
    uint16_t warnings;    /* bit APP_WARN_<id> (app_warn.h): the law raised that warning at least
                           * once since app_core_init (latched; the drive runs on) */
    uint32_t warn_tick;   /* tick at which the first warning was raised (warnings != 0) */
} app_status_t;

typedef struct app_core {
    const dtc_config_t *cfg;
    app_status_t st;
    uint16_t offset[3];    /* current-sensor offsets in use, counts */
    uint32_t cal_sum[3];
    uint16_t cal_n;
    app_hold_t hold;       /* the rotor hold (app_hold.h) */
    int64_t vmid_cal_sum_iq; /* calibration: sum of (mid-point - V_dc/2), IQ pu (cfg->vmid_cal) */
    iq_t vmid_cal_iq;      /* the two voltage sensors' inconsistency, subtracted from vmid, pu */
    uint16_t meas_ch[2];   /* the two measured current channels (HAL_ADC_IA.. IC) */
    app_enc_t enc;         /* encoder plausibility (app_enc.h) */
    volatile uint16_t clear_request; /* set by the background, adopted by the ISR */
    uint16_t t1pr;         /* Timer 1 period of the PWM form (hal_pwm_period()), counts; 0 = none */
    /* Fault tolerance (app_core_set_reconfig; reconfigure in app_core.c). */
    const dtc_config_t *post; /* the post-fault FSTP configuration (app_core_set_reconfig) or NULL */
    uint16_t perm;         /* the law's phase k is the physical phase (perm + k) mod 3: 0 before a
                            * reconfiguration, the failed phase after it */
    app_fault_t flt;       /* fault detection (app_fault.h) */
    app_plaus_params_t plaus_p; /* current-sensor plausibility, two sensors (app_plaus.h) */
    app_plaus_t plaus;
    uint16_t meas_mask;    /* bit k: the law's phase k is measured, not derived */
    volatile uint16_t ident_request; /* set by the background: identify instead of RUN */
    uint16_t plaus_win;    /* three sensors, this window: bit 0 their sum was above prot.i_sum_max_iq,
                            * bit 1 a phase read zero (check_sensors) */
    uint16_t plaus_win_held; /* the same for the window app_plaus_step holds over */
    uint16_t speed_slots;  /* RUN, the slots below: bit 0 this period is slot 0 (the law's
                            * speed-loop period), bit 1 the last one was (this one is slot 1) */
    /* Arming and the command timeout (app_core_set_arming, app_core_set_comm_timeout). */
    uint16_t arm_mode;     /* enum app_arm_mode */
    volatile uint16_t arm_request; /* enum app_arm_request: set by the background, taken by the ISR */
    volatile uint16_t comm_seen;   /* set by the background on a valid frame, taken by the ISR */
    volatile uint32_t comm_timeout_n; /* periods without a valid frame that trip, 0 = off */
    uint32_t comm_idle_n;  /* RUN: periods since the last valid frame */
    uint16_t arming;       /* 1: this calibration was started by an arm request and ends in RUN */
    /* Capture and fault log (app_core_attach), NULL = none. */
    capture_t *cap;
    /* The word the ISR tests after the control step (app_core_step): &cap->state, or without a
     * capture a constant CAPTURE_OFF, so that "no capture" and "capture off" are the same one
     * load and compare, and the capture's off state adds nothing to the ISR. */
    const volatile uint16_t *cap_state;
    faultlog_t *flog;
    app_ident_t ident;     /* self-commissioning (APP_STATE_IDENT), not read in RUN: after the ISR's fields */
    /* The configured control law (law.h), last: its state is most of the struct, and the fields
     * the ISR reads every period (above) then lie at small offsets, which the targets address in
     * one instruction (Cortex-M0: word fields below 128 bytes, halfwords below 64; the C28x's
     * short offsets likewise) where a field past the law's state needs its offset built first. */
    law_t law;
} app_core_t;

/* Validates the configuration (law_init) and enters CALIBRATE. Returns 0 or the dtc_err code;
 * on error the core is in FAULT with APP_FAULT_CONFIG. */
int16_t app_core_init(app_core_t *a, const dtc_config_t *cfg);

/* The HAL's PWM timer period T1PR (hal_pwm_period(), counts), for a law that commands the PWM
 * form (law.h law_out_form; app_pwm.h). Where the law cannot run at it (app_pwm_period_check: t1pr = 0
 * or 0xFFFF for the IM schemes SFVC, DFOC, DSVM) the core latches
 * APP_FAULT_CONFIG with DTC_ERR_SVM (in place of any fault latched before, which a clear request
 * would end) and returns that code; otherwise 0. */
int16_t app_core_set_pwm_period(app_core_t *a, uint16_t t1pr);

/* Fault tolerance: post is the FSTP configuration of the same PM drive that the
 * application switches to when a leg fails (app_fault_open_phase: a phase carries no current while the
 * others do; app_fault_open_phase), with the failed phase on the capacitor mid-point through the relay (hal_cmd_t
 * relay). It must pass its law's check (law_check_reconfig), be the running law (the PM DTC, or the IM
 * switching-table DTC with Hoang Table II: law.h law_reconfigure) on the FSTP, with the same encoder and
 * ADC scaling, three current sensors (board.i_sensors3: only the sum of three measured currents
 * tells a failed sensor from a failed leg), no mid-point calibration (the drive does not stop for
 * it), prot.relay_periods > 0; the running configuration must be that law on the SSTP with
 * three sensors and the open-phase check on. Otherwise the core latches APP_FAULT_CONFIG with
 * DTC_ERR_RECONFIG and returns it. post = NULL (the default): no relay fitted, a failed leg
 * trips (APP_FAULT_LEG). Call after app_core_init, before the first step; post must outlive the
 * core. */
int16_t app_core_set_reconfig(app_core_t *a, const dtc_config_t *post);

/* Arming mode (enum app_arm_mode); after app_core_init, before the first step. APP_ARM_AUTO
 * after app_core_init. */
void app_core_set_arming(app_core_t *a, uint16_t mode);

/* Background: the refusal an arm request gets now (enum app_arm_refusal, APP_ARM_OK = armable),
 * from a status copy s (app_get_status) and the references r the background published last:
 * READY (RUN: already armed, APP_ARM_OK), no fault, s->meas.vdc_iq in [prot.vdc_min_iq, prot.vdc_max_iq], speed and torque
 * references zero. Pure. */
uint16_t app_core_arm_refusal(const app_core_t *a, const app_status_t *s, const dtc_refs_t *r);

/* Background: asks the ISR to arm (APP_REQ_ARM: READY -> CALIBRATE -> RUN, the law reset: 2^APP_CAL_LOG2
 * periods, 2^APP_VMID_CAL_LOG2 with the mid-point calibration; ignored in any other state) or disarm (APP_REQ_DISARM: RUN -> READY, gates off; the arming mode becomes
 * APP_ARM_COMMAND). */
static inline void app_core_request_arm(app_core_t *a, uint16_t req)
{
    a->arm_request = req;
}

/* Background: a valid frame arrived from the host (restarts the command timeout). */
static inline void app_core_comm_seen(app_core_t *a)
{
    a->comm_seen = 1U;
}

/* Background: the command timeout in control periods (0 = off); counted in RUN only. */
void app_core_set_comm_timeout(app_core_t *a, uint32_t periods);

/* The capture (fed once per period after the control step, its fault trigger by the latched
 * fault) and the fault log (an entry with a snapshot at every latched fault); either may be NULL.
 * Binds the capture's quantities to the core's variables. After app_core_init. */
void app_core_attach(app_core_t *a, capture_t *cap, faultlog_t *flog);

/* One control period: raw measurement in, leg command out. Returns 1 when the gates must be
 * turned off NOW (a trip decided on this sample, or any period outside RUN), else 0. */
uint16_t app_core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd);

/* Background: identify the machine (app_ident.h) once the calibration ends, instead of entering
 * RUN. Call before the calibration ends (after app_core_init). */
void app_core_request_ident(app_core_t *a);

/* Background: one pass of the identification's background work (fits, next segment). */
void app_core_ident_service(app_core_t *a);

/* Raw counts -> per-unit with the offsets in use (the derived third current included).
 * Pure; also used by the HAL register tests. */
void app_core_convert(const app_core_t *a, const hal_meas_t *m, dtc_meas_t *pu);

#endif /* APP_CORE_H */
