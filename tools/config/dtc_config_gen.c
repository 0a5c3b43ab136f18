/* dtc_config_gen - writes the default configuration (dtc_config_si_defaults) as a C source file
 * for a target build.   usage: dtc_config_gen [--f2812-board] [--reconfig-relay DELAY_S] OUTPUT.c
 * [SYMBOL]   (SYMBOL defaults to dtc_config_default). The file also defines `const struct
 * dtc_config *const SYMBOL_post`: the post-fault FSTP configuration for a six-switch board with
 * reconfiguration relays (--reconfig-relay: their closing time; three current sensors; issue 16,
 * firmware app_core_set_reconfig), else NULL (the target passes it to app_set_reconfig). --f2812-board takes what the F2812 board's registers really produce
 * from hal/f2812/f2812_board.h instead of the rig's defaults: the dead time the dead-band unit
 * inserts (its DBT/prescaler rounding included) and the control period of timer 1, so the
 * firmware's dead-time compensation and period scaling match the hardware it runs on.
 * Exit status 1 with the converter's message on a refused configuration. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtc_config_si.h"
#include "im_tau_check.h"
#include "f2812_board.h"

int main(int argc, char **argv)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    char msg[256];
    FILE *f;
    int rc;

    int board = 0;
    double relay_s = 0.0;
    const char *sym;
    char post_sym[128];

    if (argc > 1 && strcmp(argv[1], "--f2812-board") == 0) {
        board = 1;
        --argc;
        ++argv;
    }
    if (argc > 2 && strcmp(argv[1], "--reconfig-relay") == 0) {
        char *end = NULL;
        relay_s = strtod(argv[2], &end);
        if (end == argv[2] || *end != '\0' || !(relay_s > 0.0)) {
            fprintf(stderr, "dtc_config_gen: --reconfig-relay %s: the relay's closing time in s, > 0\n", argv[2]);
            return 2;
        }
        argc -= 2;
        argv += 2;
    }
    if (argc < 2) {
        fprintf(stderr, "usage: dtc_config_gen [--f2812-board] [--reconfig-relay DELAY_S] OUTPUT.c [SYMBOL]\n");
        return 2;
    }
    sym = argc > 2 ? argv[2] : "dtc_config_default";
    dtc_config_si_defaults(&si);
    if (relay_s > 0.0) {
        si.topology = DTC_TOPO_SSTP;
        si.compensation = DTC_COMP_SSTP;
        si.i_sensors3 = 1;
        si.reconfig_relay = 1;
        si.relay_delay_s = relay_s;
    }
    if (board) {
        si.dead_time_s = (double)F2812_DEADBAND_ACTUAL_NS * 1e-9;
        si.ts_s = 1.0 / (double)F2812_CONTROL_FREQ_HZ;
    }
    rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg);
    if (rc != DTC_SI_OK) {
        fprintf(stderr, "dtc_config_gen: configuration refused (%d): %s\n", rc, msg);
        return 1;
    }
    {
        im_tau_report_t tau_report;
        char tau_msg[600];
        if (im_tau_check(&si, &tau_report, tau_msg, sizeof tau_msg)) {
            fprintf(stderr, "dtc_config_gen: warning: %s\n", tau_msg);
        }
    }
    f = fopen(argv[1], "w");
    if (f == NULL) {
        perror(argv[1]);
        return 1;
    }
    rc = dtc_config_emit_c(&cfg, sym, f);
    snprintf(post_sym, sizeof post_sym, "%s_post", sym);
    if (rc == 0 && relay_s > 0.0) {
        dtc_config_si_t post_si;
        dtc_config_t post;
        char fstp_sym[140];
        if (dtc_config_post_fault_si(&si, &post_si) != DTC_SI_OK ||
            dtc_config_from_si(&post_si, &post, msg, sizeof msg) != DTC_SI_OK) {
            fprintf(stderr, "dtc_config_gen: post-fault configuration refused: %s\n", msg);
            fclose(f);
            return 1;
        }
        snprintf(fstp_sym, sizeof fstp_sym, "%s_fstp", post_sym);
        rc = dtc_config_emit_c(&post, fstp_sym, f);
        if (rc == 0 && fprintf(f, "\n/* the post-fault configuration (app_set_reconfig) */\n"
                                 "const struct dtc_config *const %s = &%s;\n", post_sym, fstp_sym) < 0) {
            rc = -1;
        }
    } else if (rc == 0 && fprintf(f, "\n/* no reconfiguration relays: a failed leg trips (app_set_reconfig) */\n"
                                     "const struct dtc_config *const %s = 0;\n", post_sym) < 0) {
        rc = -1;
    }
    if (fclose(f) != 0 || rc != 0) {
        fprintf(stderr, "dtc_config_gen: write error on %s\n", argv[1]);
        return 1;
    }
    return 0;
}
