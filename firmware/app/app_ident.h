/*
 * app_ident.h - self-commissioning of a PM machine (docs/commissioning.md): the
 * firmware measures what it is connected to from the board data alone (ADC scaling, V_dc, the
 * encoder's counts per turn, the topology) and the rated current (the current base, 1 pu):
 *   0. the sensors' signs (start of step RS): an open-loop voltage pulse along each phase's axis
 *      (A, B, C) up to a quarter of rated current, the gates off between them: the pulsed phase
 *      must read positive, the other two not positive (a reversed sensor is named; a pulse that
 *      reaches no current is an open phase); the phase order cannot be seen at standstill (the
 *      windings are symmetric): two leads exchanged turn the rotor backward in step 3, which
 *      identifies it as a reversed count (res.enc_reversed), the same correction;
 *   1. R_s and the inverter's drop: DC current along one axis (res.axis) at four levels (1, 3/4,
 *      1/2, 1/4 of rated), after the rotor aligned on it at half rated; the mean commanded voltage
 *      against the mean current, line V = R I + V_0;
 *   2. L_s: voltage steps on the half-rated DC current, the current's rise (volt-seconds over
 *      current, the resistive part removed with the fitted R): L_d, the rotor aligned on the axis;
 *      then L_q: on the same hold, an alternating (zero-mean) voltage square wave along the
 *      quadrature axis, its half period sized from L_d for a current swing of a fifth of rated,
 *      volt-seconds over the swing in the same way (app_ident.c post_alt; the rotor's torque
 *      averages out and its swing is far below a count), and whether L_q departs from L_d beyond
 *      the measurement's accuracy (res.salient);
 *   3. encoder: the current vector stepped through one electrical turn (three DC vectors on the
 *      SSTP, two on the FSTP, whose mid-point cannot carry a lasting phase-A current), the rotor
 *      aligned on each: the counts' direction, the counts per electrical turn (pole pairs) and the
 *      count-to-magnet offset (the first dwell is step 1's alignment);
 *   4. spin: half rated current on the identified q axis up to a quarter of the base speed, then a
 *      coast with the gates off: psi_m from the q voltage's slope over speed, J, viscous and Coulomb
 *      friction from the integrated equation of motion (app_ident_results.c spin_results); on the
 *      FSTP after the mid-point's recentring and with the legs' drop compensated (app_ident.c
 *      recentre, spin_start).
 * Every step limits the current to rated (references <= 1 pu, pulses stop at 0.9 pu, any phase
 * above 1.25 pu ends the identification), checks its result against plausibility bounds and on
 * failure stops with the gates off and a reason (enum app_ident_fail).
 *
 * Split: the 50 us ISR (app_ident_isr) only regulates the current, writes the PWM command and adds
 * samples into sums (multiplications, additions, shifts); every division and fit is in the
 * background (app_ident_service), which hands the ISR one segment at a time (go / done flags).
 *
 * Current regulator (ISR): PI on the reference axis and its quadrature, reference I (cos th, sin th),
 * gains from the board's base impedance Z_b = V_b / I_b only (nothing of the machine is known):
 * kp = Z_b / 64, ki = Z_b * 4 rad/s (per period: Z_b * 4 * Ts). Amplitude-invariant Clarke
 * (Hoang eqs. 1-5 convention): i_alpha = i_a, i_beta = (i_b - i_c) / sqrt(3). The voltage reference
 * goes out as one centred pulse per leg: SSTP d_x = 1/2 + v_x / V_dc; FSTP (phase A on the
 * mid-point) d_x = (v_mid + v_x - v_a) / V_dc for legs B, C, with the measured mid-point.
 *
 * Formats: currents, voltages IQ pu (fixmath.h Q24); angles angle_t; sums int64 (at most 2^16
 * samples of |x| <= 2 pu: < 2^42); results as documented in app_ident_result_t.
 */
#ifndef APP_IDENT_H
#define APP_IDENT_H

#include <stdint.h>

#include "dtc_config.h"
#include "fixmath.h"
#include "hal.h"
#include "law_io.h"
#include "app_ident_im.h"

/* The identification's progress (app_ident_t.step). */
enum app_ident_step {
    APP_IDENT_IDLE = 0,
    APP_IDENT_RS = 1,      /* DC injection at four levels */
    APP_IDENT_LS = 2,      /* voltage steps on a DC current */
    APP_IDENT_ENCODER = 3, /* DC vectors through one electrical turn */
    APP_IDENT_DONE = 4,    /* every result set, gates off */
    APP_IDENT_FAILED = 5,  /* app_ident_t.fail says why, fail_step in which step; gates off */
    APP_IDENT_SPIN = 6     /* after ENCODER: accelerate at a known q current, coast (psi_m, J,
                            * friction); numbered after FAILED to keep the earlier values */
};

/* Why the identification stopped (app_ident_t.fail). */
enum app_ident_fail {
    APP_IDENT_OK = 0,
    APP_IDENT_FAIL_OPEN_PHASE = 1,     /* the regulator at its voltage limit and the current below a
                                        * quarter of its reference: a phase or leg carries no current */
    APP_IDENT_FAIL_BOUNDS = 2,         /* a result outside its plausibility bounds (fail_detail: which) */
    APP_IDENT_FAIL_ENC_NOT_COUNTING = 3, /* the count moved less than a 64th of a turn over one
                                          * electrical turn of the current vector */
    APP_IDENT_FAIL_ENC_LINES = 4,      /* the counts per electrical turn are no whole fraction of the
                                        * encoder's counts per turn (wrong line count) */
    APP_IDENT_FAIL_OVERCURRENT = 5,    /* a phase above 1.25 x rated */
    APP_IDENT_FAIL_TRIP = 6,           /* the drive's protection tripped (app fault latched) */
    APP_IDENT_FAIL_NOT_AT_REST = 7,    /* encoder step: the rotor did not come to rest on a DC vector
                                        * within 2 s (a coupled load, a blocked or too heavy rotor) */
    APP_IDENT_FAIL_BLOCKED = 8,        /* spin: the rotor did not reach an eighth of the spin speed
                                        * in 2 s at half rated q current (blocked, or a load coupled) */
    APP_IDENT_FAIL_VDC_LOW = 9,        /* spin: the regulator at its voltage limit before an eighth of
                                        * the spin speed (the DC link too low to spin the machine);
                                        * standstill: at its limit while a level is summed */
    APP_IDENT_FAIL_COUPLED_LOAD = 11,  /* IM spin: the rotor turned freely in the encoder step but did
                                        * not reach half the spin speed at the spin's q current (a
                                        * load coupled to the shaft; fail_detail: the last window's
                                        * count change) */
    APP_IDENT_FAIL_MOVED = 12,         /* step LS's quadrature pulses: the count left +-4 quiet_tol (about
                                        * 1/64 turn; fail_detail: the largest excursion, counts) while
                                        * they ran: the rotor turned, and the
                                        * q voltage carries its back-EMF (a very light rotor, or a
                                        * load driving the shaft) */
    APP_IDENT_FAIL_SENSOR_SIGN = 10,   /* step RS's sign pulses: a phase current of the wrong sign
                                        * (fail_detail: 1..3 the measured phase A..C that read the wrong
                                        * sign on its own pulse, a sensor mounted the wrong way round;
                                        * 0 a wrong sign elsewhere) */
    APP_IDENT_FAIL_NOT_SETTLED = 20    /* IM: a DC level's voltage and current did not settle within
                                        * 200 windows (app_ident_im.c; fail_detail: the level) */
};

/* fail_detail of APP_IDENT_FAIL_BOUNDS: the quantity out of bounds. */
enum app_ident_quantity {
    APP_IDENT_Q_RS = 1,
    APP_IDENT_Q_V0 = 2,
    APP_IDENT_Q_LS = 3,
    APP_IDENT_Q_POLE_PAIRS = 4,
    APP_IDENT_Q_PSI = 5,
    APP_IDENT_Q_MECH = 6,  /* J <= 0, or the coast fit singular (no deceleration measured) */
    APP_IDENT_Q_LQ = 7,    /* L_q: outside the L bounds, or L_q / L_d outside [1/4, 8] */
    APP_IDENT_Q_IM_LSIG = 20, /* IM: sigma L_s */
    APP_IDENT_Q_IM_TAUR = 21  /* IM: tau_r, R_r */
};

/* Segment kinds the background hands the ISR. */
enum app_ident_seg {
    APP_IDENT_SEG_OFF = 0,   /* gates off */
    APP_IDENT_SEG_HOLD = 1,  /* regulated current: ramp to (th, i_ref), settle, then sum n_meas samples */
    APP_IDENT_SEG_PULSE = 2, /* regulator frozen, hold voltage + dv on the axis until the current rose
                              * by di_stop or n_meas periods, then one more sample (the pulse's end) */
    APP_IDENT_SEG_SPIN = 3,  /* regulated current i_ref on the encoder's q axis (the identified offset,
                              * pole pairs and direction); a window of n_meas periods of sums */
    APP_IDENT_SEG_COAST = 4, /* gates off; a window of n_meas periods (the count's change) */
    APP_IDENT_SEG_SIGN = 5,  /* open loop: a voltage along th rising by dv_iq per period until a phase
                              * current reaches di_stop_iq or n_meas periods, the phase currents of
                              * that sample kept (u.sg.i), then the gates off for ID_SIGN_GAP periods */
    APP_IDENT_SEG_ALT = 6    /* regulator frozen: the hold voltage + or - dv_iq along th + 90 degrees,
                              * a lead-in of u.st.alt_n / 2 periods (+), u.st.alt_m halves of alt_n
                              * periods (-, +, ...), a lead-out of alt_n / 2 (-); sums of the
                              * quadrature current (app_ident_isr.c alt_step) */
};

/* One speed window of the spin step (background): its count change, start count and start
 * period (the count's direction applied). */
typedef struct {
    int32_t dpos;
    int32_t pos0;
    uint32_t tick0;
} app_ident_win_t;

#define APP_IDENT_R_LEVELS 4U

/* Results, pu of the configuration's bases (dtc_base.h: V_b, I_b; Ts the control period). */
typedef struct {
    angle_t axis;            /* the injection axis: 90 degrees (beta) on the FSTP, 0 (alpha) on the SSTP */
    uint16_t lq_q12;         /* L_q / L_d, Q12 (the quadrature axis's inductance over l_ts_iq's;
                              * within [1/4, 8] once measured, 0 before) */
    iq_t r_iq;               /* slope of V = R I + V_0 on the injection axis, pu (R_s + R_on: Hoang
                              * Table III's drop is in series in every state, docs/commissioning.md) */
    iq_t v0_iq;              /* intercept V_0, pu (device thresholds and dead time on that axis) */
    iq_t l_ts_iq;            /* L / (Z_b Ts): the inductance in pu per control period (L_d: the
                              * rotor aligned on the axis) */
    uint16_t pole_pairs;
    uint16_t enc_reversed;   /* 1: the count runs down for positive electrical rotation */
    angle_t enc_offset;      /* electrical angle at count 0 with the count's direction applied */
    uint16_t salient;        /* 1: |L_q - L_d| > L_d / 16 (beyond the measurement's accuracy) */
    int32_t counts_per_turn; /* counts over one electrical turn of the current vector (signed) */
    iq_t level_i_iq[APP_IDENT_R_LEVELS]; /* the fit's points: mean current, ... */
    iq_t level_v_iq[APP_IDENT_R_LEVELS]; /* ... mean commanded voltage on the axis */
    iq_t psi_iq;             /* psi_m, pu (V_b / w_b): slope of the q voltage over the electrical speed */
    int32_t j_q12;           /* J / k_t in pu current x Ts^2 per count, Q12 (k_t = 1.5 p psi_m I_b,
                              * a count = 2 pi / enc_counts mechanical rad) */
    iq_t b_iq;               /* viscous friction / k_t, pu current x Ts per count, IQ */
    iq_t tc_iq;              /* Coulomb friction / k_t, pu current, IQ */
    uint32_t ticks[7];       /* control periods spent in the steps RS, LS, ENCODER, SPIN (index = step) */
    app_ident_im_result_t im; /* an induction machine's own results (app_ident_im.h); on an IM, psi_iq
                               * is L_s i_d (the stator flux of the spin's magnetising current im.id_iq)
                               * and J, B, T_c are over k_t = 1.5 p L_M i_d (app_ident_im.c) */
} app_ident_result_t;

typedef struct {
    /* background -> ISR: the segment (written only while go = 0 and done = 1 or before start) */
    uint16_t seg;            /* enum app_ident_seg */
    uint32_t th_left_q16;    /* forward turn of the reference angle still to make, angle_t Q16 (<= half a turn) */
    uint32_t th_rate_q16;    /* angle_t LSB per period, Q16 */
    iq_t i_target;
    iq_t i_rate;             /* pu per period */
    uint16_t n_settle;       /* periods after the ramps ended before the sums start */
    uint16_t n_meas;         /* periods summed (PULSE: the pulse's longest length) */
    iq_t dv_iq;              /* PULSE: the voltage step on the axis */
    iq_t di_stop_iq;         /* PULSE: the rise that ends it */
    iq_t inv_vdc_iq;         /* 1 / V_dc measured, pu (background) */
    uint16_t slow;           /* HOLD: 1 = the slow regulator (app_ident.c regulate: the rotor settles),
                              * and the sums wait for the rotor at rest (a dwell) */
    volatile uint16_t go;    /* background sets it when the segment is ready */
    volatile uint16_t done;  /* the ISR sets it when the segment's sums are complete */
    /* ISR state */
    uint32_t th_q16;         /* the reference angle, angle_t in bits 31..16 */
    iq_t i_ref;
    iq_t integ[2];           /* regulator integrators, v_alpha, v_beta */
    iq_t v_ab[2];            /* the voltage commanded this period */
    iq_t v_hold, v_hold_b;   /* PULSE: the regulated (v_alpha, v_beta) before the step; SIGN: v_hold
                              * the open-loop voltage so far */
    uint16_t phase;          /* HOLD: 0 ramps, 1 settle, 2 sums, 4 done (regulating on);
                              * PULSE: 6 first step command, 5 start sample, 2 step on, 3 end sample */
    uint16_t n;              /* periods in the current phase */
    uint16_t sat_n;          /* periods at the voltage limit with little current (open phase) */
    uint16_t still_n;        /* encoder dwell: periods the count stayed within +-1 of still_ref */
    int32_t still_ref;
    int64_t sum_i, sum_v, sum_pos, sum_q;
    iq_t i_first, i_last;    /* PULSE: the current at its start and end */
    uint16_t last_count;
    int32_t pos;             /* unwrapped encoder count since the start */
    iq_t vdc_iq;             /* last measured DC link */
    /* kp, ki: see the file comment */
    iq_t kp_iq, ki_iq, v_lim_iq;
    /* background */
    uint16_t step;           /* enum app_ident_step */
    uint16_t sub;            /* the step's segment index */
    uint16_t fail;           /* enum app_ident_fail */
    uint16_t fail_step;      /* enum app_ident_step that failed */
    int16_t fail_detail;
    uint16_t n_dwell;        /* encoder DC vectors per electrical turn */
    uint16_t sign_k;         /* step RS: sign pulses done (0..3, along phase A, B, C) */
    /* the steps' scratch: the sign pulses' (sg), the standstill steps' (st), the spin's (sp) and an
     * induction machine's standstill and encoder steps' (im; its results are in res.im) never live
     * together (st is cleared when the alignment starts, sp when a spin's first window is taken) */
    union {
        struct {
            uint16_t bad[3];   /* per phase: bit 0 wrong sign on its own pulse, bit 1 on another's */
            iq_t i[3];         /* SEG_SIGN: the phase currents at the pulse's end */
        } sg;
        struct {
            int64_t pulse_num, pulse_den; /* L: sums over the pulses */
            int32_t dwell_pos_q8[4];      /* encoder: mean unwrapped count at each dwell, Q8 */
            int16_t dwell_ang[4];         /* encoder: the measured current's angle from the reference
                                           * axis at each dwell, angle_t LSB (signed) */
            uint32_t lq_tick0;            /* L_q: the tick its part of step LS began */
            uint16_t alt_n;               /* SEG_ALT: the half period, control periods (even) */
            uint16_t alt_m;               /* SEG_ALT: measured half periods (even) */
            uint16_t alt_sec, alt_j;      /* SEG_ALT, ISR: this command's section (0 lead-in, 1..alt_m
                                           * the halves, alt_m + 1 lead-out) and position in it */
            uint16_t alt_psec, alt_pj;    /* SEG_ALT, ISR: the previous command's (0xFFFF: none) */
            uint16_t alt_moved;           /* SEG_ALT, ISR: the count's largest excursion from its
                                           * start, counts */
        } st;
        struct {
            app_ident_win_t w[5];  /* A, B first and last acceleration windows; C, D, E coast */
            iq_t vq[2], iq[2];     /* A, B: mean q voltage and q current, IQ pu */
            int64_t acc_i;         /* the q current summed over the windows A..B (IQ x periods) */
            int64_t fit[4];        /* psi_m's line over the windows A..B (n_acc - 1 of them): sum x,
                                    * sum y, sum x^2, sum x y; x the window's count change, y its mean
                                    * q voltage less R times its mean q current (IQ) */
        } sp;
        app_ident_im_t im;         /* an induction machine's steps before its spin: scratch */
    } u;
    uint16_t count0;         /* raw count at the start */
    uint32_t gain_q16;       /* spin: electrical angle_t per count, Q16 (p 2^32 / enc_counts) */
    uint16_t fresh;          /* spin: 1 = the first window (integrators and current from zero) */
    iq_t i_perp_ref;         /* the quadrature current's reference (0 but on an IM's spin: -i_d) */
    iq_t comp_iq;            /* IM spin: each leg's drop added along its reference current's sign
                              * (ident_pwm), pu; 0 = none */
    uint32_t im_rate_q16;    /* IM spin: the field's turn per period beyond the rotor's, angle_t Q16
                              * (the encoder step: the whole rotating field; the spin: the slip) */
    iq_t spin_i_iq;          /* spin: the q current of the acceleration */
    iq_t spin_w_iq;          /* spin: the electrical speed that ends the acceleration, pu */
    uint16_t spin_a;         /* spin: the first acceleration window of the fits (window A) */
    iq_t v_ff_iq, dv_ff_iq;  /* IM spin: the q voltage's feed-forward (the back-EMF's rise since the
                              * encoder step, omega_e L_s i_d), and its rise per period (ISR adds it) */
    /* IM spin, background (outside the union: the spin's fits use u.sp meanwhile) */
    int32_t ff_dpos0;        /* the count change per window of the encoder step's field speed */
    int64_t ff_w_k;          /* electrical rad per period (IQ) of one count per window, times 2^32 */
    iq_t ff_psi_ts;          /* L_s i_d / (Z_b Ts), IQ: the back-EMF per rad per period */
    iq_t ff_prev;            /* the last window's back-EMF rise */
    int32_t win_dpos;        /* the last window's count change (ISR) */
    uint32_t win_tick;       /* the last window's first period (ISR) */
    uint16_t n_acc, n_coast; /* spin: windows so far */
    uint32_t tick, step_tick;
    app_ident_result_t res;
    uint16_t summed;         /* ISR: 1 when this period's HOLD sample went into the sums */
    uint16_t im_on;          /* 1: an induction machine (app_ident_im.c runs the background, u.im) */
    /* FSTP with the mid-point measured (app_ident_isr.c mid_hold, recentre): */
    int32_t rest_tol;        /* a dwell's rest: the count within +-rest_tol (a quarter degree) */
    int32_t quiet_tol;       /* a dwell's swing is over: the count within +-quiet_tol for ID_QUIET */
    int32_t quiet_ref;       /* ISR: the count the swing check compares with */
    uint16_t quiet_n;        /* ISR: periods the count stayed within +-quiet_tol of quiet_ref */
    uint16_t wait_n;         /* ISR: periods a dwell waited for rest before its sums began */
    uint16_t mid_on;         /* ISR: 1 once this dwell's swing is over: the mid-point is held */
    uint16_t lq_periods;     /* control periods of step LS's L_q part (in res.ticks[APP_IDENT_LS]) */
    iq_t mid_ref_iq;         /* ISR: the mid-point's deviation from V_dc/2 when the swing ended, pu */
    uint16_t recentre;       /* HOLD: 1 = the mid-point is brought back to V_dc/2 (before the spin) */
    uint16_t start_gap;      /* ISR: periods left with the gates off before the first step: the
                              * current the calibration's rotor hold left decays through the diodes */
    iq_t ia_ref_iq;          /* ISR: the phase-A (alpha) current reference that does it, pu */
} app_ident_t;

/* A background function kept out of line (as fixmath.h's fix_sat32_clamp): the large locals and
 * temporaries of a function inlined stay on its caller's stack while the caller calls on, so a
 * chain of such calls sums them. The F2812's stack is M0's 1K words (hal/f2812/stack_budget.py). */
#define APP_NOINLINE __attribute__((noinline))

/* What the background reads of an identification (app_get_ident_view, app_ident_derive): its
 * progress, the last DC link it measured and its results, without the steps' working state: a
 * copy small enough for a background call's stack (the F2812's stack is M0's 1K words,
 * hal/f2812/stack_budget.py). */
typedef struct {
    uint16_t step;           /* enum app_ident_step */
    uint16_t fail;           /* enum app_ident_fail */
    uint16_t fail_step;      /* enum app_ident_step that failed */
    int16_t fail_detail;
    uint16_t im_on;          /* 1: an induction machine's identification */
    iq_t vdc_iq;             /* the DC link it measured last */
    app_ident_result_t res;
} app_ident_view_t;

/* v = the view of d (its fields of the same names). */
void app_ident_view_of(const app_ident_t *d, app_ident_view_t *v);

/* Starts the identification (gates on from the next period). ts_pu / bases are not used: only
 * cfg->board (scaling, topology, encoder counts, mid-point measured) and the per-unit bases. */
void app_ident_start(app_ident_t *d, const dtc_config_t *cfg, uint16_t qep_count, iq_t vdc_iq);

/* ISR: one period. pu: this sample, per unit; writes cmd (PWM form at t1pr). Returns 1 when the
 * gates must be off (finished, failed, or between steps). No division. */
uint16_t app_ident_isr(app_ident_t *d, const dtc_config_t *cfg, const dtc_meas_t *pu, uint16_t t1pr,
                       hal_cmd_t *cmd);

/* Background: fits a finished segment and hands the ISR the next one. */
void app_ident_service(app_ident_t *d, const dtc_config_t *cfg);

/* The drive's protection tripped during the identification: stop, APP_IDENT_FAIL_TRIP. */
void app_ident_abort(app_ident_t *d);

/* Why applying the identification's results was refused (app_ident_derive, app_ident_apply). */
enum app_ident_apply_err {
    APP_IDENT_APPLY_OK = 0,
    APP_IDENT_APPLY_NOT_DONE = 1, /* no finished identification (step is not APP_IDENT_DONE) */
    APP_IDENT_APPLY_ARMED = 2,    /* the drive is armed or identifying */
    APP_IDENT_APPLY_LAW = 3,      /* the identification's machine is not the law's: a PM's on a
                                   * configuration other than the PM DTC law, an induction machine's
                                   * on one other than an IM law (or the law not in the image) */
    APP_IDENT_APPLY_RS = 4,       /* the R line's slope not above the board's R_on: R_s <= 0 */
    APP_IDENT_APPLY_LS = 5,       /* L_s (or L_q) below 1/128 pu (1 / L beyond IQ) or above the IQ range */
    APP_IDENT_APPLY_ENCODER = 6,  /* the encoder gain p 2^32 / enc_counts beyond its row */
    APP_IDENT_APPLY_DEADTIME = 7, /* the dead time from V_0 at or above half a period, or no V_dc */
    APP_IDENT_APPLY_CHECK = 8,    /* the law's check (law_check) refused the copy (detail: its
                                   * enum dtc_err code) */
    APP_IDENT_APPLY_IM = 9,       /* an induction machine's rows out of range: L_s not above sigma
                                   * L_s, R_r <= 0, the magnetising current phi_r* / M not below
                                   * rated (the current base), a row beyond its format */
    APP_IDENT_APPLY_J = 10        /* the speed PI's gains or the lost-encoder level from the
                                   * identified J beyond their rows (or no torque constant) */
};

/* Background: the finished identification d (a PM's or an induction machine's) written into out, a copy of in (the configuration
 * in force), with the rows derived from it (app_ident_apply.c lists them, their formats and
 * rounding). Returns APP_IDENT_APPLY_OK or why not (out then partly written: discard it). No law
 * check: the caller's. */
int16_t app_ident_derive(const app_ident_view_t *d, const dtc_config_t *in, dtc_config_t *out);

/* Background, disarmed: the identification's results (app_get_ident_view) into a copy of the
 * configuration in force (app_ident_derive), checked by law_check and made the configuration in
 * force (app_reconfigure: calibration, then READY). Returns enum app_ident_apply_err; *changed the
 * configuration rows whose value changed (0 unless applied), *detail the check's enum dtc_err code
 * for APP_IDENT_APPLY_CHECK. */
int16_t app_ident_apply(uint16_t *changed, int16_t *detail);

#endif /* APP_IDENT_H */
