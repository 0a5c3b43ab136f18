/*
 * app_hold.c - the rotor hold during the FSTP mid-point calibration (see app_hold.h).
 */
#include "app_hold.h"

#include "app_core.h"
#include "app_enc.h"
#include "law.h"

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
 * encoder check, within app_enc_t.jump_counts); v is Q16, saturated (|step| < 2^15); the predicted
 * deviation is Q16 in 64 bits, taken to Q8 before the product with i_hold (< 2^31: below 2^62),
 * which is saturated after the shift;
 * u and 2u saturate at +-2^31 (never reached: |u| <= i_hold < i_trip). The angle is the current
 * model's (law_enc_angle), its cosine's sign a comparison: no trigonometry. */
void app_hold_step(app_hold_t *h, const dtc_config_t *c, const dtc_meas_t *pu, const hal_meas_t *m,
                   hal_cmd_t *cmd)
{
    const iq_t ih = c->prot.i_hold_iq;
    const int32_t d = app_enc_fold((int32_t)m->qep_count - (int32_t)h->count0, c->board.enc_counts);
    const int32_t step = app_enc_fold((int32_t)m->qep_count - (int32_t)h->prev, c->board.enc_counts);
    const angle_t th = law_enc_angle(c, m->qep_count);
    int64_t d_q16;
    iq_t u;
    h->prev = m->qep_count;
    /* speed, counts per period in Q16, low-passed: v += (step - v) / 2^APP_HOLD_LEAD_LOG2 */
    h->v_q16 = fix_add32(h->v_q16, fix_rshift_rnd32(fix_sub32(fix_sat32((int64_t)step * 65536), h->v_q16),
                                                   APP_HOLD_LEAD_LOG2));
    /* deviation predicted 2^APP_HOLD_LEAD_LOG2 periods ahead, Q16 counts */
    d_q16 = (int64_t)d * 65536 + (int64_t)h->v_q16 * ((int64_t)1 << APP_HOLD_LEAD_LOG2);
    u = fix_sat32((-(d_q16 >> 8) * (int64_t)ih) >> (8U + APP_HOLD_ZONE_LOG2));
    if (u > ih) {
        u = ih;
    } else if (u < -ih) {
        u = -ih;
    }
    if ((uint16_t)(th + 0x4000U) >= 0x8000U) { /* cos(theta_e) < 0 */
        u = fix_neg32(u);
    }
    if (fix_sub32(pu->ib_iq, pu->ic_iq) < fix_add32(u, u)) {
        cmd->sb = 1U;
        cmd->sc = 0U;
    } else {
        cmd->sb = 0U;
        cmd->sc = 1U;
    }
    cmd->enable = 1U;
}

/* The rest test (APP_HOLD_REST_COUNTS): d1 = prev - count0, d2 = count - prev, folded into
 * (-enc_counts/2, enc_counts/2] (|d| < 2^15, so 3 d1 - d2 fits int32). The test is on raw counts,
 * the encoder's own resolution. */
uint16_t app_hold_cal(app_hold_t *h, const dtc_config_t *c, uint16_t count, uint16_t n)
{
    const uint16_t last = (uint16_t)((1U << APP_CAL_LOG2) - 1U);
    int32_t d1, d2;
    if (n == 1U) {
        h->count0 = count;
    } else if (n == (uint16_t)(1U << (APP_CAL_LOG2 - 1U))) {
        h->prev = count;
    }
    if (n != last || c->board.vmid_cal == 0U || c->prot.i_hold_iq <= 0) {
        return 0U;
    }
    d1 = app_enc_fold((int32_t)h->prev - (int32_t)h->count0, c->board.enc_counts);
    d2 = app_enc_fold((int32_t)count - (int32_t)h->prev, c->board.enc_counts);
    if (fix_abs32(3 * d1 - d2) > (int32_t)APP_HOLD_REST_COUNTS) {
        return 0U; /* turning: no hold, the drive starts into the rotor */
    }
    h->on = 1U;
    h->count0 = count;
    h->prev = count;
    h->v_q16 = 0;
    return 1U;
}
