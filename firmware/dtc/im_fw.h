/*
 * im_fw.h - flux weakening of the IM DTC drive by monitoring the torque comparator (Casadei et al.
 * 2006, section 12: the null-vector monitor).
 *
 * Section 12.2: the output of the torque hysteresis comparator is watched for N consecutive
 * control periods. If the torque demand was never met in that window (the text: no null vector
 * applied), the DTC could not hold the torque (the back-EMF is at the voltage limit, Casadei eq. 32): the
 * stator-flux reference steps down. If it was met at least once (at least one null vector), the
 * reference steps up. The caller says what "met" is for its table (im_dtc.c: the comparator asked
 * for less torque in the sense of the command; with ST-A that is exactly the null vector, with
 * Casadei Table 1 and a zero band it is V_{k-1}/V_{k-2}, and counting null vectors there would weaken
 * the flux at any speed). It stays within [phi_min,
 * phi_rated]. Section 12.3: the flux reference may change at most once per 20 control periods,
 * so N >= 20 (im_fw_check refuses less).
 * The torque reference follows the command in proportion to the flux reference (Casadei eq. 33),
 *     T* = T_command phi_s* / phi_s,rated,
 * limited by the pull-out torque at that flux (eqs. 29, 34),
 *     |T*| <= k_T (phi_s*)^2,
 * with k_T = T_max,rated / phi_s,rated^2 (the ratio the paper gives, eq. 31 in SI; no other machine
 * parameter is needed). 1/phi_s,rated is precomputed by the host, so nothing here divides.
 *
 * Formats: IQ pu (flux, torque, k_T in pu torque per pu flux squared).
 * Scaling and overflow: rounded IQ products, saturated; the reference steps are saturating sums
 * clamped to [phi_min, phi_rated].
 */
#ifndef IM_FW_H
#define IM_FW_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    uint16_t window;          /* N control periods per decision (>= 20, section 12.3) */
    iq_t step_down_iq;        /* flux-reference decrement per window with the demand never met, > 0 */
    iq_t step_up_iq;          /* increment per window with it met, > 0 */
    iq_t psi_min_iq;          /* lower bound, > 0 */
    iq_t psi_rated_iq;        /* rated stator flux, >= psi_min */
    iq_t inv_psi_rated_iq;    /* 1 / psi_rated */
    iq_t kt_iq;               /* k_T of Casadei eq. 34, > 0 */
} im_fw_params_t;

typedef struct {
    iq_t psi_ref_iq;          /* stator-flux reference in force */
    uint16_t count;           /* periods in the current window */
    uint16_t met_seen;        /* the torque demand was met in this window */
} im_fw_t;

/* 0, or a nonzero code for inconsistent parameters. */
int16_t im_fw_check(const im_fw_params_t *p);
/* Starts at the rated flux. */
void im_fw_reset(im_fw_t *s, const im_fw_params_t *p);
/* One control period: `demand_met` is 1 if the torque demand was met in this period (above).
 * Returns the torque reference of Casadei eqs. 33-34 for the command t_cmd. */
iq_t im_fw_step(im_fw_t *s, const im_fw_params_t *p, uint16_t demand_met, iq_t t_cmd_iq);

#endif /* IM_FW_H */
