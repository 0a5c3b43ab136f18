#include "dqpi.h"

void dqpi_reset(dqpi_t *s, iq_t int_d_iq, iq_t int_q_iq)
{
    s->int_d_iq = int_d_iq;
    s->int_q_iq = int_q_iq;
}

/* One axis's output before the limit and its candidate integral (dqpi.h). */
static iq_t dqpi_axis(const dqpi_params_t *p, iq_t e, iq_t integ, iq_t ff, iq_t *integ_new)
{
    *integ_new = dqpi_integrate(integ, p->ki_ts_iq, e, p->int_max_iq);
    return iq_add(ff, iq_add(iq_mpy(p->kp_iq, e), *integ_new));
}

/* Conditional integration: keep the new integral unless the limit cut u to v and e pushes u
 * further that way. */
static iq_t dqpi_keep(iq_t u, iq_t v, iq_t e, iq_t integ_old, iq_t integ_new)
{
    if ((u > v && e > 0) || (u < v && e < 0)) {
        return integ_old;
    }
    return integ_new;
}

void dqpi_step(dqpi_t *s, const dqpi_params_t *p, const dqpi_in_t *in, dqpi_out_t *o)
{
    const iq_t ed = iq_sub(in->ref_d_iq, in->meas_d_iq);
    const iq_t eq = iq_sub(in->ref_q_iq, in->meas_q_iq);
    const iq_t vmax = in->vmax_iq > 0 ? in->vmax_iq : 0;
    iq_t id, iq, ud, uq, vd, vq;

    ud = dqpi_axis(p, ed, s->int_d_iq, in->ff_d_iq, &id);
    uq = dqpi_axis(p, eq, s->int_q_iq, in->ff_q_iq, &iq);
    vd = ud;
    vq = uq;
    o->limited = 0U;
    if (iq_sumsq_q48(ud, uq) > iq_sumsq_q48(vmax, 0)) {
        /* d axis first, then what the circle leaves to q: sqrt(V_max^2 - v_d^2), Q48 -> Q24 */
        iq_t vq_max;
        vd = fix_clamp32(ud, -vmax, vmax);
        vq_max = (iq_t)fix_isqrt64(iq_sumsq_q48(vmax, 0) - iq_sumsq_q48(vd, 0));
        vq = fix_clamp32(uq, -vq_max, vq_max);
        o->limited = 1U;
    }
    s->int_d_iq = dqpi_keep(ud, vd, ed, s->int_d_iq, id);
    s->int_q_iq = dqpi_keep(uq, vq, eq, s->int_q_iq, iq);
    o->v_d_iq = vd;
    o->v_q_iq = vq;
}
