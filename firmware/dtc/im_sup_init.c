/* im_sup_init.c - the IM model supervision's parameters (im_sup.h), derived from the configuration
 * once at init (init-only code: flash on the F2812, archive dtc_init). No division: the one
 * reciprocal by the SVM's Newton steps (svm.h svm_recip), the count by summing. */
#include "im_dtc_internal.h"

void im_sup_init(im_dtc_t *c, const dtc_config_t *cfg)
{
    im_sup_t *s = &c->sup;
    const iq_t k_filt = iq_from_q31(cfg->u.im.ref.speed_filt_q31); /* T_sp / T_filt, IQ */
    /* Casadei eq. 16's slip at the torque limit and the configured rotor flux, times 4 (im_sup.h),
     * floored at 2^-7 pu where the reciprocal is exact */
    iq_t slip4 = fix_sat32((int64_t)4 * im_ref_slip(cfg->u.im.machine.rr_iq, cfg->speed.torque_limit_iq,
                                                    cfg->u.im.ref.inv_psir_sq_iq));
    const iq_t i_lim = cfg->prot.i_lim_iq > 0 ? cfg->prot.i_lim_iq : cfg->prot.i_trip_iq;
    iq_t sum = 0;
    uint16_t n = 0U;

    if (slip4 < IQ(1.0 / 128.0)) {
        slip4 = IQ(1.0 / 128.0);
    }
    s->rr_cfg_iq = cfg->u.im.machine.rr_iq;
    s->rs_cfg_iq = cfg->machine.rs_iq;
    s->kslip_cfg_iq = c->sfvc_kslip_iq;
    s->k_rho_iq = iq_mpy(k_filt, svm_recip(0, slip4));
    /* T_sp / tau_r = speed_div (Ts / tau_r), saturated (Q31 < 1) */
    s->k_cm_q31 = fix_sat32((int64_t)cfg->u.im.ref.magn_k_q31 * (int64_t)cfg->speed.speed_div);
    /* the speed at which the drop r_s I_lim equals the back-EMF w phi_s* (pu: e = w psi) */
    s->w_min_iq = iq_mpy(iq_mpy(cfg->machine.rs_iq, i_lim), svm_recip(0, cfg->speed.flux_ref_iq));
    s->te_min_iq = fix_rshift_rnd32(cfg->speed.torque_limit_iq, 5U);
    /* n_confirm: speed periods in 4 T_filt, the count of k_filt's that sum to 4 (at most 65535) */
    while (sum < IQ(4.0) && n < 65535U && k_filt > 0) {
        sum = iq_add(sum, k_filt);
        ++n;
    }
    s->n_confirm = n;
    s->track = cfg->u.im.ref.rr_track;
    s->slot = cfg->speed.speed_div > 4U ? 4U : 0U;
    s->rho_iq = IQ(1.0);
    /* the current model's blend (im_sup.h): W = k_r (Ts/tau)(Ts/tau_r) (Q31, rounded products), 3W
     * shifted by cm_n into [1/2, 1) (Q31; 3W < 4 as k_r < 2^6 and both ratios < 1, so the shift
     * right ends within two steps), its reciprocal by the SVM's Newton steps from [1/2, 1) pu */
    s->cm_on = 0U;
    s->cm_n = 0U;
    s->cm_inv_iq = 0;
    /* one count's electrical angle, 2 pi p / counts rad = enc_gain_q16 (65536 p / counts, Q16) x
     * 2 pi / 2^32; in Q31 that is enc_gain_q16 x pi: the product with round(pi 2^30) (< 2^64 as
     * both factors are below 2^32), shifted right by 30 with rounding, saturated at 1 rad */
    {
        const uint64_t k = ((uint64_t)cfg->board.enc_gain_q16 * 3373259426ULL + (1ULL << 29)) >> 30;
        s->cm_k_q31 = k > 2147483647ULL ? (q31_t)2147483647L : (q31_t)k;
    }
    if (cfg->u.im.ref.cm_ref != 0U && cfg->speed.sensor != DTC_SPEED_NONE && c->est_p.estimator == IM_EST_IMPROVED &&
        cfg->law != DTC_LAW_IM_DSVM) {
        const q31_t w = iq_mpy(cfg->u.im.machine.kr_iq, q31_mul(c->est_p.k_lo_q31, cfg->u.im.ref.magn_k_q31));
        int64_t x = (int64_t)3 * (int64_t)w;
        int16_t sh = 0;
        if (x > 0) {
            while (x < ((int64_t)1 << 30)) {
                x <<= 1;
                ++sh;
            }
            while (x >= ((int64_t)1 << 31)) {
                x >>= 1;
                --sh;
            }
            s->cm_on = sh >= 0 ? 1U : 0U; /* 3W >= 1: a slow pole above 1/tau_r at any speed */
            s->cm_n = (uint16_t)(sh >= 0 ? sh : 0);
            s->cm_inv_iq = svm_recip(0, (iq_t)(x >> 7));
        }
    }
}
