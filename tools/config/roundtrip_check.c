/* Round-trip check of the C emitter: the generated file (compiled into this program) must hold
 * exactly the struct dtc_config_from_si() produces from the defaults, field by field. */
#include <stdio.h>
#include <string.h>

#include "dtc_config_si.h"
#include "dtc_params.h"
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
    {
        /* every row of the common part and of the law's part (dtc_param.h) */
        const dtc_param_list_t *lists[2] = {&dtc_params_common, dtc_param_law_list(cfg.law)};
        uint16_t l, k;
        for (l = 0U; l < 2U; l++) {
            for (k = 0U; lists[l] != NULL && k < lists[l]->n; k++) {
                const dtc_param_t *p = &lists[l]->rows[k];
                if (dtc_param_raw(&cfg, p) != dtc_param_raw(&dtc_config_default, p)) {
                    fprintf(stderr, "field %s (#%u) differs\n", p->name, (unsigned)p->id);
                    bad = 1;
                }
            }
        }
        if (lists[1] == NULL) {
            fprintf(stderr, "law %u has no linked part\n", (unsigned)cfg.law);
            bad = 1;
        }
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
