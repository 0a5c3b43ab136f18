/*
 * im_est.h - stator- and rotor-flux estimation of the induction machine (Casadei et al. 2006,
 * sections 2 and 10.2, appendix A).
 *
 * Per-unit bases as in dtc_base.h (the IM configuration picks V_base, I_base, w_base); T-model
 * quantities: l_s = L_s/L_base, m = M/L_base, l_r = L_r/L_base, sigma = 1 - m^2/(l_s l_r).
 * "Rotor flux" is Casadei's T-model rotor flux phi_r = L_r i_r + M i_s (not the Gamma or inverse-
 * Gamma one; see ../shared/reference/im-facts.md).
 *
 * Two stator-flux estimators, chosen by the configuration:
 *   IM_EST_VOLTAGE  Casadei eq. 1, d phi_s/dt = v_s - R_s i_s, integrated by the same exactly
 *                   discretised first-order low-pass as the PM drive's voltage model (flux_est_lpf,
 *                   cut-off w_c) to stop offset drift. Not during the start-up (in->start): the
 *                   machine is magnetised at DC there, where the low-pass has no gain (its estimate
 *                   of a DC flux decays as exp(-w_c t) while the machine holds it), so the drive
 *                   would keep adding volt-seconds the estimate loses, w_c |phi_s*| a second
 *                   (the machine over-magnetised beyond 2.5 x phi_s* in the 0.44 s start of the
 *                   default IM, and a trip when torque is applied: Casadei Fig. 17a's
 *                   statement for the pure integrator). During the start-up the voltage model
 *                   takes Casadei eq. 20's correction (below, at the low-speed gain k_lo)
 *                   towards the start-up's rotor-flux model, which is exact at DC (im_dtc.h);
 *                   the low-pass then runs on from the flux so reached.
 *   IM_EST_IMPROVED Casadei eq. 20, the voltage model pulled towards the rotor-flux reference:
 *                     d phi_s/dt = v_s - R_s i_s + (phi_r* e^{j theta} - phi_r) / tau
 *                   with phi_r from Casadei eq. 21 and e^{j theta} = x/|x| from eq. 22. Discretised by forward Euler over
 *                   one period (the correction term changes at the rate 1/tau, Ts/tau <= 0.01 for
 *                   any sensible tau, so the Euler error of that term is below 0.5 % of it):
 *                     phi_s[k+1] = phi_s[k] + ts_pu (v - r_s i) + (Ts/tau) (phi_r* c - k_r x)
 *                   x = phi_s[k] - sigma l_s i[k], c = (cos theta, sin theta), k_r = l_r/m.
 *                   With in->ref_vec the caller's vector ref_* stands for phi_r* c (the IM law at
 *                   low speed with the encoder: a current model's rotor flux, im_sup.h).
 *                   Timing as in the PM drive (dtc.h): v is the (zero-order held) voltage of the
                   period that ends at this step and i the current sampled at this step, so the
                   state after the step is the flux at this instant and Casadei eqs. 21-22 pair it with the
                   current of the same instant.
 *                   tau may depend on speed (section 10.2): Ts/tau = k_lo below |w| = w_lo, k_hi
 *                   above w_hi, linear in between (the slope is precomputed: no division here).
 * Both then give, every period:
 *   x = phi_s - sigma l_s i                 (Casadei eq. 21 without the factor L_r/M)
 *   e^{j theta} = x / |x|, |x|              (eq. 22) without a division or a square root: the
 *                                           reciprocal r = 1/|x| is tracked by Newton steps for
 *                                           the inverse square root, r <- r (3 - t) / 2 with
 *                                           t = |x r|^2, from the previous period's r until
 *                                           |t - 1| < 2^-20 (none when |x| holds; one only when
 *                                           |t - 1| < 2^-6, which leaves it below 2^-12 and
 *                                           the next periods refine), re-seeded from a power of two when
 *                                           t leaves (1/4, 9/4) or r exceeds 64; the direction
 *                                           is taken as alpha (e^{j0}) when a re-seed finds
 *                                           |x| < 2^-6 pu
 * and, only on the periods the caller asks for them (want_polar: the IM law's speed-loop
 * periods, for the sensorless speed and the telemetry):
 *   theta = arg x, |x|                      (Casadei eq. 22) by CORDIC (fix_polar)
 *   |phi_r| = k_r |x|                       (eq. 21)
 * and every period:
 *   phi_r = k_r x                           (Casadei eq. 21, vector)
 * and the torque T = phi_s x i (appendix eq. A10 with T_base = 3/2 p psi_base I_base, the same
 * form as Hoang eq. 10: torque.h).
 *
 * Formats: v, i, phi IQ pu; ts_pu, k_lo, k_hi Q31 in [0, 1); slope Q31 per pu of speed;
 * theta angle_t.
 * Scaling and overflow: the flux update ts_pu*e + k*corr is accumulated in 64 bits (each product
 * < 2^62) and rounded once, then added to the state with saturation (+-128 pu, never wraps). The
 * products sigma_ls*i and k_r*x are rounded IQ products (<= 0.5 LSB) with saturation. Unit
 * vector: r in IQ (r <= 64 as |x| >= 2^-6 pu), u = x r rounded to IQ (product < 2^62), |u|^2
 * exact in 64 bits then Q30; the Newton product r (3 - t) is formed only for t in (1/4, 9/4)
 * (Q30), so < 2^31 * 2^32 = 2^63; |x| = x . u rounded to IQ. The unit vector's length is within
 * 2^-21 of 1 whenever the loop converged (2^-13 after the single step for a small move of |x|),
 * which it does within the re-seed and 8 steps from any start
 * (re-seed plus six steps) for |x| up to 8 pu (beyond, r's IQ resolution limits it to about
 * 2^-24 / r relative).
 */
#ifndef IM_EST_H
#define IM_EST_H

#include <stdint.h>

#include "fixmath.h"

enum im_estimator {
    IM_EST_VOLTAGE = 0,  /* Casadei eq. 1 through the low-pass of flux_est.h */
    IM_EST_IMPROVED = 1  /* Casadei eq. 20 */
};

typedef struct {
    uint16_t estimator;   /* enum im_estimator */
    iq_t rs_iq;           /* stator resistance, pu */
    iq_t sigma_ls_iq;     /* sigma * l_s, pu (stator transient inductance) */
    iq_t kr_iq;           /* l_r / m */
    q31_t ts_pu_q31;      /* Ts * w_base */
    q31_t k_in_q31;       /* IM_EST_VOLTAGE: low-pass input gain (flux_est.h) */
    q31_t k_leak_q31;     /* IM_EST_VOLTAGE: low-pass leak 1 - exp(-w_c Ts) */
    q31_t k_lo_q31;       /* IM_EST_IMPROVED: Ts/tau at low speed */
    q31_t k_hi_q31;       /* IM_EST_IMPROVED: Ts/tau at high speed */
    iq_t w_lo_iq;         /* |speed| up to which k_lo applies, pu (>= 0) */
    iq_t w_hi_iq;         /* |speed| from which k_hi applies, pu (>= w_lo) */
    q31_t k_slope_q31;    /* (k_hi - k_lo) / (w_hi - w_lo) in Q31 per pu; 0 if w_hi = w_lo */
} im_est_params_t;

typedef struct {
    const im_est_params_t *p;
    iq_t psi_alpha_iq, psi_beta_iq;     /* stator flux estimate (state), pu */
    iq_t psir_alpha_iq, psir_beta_iq;   /* rotor flux (Casadei eq. 21), pu */
    iq_t psir_mag_iq;                   /* |phi_r|, pu, when asked for */
    angle_t theta_r;                    /* rotor-flux angle (Casadei eq. 22), when asked for */
    iq_t u_alpha_iq, u_beta_iq;         /* e^{j theta} = x/|x| (Casadei eq. 22), IQ */
    iq_t inv_mag_iq;                    /* r = 1/|x|, IQ; 0: not known (re-seed) */
    q31_t k_q31;                        /* Ts/tau in use, for the speed k_speed_iq */
    iq_t k_speed_iq;
    uint16_t k_valid;                   /* 0 after a reset */
    iq_t x_alpha_iq, x_beta_iq;         /* x = phi_s - sigma l_s i of the last step (Casadei eq. 21) */
    iq_t ri_alpha_iq, ri_beta_iq;       /* r_s i of the last step (Casadei eq. 1), pu */
    fix_polar_t polar;                  /* the CORDIC between im_est_polar_begin and _end */
} im_est_t;

typedef struct {
    iq_t v_alpha_iq, v_beta_iq;  /* stator voltage applied over the period that ends now, pu */
    iq_t i_alpha_iq, i_beta_iq;  /* stator current sampled now (the end of that period), pu */
    iq_t psir_ref_iq;            /* rotor-flux reference magnitude phi_r* (improved estimator) */
    iq_t speed_iq;               /* electrical speed for a speed-dependent tau, pu */
    uint16_t want_polar;         /* 1: compute theta_r and |phi_r| (CORDIC) in this period */
    uint16_t start;              /* 1: the start-up's magnetisation (IM_EST_VOLTAGE corrected as
                                  * Casadei eq. 20, file comment) */
    uint16_t ref_vec;            /* 1: Casadei eq. 20's correction pulls towards the vector ref_*
                                  * in place of phi_r* e^{j theta} (im_sup.h, the current model) */
    iq_t ref_alpha_iq, ref_beta_iq; /* that reference vector, pu */
} im_est_in_t;

/* Returns 0, or a nonzero code when the parameters are inconsistent (negative resistance,
 * k_r <= 0, w_hi < w_lo, gains outside [0, 1)). */
int16_t im_est_check(const im_est_params_t *p);
void im_est_init(im_est_t *s, const im_est_params_t *p);
/* Zero flux: the machine is demagnetised at start. */
void im_est_reset(im_est_t *s);
/* Integrates one period, then updates the rotor flux and its direction (and its angle and
 * magnitude when in->want_polar): im_est_flux, then im_est_polar when asked. */
void im_est_step(im_est_t *s, const im_est_in_t *in);
/* The parts of im_est_step, for a caller that keeps the CORDIC's frame off the flux update's stack
 * path (the IM laws): the flux, the rotor flux and its direction (in->want_polar not read); the
 * rotor-flux angle and magnitude of that step's x. */
void im_est_flux(im_est_t *s, const im_est_in_t *in);
/* Casadei eq. 22 by CORDIC (fix_polar) on x: theta_r and |phi_r| = k_r |x| (Casadei eq. 21),
 * the magnitude a rounded IQ product, saturated. Inline: the speed-loop periods pay for one call
 * (the CORDIC's) and no frame. */
static inline void im_est_polar(im_est_t *s)
{
    fix_polar(s->x_alpha_iq, s->x_beta_iq, &s->theta_r, &s->psir_mag_iq);
    s->psir_mag_iq = iq_mpy(s->p->kr_iq, s->psir_mag_iq);
}
/* im_est_polar in two halves (fixmath.h fix_polar_begin, fix_polar_end), for a caller that
 * spreads the CORDIC over two periods (the IM laws, im_dtc_internal.h): _begin on this step's x,
 * _end in a later step gives theta_r and |phi_r| of that x, bit for bit im_est_polar's.
 * (im_est_reset leaves a (0, 0) vector pending: angle 0, magnitude 0.) */
static inline void im_est_polar_begin(im_est_t *s)
{
    fix_polar_begin(s->x_alpha_iq, s->x_beta_iq, &s->polar);
}
static inline void im_est_polar_end(im_est_t *s)
{
    fix_polar_end(&s->polar, &s->theta_r, &s->psir_mag_iq);
    s->psir_mag_iq = iq_mpy(s->p->kr_iq, s->psir_mag_iq);
}

/* Ts/tau at electrical speed w (improved estimator; exposed for the tests). */
q31_t im_est_gain(const im_est_params_t *p, iq_t speed_iq);

#endif /* IM_EST_H */
