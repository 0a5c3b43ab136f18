/*
 * app_core_init.c - the application core's init-time and background calls (app_core.h): init,
 * the PWM period, the post-fault configuration, the arming mode, the arm check, the command
 * timeout, the capture and fault-log binding. In libdtc_app_init.a, which the F2812 image runs
 * from flash (linker/f2812_flash.cmd places only libdtc_app.a, the ISR path, in zero-wait RAM).
 */
#include "app_core.h"
#include "app_core_internal.h"

#include "app_pwm.h"

#include <stddef.h>

int16_t app_core_init(app_core_t *a, const dtc_config_t *cfg)
{
    static const dtc_meas_t no_meas; /* zeros: nothing measured before the first period */
    int16_t rc;
    uint16_t k;

    a->cfg = NULL;
    a->post = NULL;
    a->perm = 0U;
    a->arm_mode = (uint16_t)APP_ARM_AUTO;
    a->arm_request = (uint16_t)APP_REQ_NONE;
    a->comm_seen = 0U;
    a->comm_timeout_n = 0U;
    a->comm_idle_n = 0U;
    a->cap = NULL;
    a->cap_state = &app_core_cap_none;
    a->flog = NULL;
    app_fault_init(&a->flt);
    a->clear_request = 0U;
    a->t1pr = 0U;
    a->st.tick = 0U;
    a->st.fault_tick = 0U;
    a->st.state = APP_STATE_INIT;
    a->st.fault = APP_FAULT_NONE;
    a->st.fault_detail = 0;
    a->st.reconfigured = 0U;
    a->st.warnings = 0U;
    a->st.warn_tick = 0U;
    a->st.meas = no_meas;
    a->ident_request = 0U;
    a->ident.step = (uint16_t)APP_IDENT_IDLE;
    rc = law_init(&a->law, cfg);
    if (rc != DTC_OK) {
        app_core_latch(a, APP_FAULT_CONFIG, rc);
        return rc;
    }
    a->cfg = cfg;
    for (k = 0U; k < 3U; k++) {
        a->offset[k] = cfg->board.adc_i_offset[k];
    }
    /* Which two currents are measured (clarke.h): SSTP i_a, i_b; FSTP i_b, i_c, the two switched
     * phases whose signs the FSTP compensation tables need (Hoang Tables V-VI). */
    if (cfg->board.topology == (uint16_t)DTC_TOPO_FSTP) {
        a->meas_ch[0] = (uint16_t)HAL_ADC_IB;
        a->meas_ch[1] = (uint16_t)HAL_ADC_IC;
    } else {
        a->meas_ch[0] = (uint16_t)HAL_ADC_IA;
        a->meas_ch[1] = (uint16_t)HAL_ADC_IB;
    }
    a->meas_mask = cfg->board.i_sensors3 != 0U ? 7U
                   : (cfg->board.topology == (uint16_t)DTC_TOPO_FSTP ? 6U : 3U);
    if (dtc_law_is_im(cfg->law) != 0U) {
        app_plaus_init(&a->plaus_p, cfg->board.adc_i_gain_iq, APP_PLAUS_WIN_LOG2_IM, APP_PLAUS_BIAS_LOG2_IM);
    } else {
        app_plaus_init(&a->plaus_p, cfg->board.adc_i_gain_iq, APP_PLAUS_WIN_LOG2, APP_PLAUS_BIAS_LOG2);
    }
    app_enc_init(&a->enc, cfg);
    app_core_enter_calibrate(a);
    return 0;
}

int16_t app_core_set_reconfig(app_core_t *a, const dtc_config_t *post)
{
    if (post == NULL) {
        a->post = NULL;
        return 0;
    }
    if (a->cfg == NULL || a->st.reconfigured != 0U || app_fault_post_ok(a->cfg, post) == 0U) {
        a->post = NULL;
        app_core_latch(a, APP_FAULT_CONFIG, DTC_ERR_RECONFIG);
        return DTC_ERR_RECONFIG;
    }
    a->post = post;
    return 0;
}

int16_t app_core_set_pwm_period(app_core_t *a, uint16_t t1pr)
{
    a->t1pr = t1pr;
    if (a->cfg != NULL && app_pwm_period_check(law_out_form(&a->law), t1pr) != 0) {
        app_core_latch(a, APP_FAULT_CONFIG, DTC_ERR_SVM);
        /* also over a fault latched before: a clear request ends that one, this one it must not */
        a->st.fault = APP_FAULT_CONFIG;
        a->st.fault_detail = DTC_ERR_SVM;
        return DTC_ERR_SVM;
    }
    return 0;
}

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
    /* FSTP: the split link's mid-point where the balancing resistors hold it at rest. After a trip
     * at speed the machine's back-EMF, rectified by the two legs' diodes, charges one capacitor
     * (measured: 62.5 V of 70 V after a stall trip at 1500 rpm, Hoang Table VIII's rig); arming
     * then would calibrate that imbalance as an offset and drive phase A, on the mid-point, with it.
     * Refused (vmid_range) until the resistors bring it back. Background: a comparison of the
     * status copy's samples, no division. */
    if (a->cfg->board.topology == (uint16_t)DTC_TOPO_FSTP && a->cfg->board.fstp_vmid_measured != 0U &&
        fix_abs32(fix_sub32(s->meas.vmid_iq, fix_rshift_rnd32(s->meas.vdc_iq, 1U))) >
            fix_rshift_rnd32(fix_abs32(s->meas.vdc_iq), APP_VMID_TOL_LOG2)) {
        return APP_ARM_VMID_RANGE;
    }
    if (r->speed_ref_iq != 0 || r->torque_ref_iq != 0) {
        return APP_ARM_REF_NONZERO;
    }
    return APP_ARM_OK;
}

void app_core_attach(app_core_t *a, capture_t *cap, faultlog_t *flog)
{
    a->cap = cap;
    a->cap_state = cap != NULL ? &cap->state : &app_core_cap_none;
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
