/*
 * app_ident_im.h - the induction machine's part of the self-commissioning (app_ident_im.c,
 * docs/commissioning.md "Induction machine"): its results and the background's scratch. The
 * sequence shares the PM's segments (app_ident.h: HOLD, PULSE, SPIN, COAST), its R_s line, its
 * spin's fits and its failure handling; app_ident_t carries the scratch (u.im) and the results
 * (res.im).
 *
 * Units: inductances as L / (Z_b Ts) in IQ (the PM's l_ts_iq), resistances in pu of Z_b (IQ), the
 * rotor time constant in control periods (Q4). Model (Casadei eqs. A6-A9 at standstill, written in
 * the inverse-Gamma form that is all a stator's terminals can see): psi_s = sigma L_s i_s + psi_R,
 * d psi_R / dt = R_R i_s - psi_R / tau_r, with L_s = sigma L_s + L_M, L_M = L_m^2 / L_r,
 * R_R = R_r (L_m / L_r)^2 = L_M / tau_r, tau_r = L_r / R_r.
 */
#ifndef APP_IDENT_IM_H
#define APP_IDENT_IM_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    iq_t ls_ts_iq;   /* L_s / (Z_b Ts): the stator flux over the current after the DC step settled */
    iq_t lsig_ts_iq; /* sigma L_s / (Z_b Ts): the voltage steps' current rise (transient inductance) */
    int32_t taur_q4; /* tau_r = L_r / R_r, control periods, Q4 */
    iq_t rr_iq;      /* R_r of the T model with L_lr = L_ls (so L_r = L_s): L_s / tau_r, pu (the
                      * inverse-Gamma R_R = (L_s - sigma L_s) / tau_r follows from the three above) */
    iq_t id_iq;      /* the spin's magnetising current i_d, pu: the configured stator flux over L_s */
    iq_t vq_pole_iq; /* encoder step: the mean q voltage of the rotating field, pu (omega_e L_s i_d
                      * when the rotor follows it, about sigma L_s omega_e i_d when it is blocked) */
} app_ident_im_result_t;

/* The background's scratch of the IM steps. The DC step's integrals are kept as sums that are
 * linear in the not yet known R and V_0 (app_ident_im.c im_flux), so they are evaluated after the
 * R_s line. Magnitudes: means |x| < 2 pu (2^25) over at most 2^17 periods: a_* < 2^42,
 * b_* < 2^59 (periods^2 / 2 x 2^25). */
typedef struct {
    int64_t a_v, a_i;   /* integral of the commanded axis voltage and the axis current, IQ x periods */
    int64_t b_v, b_i;   /* integral of a_v and a_i over time, IQ x periods^2 */
    uint32_t t;         /* periods since the DC step */
    uint32_t tick_prev; /* the ISR's tick at the previous window's end */
    iq_t i_end;         /* the DC step's settled current (its last window's mean) */
    iq_t y_hist[8];     /* the settling test's last eight values (app_ident_im.c im_settle) */
    uint16_t n_win;     /* windows at this level */
    uint16_t n_ok;      /* consecutive windows that met the settling test */
    uint16_t level;     /* the DC level index (0: the step from zero) */
    uint16_t pulses;    /* voltage steps done */
    uint32_t p_n;       /* the steps' periods, summed (each at dv = V_b / 8) */
    int64_t p_trap;     /* sum of the trapezoid of the rise, IQ x periods */
    int64_t p_rise;     /* sum of the rises, IQ */
    uint16_t t1pr;      /* the PWM period in timer counts, as the ISR saw it */
    int32_t quant_k;    /* V_dc / (3 t1pr), IQ pu per count (background; 0 until known) */
    int32_t pole_pos0;  /* encoder step: the count at the first summed window's start */
    uint32_t pole_tick0; /* ... and its period */
    int64_t pole_sum_v; /* ... the q voltage summed over the summed windows (IQ x periods) */
    uint16_t pole_win;  /* ... windows so far */
    uint32_t pole_rate_q16; /* encoder step: the field's turn per period at full speed, angle_t Q16 */

} app_ident_im_t;

#endif /* APP_IDENT_IM_H */
