#include "speed_pi.h"

void speed_pi_reset(speed_pi_t *s, iq_t preload_iq, iq_t limit_iq)
{
    s->integ_iq = iq_sat(preload_iq, fix_neg32(limit_iq), limit_iq);
    s->out_iq = s->integ_iq;
}

iq_t speed_pi_step(speed_pi_t *s, const speed_pi_params_t *p, iq_t ref_iq, iq_t meas_iq)
{
    iq_t lim = p->limit_iq;
    iq_t e = iq_sub(ref_iq, meas_iq);
    iq_t prop = iq_mpy(p->kp_iq, e);
    iq_t integ = iq_sat(iq_add(s->integ_iq, iq_mpy(p->ki_ts_iq, e)), fix_neg32(lim), lim);
    iq_t u = iq_add(prop, integ);

    if (u > lim) {
        u = lim;
        if (e > 0) {
            integ = iq_sat(s->integ_iq, fix_neg32(lim), lim); /* frozen: would wind up */
        }
    } else if (u < fix_neg32(lim)) {
        u = fix_neg32(lim);
        if (e < 0) {
            integ = iq_sat(s->integ_iq, fix_neg32(lim), lim);
        }
    }
    s->integ_iq = integ;
    s->out_iq = u;
    return u;
}
