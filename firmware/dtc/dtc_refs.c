#include "dtc_refs.h"

#include "dtc_config.h"

int16_t dtc_refs_check(const dtc_refs_t *r)
{
    if (r->mode > DTC_MODE_TORQUE) {
        return DTC_ERR_VARIANT;
    }
    if (r->kp_iq < 0 || r->ki_ts_iq < 0) {
        return DTC_ERR_PI;
    }
    if (r->flux_ref_iq <= 0) {
        return DTC_ERR_REFERENCE;
    }
    return DTC_OK;
}

int16_t dtc_shadow_publish(dtc_shadow_t *s, const dtc_refs_t *r)
{
    int16_t err = dtc_refs_check(r);
    uint16_t seq;

    if (err != DTC_OK) {
        return err;
    }
    seq = s->seq;
    s->seq = (uint16_t)((seq | 1U) == seq ? seq + 2U : seq + 1U); /* odd: writing */
    s->speed_ref_iq = r->speed_ref_iq;
    s->torque_ref_iq = r->torque_ref_iq;
    s->flux_ref_iq = r->flux_ref_iq;
    s->kp_iq = r->kp_iq;
    s->ki_ts_iq = r->ki_ts_iq;
    s->mode = r->mode;
    s->seq = (uint16_t)(s->seq + 1U); /* even: complete */
    return DTC_OK;
}

iq_t dtc_trim_step(iq_t *trim_iq, iq_t ref_iq, iq_t te_iq, q15_t k_q15, iq_t limit_iq)
{
    const iq_t lim = fix_rshift_rnd32(limit_iq, 2U);
    const iq_t d = iq_mpy_q15(iq_sub(ref_iq, te_iq), k_q15);
    *trim_iq = iq_sat(iq_add(*trim_iq, d), fix_neg32(lim), lim);
    return iq_sat(iq_add(ref_iq, *trim_iq), fix_neg32(limit_iq), limit_iq);
}

void dtc_shadow_take(dtc_shadow_t *s, uint16_t seq, dtc_refs_t *r)
{
    r->speed_ref_iq = s->speed_ref_iq;
    r->torque_ref_iq = s->torque_ref_iq;
    r->flux_ref_iq = s->flux_ref_iq;
    r->kp_iq = s->kp_iq;
    r->ki_ts_iq = s->ki_ts_iq;
    r->mode = s->mode;
    s->adopted = seq;
}

void dtc_speed_params_from_config(speed_meas_params_t *sm_p, speed_pi_params_t *pi_p,
                                  const dtc_config_t *cfg)
{
    sm_p->enc_counts = cfg->board.enc_counts;
    sm_p->k_speed_iq = cfg->speed.speed_k_iq;
    sm_p->min_counts = cfg->speed.speed_min_counts;
    pi_p->kp_iq = cfg->speed.kp_iq;
    pi_p->ki_ts_iq = cfg->speed.ki_ts_iq;
    pi_p->limit_iq = cfg->speed.torque_limit_iq;
}
