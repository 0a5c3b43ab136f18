/*
 * im_tau_dump.c - im_tau_check.h on standard input, for the test that holds it to
 * tools/report/im_linear.py (tests/unit/test_im_linear.py). One request per line:
 *
 *   re RR LLS LLR LM W0 WSL TAU        -> the dominant real part of Casadei eq. 27's [A]
 *   check RR LLS LLR LM P PSIR TLIM NMAX TAU_LO TAU_HI W_LO_RPM W_HI_RPM TS
 *                                      -> "unstable worst_re worst_rpm worst_torque rpm_lo rpm_hi t_min points"
 */
#include <stdio.h>
#include <string.h>

#include "im_tau_check.h"

int main(void)
{
    char kind[16];
    while (scanf("%15s", kind) == 1) {
        im_lin_machine_t m;
        if (scanf("%lf %lf %lf %lf", &m.rr_ohm, &m.lls_h, &m.llr_h, &m.lm_h) != 4) {
            fprintf(stderr, "im_tau_dump: expected RR LLS LLR LM after '%s'\n", kind);
            return 1;
        }
        if (strcmp(kind, "re") == 0) {
            double w0, wsl, tau;
            if (scanf("%lf %lf %lf", &w0, &wsl, &tau) != 3) {
                fprintf(stderr, "im_tau_dump: re: expected W0 WSL TAU\n");
                return 1;
            }
            printf("%.17g\n", im_lin_dominant_re(&m, w0, wsl, tau));
        } else if (strcmp(kind, "check") == 0) {
            dtc_config_si_t si;
            memset(&si, 0, sizeof si);
            si.law = DTC_LAW_IM_DTC;
            si.estimator = DTC_EST_IMPROVED;
            si.rr_ohm = m.rr_ohm;
            si.lls_h = m.lls_h;
            si.llr_h = m.llr_h;
            si.lm_h = m.lm_h;
            if (scanf("%d %lf %lf %lf %lf %lf %lf %lf %lf", &si.pole_pairs, &si.psir_ref_wb, &si.torque_limit_nm,
                      &si.speed_limit_rpm, &si.tau_lo_s, &si.tau_hi_s, &si.tau_w_lo_rpm, &si.tau_w_hi_rpm,
                      &si.ts_s) != 9) {
                fprintf(stderr, "im_tau_dump: check: expected P PSIR TLIM NMAX TAU_LO TAU_HI W_LO W_HI TS\n");
                return 1;
            }
            si.rated_speed_rpm = si.speed_limit_rpm;
            im_tau_report_t r;
            char msg[512];
            const int u = im_tau_check(&si, &r, msg, sizeof msg);
            printf("%d %.17g %.17g %.17g %.17g %.17g %.17g %d\n", u, r.worst_re, r.worst_rpm, r.worst_torque_nm,
                   r.rpm_lo, r.rpm_hi, r.torque_min_nm, r.points);
        } else {
            fprintf(stderr, "im_tau_dump: unknown request '%s'\n", kind);
            return 1;
        }
    }
    return 0;
}
