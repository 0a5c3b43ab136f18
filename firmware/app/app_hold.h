/*
 * app_hold.h - the rotor hold: a position loop that keeps the rotor where the FSTP mid-point
 * calibration found it (prot.i_hold_iq > 0), with a current in phases B and C only
 * (app_hold_step, app_hold.c), while the application core (app_core.h) calibrates.
 *
 * State: app_hold_t, owned by the caller, no static state.
 */
#ifndef APP_HOLD_H
#define APP_HOLD_H

#include <stdint.h>

#include "hal.h"
#include "law.h"

/* Rotor hold during the mid-point calibration (app_hold_step): the hold current reaches
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
/* A rotor at rest when the calibration begins (app_hold_cal): the counts at samples 1, n/2 and
 * n-1 of the gates-off offset window of n = 2^APP_CAL_LOG2 periods split it in two halves of
 * h = n/2 - 1 periods with displacements d1 and d2 (counts). Under a constant acceleration a (an
 * active load pulling the rotor) d1 = v0 h + a h^2/2 and d2 = v0 h + 3 a h^2/2, so
 * 3 d1 - d2 = 2 v0 h whatever the load: it measures the speed v0 the rotor had when the window
 * began. Each displacement is the difference of two counts, off by at most one count of
 * quantisation, so 3 d1 - d2 is off by at most 3 + 1 counts: beyond that the rotor was turning (at
 * least 5 / (2 h) counts per period: 12.1 rpm with 8000 counts and h = 31 periods of 50 us) and
 * the hold does not engage: the drive starts into the rotor (flying start). A rotor slower than
 * that is held as one at rest: its back-EMF and kinetic energy are those of the creep an active
 * load causes during the window, which the hold is built for. */
#define APP_HOLD_REST_COUNTS 4

typedef struct {
    uint16_t on;      /* 1: the rotor hold runs (CALIBRATE after the current offsets) */
    uint16_t count0;  /* encoder count the hold keeps the rotor at (offset window: of sample 1) */
    uint16_t prev;    /* encoder count of the previous hold period (offset window: of its half) */
    uint16_t extra;   /* hold periods after the calibration, waiting for the rotor to settle */
    int32_t v_q16;    /* rotor speed, counts per period, Q16, low-passed over 2^APP_HOLD_LEAD_LOG2 */
} app_hold_t;

/* Hold off, its counters zero. */
static inline void app_hold_reset(app_hold_t *h)
{
    h->on = 0U;
    h->count0 = 0U;
    h->prev = 0U;
    h->extra = 0U;
    h->v_q16 = 0;
}

/* Period n (0 .. 2^APP_CAL_LOG2 - 1, app_core.h) of the calibration's gates-off offset window,
 * encoder count `count` (app_hold.c): keeps the counts of samples 1 and 2^(APP_CAL_LOG2-1) (count0,
 * prev); on the window's last sample, with the mid-point calibration and a hold current, the hold
 * stays off for a rotor that was turning when the window began (APP_HOLD_REST_COUNTS) and starts at
 * `count` for a rotor at rest. Returns 1 when the hold started. */
uint16_t app_hold_cal(app_hold_t *h, const dtc_config_t *c, uint16_t count, uint16_t n);

/* 1 when the calibration may end as far as the hold is concerned: no hold, or the rotor has
 * settled (speed at most one count per 2^APP_HOLD_LEAD_LOG2 periods). */
static inline uint16_t app_hold_settled(const app_hold_t *h)
{
    return (uint16_t)(h->on == 0U || fix_abs32(h->v_q16) <= ((int32_t)1 << (16U - APP_HOLD_LEAD_LOG2)));
}

/* One hold period (app_hold.c): the per-unit sample pu and the raw encoder count of m in,
 * the legs B and C of cmd (enable set) out. */
void app_hold_step(app_hold_t *h, const dtc_config_t *c, const dtc_meas_t *pu, const hal_meas_t *m,
                   hal_cmd_t *cmd);

#endif /* APP_HOLD_H */
