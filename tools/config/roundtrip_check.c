/* Round-trip check of the C emitter: the generated file (compiled into this program) must hold
 * exactly the struct dtc_config_from_si() produces from the defaults, field by field. */
#include <stdio.h>
#include <string.h>

#include "dtc_config_si.h"
#include "dtc_config_fields.h"
#include "law.h"

extern const dtc_config_t dtc_config_default;

int main(void)
{
    dtc_config_si_t si;
    dtc_config_t cfg;
    char msg[256];
    int bad = 0;

    dtc_config_si_defaults(&si);
    if (dtc_config_from_si(&si, &cfg, msg, sizeof msg) != DTC_SI_OK) {
        fprintf(stderr, "defaults refused: %s\n", msg);
        return 1;
    }
#define CHK(f) do { if (cfg.f != dtc_config_default.f) { fprintf(stderr, "field %s differs\n", #f); bad = 1; } } while (0);
#define NOP(part)
#define CHKF(part, name) CHK(part.name)
#define CHKA(part, name) CHK(part.name[0]) CHK(part.name[1]) CHK(part.name[2])
    CHK(version) CHK(law)
    DTC_CONFIG_COMMON_FIELDS(NOP, CHKF, CHKF, CHKF, CHKF, CHKA, NOP)
    if (dtc_law_is_im(cfg.law) != 0U) {
        DTC_CONFIG_IM_FIELDS(NOP, CHKF, CHKF, CHKF, CHKF, CHKA, NOP)
    } else {
        DTC_CONFIG_PM_DTC_FIELDS(NOP, CHKF, CHKF, CHKF, CHKF, CHKA, NOP)
    }
    if (law_check(&dtc_config_default, NULL) != DTC_OK) {
        fprintf(stderr, "generated configuration refused by law_check\n");
        bad = 1;
    }
    if (!bad) {
        printf("emitted configuration matches the converter, field by field\n");
    }
    return bad;
}
