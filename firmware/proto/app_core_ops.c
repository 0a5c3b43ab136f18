/*
 * app_core_ops.c - the application core's background calls (app_core.h): the arming mode, the
 * arm check, the command timeout, the capture and fault-log binding. Background code, run from
 * flash on the F2812 (libdtc_proto.a); the ISR's side of each is in app_core.c.
 */
#include "app_core.h"

#include <stddef.h>

void app_core_set_arming(app_core_t *a, uint16_t mode)
{
    a->arm_mode = mode == (uint16_t)APP_ARM_COMMAND ? (uint16_t)APP_ARM_COMMAND : (uint16_t)APP_ARM_AUTO;
}

void app_core_set_comm_timeout(app_core_t *a, uint32_t periods)
{
    a->comm_timeout_n = periods;
}

uint16_t app_core_arm_refusal(const app_core_t *a, const app_status_t *s, const dtc_refs_t *r)
{
    if (s->state == APP_STATE_FAULT) {
        return APP_ARM_FAULT;
    }
    if (s->state == APP_STATE_RUN) {
        return APP_ARM_OK;
    }
    if (s->state != APP_STATE_READY || a->cfg == NULL) {
        return APP_ARM_NOT_CALIBRATED;
    }
    if (s->meas.vdc_iq < a->cfg->prot.vdc_min_iq || s->meas.vdc_iq > a->cfg->prot.vdc_max_iq) {
        return APP_ARM_VDC_RANGE;
    }
    if (r->speed_ref_iq != 0 || r->torque_ref_iq != 0) {
        return APP_ARM_REF_NONZERO;
    }
    return APP_ARM_OK;
}

void app_core_attach(app_core_t *a, capture_t *cap, faultlog_t *flog)
{
    a->cap = cap;
    a->flog = flog;
    if (cap != NULL) {
        (void)capture_bind(cap, CAPTURE_Q_I_A, &a->st.meas.ia_iq);
        (void)capture_bind(cap, CAPTURE_Q_I_B, &a->st.meas.ib_iq);
        (void)capture_bind(cap, CAPTURE_Q_I_C, &a->st.meas.ic_iq);
        (void)capture_bind(cap, CAPTURE_Q_PSI_ALPHA_EST, &a->st.out.psi_alpha_iq);
        (void)capture_bind(cap, CAPTURE_Q_PSI_BETA_EST, &a->st.out.psi_beta_iq);
        (void)capture_bind(cap, CAPTURE_Q_TORQUE_EST, &a->st.out.te_iq);
        (void)capture_bind(cap, CAPTURE_Q_SPEED, &a->st.out.speed_iq);
        if (a->cfg != NULL) {
            (void)capture_bind(cap, CAPTURE_Q_SPEED_REF, law_speed_ref_ptr(&a->law));
        }
        (void)capture_bind(cap, CAPTURE_Q_TORQUE_REF, &a->st.out.te_ref_iq);
        (void)capture_bind(cap, CAPTURE_Q_PSI_REF, &a->st.out.psi_ref_iq);
        (void)capture_bind(cap, CAPTURE_Q_VDC, &a->st.meas.vdc_iq);
        (void)capture_bind(cap, CAPTURE_Q_VMID, &a->st.meas.vmid_iq);
        (void)capture_bind_u16(cap, CAPTURE_Q_SECTOR, &a->st.out.sector);
        (void)capture_bind_u16(cap, CAPTURE_Q_VECTOR, &a->st.out.vector);
    }
}
