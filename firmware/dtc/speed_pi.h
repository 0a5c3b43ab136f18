/*
 * speed_pi.h - speed PI controller with anti-windup and torque limit, run once per speed period
 * (Hoang section IV: the speed loop is 10 times slower than the 50 us torque/flux loop).
 *
 *   e = w* - w;  u = kp e + I;  T* = clamp(u, -T_lim, +T_lim)
 *   I += ki_ts e, where ki_ts = K_i * T_speed (pu), then clamped to [-T_lim, T_lim];
 *   anti-windup by conditional integration: when the output is saturated and the error would
 *   drive it further into saturation, the integrator is frozen.
 * Bumpless start: speed_pi_reset(s, T) preloads the integrator with T (the torque reference in
 * force when the loop is (re)engaged, e.g. on a switch from torque mode to speed mode).
 *
 * Formats: speeds, torques, gains IQ pu (kp in pu torque per pu speed, may exceed 1).
 * Scaling and overflow: the error is a saturating difference; kp*e and ki_ts*e are rounded IQ
 * products saturating at +-128 pu; sums saturate; the output is always within +-T_lim.
 */
#ifndef SPEED_PI_H
#define SPEED_PI_H

#include "fixmath.h"

typedef struct {
    iq_t kp_iq;
    iq_t ki_ts_iq;
    iq_t limit_iq; /* > 0 */
} speed_pi_params_t;

typedef struct {
    iq_t integ_iq;
    iq_t out_iq;
} speed_pi_t;

void speed_pi_reset(speed_pi_t *s, iq_t preload_iq, iq_t limit_iq);
iq_t speed_pi_step(speed_pi_t *s, const speed_pi_params_t *p, iq_t ref_iq, iq_t meas_iq);

#endif /* SPEED_PI_H */
