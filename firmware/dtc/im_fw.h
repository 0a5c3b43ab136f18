/*
 * im_fw.h - flux weakening of the IM DTC drive by null-vector monitoring (Casadei et al. 2006,
 * section 12).
 *
 * Section 12.2: the output of the switching table is watched for N consecutive control periods. If
 * no null vector was applied in that window, the DTC could not hold the torque (the back-EMF is
 * at the voltage limit, eq. 32): the stator-flux reference steps down. If at least one null vector
 * was applied, the torque demand was met: the reference steps up. It stays within [phi_min,
 * phi_rated]. Section 12.3: the flux reference may change at most once per 20 control periods,
 * so N >= 20 (im_fw_check refuses less).
 * The torque reference follows the command in proportion to the flux reference (eq. 33),
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
    iq_t step_down_iq;        /* flux-reference decrement per window without a null vector, > 0 */
    iq_t step_up_iq;          /* increment per window with one, > 0 */
    iq_t psi_min_iq;          /* lower bound, > 0 */
    iq_t psi_rated_iq;        /* rated stator flux, >= psi_min */
    iq_t inv_psi_rated_iq;    /* 1 / psi_rated */
    iq_t kt_iq;               /* k_T of eq. 34, > 0 */
} im_fw_params_t;

typedef struct {
    iq_t psi_ref_iq;          /* stator-flux reference in force */
    uint16_t count;           /* periods in the current window */
    uint16_t null_seen;       /* a null vector was applied in this window */
} im_fw_t;

/* 0, or a nonzero code for inconsistent parameters. */
int16_t im_fw_check(const im_fw_params_t *p);
/* Starts at the rated flux. */
void im_fw_reset(im_fw_t *s, const im_fw_params_t *p);
/* One control period: `null_applied` is 1 if the vector chosen for this period is V0 or V7.
 * Returns the torque reference of eqs. 33-34 for the command t_cmd. */
iq_t im_fw_step(im_fw_t *s, const im_fw_params_t *p, uint16_t null_applied, iq_t t_cmd_iq);

#endif /* IM_FW_H */
