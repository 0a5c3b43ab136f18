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

typedef struct {
    uint16_t on;      /* 1: the rotor hold runs (CALIBRATE after the current offsets) */
    uint16_t count0;  /* encoder count the hold keeps the rotor at */
    uint16_t prev;    /* encoder count of the previous hold period */
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

/* Starts the hold at the encoder count `count`, at rest. */
static inline void app_hold_start(app_hold_t *h, uint16_t count)
{
    h->on = 1U;
    h->count0 = count;
    h->prev = count;
    h->v_q16 = 0;
}

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
