/*
 * im_ref.h - induction-machine references and sensorless speed (Casadei et al. 2006, sec. 10.1).
 *
 * Stator-flux reference for a rotor-flux command (Casadei eq. 19), in pu (dtc_base.h bases, so
 * (2/3)(T/p) in SI becomes psi_base I_base T_pu and sigma L_r / phi_r becomes sigma l_r / phi_r pu):
 *     phi_s* = (l_s/m) sqrt(phi_r*^2 + (sigma l_r T* / phi_r*)^2)
 * Slip from the torque (Casadei eq. 16, valid also in transients), in pu:
 *     w_slip = r_r T / phi_r^2
 * Sensorless speed: w_r = w_psi - w_slip, w_psi the angular speed of the rotor-flux vector (the
 * change of its angle, Casadei eq. 22, between two calls, times 1/T_call, first-order filtered; the IM law
 * calls it once per speed period, so |w| < pi / T_call, 25 pu at 10 x 40 us).
 * 1/phi_r* and 1/phi_r*^2 change only when the rotor-flux command does: the host (or the
 * background loop, through the shadow set) computes them, so nothing here divides.
 *
 * Formats: IQ pu; angle_t; filter gain Q31; gain_w_iq in pu of speed per angle_t LSB per call.
 * Scaling and overflow: rounded IQ products with saturation; the speed increment int16 * IQ gain is
 * formed in 64 bits and saturated; the filter update is one rounded Q31 product added with
 * saturation.
 */
#ifndef IM_REF_H
#define IM_REF_H

#include <stdint.h>

#include "fixmath.h"

/* Casadei eq. 19. ks = l_s/m, sigma_lr = sigma * l_r; the result saturates at 128 pu. */
static inline iq_t im_ref_stator_flux(iq_t ks_iq, iq_t sigma_lr_iq, iq_t psir_ref_iq, iq_t inv_psir_ref_iq,
                                      iq_t te_ref_iq)
{
    const iq_t q = iq_mpy(iq_mpy(sigma_lr_iq, te_ref_iq), inv_psir_ref_iq);
    return iq_mpy(ks_iq, iq_mag(psir_ref_iq, q));
}

/* Casadei eq. 16 solved for the slip. */
static inline iq_t im_ref_slip(iq_t rr_iq, iq_t te_iq, iq_t inv_psir_sq_iq)
{
    return iq_mpy(iq_mpy(rr_iq, te_iq), inv_psir_sq_iq);
}

typedef struct {
    iq_t gain_w_iq;     /* 2 pi / (65536 T_call w_base): pu speed of one angle_t LSB per call */
    q31_t k_filt_q31;   /* 1 - exp(-T_call / T_filter) */
    iq_t rr_iq;         /* rotor resistance, pu */
} im_speed_params_t;

typedef struct {
    angle_t theta_prev;
    uint16_t primed;    /* 0 until the first angle is seen */
    iq_t w_psi_iq;      /* filtered rotor-flux angular speed, pu */
    iq_t te_filt_iq;    /* torque through the same filter, pu */
    iq_t speed_iq;      /* estimated electrical rotor speed w_psi - w_slip, pu */
} im_speed_t;

/* x += k (u - x): the first-order filter of the sensorless speed (one rounded Q31 product,
 * saturated), also applied to the encoder's speed for the plausibility (im_dtc.h). */
static inline iq_t im_speed_lpf(iq_t x, iq_t u, q31_t k)
{
    return fix_add32(x, fix_rshift_rnd64_sat32((int64_t)fix_sub32(u, x) * (int64_t)k, 31U));
}

void im_speed_reset(im_speed_t *s);
/* One period: the rotor-flux angle (Casadei eq. 22), the estimated torque, and 1/phi_r*^2.
 * Inline: the speed-loop period pays for no call (the IM laws' worst step). */
static inline void im_speed_step(im_speed_t *s, const im_speed_params_t *p, angle_t theta_r, iq_t te_iq,
                                 iq_t inv_psir_sq_iq)
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

#endif /* IM_REF_H */
