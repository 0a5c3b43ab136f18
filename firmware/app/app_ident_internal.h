/*
 * app_ident_internal.h - what the commissioning's files (app_ident.c: the sequence and the
 * standstill steps; app_ident_results.c: the evaluations and the spin step) share: segment timing and the background
 * helpers. Not part of the application's interface (app_ident.h).
 */
#ifndef APP_IDENT_INTERNAL_H
#define APP_IDENT_INTERNAL_H

#include "app_ident.h"

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
#define ID_ALT_PP IQ(0.2)       /* L_q: the square wave's current swing, peak to peak, pu of rated */
#define ID_ALT_NMIN 4U          /* L_q: the shortest half period (periods) */
#define ID_ALT_NMAX 1000U       /* L_q: the longest half period (50 ms) */
#define ID_ALT_MEAS 2000U       /* L_q: the measured halves span at least this many periods (0.1 s) */
#define ID_ALT_GAP 400U         /* L_q: regulated hold before the square wave (20 ms) */
#define ID_ENC_MOVE_SSTP 3000U  /* periods for one 120-degree move of the vector (SSTP) */
#define ID_ENC_MOVE_FSTP 3000U  /* one 180-degree move (FSTP) */
#define ID_ENC_LEVEL IQ(0.5)    /* the aligning and encoder current (see app_ident_start) */
#define ID_ENC_SETTLE 1500U     /* encoder dwell: the least settling before the wait for rest */
#define ID_ENC_MEAS 1024U
#define ID_SIGN_RATE IQ(1.0 / 1600.0) /* sign pulse: the voltage's rise per period (V_b / 8 in 10 ms) */
#define ID_SIGN_MAX 400U        /* sign pulse: the longest (the voltage at V_b / 4, the regulator's limit) */
#define ID_SIGN_STOP IQ(0.25)   /* sign pulse: ends when a phase current reaches a quarter of rated */
#define ID_SIGN_GAP 100U        /* gates off after a sign pulse (the current decays through the diodes) */
#define ID_OPEN_PERIODS 400U    /* regulator saturated with little current this long: open phase */
#define ID_STILL 1000U          /* dwell: periods with the count within +-1 before the sums (50 ms) */
#define ID_SETTLE_MAX 40000U    /* dwell: the longest wait for the rotor to come to rest (2 s) */
#define ID_QUIET 400U           /* dwell: periods with the count within +-quiet_tol that end the swing (20 ms) */
#define ID_MID_HOLD_LOG2 5U     /* dwell: the mid-point hold's gain, 1/32 volt per volt (app_ident_isr.c mid_hold) */
#define ID_RECENTRE_LOG2 3U     /* recentring: 8 pu phase-A current per pu of mid-point deviation ... */
#define ID_RECENTRE_I IQ(0.5)   /* ... at most half rated */
#define ID_RECENTRE_TOL IQ(1.0 / 128.0) /* recentred: within V_b / 128 of V_dc / 2 (0.55 V on 70 V) */
#define ID_RECENTRE_MAX 10000U  /* the longest recentring (0.5 s) */
#define ID_SPIN_RECENTRE 3U     /* the spin step's sub while the mid-point is recentred */
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
 * binary long division (no division helper; app_ident.c). */
int64_t app_ident_div64(int64_t num, int64_t den);
/* Stops the identification with the gates off and the named reason (app_ident.h fail codes). */
void app_ident_fail(app_ident_t *d, uint16_t why, int16_t detail);
/* Closes the current step's time and starts step. */
void app_ident_next_step(app_ident_t *d, uint16_t step);
/* Background: one spin window with the q current i (SEG_SPIN) or with the gates off (SEG_COAST). */
void app_ident_post_window(app_ident_t *d, uint16_t seg, iq_t i);
/* Background: the R_s line through the levels' means (step RS). */
void app_ident_fit_line(app_ident_t *d);
/* The angle between two encoder dwells: 180 degrees on the FSTP (two dwells), 120 on the SSTP. */
uint32_t app_ident_span_of(const app_ident_t *d);
/* Background: encoder lines, pole pairs, direction and offset from the dwells (step ENCODER). */
void app_ident_encoder_results(app_ident_t *d, const dtc_config_t *cfg);
/* Background: the spin step's service after each window (app_ident_results.c). */
void app_ident_spin_service(app_ident_t *d, const dtc_config_t *cfg);

/* Background: a HOLD segment (app_ident.c post_hold). */
void app_ident_post_hold(app_ident_t *d, uint32_t th_move_q16, uint32_t th_rate_q16, iq_t i_target, iq_t i_rate,
                         uint16_t n_settle, uint16_t n_meas, uint16_t slow);

/* Background: the R line's plausibility bounds; 0 (and the identification failed) when outside. */
uint16_t app_ident_rs_bounds(app_ident_t *d);

/* The induction machine's sequence (app_ident_im.c): its first segment, and its background. */
void app_ident_im_start(app_ident_t *d);
void app_ident_im_service(app_ident_t *d, const dtc_config_t *cfg);

/* ISR (no division): the applied voltage's share of this period's HOLD sample, from the compare
 * values' rounding (rq3 = 2 rq_a - rq_b - rq_c, counts Q24; app_ident.c ident_pwm). */
void app_ident_im_quant(app_ident_t *d, int64_t rq3, uint16_t t1pr);

#endif /* APP_IDENT_INTERNAL_H */
