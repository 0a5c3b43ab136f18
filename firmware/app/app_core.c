/*
 * app_core.c - drive state machine and ISR body (see app_core.h).
 */
#include "app_core.h"
#include "app_core_internal.h"

#include "app_adc.h"
#include "app_pwm.h"

#include <stddef.h>

const uint16_t app_core_cap_none = (uint16_t)CAPTURE_OFF;

/* The fault log's snapshot: the last per-unit sample and the law's output of the last step. */
static void log_fault(app_core_t *a)
{
    faultlog_snapshot_t s;
    s.ia_iq = a->st.meas.ia_iq;
    s.ib_iq = a->st.meas.ib_iq;
    s.ic_iq = a->st.meas.ic_iq;
    s.vdc_iq = a->st.meas.vdc_iq;
    s.vmid_iq = a->st.meas.vmid_iq;
    s.speed_iq = a->st.out.speed_iq;
    s.psi_alpha_iq = a->st.out.psi_alpha_iq;
    s.psi_beta_iq = a->st.out.psi_beta_iq;
    s.te_iq = a->st.out.te_iq;
    s.te_ref_iq = a->st.out.te_ref_iq;
    s.speed_ref_iq = a->cfg != NULL ? law_speed_ref(&a->law) : 0;
    s.sector = a->st.out.sector;
    s.vector = a->st.out.vector;
    s.state = a->st.state;
    faultlog_record(a->flog, a->st.tick, a->st.fault, a->st.fault_detail, &s);
}

void app_core_latch(app_core_t *a, uint16_t fault, int16_t detail)
{
    if (a->st.state != APP_STATE_FAULT) {
        const uint16_t was = a->st.state;
        a->st.state = APP_STATE_FAULT;
        a->st.fault = fault;
        a->st.fault_detail = detail;
        a->st.fault_tick = a->st.tick;
        if (a->flog != NULL) {
            a->st.state = was; /* the snapshot's state: the one the fault ended */
            log_fault(a);
            a->st.state = APP_STATE_FAULT;
        }
    }
}

void app_core_enter_calibrate(app_core_t *a)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        a->cal_sum[k] = 0U;
    }
    a->cal_n = 0U;
    app_hold_reset(&a->hold);
    a->vmid_cal_sum_iq = 0;
    a->vmid_cal_iq = 0;
    app_enc_reset(&a->enc);
    app_fault_reset(&a->flt);
    app_plaus_reset(&a->plaus);
    a->plaus_win = 0U;
    a->speed_slots = 0U;
    a->st.out.speed_iq = 0; /* the encoder-freeze check reads the last reported speed */
    a->arming = 0U;
    a->st.fault = APP_FAULT_NONE;
    a->st.fault_detail = 0;
    a->st.state = APP_STATE_CALIBRATE;
}

void app_core_convert(const app_core_t *a, const hal_meas_t *m, dtc_meas_t *pu)
{
    const dtc_config_t *c = a->cfg;
    iq_t i[3];
    uint16_t k;
    /* the law's phases with a sensor (meas_mask, set with the configuration at init and at a
     * reconfiguration: 7 all three, 6 FSTP b', c', 3 SSTP a', b'; the unmeasured one's ADC
     * channel is not converted: its value would be replaced below) */
    const uint16_t k0 = (a->meas_mask & 1U) == 0U ? 1U : 0U;
    const uint16_t k1 = (a->meas_mask & 4U) == 0U ? 2U : 3U;

    for (k = k0; k < k1; k++) {
        /* the law's phase k is the physical phase (perm + k) mod 3 (reconfigure) */
        const uint16_t ch = app_fault_phase(a->perm, k);
        i[k] = app_adc_to_pu(m->adc[ch], a->offset[ch], c->board.adc_i_gain_iq);
    }
    /* The unmeasured phase from Kirchhoff's current law (isolated star point). All three
     * measured: each as it is (their sum is checked, app_fault_trips). */
    if (k0 != 0U) {
        i[0] = fix_neg32(fix_add32(i[1], i[2]));
    } else if (k1 != 3U) {
        i[2] = fix_neg32(fix_add32(i[0], i[1]));
    }
    pu->ia_iq = i[0];
    pu->ib_iq = i[1];
    pu->ic_iq = i[2];
    pu->vdc_iq = app_adc_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    pu->vmid_iq = fix_sub32(app_adc_to_pu(m->adc[HAL_ADC_VMID], c->board.adc_vmid_offset,
                                         c->board.adc_vmid_gain_iq),
                            a->vmid_cal_iq);
    pu->enc_count = m->qep_count;
}

/* The hardware trip and desaturation inputs (app_fault_hw); latches and returns 1 on a trip. */
static uint16_t check_hw_trip(app_core_t *a, const hal_meas_t *m)
{
    int16_t detail = 0;
    const uint16_t f = app_fault_hw(m, &detail);
    if (f != (uint16_t)APP_FAULT_NONE) {
        app_core_latch(a, f, detail);
        return 1U;
    }
    return 0U;
}

/* Trip checks on one per-unit sample (the hardware inputs, app_fault_trips) and the encoder
 * (app_enc_check); latches and returns 1 on a trip. */
static uint16_t check_trips(app_core_t *a, const hal_meas_t *m, const dtc_meas_t *pu)
{
    int16_t detail = 0;
    uint16_t f;
    if (check_hw_trip(a, m) != 0U) {
        return 1U;
    }
    f = app_fault_trips(&a->flt, a->cfg, pu, a->perm, &detail);
    if (f != (uint16_t)APP_FAULT_NONE) {
        app_core_latch(a, f, detail);
        return 1U;
    }
    detail = app_enc_check(&a->enc, a->cfg, m, a->st.out.speed_iq);
    if (detail != 0) {
        app_core_latch(a, APP_FAULT_ENCODER, detail);
        return 1U;
    }
    return 0U;
}

/* Mid-point calibration (dtc_config.h vmid_cal; FSTP with the mid-point measured). With the
 * gates off the balancing resistors hold the mid-point at V_dc/2 (equal resistors; docs/plant.md),
 * so the mean of (mid-point - V_dc/2) measured then is the inconsistency of the two voltage
 * sensors (gain and offset errors of either, at the link voltage): subtracted from every
 * mid-point sample, the reconstruction (Hoang eqs. 1-5 with phase A on the mid-point, vrec.h)
 * gets no DC part on v_alpha that the machine does not see. Without it a 2 % link-gain error is
 * (0.02 * 70 V)/3 = 0.47 V of DC on v_alpha, which the voltage model's low-pass turns into a flux
 * offset E / w_c (~ psi_m at 5 rad/s) (docs/firmware-core.md).
 * Scaling: the deviation is IQ pu (saturated), 2^APP_VMID_CAL_LOG2 of them sum in 64 bits without
 * overflow; the mean is a rounded arithmetic shift (no division), saturated to 32 bits. */
static void app_vmid_cal_add(app_core_t *a, const hal_meas_t *m)
{
    const dtc_config_t *c = a->cfg;
    iq_t vdc = app_adc_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    iq_t vmid = app_adc_to_pu(m->adc[HAL_ADC_VMID], c->board.adc_vmid_offset, c->board.adc_vmid_gain_iq);
    a->vmid_cal_sum_iq += (int64_t)fix_sub32(vmid, fix_rshift_rnd32(vdc, 1U));
}

/* Ends the mid-point calibration: the mean, checked against V_dc / 2^APP_VMID_TOL_LOG2 (4.4 V at
 * 70 V: a sensor that far off is broken, not inaccurate). Returns 1 on a fault (latched). */
static uint16_t app_vmid_cal_set(app_core_t *a, const hal_meas_t *m)
{
    const dtc_config_t *c = a->cfg;
    iq_t vdc = app_adc_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    iq_t mean = fix_sat32((a->vmid_cal_sum_iq + ((int64_t)1 << (APP_VMID_CAL_LOG2 - 1U))) >>
                          APP_VMID_CAL_LOG2);
    if (fix_abs32(mean) > fix_rshift_rnd32(fix_abs32(vdc), APP_VMID_TOL_LOG2)) {
        app_core_latch(a, APP_FAULT_ADC_OFFSET, (int16_t)HAL_ADC_VMID);
        return 1U;
    }
    a->vmid_cal_iq = mean;
    return 0U;
}

/* End of the calibration: the mid-point and the DC link checked, the law reset, RUN. */
static void calibrate_finish(app_core_t *a, const hal_meas_t *m)
{
    a->hold.on = 0U;
    if (a->cfg->board.vmid_cal != 0U && app_vmid_cal_set(a, m) != 0U) {
        return;
    }
    /* Into the status's measurement: a status read between this period and the next (READY
     * converts every period from the next one) shows this period's V_dc, not the zeros of init
     * (the fault snapshot of a DC-link trip here holds the level that tripped). */
    app_core_convert(a, m, &a->st.meas);
    if (a->st.meas.vdc_iq < a->cfg->prot.vdc_min_iq) {
        app_core_latch(a, APP_FAULT_DC_UNDERVOLTAGE, 0);
        return;
    }
    if (a->st.meas.vdc_iq > a->cfg->prot.vdc_max_iq) {
        app_core_latch(a, APP_FAULT_DC_OVERVOLTAGE, 0);
        return;
    }
    if (a->ident_request != 0U) {
        app_ident_start(&a->ident, a->cfg, m->qep_count, a->st.meas.vdc_iq);
        a->ident_request = 0U; /* once: a later calibration (fault clear, arm) ends as usual */
        a->st.state = APP_STATE_IDENT;
        return;
    }
    if (a->arm_mode == (uint16_t)APP_ARM_COMMAND && a->arming == 0U) {
        a->st.state = APP_STATE_READY;
        return;
    }
    a->arming = 0U;
    a->comm_seen = 0U;
    a->comm_idle_n = 0U;
    law_reset(&a->law);
    a->st.state = APP_STATE_RUN;
}

void app_core_request_ident(app_core_t *a) { a->ident_request = 1U; }

void app_core_ident_service(app_core_t *a)
{
    if (a->cfg != NULL && a->st.state == APP_STATE_IDENT) {
        app_ident_service(&a->ident, a->cfg);
    }
}

/* Calibration period: accumulate the measured channels; after 2^APP_CAL_LOG2 samples set the
 * current offsets (rounded mean, a shift: no division) and check them; with the mid-point
 * calibration and a hold current, the rotor hold starts then on a rotor at rest (app_hold_cal,
 * app_hold.h; a turning rotor is started into when the calibration ends); at the end of the
 * calibration check the mid-point and the DC link and enter RUN. */
static void calibrate_step(app_core_t *a, const hal_meas_t *m)
{
    uint16_t k;
    const uint16_t n_off = (uint16_t)(1U << APP_CAL_LOG2);
    const uint16_t n_cal = (uint16_t)(1U << (a->cfg->board.vmid_cal != 0U ? APP_VMID_CAL_LOG2 : APP_CAL_LOG2));
    const uint16_t n_ch = a->cfg->board.i_sensors3 != 0U ? 3U : 2U; /* channels with a sensor */
    if (a->cal_n >= n_cal) {
        /* calibration done, the hold waits for the rotor to settle */
        if (app_hold_settled(&a->hold) == 0U && ++a->hold.extra < ((uint16_t)1U << APP_VMID_CAL_LOG2)) {
            return;
        }
        calibrate_finish(a, m);
        return;
    }
    if (a->cal_n < n_off) {
        if (app_hold_cal(&a->hold, a->cfg, m->qep_count, a->cal_n) != 0U) {
            a->enc.primed = 0U; /* the hold starts with this period's offsets (app_hold.h) */
        }
        for (k = 0U; k < n_ch; k++) {
            uint16_t ch = n_ch == 3U ? k : a->meas_ch[k];
            a->cal_sum[ch] += (uint32_t)m->adc[ch];
        }
    }
    if (a->cfg->board.vmid_cal != 0U) {
        app_vmid_cal_add(a, m);
    }
    a->cal_n++;
    if (a->cal_n == n_off) {
        for (k = 0U; k < n_ch; k++) {
            uint16_t ch = n_ch == 3U ? k : a->meas_ch[k];
            uint32_t mean = (a->cal_sum[ch] + ((uint32_t)1U << (APP_CAL_LOG2 - 1U))) >> APP_CAL_LOG2;
            int32_t dev = (int32_t)mean - (int32_t)a->cfg->board.adc_i_offset[ch];
            if (fix_abs32(dev) > (int32_t)DTC_ADC_OFFSET_TOL_COUNTS) {
                app_core_latch(a, APP_FAULT_ADC_OFFSET, (int16_t)ch);
                return;
            }
            a->offset[ch] = (uint16_t)mean;
        }
    }
    if (a->cal_n < n_cal || app_hold_settled(&a->hold) == 0U) {
        return; /* calibrating, or the rotor still moving: hold on (above) */
    }
    calibrate_finish(a, m);
}

/* Reconfiguration after leg x failed (app_core_set_reconfig, dtc.h dtc_reconfigure): the law
 * goes on as the FSTP with phase A' = x; from now on the currents come in and the legs go out
 * through the permutation perm = x; the relay command ties phase x to the mid-point (hal_cmd_t
 * relay; the HAL keeps leg x off while it is set) and the open-phase check waits until it has
 * closed. Returns 1 when the law refused (the core then trips). */
static uint16_t reconfigure(app_core_t *a, uint16_t x)
{
    if (law_reconfigure(&a->law, a->post, x) != DTC_OK) {
        app_core_latch(a, APP_FAULT_LEG, (int16_t)x);
        return 1U;
    }
    a->cfg = a->post;
    a->perm = x;
    a->st.reconfigured = (uint16_t)(x + 1U);
    a->meas_ch[0] = app_fault_phase(x, 1U);
    a->meas_ch[1] = app_fault_phase(x, 2U);
    app_fault_reconfigured(&a->flt, a->post->prot.relay_periods);
    a->meas_mask = 7U; /* the post-fault configuration has three sensors (app_fault_post_ok) */
    app_plaus_reset(&a->plaus);
    return 0U;
}

/* Open phase (app_fault_open_phase): reconfigures when a post-fault configuration is set and the
 * drive is not yet reconfigured, else trips (APP_FAULT_LEG). Returns 1 on a trip. */
static uint16_t check_open_phase(app_core_t *a)
{
    uint16_t x = 0U;
    if (app_fault_open_phase_held(&a->flt, a->cfg, a->st.out.speed_tick) != 0U) {
        return 0U; /* the speed-loop period's sample, held over without the call */
    }
    if (app_fault_open_phase(&a->flt, a->cfg, &a->st.meas, a->st.out.speed_iq, a->perm, a->st.out.speed_tick, &x) ==
        0U) {
        return 0U;
    }
    if (a->post != NULL && a->st.reconfigured == 0U) { /* post: a leg-form law on the FSTP (set_reconfig) */
        return reconfigure(a, x);
    }
    app_core_latch(a, APP_FAULT_LEG, (int16_t)x);
    return 1U;
}

/* Overspeed (app_fault_overspeed), the encoder against the flux speed (app_enc_flux_check, on the
 * steps the law compared them, not while a phase looks open: app_fault_phase_suspect) and stall
 * (app_fault_stall); latches and returns 1 on a trip. Overspeed and stall judge the speed-loop
 * period's speed and act on it only (slot 0, app_core.h): the other periods skip them and the
 * speed reference's look-up. */
static uint16_t check_speed(app_core_t *a)
{
    int16_t detail = 0;
    iq_t err = 0, tol = 0;
    const uint16_t tick = a->st.out.speed_tick;
    uint16_t f = tick != 0U ? app_fault_overspeed(a->cfg, &a->st.out, &detail) : (uint16_t)APP_FAULT_NONE;
    if (f == (uint16_t)APP_FAULT_NONE && law_enc_plaus(&a->law, &err, &tol) != 0U &&
        app_fault_phase_suspect(&a->flt) == 0U) {
        detail = app_enc_flux_check(&a->enc, err, tol);
        f = detail != 0 ? (uint16_t)APP_FAULT_ENCODER_SPEED : (uint16_t)APP_FAULT_NONE;
    }
    if (f == (uint16_t)APP_FAULT_NONE && tick != 0U) {
        f = app_fault_stall(&a->flt, a->cfg, &a->st.out, law_speed_ref(&a->law), &detail);
    }
    if (f != (uint16_t)APP_FAULT_NONE) {
        app_core_latch(a, f, detail);
        return 1U;
    }
    return 0U;
}

/* Current-sensor plausibility (app_plaus.h, prot.i_plaus; with the fault detection):
 * measured channels that did not follow the current the law predicted from the voltage it
 * applied. An open phase does that too (its phase reads zero and the others no longer follow a
 * three-phase model), so:
 *  - three sensors: a sensor where their sum disagreed as well (|sum| > prot.i_sum_max_iq on a
 *    sample of the window), or where no phase read zero (inside the open-phase zero band) in the
 *    window; a phase at zero with the sum at zero is an open phase or device, left to the
 *    open-phase check and its reconfiguration (app_fault_open_phase). The sum alone (app_fault_trips) needs it for
 *    APP_ISUM_PERIODS periods in a row, which a sensor stuck near the current's own range may take
 *    milliseconds to give;
 *  - two sensors: a channel that reads zero (inside the open-phase zero band) while the law drives
 *    current into it is named as such (a sensor stuck at zero and an open phase look the same to two
 *    sensors, APP_SENSOR_DETAIL_LIST 2); either must turn the gates off before the unseen current
 *    runs away. Otherwise the first channel that failed (APP_SENSOR_DETAIL_LIST 0).
 * Returns 1 on a trip. */
static uint16_t check_sensors(app_core_t *a)
{
    const dtc_config_t *c = a->cfg;
    const iq_t i[3] = {a->st.meas.ia_iq, a->st.meas.ib_iq, a->st.meas.ic_iq};
    const iq_t zero = fix_rshift_rnd32(c->prot.leg_i_min_iq, APP_LEG_ZERO_LOG2);
    iq_t i1[3];
    uint16_t bad, k, pick = 3U, kind = 0U, win, fl = 0U;
    if (c->prot.i_plaus == 0U) {
        return 0U;
    }
    if (a->flt.relay_wait > 0U) {
        /* reconfigured, the relay not yet closed: the failed leg's diodes still carry its phase's
         * current (an open device), which the FSTP law cannot predict; the check starts afresh
         * once the phase is on the mid-point */
        app_plaus_reset(&a->plaus);
        a->plaus_win = 0U;
        return 0U;
    }
    if (c->board.i_sensors3 != 0U) {
        if (fix_abs32(fix_add32(fix_add32(i[0], i[1]), i[2])) > c->prot.i_sum_max_iq) {
            fl |= 1U;
        }
        for (k = 0U; k < 3U; k++) {
            if (fix_abs32(i[k]) < zero) {
                fl |= 2U;
            }
        }
    }
    bad = app_plaus_step(&a->plaus, &a->plaus_p, i, law_i_pred(&a->law, a->st.meas.vdc_iq, i1) != 0U ? i1 : NULL,
                         a->meas_mask, a->speed_slots);
    fl |= a->plaus_win; /* this window's flags with this sample's */
    win = fl;
    if (a->plaus.judged != 0U) {
        /* the windows judged in this call: one held over from a speed-loop slot (judged before
         * this sample) and the one this sample ended */
        win = (uint16_t)(((a->plaus.judged & APP_PLAUS_JUDGED_HELD) != 0U ? a->plaus_win_held : 0U) |
                         ((a->plaus.judged & APP_PLAUS_JUDGED_NOW) != 0U ? fl : 0U));
    }
    a->plaus_win = fl;
    if (a->plaus.n == 0U && a->plaus.due != 2U) {
        /* a window ended (or the block rests): the next one starts afresh (due 2: this sample,
         * which waits, is the next window's first) */
        if (a->plaus.due == 1U) {
            a->plaus_win_held = fl; /* it ended in a held slot: judged later */
        }
        a->plaus_win = 0U;
    }
    if (bad == 0U || win == 2U) {
        return 0U; /* three sensors, a phase at zero and the sum at zero: an open phase's signature */
    }
    for (k = 0U; k < 3U; k++) {
        if ((bad & (uint16_t)(1U << k)) != 0U) {
            if (c->board.i_sensors3 == 0U && fix_abs32(i[k]) < zero) {
                pick = k;
                kind = 2U;
                break;
            }
            if (pick == 3U) {
                pick = k;
            }
        }
    }
    app_core_latch(a, APP_FAULT_CURRENT_SENSOR, (int16_t)(3U * kind + app_fault_phase(a->perm, pick)));
    return 1U;
}

/* The background's arm and disarm requests (app_core_request_arm), taken once per period. An arm
 * request in READY starts a calibration that ends in RUN: fresh current offsets, the DC link
 * checked on the last sample (calibrate_finish), every detector reset (enter_calibrate). */
static void take_arm_request(app_core_t *a)
{
    const uint16_t req = a->arm_request;
    if (req == (uint16_t)APP_REQ_NONE) {
        return;
    }
    a->arm_request = (uint16_t)APP_REQ_NONE;
    if (req == (uint16_t)APP_REQ_ARM && a->st.state == APP_STATE_READY) {
        app_core_enter_calibrate(a);
        a->arming = 1U;
    } else if (req == (uint16_t)APP_REQ_DISARM) {
        /* a drive disarmed by a host stays under its command: no calibration re-arms it */
        a->arm_mode = (uint16_t)APP_ARM_COMMAND;
        if (a->st.state != APP_STATE_RUN) {
            return;
        }
        a->st.state = APP_STATE_READY;
        a->st.out.te_iq = 0; /* gates off: no torque (the status must not show the last one) */
        a->st.out.te_ref_iq = 0;
    }
}

/* RUN with the command timeout on: counts the periods since the background last saw a valid
 * frame; latches APP_FAULT_COMM_TIMEOUT when they reach comm_timeout_n. Returns 1 on a trip. */
static uint16_t check_comm(app_core_t *a)
{
    const uint32_t n = a->comm_timeout_n;
    if (n == 0U || a->arm_mode != (uint16_t)APP_ARM_COMMAND) {
        return 0U;
    }
    if (a->comm_seen != 0U) {
        a->comm_seen = 0U;
        a->comm_idle_n = 0U;
        return 0U;
    }
    if (++a->comm_idle_n >= n) {
        app_core_latch(a, APP_FAULT_COMM_TIMEOUT, 0);
        return 1U;
    }
    return 0U;
}

static uint16_t core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd);

uint16_t app_core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd)
{
    hal_meas_t rev;
    const hal_meas_t *mm = m;
    uint16_t off;
    if (a->cfg != NULL && a->cfg->board.enc_reversed != 0U) {
        app_enc_reverse(a->cfg, m, &rev); /* every consumer of the count sees it forward */
        mm = &rev;
    }
    off = core_step(a, mm, cmd);
    /* capture_isr's test on the word app_core_attach chose: one load and compare whether a
     * capture is attached or not */
    if (*a->cap_state >= (uint16_t)CAPTURE_ARMED) {
        capture_isr_run(a->cap, a->st.tick, (uint16_t)(a->st.state == APP_STATE_FAULT ? 1U : 0U));
    }
    return off;
}

static uint16_t core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd)
{
    cmd->sa = 0U;
    cmd->sb = 0U;
    cmd->sc = 0U;
    cmd->enable = 0U;
    cmd->form = (uint16_t)HAL_CMD_LEGS; /* leg states for the whole period (hal.h) */
    cmd->relay = a->st.reconfigured;    /* hal.h: a closed relay stays closed (the leg failed for good) */
    for (uint16_t x = 0U; x < 3U; x++) { /* the PWM fields: defined even where the form ignores them */
        cmd->cmpr_up[x] = 0U;
        cmd->cmpr_dn[x] = 0U;
        cmd->act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
    }
    a->st.tick = m->tick;

    if (a->clear_request != 0U) {
        a->clear_request = 0U;
        if (a->st.state == APP_STATE_FAULT && a->st.fault != (uint16_t)APP_FAULT_CONFIG) {
            app_core_enter_calibrate(a);
        }
    }
    take_arm_request(a);

    switch (a->st.state) {
    case APP_STATE_CALIBRATE:
        /* Hardware trip still counts while calibrating. */
        if (check_hw_trip(a, m) != 0U) {
            return 1U;
        }
        if (a->hold.on != 0U) {
            /* rotor hold (app_hold.h): the offsets are set, the protection runs as in RUN */
            app_core_convert(a, m, &a->st.meas);
            if (check_trips(a, m, &a->st.meas) != 0U) {
                a->hold.on = 0U;
                return 1U;
            }
            app_hold_step(&a->hold, a->cfg, &a->st.meas, m, cmd);
            calibrate_step(a, m);
            if (a->st.state == APP_STATE_FAULT) {
                cmd->sb = 0U;
                cmd->sc = 0U;
                cmd->enable = 0U;
                return 1U;
            }
            return 0U; /* this period's hold command; RUN from the next one */
        }
        calibrate_step(a, m);
        return 1U; /* gates off until RUN (or the hold) */

    case APP_STATE_READY:
        /* disarmed: the measurement kept fresh for the status and the arm check; gates off */
        app_core_convert(a, m, &a->st.meas);
        (void)check_hw_trip(a, m);
        return 1U;

    case APP_STATE_RUN:
        app_core_convert(a, m, &a->st.meas);
        if (check_trips(a, m, &a->st.meas) != 0U || check_comm(a) != 0U) {
            return 1U;
        }
        law_step(&a->law, &a->st.meas, &a->st.out);
        /* this period's slot in the speed-loop cycle (app_core.h speed_slots) */
        a->speed_slots = (uint16_t)(((uint16_t)(a->speed_slots << 1) | a->st.out.speed_tick) & APP_SLOTS_HELD);
        if (a->st.out.speed_tick != 0U) {
            /* the laws' warnings change at the speed-loop rate */
            const uint16_t w = law_warnings(&a->law);
            if (w != 0U && a->st.warnings == 0U) {
                a->st.warn_tick = a->st.tick;
            }
            a->st.warnings |= w;
        }
        if (check_sensors(a) != 0U) {
            return 1U;
        }
        {
            const uint16_t before = a->st.reconfigured;
            if (check_open_phase(a) != 0U || check_speed(a) != 0U) {
                return 1U;
            }
            if (a->st.reconfigured != before) {
                /* this period's legs were chosen by the six-switch law: leg x is off (relay set) */
                cmd->relay = a->st.reconfigured;
                cmd->sa = a->perm == 0U ? 0U : a->st.out.sa;
                cmd->sb = a->perm == 1U ? 0U : a->st.out.sb;
                cmd->sc = a->perm == 2U ? 0U : a->st.out.sc;
                cmd->enable = 1U;
                return 0U;
            }
        }
        if (a->perm == 0U) {
            /* not reconfigured: the law's legs are the physical legs */
            cmd->sa = a->st.out.sa;
            cmd->sb = a->st.out.sb;
            cmd->sc = a->st.out.sc;
        } else {
            /* the law's legs (a', b', c') onto the physical legs: leg (perm + k) mod 3 = law leg k */
            const uint16_t s3[3] = {a->st.out.sa, a->st.out.sb, a->st.out.sc};
            cmd->sa = s3[app_fault_phase(3U - a->perm, 0U)];
            cmd->sb = s3[app_fault_phase(3U - a->perm, 1U)];
            cmd->sc = s3[app_fault_phase(3U - a->perm, 2U)];
        }
        cmd->enable = 1U;
        app_pwm_encode(law_out_form(&a->law), &a->st.out, a->t1pr, cmd);
        return 0U;

    case APP_STATE_IDENT: {
        /* self-commissioning: the hardware trip, the phase over-current and the DC link trip
         * as in RUN; the identification limits the current itself (app_ident.h) */
        int16_t detail = 0;
        uint16_t f;
        app_core_convert(a, m, &a->st.meas);
        if (check_hw_trip(a, m) != 0U) {
            app_ident_abort(&a->ident);
            return 1U;
        }
        f = app_fault_trips(&a->flt, a->cfg, &a->st.meas, a->perm, &detail);
        if (f != (uint16_t)APP_FAULT_NONE) {
            app_core_latch(a, f, detail);
            app_ident_abort(&a->ident);
            return 1U;
        }
        return app_ident_isr(&a->ident, a->cfg, &a->st.meas, a->t1pr, cmd);
    }

    case APP_STATE_INIT:
    case APP_STATE_FAULT:
    default:
        return 1U;
    }
}
