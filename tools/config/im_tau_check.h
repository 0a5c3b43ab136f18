/*
 * im_tau_check.h - stability of the sensorless stator-flux vector control with Casadei's
 * improved estimator (Casadei sec. 10.6-10.7, eqs. 26-28, Fig. 21), and a check of the configured
 * estimator time constant tau against it.
 *
 * Host code (C99, double and libm). The linearised model is that of tools/report/im_linear.py;
 * the test unit.im_tau_check_matches_python holds the two to the same eigenvalues.
 *
 *   im_lin_dominant_re()  real part of the dominant eigenvalue of Casadei eq. 27's [A] at rotor
 *                         speed w0 and slip w_sl (electrical rad/s) for a given tau.
 *   im_tau_check()        scans the configured operating range (|speed| up to speed_limit_rpm,
 *                         |torque| up to torque_limit_nm at the configured rotor flux, both
 *                         signs) with the configured tau schedule and reports where the dominant
 *                         pole is in the right half plane.
 */
#ifndef IM_TAU_CHECK_H
#define IM_TAU_CHECK_H

#include <stddef.h>

#include "dtc_config_si.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The T-model machine (stator-referred, the plant's names). */
typedef struct {
    double rr_ohm;
    double lls_h, llr_h;
    double lm_h;
} im_lin_machine_t;

/* Casadei eq. 27 at rotor speed w0_rad_s and slip w_sl_rad_s (both electrical; the estimated
 * stator-flux frequency is w0 + w_sl) and estimator time constant tau_s > 0: the largest real part
 * of the eigenvalues of [A], 1/s. The estimator row carries (L_r/M)/tau where Casadei eq. 27 prints 1/tau:
 * Casadei eqs. 20-21 give d phi_r^/dt a correction (L_r/M)(phi_r* e^{j theta} - phi_r^)/tau (the two agree
 * when L_r = M). */
double im_lin_dominant_re(const im_lin_machine_t *m, double w0_rad_s, double w_sl_rad_s, double tau_s);

/* The estimator time constant the firmware uses at electrical rotor speed w (rad/s): tau_lo_s up
 * to tau_w_lo_rpm, tau_hi_s from tau_w_hi_rpm, Ts/tau linear in between (firmware/dtc/im_est.c
 * im_est_gain). */
double im_tau_at(const dtc_config_si_t *si, double w_rad_s);

typedef struct {
    int unstable;            /* 1: some operating point has a dominant pole in the right half plane */
    double worst_re;         /* largest dominant real part found, 1/s */
    double worst_rpm;        /* ... at this rotor speed (mechanical rpm) */
    double worst_torque_nm;  /* ... and this torque (the sign of the slip) */
    double worst_tau_s;      /* ... and this tau */
    double rpm_lo, rpm_hi;   /* unstable points under positive torque: speed range, rpm (signed; the
                              * negative torques mirror it) */
    double torque_min_nm;    /* unstable points: smallest |torque| */
    int points;              /* operating points evaluated */
} im_tau_report_t;

/* Scans the operating range of an induction-machine configuration (si->law DTC_LAW_IM_DTC with the
 * improved estimator). Returns 1 and writes a warning naming the keys into msg when some range is
 * unstable, 0 when every point is stable or the check does not apply (then r->points = 0). */
int im_tau_check(const dtc_config_si_t *si, im_tau_report_t *r, char *msg, size_t msg_size);

#ifdef __cplusplus
}
#endif

#endif
