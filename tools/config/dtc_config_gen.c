/* dtc_config_gen - writes the default configuration (dtc_config_si_defaults) as a C source file
 * for a target build.   usage: dtc_config_gen OUTPUT.c [SYMBOL]   (SYMBOL defaults to
 * dtc_config_default). Exit status 1 with the converter's message on a refused configuration. */
#include <stdio.h>

#include "dtc_config_si.h"

int main(int argc, char **argv)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    char msg[256];
    FILE *f;
    int rc;

    if (argc < 2) {
        fprintf(stderr, "usage: %s OUTPUT.c [SYMBOL]\n", argv[0]);
        return 2;
    }
    dtc_config_si_defaults(&si);
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
