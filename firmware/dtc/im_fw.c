#include "im_fw.h"

int16_t im_fw_check(const im_fw_params_t *p)
{
    if (p->window < 20U) {
        return 1; /* section 12.3: the flux reference at most every 20 DTC periods */
    }
    if (p->step_down_iq <= 0 || p->step_up_iq <= 0 || p->psi_min_iq <= 0 || p->psi_rated_iq < p->psi_min_iq) {
        return 2;
    }
    if (p->inv_psi_rated_iq <= 0 || p->kt_iq <= 0) {
        return 3;
    }
    return 0;
}

void im_fw_reset(im_fw_t *s, const im_fw_params_t *p)
{
    s->psi_ref_iq = p->psi_rated_iq;
    s->count = 0U;
    s->met_seen = 0U;
}

iq_t im_fw_step(im_fw_t *s, const im_fw_params_t *p, uint16_t demand_met, iq_t t_cmd_iq)
{
    iq_t t_ref, t_max;

    if (demand_met != 0U) {
        s->met_seen = 1U;
    }
    if (++s->count >= p->window) {
        /* Section 12.2: demand not met in N periods -> flux too high for the voltage limit. */
        const iq_t next = s->met_seen != 0U ? fix_add32(s->psi_ref_iq, p->step_up_iq)
                                             : fix_sub32(s->psi_ref_iq, p->step_down_iq);
        s->psi_ref_iq = iq_sat(next, p->psi_min_iq, p->psi_rated_iq);
        s->count = 0U;
        s->met_seen = 0U;
    }
    /* Casadei Eq. 33, then the limit of eq. 34 on either sign. */
    t_ref = iq_mpy(iq_mpy(t_cmd_iq, s->psi_ref_iq), p->inv_psi_rated_iq);
    t_max = iq_mpy(p->kt_iq, iq_mpy(s->psi_ref_iq, s->psi_ref_iq));
    return iq_sat(t_ref, fix_neg32(t_max), t_max);
}
