#include "vrec.h"

void deadtime_error(const deadtime_params_t *p, iq_t vdc_iq, const clarke_out_t *i, const swtab_legs_t *prev,
                    const swtab_legs_t *cur, iq_t *dva, iq_t *dvb)
{
    deadtime_apply(p, vdc_iq, deadtime_code(p, i, prev, cur), dva, dvb);
}
