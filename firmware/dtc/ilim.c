#include "ilim.h"

/* |i| > limit, on the exact squares (unsigned Q48). External linkage on purpose: inlined, its
 * 64-bit temporaries would sit in ilim_select's frame on the deepest stack path. */
uint16_t ilim_over(iq_t lim_iq, const clarke_out_t *i)
{
    return iq_sumsq_q48(i->i_alpha_iq, i->i_beta_iq) > iq_sumsq_q48(lim_iq, 0) ? 1U : 0U;
}

uint16_t ilim_select(const ilim_params_t *p, const clarke_out_t *i, uint16_t vec, uint16_t *limited)
{
    *limited = 0U;
    if (p->i_lim_iq <= 0 || ilim_over(p->i_lim_iq, i) == 0U) {
        return vec;
    }
    *limited = 1U;
    return ilim_pick(p, i);
}
