/*
 * app_core.c - drive state machine and ISR body (see app_core.h).
 */
#include "app_core.h"

#include "dsvm.h"
#include "flux_est.h"
#include "svm.h"

#include <stddef.h>

/* Counts -> pu: (count - offset) * gain. Scaling and overflow: |count - offset| <= 4095 fits in
 * int32; the product with an IQ gain is formed in 64 bits and saturates at +-128 pu. */
static iq_t counts_to_pu(uint16_t count, uint16_t offset, iq_t gain_iq)
{
    int32_t d = (int32_t)count - (int32_t)offset;
#ifdef DTC_TEST_DEFECT_16BIT_INT
    /* Test-only defect, compiled only into the tests/pil images that prove the emulators catch
     * it (docs/pil.md): a 16 x 16-bit shortcut with the widening forgotten. A non-negative
     * deviation of the 12-bit ADC and a gain below 2^16 (the recorded boards' gains are 16-bit
     * numbers: PM rig 37245 for the currents, 5853 for V_dc) are multiplied as two uint16_t at
     * int width, (iq_t)(du * gu) instead of (iq_t)du * gu. Where int has 32 bits both promote
     * to int and the product (< 4096 * 2^16 = 2^28) is exact, the value below; where it has 16
     * bits (C28x, AVR) they promote to unsigned int and the product is taken modulo 2^16. */
    if (d >= 0 && d <= 4095 && gain_iq >= 0 && gain_iq <= 0xFFFF) {
        const uint16_t du = (uint16_t)d;
        const uint16_t gu = (uint16_t)gain_iq;
        return (iq_t)(du * gu);
    }
#endif
    return fix_sat32((int64_t)d * (int64_t)gain_iq);
}

/* (p + k) mod 3 for p, k in 0..2 without a division: APP_PH3[p + k] (the law's phase k is the
 * physical phase (perm + k) mod 3; the physical leg q carries the law's leg (q + 3 - perm) mod 3) */
static const uint16_t APP_PH3[6] = {0U, 1U, 2U, 0U, 1U, 2U};

/* Folds a counter difference into (-counts/2, counts/2] (counter runs 0 .. counts-1). */
static int32_t fold_counts(int32_t d, uint16_t counts)
{
    int32_t half = (int32_t)(counts >> 1);
    if (d > half) {
        d -= (int32_t)counts;
    } else if (d <= -half) {
        d += (int32_t)counts;
    }
    return d;
}

static void latch_fault(app_core_t *a, uint16_t fault, int16_t detail)
{
    if (a->st.state != APP_STATE_FAULT) {
        a->st.state = APP_STATE_FAULT;
        a->st.fault = fault;
        a->st.fault_detail = detail;
        a->st.fault_tick = a->st.tick;
    }
}

static void enter_calibrate(app_core_t *a)
{
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        a->cal_sum[k] = 0U;
    }
    a->cal_n = 0U;
    a->hold_on = 0U;
    a->hold_count0 = 0U;
    a->hold_prev = 0U;
    a->hold_extra = 0U;
    a->hold_v_q16 = 0;
    a->vmid_cal_sum_iq = 0;
    a->vmid_cal_iq = 0;
    a->enc_primed = 0U;
    a->index_known = 0U;
    a->isum_n = 0U;
    a->enc_still_n = 0U;
    for (k = 0U; k < 3U; k++) {
        a->leg_acc_iq[k] = 0;
    }
    a->st.out.speed_iq = 0; /* the encoder-freeze check reads the last reported speed */
    a->st.fault = APP_FAULT_NONE;
    a->st.fault_detail = 0;
    a->st.state = APP_STATE_CALIBRATE;
}

/* The largest count change in one control period that is still plausible: N with N * k <= 2 *
 * speed limit, k = pu speed of one count per control period (speed_k * speed_div), found by
 * bisection on products (no division), and never below 1: a single count step is quantisation
 * and cannot be told from a real speed however short the period or coarse the encoder.
 * Scaling: N < 2^15 counts, N * k formed in 64 bits. */
static uint16_t enc_jump_counts(const dtc_config_t *cfg)
{
    const int64_t k = (int64_t)cfg->speed.speed_k_iq * (int64_t)cfg->speed.speed_div;
    const int64_t jump = 2 * (int64_t)cfg->speed.speed_limit_iq;
    uint32_t lo = 0U, hi = (uint32_t)cfg->board.enc_counts / 2U + 1U; /* lo fits, hi does not (or is max) */
    while (hi - lo > 1U) {
        const uint32_t mid = (lo + hi) / 2U;
        if ((int64_t)mid * k <= jump) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return (uint16_t)(lo < 1U ? 1U : lo);
}

int16_t app_core_init(app_core_t *a, const dtc_config_t *cfg)
{
    int16_t rc;
    uint16_t k;

    a->cfg = NULL;
    a->post = NULL;
    a->perm = 0U;
    a->relay_wait = 0U;
    a->clear_request = 0U;
    a->t1pr = 0U;
    a->st.out.pwm = 0U; /* the DTC laws never write it (dtc_out_t) */
    a->st.tick = 0U;
    a->st.fault_tick = 0U;
    a->st.state = APP_STATE_INIT;
    a->st.fault = APP_FAULT_NONE;
    a->st.fault_detail = 0;
    a->st.reconfigured = 0U;
    rc = law_init(&a->law, cfg);
    if (rc != DTC_OK) {
        latch_fault(a, APP_FAULT_CONFIG, rc);
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
    a->enc_jump_counts = enc_jump_counts(cfg);
    a->stall_n = 0U;
    a->stall_err0_iq = 0;
    enter_calibrate(a);
    return 0;
}

void app_core_convert(const app_core_t *a, const hal_meas_t *m, dtc_meas_t *pu)
{
    const dtc_config_t *c = a->cfg;
    iq_t i[3];
    uint16_t k;

    for (k = 0U; k < 3U; k++) {
        /* the law's phase k is the physical phase (perm + k) mod 3 (reconfigure) */
        const uint16_t ch = APP_PH3[a->perm + k];
        i[k] = counts_to_pu(m->adc[ch], a->offset[ch], c->board.adc_i_gain_iq);
    }
    /* The unmeasured phase from Kirchhoff's current law (isolated star point). */
    if (c->board.i_sensors3 != 0U) {
        /* all three measured: each as it is (their sum is checked, check_trips) */
    } else if (c->board.topology == (uint16_t)DTC_TOPO_FSTP) {
        i[0] = fix_neg32(fix_add32(i[1], i[2]));
    } else {
        i[2] = fix_neg32(fix_add32(i[0], i[1]));
    }
    pu->ia_iq = i[0];
    pu->ib_iq = i[1];
    pu->ic_iq = i[2];
    pu->vdc_iq = counts_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    pu->vmid_iq = fix_sub32(counts_to_pu(m->adc[HAL_ADC_VMID], c->board.adc_vmid_offset,
                                         c->board.adc_vmid_gain_iq),
                            a->vmid_cal_iq);
    pu->enc_count = m->qep_count;
}

/* The hardware protection input (PDPINTA) and the gate drivers' desaturation outputs that pull
 * it: a desaturation is named with its leg (the lowest one flagged), any other trip as the
 * hardware trip. Latches and returns 1 on a trip. */
static uint16_t check_hw_trip(app_core_t *a, const hal_meas_t *m)
{
    uint16_t x;
    for (x = 0U; x < 3U; x++) {
        if ((m->desat & (uint16_t)(1U << x)) != 0U) {
            latch_fault(a, APP_FAULT_DESAT, (int16_t)x);
            return 1U;
        }
    }
    if (m->trip != 0U) {
        latch_fault(a, APP_FAULT_HW_TRIP, 0);
        return 1U;
    }
    return 0U;
}

/* Trip checks on one per-unit sample; latches and returns 1 on a trip. */
static uint16_t check_trips(app_core_t *a, const hal_meas_t *m, const dtc_meas_t *pu)
{
    const dtc_config_t *c = a->cfg;
    const iq_t i[3] = {pu->ia_iq, pu->ib_iq, pu->ic_iq};
    uint16_t k;

    if (check_hw_trip(a, m) != 0U) {
        return 1U;
    }
    for (k = 0U; k < 3U; k++) {
        if (fix_abs32(i[k]) > c->prot.i_trip_iq) {
            latch_fault(a, APP_FAULT_OVERCURRENT, (int16_t)APP_PH3[a->perm + k]);
            return 1U;
        }
    }
    /* Failed current sensor (three sensors, prot.i_sum_max_iq): the star point is isolated, so
     * the three phase currents sum to zero; a sum above the level for APP_ISUM_PERIODS periods
     * is a sensor that does not measure its current (stuck, lost, wrong gain). The sum alone does
     * not say which: the detail is the phase reading the least |i|, the signature of a sensor
     * stuck at its zero (mid-scale), the common case. Sums saturate. */
    if (c->prot.i_sum_max_iq > 0) {
        if (fix_abs32(fix_add32(fix_add32(i[0], i[1]), i[2])) > c->prot.i_sum_max_iq) {
            if (++a->isum_n >= APP_ISUM_PERIODS) {
                uint16_t lo = 0U;
                for (k = 1U; k < 3U; k++) {
                    if (fix_abs32(i[k]) < fix_abs32(i[lo])) {
                        lo = k;
                    }
                }
                latch_fault(a, APP_FAULT_CURRENT_SENSOR, (int16_t)APP_PH3[a->perm + lo]);
                return 1U;
            }
        } else {
            a->isum_n = 0U;
        }
    }
    if (pu->vdc_iq > c->prot.vdc_max_iq) {
        latch_fault(a, APP_FAULT_DC_OVERVOLTAGE, 0);
        return 1U;
    }
    if (pu->vdc_iq < c->prot.vdc_min_iq) {
        latch_fault(a, APP_FAULT_DC_UNDERVOLTAGE, 0);
        return 1U;
    }
    return 0U;
}

/* Encoder plausibility (the current-model estimator and the speed loop rely on it):
 *  1. the count change of one period must stay within enc_jump_counts (twice the speed limit,
 *     at least one count);
 *  2. the counter value latched by each index pulse (hal_meas_t.qep_index_count, the capture unit)
 *     must equal the one latched by the first pulse within APP_INDEX_TOL_COUNTS: lost or extra
 *     counts show up as that difference, at whatever speed;
 *  3. a lost signal (cable, supply: the counter stops) is a count that does not move for
 *     APP_ENC_FREEZE_PERIODS while the last measured speed is above prot.enc_freeze_speed_iq,
 *     which the host sets where the rotor turns several counts in that time even at the drive's
 *     largest deceleration: physically impossible, so the signal is gone (detail 3).
 * Scaling and overflow: |delta| <= counts/2 (<= 32768), compared as integers. */
static uint16_t check_encoder(app_core_t *a, const hal_meas_t *m)
{
    const uint16_t counts = a->cfg->board.enc_counts;
    int32_t d;

    if (a->enc_primed == 0U) {
        a->enc_last = m->qep_count;
        a->enc_primed = 1U;
        d = 0;
    } else {
        d = fold_counts((int32_t)m->qep_count - (int32_t)a->enc_last, counts);
        a->enc_last = m->qep_count;
        if (fix_abs32(d) > (int32_t)a->enc_jump_counts) {
            latch_fault(a, APP_FAULT_ENCODER, 1);
            return 1U;
        }
        if (d != 0) {
            a->enc_still_n = 0U;
        } else if (a->enc_still_n < 0xFFFFU) {
            a->enc_still_n++;
        }
        if (a->cfg->prot.enc_freeze_speed_iq > 0 && a->enc_still_n >= APP_ENC_FREEZE_PERIODS &&
            fix_abs32(a->st.out.speed_iq) > a->cfg->prot.enc_freeze_speed_iq) {
            latch_fault(a, APP_FAULT_ENCODER, 3);
            return 1U;
        }
    }
    if (m->qep_count >= counts) {
        latch_fault(a, APP_FAULT_ENCODER, 1);
        return 1U;
    }
    if (m->qep_index_seen != 0U) {
        if (a->index_known == 0U) {
            a->index_ref = m->qep_index_count;
            a->index_known = 1U;
        } else {
            int32_t e = fold_counts((int32_t)m->qep_index_count - (int32_t)a->index_ref, counts);
            if (fix_abs32(e) > (int32_t)APP_INDEX_TOL_COUNTS) {
                latch_fault(a, APP_FAULT_ENCODER, 2);
                return 1U;
            }
        }
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
 * offset E / w_c (~ psi_m at 5 rad/s) (docs/firmware-core.md, issue 10).
 * Scaling: the deviation is IQ pu (saturated), 2^APP_VMID_CAL_LOG2 of them sum in 64 bits without
 * overflow; the mean is a rounded arithmetic shift (no division), saturated to 32 bits. */
static void app_vmid_cal_add(app_core_t *a, const hal_meas_t *m)
{
    const dtc_config_t *c = a->cfg;
    iq_t vdc = counts_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    iq_t vmid = counts_to_pu(m->adc[HAL_ADC_VMID], c->board.adc_vmid_offset, c->board.adc_vmid_gain_iq);
    a->vmid_cal_sum_iq += (int64_t)fix_sub32(vmid, fix_rshift_rnd32(vdc, 1U));
}

/* Ends the mid-point calibration: the mean, checked against V_dc / 2^APP_VMID_TOL_LOG2 (4.4 V at
 * 70 V: a sensor that far off is broken, not inaccurate). Returns 1 on a fault (latched). */
static uint16_t app_vmid_cal_set(app_core_t *a, const hal_meas_t *m)
{
    const dtc_config_t *c = a->cfg;
    iq_t vdc = counts_to_pu(m->adc[HAL_ADC_VDC], c->board.adc_vdc_offset, c->board.adc_vdc_gain_iq);
    iq_t mean = fix_sat32((a->vmid_cal_sum_iq + ((int64_t)1 << (APP_VMID_CAL_LOG2 - 1U))) >>
                          APP_VMID_CAL_LOG2);
    if (fix_abs32(mean) > fix_rshift_rnd32(fix_abs32(vdc), APP_VMID_TOL_LOG2)) {
        latch_fault(a, APP_FAULT_ADC_OFFSET, (int16_t)HAL_ADC_VMID);
        return 1U;
    }
    a->vmid_cal_iq = mean;
    return 0U;
}

/* End of the calibration: the mid-point and the DC link checked, the law reset, RUN. */
static void calibrate_finish(app_core_t *a, const hal_meas_t *m)
{
    a->hold_on = 0U;
    if (a->cfg->board.vmid_cal != 0U && app_vmid_cal_set(a, m) != 0U) {
        return;
    }
    {
        dtc_meas_t pu;
        app_core_convert(a, m, &pu);
        if (pu.vdc_iq < a->cfg->prot.vdc_min_iq) {
            latch_fault(a, APP_FAULT_DC_UNDERVOLTAGE, 0);
            return;
        }
        if (pu.vdc_iq > a->cfg->prot.vdc_max_iq) {
            latch_fault(a, APP_FAULT_DC_OVERVOLTAGE, 0);
            return;
        }
    }
    law_reset(&a->law);
    a->st.state = APP_STATE_RUN;
}

/* 1 when the calibration may end as far as the hold is concerned: no hold, or the rotor has
 * settled (speed at most one count per 2^APP_HOLD_LEAD_LOG2 periods, app_core.h). */
static uint16_t hold_settled(const app_core_t *a)
{
    return (uint16_t)(a->hold_on == 0U ||
                      fix_abs32(a->hold_v_q16) <= ((int32_t)1 << (16U - APP_HOLD_LEAD_LOG2)));
}

/* Calibration period: accumulate the measured channels; after 2^APP_CAL_LOG2 samples set the
 * current offsets (rounded mean, a shift: no division) and check them; with the mid-point
 * calibration and a hold current, start the rotor hold then (hold_step); at the end of the
 * calibration check the mid-point and the DC link and enter RUN. */
static void calibrate_step(app_core_t *a, const hal_meas_t *m)
{
    uint16_t k;
    const uint16_t n_off = (uint16_t)(1U << APP_CAL_LOG2);
    const uint16_t n_cal = (uint16_t)(1U << (a->cfg->board.vmid_cal != 0U ? APP_VMID_CAL_LOG2 : APP_CAL_LOG2));
    const uint16_t n_ch = a->cfg->board.i_sensors3 != 0U ? 3U : 2U; /* channels with a sensor */
    if (a->cal_n >= n_cal) {
        /* calibration done, the hold waits for the rotor to settle */
        if (hold_settled(a) == 0U && ++a->hold_extra < ((uint16_t)1U << APP_VMID_CAL_LOG2)) {
            return;
        }
        calibrate_finish(a, m);
        return;
    }
    if (a->cal_n < n_off) {
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
                latch_fault(a, APP_FAULT_ADC_OFFSET, (int16_t)ch);
                return;
            }
            a->offset[ch] = (uint16_t)mean;
        }
        if (a->cfg->board.vmid_cal != 0U && a->cfg->prot.i_hold_iq > 0 && n_cal > n_off) {
            a->hold_on = 1U;
            a->hold_count0 = m->qep_count;
            a->hold_prev = m->qep_count;
            a->hold_v_q16 = 0;
            a->enc_primed = 0U;
        }
    }
    if (a->cal_n < n_cal || hold_settled(a) == 0U) {
        return; /* calibrating, or the rotor still moving: hold on (above) */
    }
    calibrate_finish(a, m);
}

/* Rotor hold while the FSTP mid-point is calibrated (prot.i_hold_iq > 0). With the gates off an
 * active load (a hoist, a constant torque) turns the rotor backwards for the whole calibration
 * (0.3 N*m on 5e-4 kg m^2: -287 rpm after 51 ms), and the reversal that follows can pass more
 * charge through phase A, on the mid-point, than the split link holds (docs/firmware-core.md).
 * The hold keeps the rotor where the calibration found it with a current in phases B and C
 * only, so the mid-point carries none and stays where the balancing resistors hold it, which is
 * what the calibration measures:
 *  - legs (S_B, S_C) = (1, 0) or (0, 1) only: v_alpha = 0, v_beta = +-V_dc/sqrt(3) (Hoang Table I,
 *    vrec.h), so the phase-A voltage is zero and with the rotor at rest (no back-EMF) i_a stays 0;
 *    the device drops of the two conducting legs are equal and opposite for i_b = -i_c, so they
 *    add no common-mode voltage either;
 *  - torque T = 3/2 p psi_m (i_beta cos theta_e - i_alpha sin theta_e) (Hoang eq. 10 with the
 *    flux of eqs. 8-9) = 3/2 p psi_m i_beta cos theta_e, i_beta = (i_b - i_c)/sqrt(3);
 *  - position loop: u = -(d + 2^L v) i_hold / 2^APP_HOLD_ZONE_LOG2 for a deviation of d counts and
 *    the low-passed speed v (counts per period; L = APP_HOLD_LEAD_LOG2, the damping), saturated at
 *    +-i_hold, times the sign of cos theta_e (so T has the sign of u); where |cos theta_e| is too
 *    small for the load the rotor turns until it is large enough (at most the angle where
 *    i_hold |cos theta_e| carries it);
 *  - current: a two-level comparator on i_b - i_c against 2u (= i_b - i_c when i_b = u = -i_c):
 *    below it (1, 0), which raises it at V_dc/L_s, else (0, 1). The ripple is one period's rise,
 *    which the host's bound i_hold <= current limit keeps below the trip.
 * Scaling: d and the per-period step are within +-enc_counts/2 (int32; the step, after the
 * encoder check, within enc_jump_counts); v is Q16, saturated (|step| < 2^15); the predicted
 * deviation is Q16 in 64 bits, taken to Q8 before the product with i_hold (< 2^31: below 2^62),
 * which is saturated after the shift;
 * u and 2u saturate at +-2^31 (never reached: |u| <= i_hold < i_trip). The angle is the current
 * model's (flux_est_angle), its cosine's sign a comparison: no trigonometry. */
static void hold_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd)
{
    const dtc_config_t *c = a->cfg;
    const iq_t ih = c->prot.i_hold_iq;
    const int32_t d = fold_counts((int32_t)m->qep_count - (int32_t)a->hold_count0, c->board.enc_counts);
    const int32_t step = fold_counts((int32_t)m->qep_count - (int32_t)a->hold_prev, c->board.enc_counts);
    const angle_t th = flux_est_angle(m->qep_count, c->board.enc_gain_q16, c->board.enc_offset);
    int64_t d_q16;
    iq_t u;
    a->hold_prev = m->qep_count;
    /* speed, counts per period in Q16, low-passed: v += (step - v) / 2^APP_HOLD_LEAD_LOG2 */
    a->hold_v_q16 = fix_add32(a->hold_v_q16, fix_rshift_rnd32(fix_sub32(fix_sat32((int64_t)step * 65536),
                                                                         a->hold_v_q16),
                                                               APP_HOLD_LEAD_LOG2));
    /* deviation predicted 2^APP_HOLD_LEAD_LOG2 periods ahead, Q16 counts */
    d_q16 = (int64_t)d * 65536 + (int64_t)a->hold_v_q16 * ((int64_t)1 << APP_HOLD_LEAD_LOG2);
    u = fix_sat32((-(d_q16 >> 8) * (int64_t)ih) >> (8U + APP_HOLD_ZONE_LOG2));
    if (u > ih) {
        u = ih;
    } else if (u < -ih) {
        u = -ih;
    }
    if ((uint16_t)(th + 0x4000U) >= 0x8000U) { /* cos(theta_e) < 0 */
        u = fix_neg32(u);
    }
    if (fix_sub32(a->st.meas.ib_iq, a->st.meas.ic_iq) < fix_add32(u, u)) {
        cmd->sb = 1U;
        cmd->sc = 0U;
    } else {
        cmd->sb = 0U;
        cmd->sc = 1U;
    }
    cmd->enable = 1U;
}

/* Reconfiguration after leg x failed (app_core_set_reconfig, dtc.h dtc_reconfigure): the law
 * goes on as the FSTP with phase A' = x; from now on the currents come in and the legs go out
 * through the permutation perm = x; the relay command ties phase x to the mid-point (hal_cmd_t
 * relay; the HAL keeps leg x off while it is set) and the open-phase check waits until it has
 * closed. Returns 1 when the law refused (the core then trips). */
static uint16_t reconfigure(app_core_t *a, uint16_t x)
{
    uint16_t k;
    if (law_reconfigure(&a->law, a->post, x) != DTC_OK) {
        latch_fault(a, APP_FAULT_LEG, (int16_t)x);
        return 1U;
    }
    a->cfg = a->post;
    a->perm = x;
    a->st.reconfigured = (uint16_t)(x + 1U);
    a->meas_ch[0] = APP_PH3[x + 1U];
    a->meas_ch[1] = APP_PH3[x + 2U];
    a->relay_wait = a->post->prot.relay_periods;
    a->stall_n = 0U;
    for (k = 0U; k < 3U; k++) {
        a->leg_acc_iq[k] = 0;
    }
    return 0U;
}

/* Open phase (prot.leg_i_min_iq > 0): a leg that no longer switches its phase (leg or phase open)
 * leaves that phase's current at zero, and one open device leaves it at zero for every half-wave
 * the device should carry, while the other two phases carry the machine's current. Per phase k:
 * while |i_k| stays inside the zero band leg_i_min / 2^APP_LEG_ZERO_LOG2, the electrical angle
 * w Ts the machine turns is summed over the periods with |i| > leg_i_min (|i| the Clarke
 * magnitude, |i|^2 = (2/3) sum i_k^2 for an isolated star; below it the sum waits: the current
 * of the two remaining phases of an open one passes zero twice a turn), and a sum above
 * APP_LEG_ANGLE_IQ (60 deg) is an open phase (detection time pi / (3 w): 6.7 ms at 25 Hz, more
 * where the current dips). A healthy phase crosses the band: its
 * switching ripple alone moves it by several times the band every period or two (Table VIII,
 * 70 V: 0.1-0.5 A per period against 0.14 A), and even a phase current with a large DC part
 * (the uncompensated FSTP just after its hand-over: i_a ~ 4.5 A DC, phase B within |i|/4 for
 * 135 deg, SIL) keeps that ripple. A relative criterion (|i_k| < |i|/4) tripped there; the band
 * does not. A sum of the three measured currents of |i|/4 or more is a sensor, not a leg
 * (check_trips names it once it lasts), and stops the sums. Found: reconfigure when a post-fault
 * configuration is set and the drive is not yet reconfigured, else trip (APP_FAULT_LEG). At
 * standstill no angle accumulates: a phase open at rest is found once the machine turns.
 * Scaling and overflow: currents are bounded by the trip level (check_trips ran), at most 128 pu
 * (2^31 IQ); squares are formed in 64 bits and shifted right by 5 (<= 2^57), so 24 x^2 and the
 * sum of three stay below 2^63; 3 i_min^2 likewise; the angle sum saturates. */
static uint16_t check_open_phase(app_core_t *a)
{
    const dtc_config_t *c = a->cfg;
    const iq_t i[3] = {a->st.meas.ia_iq, a->st.meas.ib_iq, a->st.meas.ic_iq};
    const iq_t s = fix_add32(fix_add32(i[0], i[1]), i[2]);
    const iq_t zero = fix_rshift_rnd32(c->prot.leg_i_min_iq, APP_LEG_ZERO_LOG2);
    uint64_t sq[3], tot, s2, imin2;
    iq_t dth;
    uint16_t k;

    if (c->prot.leg_i_min_iq <= 0) {
        return 0U;
    }
    for (k = 0U; k < 3U; k++) {
        sq[k] = (uint64_t)((int64_t)i[k] * (int64_t)i[k]) >> 5;
    }
    tot = sq[0] + sq[1] + sq[2];
    s2 = (uint64_t)((int64_t)s * (int64_t)s) >> 5;
    imin2 = (uint64_t)((int64_t)c->prot.leg_i_min_iq * (int64_t)c->prot.leg_i_min_iq) >> 5;
    if (a->relay_wait > 0U || 24U * s2 >= tot) {
        if (a->relay_wait > 0U) {
            a->relay_wait--;
        }
        for (k = 0U; k < 3U; k++) {
            a->leg_acc_iq[k] = 0;
        }
        return 0U;
    }
    if (2U * tot <= 3U * imin2) {
        return 0U; /* too little current to judge: the sums wait (a healthy phase leaves the band,
                    * which resets its sum, as soon as there is current again) */
    }
    dth = iq_mpy(fix_abs32(a->st.out.speed_iq), c->board.ts_pu_iq);
    for (k = 0U; k < 3U; k++) {
        if (fix_abs32(i[k]) >= zero) {
            a->leg_acc_iq[k] = 0;
            continue;
        }
        a->leg_acc_iq[k] = fix_add32(a->leg_acc_iq[k], dth);
        if (a->leg_acc_iq[k] > APP_LEG_ANGLE_IQ) {
            const uint16_t x = APP_PH3[a->perm + k];
            if (a->post != NULL && a->st.reconfigured == 0U) { /* post is a PM leg-form law (set_reconfig) */
                return reconfigure(a, x);
            }
            latch_fault(a, APP_FAULT_LEG, (int16_t)x);
            return 1U;
        }
    }
    return 0U;
}

int16_t app_core_set_reconfig(app_core_t *a, const dtc_config_t *post)
{
    const dtc_config_t *c = a->cfg;
    uint16_t k, same_adc = 1U;
    if (post == NULL) {
        a->post = NULL;
        return 0;
    }
    if (c != NULL) {
        for (k = 0U; k < 3U; k++) {
            if (post->board.adc_i_offset[k] != c->board.adc_i_offset[k]) {
                same_adc = 0U;
            }
        }
    }
    if (c == NULL || a->st.reconfigured != 0U || dtc_config_validate(post) != DTC_OK ||
        c->law != (uint16_t)DTC_LAW_PM_DTC || post->law != (uint16_t)DTC_LAW_PM_DTC ||
        c->board.topology != (uint16_t)DTC_TOPO_SSTP || post->board.topology != (uint16_t)DTC_TOPO_FSTP ||
        c->board.i_sensors3 == 0U || post->board.i_sensors3 == 0U || c->prot.leg_i_min_iq <= 0 ||
        post->board.vmid_cal != 0U || post->prot.relay_periods == 0U ||
        post->est.estimator != c->est.estimator || same_adc == 0U ||
        post->board.enc_counts != c->board.enc_counts || post->board.enc_gain_q16 != c->board.enc_gain_q16 ||
        post->board.enc_offset != c->board.enc_offset || post->board.adc_i_gain_iq != c->board.adc_i_gain_iq ||
        post->board.adc_vdc_gain_iq != c->board.adc_vdc_gain_iq ||
        post->board.adc_vdc_offset != c->board.adc_vdc_offset || post->board.ts_pu_iq != c->board.ts_pu_iq ||
        post->speed.speed_div != c->speed.speed_div) {
        a->post = NULL;
        latch_fault(a, APP_FAULT_CONFIG, DTC_ERR_RECONFIG);
        return DTC_ERR_RECONFIG;
    }
    a->post = post;
    return 0;
}

/* Stall (speed mode): on each speed-loop period, with the torque reference at its limit, a window
 * of cfg->prot.stall_speed_periods is open; it trips when at its end the speed error has not shrunk
 * since its start. Any period below the limit closes the window. Torque mode has no speed error
 * to watch and is left alone. Scaling: |speed_ref - speed| saturated difference; compared. */
static uint16_t check_stall(app_core_t *a)
{
    const dtc_out_t *o = &a->st.out;
    iq_t err;
    if (a->cfg->speed.mode != (uint16_t)DTC_MODE_SPEED || o->speed_tick == 0U) {
        return 0U;
    }
    if (fix_abs32(o->te_ref_iq) < a->cfg->speed.torque_limit_iq) {
        a->stall_n = 0U;
        return 0U;
    }
    err = fix_abs32(fix_sub32(law_speed_ref(&a->law), o->speed_iq));
    if (a->stall_n == 0U) {
        a->stall_err0_iq = err;
    }
    if (++a->stall_n < a->cfg->prot.stall_speed_periods) {
        return 0U;
    }
    a->stall_n = 0U;
    if (err >= a->stall_err0_iq) {
        latch_fault(a, APP_FAULT_STALL, (int16_t)(o->te_ref_iq < 0 ? -1 : 1));
        return 1U;
    }
    return 0U;
}

int16_t app_core_set_pwm_period(app_core_t *a, uint16_t t1pr)
{
    a->t1pr = t1pr;
    if (a->cfg != NULL && a->cfg->law == (uint16_t)DTC_LAW_IM_DTC &&
        (a->cfg->sw.scheme == (uint16_t)DTC_SCHEME_SFVC || a->cfg->sw.scheme == (uint16_t)DTC_SCHEME_DFOC ||
         a->cfg->sw.scheme == (uint16_t)DTC_SCHEME_DSVM) && (t1pr == 0U || t1pr == 0xFFFFU)) {
        latch_fault(a, APP_FAULT_CONFIG, DTC_ERR_SVM);
        /* also over a fault latched before: a clear request ends that one, this one it must not */
        a->st.fault = APP_FAULT_CONFIG;
        a->st.fault_detail = DTC_ERR_SVM;
        return DTC_ERR_SVM;
    }
    return 0;
}

uint16_t app_core_step(app_core_t *a, const hal_meas_t *m, hal_cmd_t *cmd)
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
            enter_calibrate(a);
        }
    }

    switch (a->st.state) {
    case APP_STATE_CALIBRATE:
        /* Hardware trip still counts while calibrating. */
        if (check_hw_trip(a, m) != 0U) {
            return 1U;
        }
        if (a->hold_on != 0U) {
            /* rotor hold (hold_step): the offsets are set, the protection runs as in RUN */
            app_core_convert(a, m, &a->st.meas);
            if (check_trips(a, m, &a->st.meas) != 0U || check_encoder(a, m) != 0U) {
                a->hold_on = 0U;
                return 1U;
            }
            hold_step(a, m, cmd);
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

    case APP_STATE_RUN:
        app_core_convert(a, m, &a->st.meas);
        if (check_trips(a, m, &a->st.meas) != 0U || check_encoder(a, m) != 0U) {
            return 1U;
        }
        law_step(&a->law, &a->st.meas, &a->st.out);
        {
            const uint16_t before = a->st.reconfigured;
            if (check_open_phase(a) != 0U || check_stall(a) != 0U) {
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
        {
            /* the law's legs (a', b', c') onto the physical legs: leg (perm + k) mod 3 = law leg k */
            const uint16_t s3[3] = {a->st.out.sa, a->st.out.sb, a->st.out.sc};
            cmd->sa = s3[APP_PH3[3U - a->perm]];
            cmd->sb = s3[APP_PH3[4U - a->perm]];
            cmd->sc = s3[APP_PH3[5U - a->perm]];
        }
        cmd->enable = 1U;
        if (a->st.out.pwm == 2U) {
            /* DSVM: one pulse per leg holding the three sub-interval states (dsvm.h, hal.h) */
            const uint16_t c23 = dsvm_c23(a->t1pr);
            uint16_t x;
            cmd->form = (uint16_t)HAL_CMD_PWM;
            for (x = 0U; x < 3U; x++) {
                dsvm_pwm(a->st.out.thirds[x], a->t1pr, c23, &cmd->cmpr_up[x], &cmd->cmpr_dn[x], &cmd->act[x]);
            }
        } else if (a->st.out.pwm != 0U) {
            /* one centred pulse per leg (hal.h): compare values of the law's duties */
            uint16_t x;
            cmd->form = (uint16_t)HAL_CMD_PWM;
            for (x = 0U; x < 3U; x++) {
                const uint16_t c = svm_cmpr(a->st.out.duty_iq[x], a->t1pr);
                cmd->cmpr_up[x] = c;
                cmd->cmpr_dn[x] = c;
                cmd->act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
            }
        }
        return 0U;

    case APP_STATE_INIT:
    case APP_STATE_FAULT:
    default:
        return 1U;
    }
}

const char *app_fault_name(uint16_t fault)
{
    switch (fault) {
    case APP_FAULT_NONE: return "none";
    case APP_FAULT_CONFIG: return "config";
    case APP_FAULT_OVERCURRENT: return "overcurrent";
    case APP_FAULT_DC_OVERVOLTAGE: return "dc_overvoltage";
    case APP_FAULT_DC_UNDERVOLTAGE: return "dc_undervoltage";
    case APP_FAULT_ENCODER: return "encoder";
    case APP_FAULT_HW_TRIP: return "hw_trip";
    case APP_FAULT_ADC_OFFSET: return "adc_offset";
    case APP_FAULT_STALL: return "stall";
    case APP_FAULT_DESAT: return "desat";
    case APP_FAULT_CURRENT_SENSOR: return "current_sensor";
    case APP_FAULT_LEG: return "leg";
    default: return "unknown";
    }
}
