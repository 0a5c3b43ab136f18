/*
 * im_tau_check.c - Casadei eqs. 26-28 (linearised sensorless SFVC drive with the improved
 * estimator), their dominant eigenvalue, and the check of the configured tau (im_tau_check.h).
 */
#include "im_tau_check.h"

#include <math.h>
#include <stdio.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Largest real part of the roots of x^3 + a x^2 + b x + c (real coefficients), by Cardano in the
 * trigonometric form for three real roots and the algebraic form otherwise. */
static double cubic_max_re(double a, double b, double c)
{
    const double q = (a * a - 3.0 * b) / 9.0;
    const double r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0;
    if (r * r < q * q * q) {
        const double th = acos(r / sqrt(q * q * q));
        const double s = -2.0 * sqrt(q);
        const double x1 = s * cos(th / 3.0) - a / 3.0;
        const double x2 = s * cos((th + 2.0 * M_PI) / 3.0) - a / 3.0;
        const double x3 = s * cos((th - 2.0 * M_PI) / 3.0) - a / 3.0;
        return fmax(x1, fmax(x2, x3));
    }
    const double big = -copysign(cbrt(fabs(r) + sqrt(r * r - q * q * q)), r);
    const double small = big == 0.0 ? 0.0 : q / big;
    const double real_root = big + small - a / 3.0;
    const double pair_re = -0.5 * (big + small) - a / 3.0;
    return fmax(real_root, pair_re);
}

double im_lin_dominant_re(const im_lin_machine_t *m, double w0_rad_s, double w_sl_rad_s, double tau_s)
{
    const double ls = m->lls_h + m->lm_h, lr = m->llr_h + m->lm_h;
    const double sigma = 1.0 - m->lm_h * m->lm_h / (ls * lr);
    const double tau_r = lr / m->rr_ohm;
    const double k = m->lm_h * m->lm_h / (sigma * ls * lr * tau_r); /* M^2 / (sigma L_s L_r tau_r) */
    const double g = lr / m->lm_h / tau_s;                           /* (L_r/M) / tau */
    const double ws = w0_rad_s + w_sl_rad_s;                         /* estimated stator frequency */
    /* Casadei eq. 27, states (d phi_rd, d phi_rq, d phi_r^) in the estimated rotor-flux frame:
     *   [ -1/tau_r   w_s - w0   -k      ]
     *   [ -w_s       0           w_s    ]
     *   [ -1/tau_r   -w0        -k - g  ]                                                     */
    const double a11 = -1.0 / tau_r, a12 = w_sl_rad_s, a13 = -k;
    const double a21 = -ws, a22 = 0.0, a23 = ws;
    const double a31 = -1.0 / tau_r, a32 = -w0_rad_s, a33 = -k - g;
    const double tr = a11 + a22 + a33;
    const double minors = (a11 * a22 - a12 * a21) + (a11 * a33 - a13 * a31) + (a22 * a33 - a23 * a32);
    const double det = a11 * (a22 * a33 - a23 * a32) - a12 * (a21 * a33 - a23 * a31) + a13 * (a21 * a32 - a22 * a31);
    /* det(lambda I - A) = lambda^3 - tr lambda^2 + minors lambda - det */
    return cubic_max_re(-tr, minors, -det);
}

double im_tau_at(const dtc_config_si_t *si, double w_rad_s)
{
    const double rpm = fabs(w_rad_s) * 30.0 / M_PI / (double)si->pole_pairs;
    const double k_lo = si->ts_s / si->tau_lo_s, k_hi = si->ts_s / si->tau_hi_s;
    if (rpm <= si->tau_w_lo_rpm) {
        return si->tau_lo_s;
    }
    if (rpm >= si->tau_w_hi_rpm) {
        return si->tau_hi_s;
    }
    return si->ts_s / (k_lo + (k_hi - k_lo) * (rpm - si->tau_w_lo_rpm) / (si->tau_w_hi_rpm - si->tau_w_lo_rpm));
}

/* Operating points: N_TORQUE torque magnitudes up to the limit, and stator frequencies w_s
 * = +-w_max (i/N_SPEED)^3, dense at low speed where the unstable region lies (Casadei Fig. 21). Positive
 * slip only: (w0, w_sl) -> (-w0, -w_sl) is the similarity diag(1, -1, 1) of [A] and tau depends
 * on |w0|, so the negative torques repeat the positive ones mirrored. */
#define N_TORQUE 24
#define N_SPEED 800

int im_tau_check(const dtc_config_si_t *si, im_tau_report_t *r, char *msg, size_t msg_size)
{
    r->unstable = 0;
    r->worst_re = -HUGE_VAL;
    r->worst_rpm = r->worst_torque_nm = r->worst_tau_s = 0.0;
    r->rpm_lo = HUGE_VAL;
    r->rpm_hi = -HUGE_VAL;
    r->torque_min_nm = HUGE_VAL;
    r->points = 0;
    if (msg_size > 0) {
        msg[0] = '\0';
    }
    if (si->law != DTC_LAW_IM_DTC || si->estimator != DTC_EST_IMPROVED || si->pole_pairs < 1 ||
        !(si->tau_lo_s > 0.0 && si->tau_hi_s > 0.0 && si->rr_ohm > 0.0 && si->lm_h > 0.0)) {
        return 0;
    }
    const im_lin_machine_t m = {si->rr_ohm, si->lls_h, si->llr_h, si->lm_h};
    const double ls = si->lls_h + si->lm_h;
    /* rotor flux: the constant rotor-flux reference, or that of the stator-flux reference at no load */
    const double psir = si->psir_ref_wb > 0.0 ? si->psir_ref_wb : si->flux_ref_wb * si->lm_h / ls;
    const double p = (double)si->pole_pairs;
    const double w_max = fmax(si->speed_limit_rpm, si->rated_speed_rpm) * M_PI / 30.0 * p;
    /* Casadei eq. 16 at constant rotor flux (amplitude-invariant): T = 3/2 p phi_r^2 w_sl / R_r */
    const double slip_per_nm = si->rr_ohm / (1.5 * p * psir * psir);
    for (int j = 1; j <= N_TORQUE; ++j) {
        const double t = si->torque_limit_nm * (double)j / N_TORQUE;
        const double w_sl = t * slip_per_nm;
        for (int i = -N_SPEED; i <= N_SPEED; ++i) {
            const double x = (double)i / N_SPEED;
            const double ws = w_max * x * x * x;
            const double w0 = ws - w_sl;
            if (fabs(w0) > w_max) {
                continue;
            }
            const double tau = im_tau_at(si, w0);
            const double re = im_lin_dominant_re(&m, w0, w_sl, tau);
            ++r->points;
            const double rpm = w0 * 30.0 / M_PI / p;
            if (re > r->worst_re) {
                r->worst_re = re;
                r->worst_rpm = rpm;
                r->worst_torque_nm = t;
                r->worst_tau_s = tau;
            }
            /* w_s = 0 is a pole at the origin for every tau (Casadei eq. 27's second row vanishes): the
             * marginal line of Casadei Fig. 21, not an unstable range */
            if (re > 1e-9 * (1.0 / tau + w_max)) {
                r->unstable = 1;
                r->rpm_lo = fmin(r->rpm_lo, rpm);
                r->rpm_hi = fmax(r->rpm_hi, rpm);
                r->torque_min_nm = fmin(r->torque_min_nm, t);
            }
        }
    }
    if (!r->unstable) {
        return 0;
    }
    if (msg_size > 0) {
        snprintf(msg, msg_size,
                 "improved-estimator tau (%g s at low speed, %g s at high speed): the linearised drive (Casadei "
                 "eqs. 26-28) is unstable at speeds %.1f..%.1f rpm under a positive torque of %.2f N*m or more "
                 "(and mirrored: the same speeds negated under a negative torque%s); dominant pole %+.2f 1/s at "
                 "%.1f rpm, %.2f N*m, tau %g s (Casadei Fig. 21: a longer tau there shrinks the range)",
                 si->tau_lo_s, si->tau_hi_s, r->rpm_lo, r->rpm_hi, r->torque_min_nm,
                 r->rpm_hi < 0.0 ? ": regenerating" : "", r->worst_re, r->worst_rpm, r->worst_torque_nm,
                 r->worst_tau_s);
    }
    return 1;
}
