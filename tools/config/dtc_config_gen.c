/* dtc_config_gen - writes the default configuration (dtc_config_si_defaults) as a C source file
 * for a target build.   usage: dtc_config_gen [--f2812-board] OUTPUT.c [SYMBOL]   (SYMBOL defaults
 * to dtc_config_default). --f2812-board takes what the F2812 board's registers really produce
 * from hal/f2812/f2812_board.h instead of the rig's defaults: the dead time the dead-band unit
 * inserts (its DBT/prescaler rounding included) and the control period of timer 1, so the
 * firmware's dead-time compensation and period scaling match the hardware it runs on.
 * Exit status 1 with the converter's message on a refused configuration. */
#include <stdio.h>
#include <string.h>

#include "dtc_config_si.h"
#include "f2812_board.h"

int main(int argc, char **argv)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    char msg[256];
    FILE *f;
    int rc;

    int board = 0;

    if (argc > 1 && strcmp(argv[1], "--f2812-board") == 0) {
        board = 1;
        --argc;
        ++argv;
    }
    if (argc < 2) {
        fprintf(stderr, "usage: dtc_config_gen [--f2812-board] OUTPUT.c [SYMBOL]\n");
        return 2;
    }
    dtc_config_si_defaults(&si);
    if (board) {
        si.dead_time_s = (double)F2812_DEADBAND_ACTUAL_NS * 1e-9;
        si.ts_s = 1.0 / (double)F2812_CONTROL_FREQ_HZ;
    }
    rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg);
    if (rc != DTC_SI_OK) {
        fprintf(stderr, "dtc_config_gen: configuration refused (%d): %s\n", rc, msg);
        return 1;
    }
    f = fopen(argv[1], "w");
    if (f == NULL) {
        perror(argv[1]);
        return 1;
    }
    rc = dtc_config_emit_c(&cfg, argc > 2 ? argv[2] : "dtc_config_default", f);
    if (fclose(f) != 0 || rc != 0) {
        fprintf(stderr, "dtc_config_gen: write error on %s\n", argv[1]);
        return 1;
    }
    return 0;
}
