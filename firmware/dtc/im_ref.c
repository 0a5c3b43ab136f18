#include "im_ref.h"

void im_speed_reset(im_speed_t *s)
{
    s->theta_prev = 0U;
    s->primed = 0U;
    s->w_psi_iq = 0;
    s->te_filt_iq = 0;
    s->speed_iq = 0;
}

void im_speed_step(im_speed_t *s, const im_speed_params_t *p, angle_t theta_r, iq_t te_iq, iq_t inv_psir_sq_iq)
{
    /* The angle difference modulo one turn, as a signed number of LSB: exact through the wrap. */
    const int16_t d = (int16_t)(uint16_t)(theta_r - s->theta_prev);
    const iq_t w_raw = fix_sat32((int64_t)d * (int64_t)p->gain_w_iq);
    s->theta_prev = theta_r;
    if (s->primed == 0U) {
        s->primed = 1U;
        return;
    }
    s->w_psi_iq = im_speed_lpf(s->w_psi_iq, w_raw, p->k_filt_q31);
    s->te_filt_iq = im_speed_lpf(s->te_filt_iq, te_iq, p->k_filt_q31);
    /* Casadei eq. 16: w_r = w_psi - r_r T / phi_r^2. */
    s->speed_iq = fix_sub32(s->w_psi_iq, im_ref_slip(p->rr_iq, s->te_filt_iq, inv_psir_sq_iq));
}
