/*
 * dtc_internal.h - the PM DTC law's functions internal to its own files (dtc.c, dtc_reconfig.c)
 * and to their white-box tests: the steps of dtc_step kept out of line (external linkage on
 * purpose: inlined, their temporaries would widen dtc_step's frame on the deepest stack path,
 * tools/bench budget <= 256 bytes on the Cortex-M0 proxy). Not for the application, which reaches
 * the law through app/law.h.
 */
#ifndef DTC_INTERNAL_H
#define DTC_INTERNAL_H

#include <stdint.h>

#include "dtc.h"

/* Largest beta of the restoring mid-point reconstruction (dtc.c dtc_vmid_dev): 2^-4. */
#define DTC_VMID_BETA_MAX_LOG2 4U

/* Used by dtc_step() (ISR side): adopts the shadow set whose (even) sequence number is seq.
 * Not for the background. */
void dtc_shadow_adopt(dtc_t *c, uint16_t seq);
/* dtc_predict's flux step over the period, dpsi = Ts (v(legs_1) + v_f - r_s i) (formats there). */
static inline void dtc_predict_dpsi(const dtc_t *c, iq_t *dpa, iq_t *dpb)
{
    const iq_t va = fix_add32(fix_add32(c->v1_alpha_iq, c->v1f_alpha_iq), c->v1d_alpha_iq);
    const iq_t vb = fix_add32(fix_add32(c->v1_beta_iq, c->v1f_beta_iq), c->v1d_beta_iq);
    *dpa = iq_mpy(c->cfg->board.ts_pu_iq, iq_sub(va, c->ri_alpha_iq));
    *dpb = iq_mpy(c->cfg->board.ts_pu_iq, iq_sub(vb, c->ri_beta_iq));
}

/* dtc_predict's end: the flux and torque at k+1 (Hoang eq. 10) and the current for the limit. */
static inline void dtc_predict_end(dtc_t *c, iq_t *psi_a, iq_t *psi_b, iq_t *te, iq_t dpa, iq_t dpb, iq_t ia1,
                                   iq_t ib1)
{
    *psi_a = fix_add32(*psi_a, dpa);
    *psi_b = fix_add32(*psi_b, dpb);
    *te = torque_eq10(*psi_a, *psi_b, ia1, ib1);
    clarke_inv(ia1, ib1, &c->i1); /* for the current limit (ilim.h) */
}

/* Internal to dtc_step (actuation-delay compensation); out of line for the stack. On entry
 * *psi_a, *psi_b, *te hold the estimate at k; on return the prediction for k+1; the predicted current goes to c->i1_*. */
void dtc_predict(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te);
/* dtc_predict on a salient PM (l_q != l_d; pm_salient.c): the same contract. */
void dtc_predict_salient(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te);
/* Internal to dtc_step (ripple-robust polarity: the period-mean current into c->i_mid); out of line
 * for the stack (inlined, its saturating sums widen dtc_step's frame on the deepest chain). */
void dtc_pol_mid(dtc_t *c, const clarke_out_t *i);
/* Internal to dtc_step (torque mode: reference plus mean-torque trim); out of line for the stack. */
void dtc_torque_trim(dtc_t *c, iq_t te);

/* Internal to dtc_step (DC-current suppression): updates the correction from the measured
 * current (and, FSTP, the mid-point deviation c->vmid_dev_iq of this step) and adds it to the
 * estimate *psi_a, *psi_b. */
void dtc_dcsupp(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b);
/* Internal to dtc_step (restoring mid-point reconstruction, dtc.c dtc_vmid_beta; dtc_dcsupp reads
 * the step's value from c->vmid_dev_iq):
 * the mid-point's deviation from V_dc/2 as the law uses it, (1 - beta)(vmid - V_dc/2), IQ pu;
 * the shift rounds, the product rounds and saturates, the differences saturate. */
static inline iq_t dtc_vmid_dev(const dtc_t *c, const dtc_meas_t *m)
{
    const iq_t d = iq_sub(m->vmid_iq, fix_rshift_rnd32(m->vdc_iq, 1U));
    return iq_sub(d, iq_mpy(c->vmid_beta_iq, d));
}
/* Internal to dtc_step: beta = min(2^-DTC_VMID_BETA_MAX_LOG2, (s w)^2) at the measured speed. */
void dtc_vmid_beta(dtc_t *c);
/* Internal to dtc_reset and dtc_reconfigure: the currents kept from earlier periods (previous
 * sample, period mean, prediction) and the current-limit flag back to zero. */
void dtc_reset_currents(dtc_t *c);
/* Internal to dtc_step and dtc_reconfigure: the hand-over decision on c->speed_iq (dtc.c). */
void dtc_handover(dtc_t *c);
/* Internal to dtc_init and dtc_reconfigure: the shared blocks' parameters (vrec.h deadtime_error,
 * ilim.h) from cfg. */
static inline void dtc_block_params(dtc_t *c, const dtc_config_t *cfg)
{
    const uint16_t fstp = cfg->board.topology == DTC_TOPO_FSTP ? 1U : 0U;
    c->dt_p.td_ts_q15 = cfg->board.td_ts_q15;
    c->dt_p.fstp = fstp;
    c->il_p.i_lim_iq = cfg->prot.i_lim_iq;
    c->il_p.fstp = fstp;
    c->ilim2_q48 = iq_sumsq_q48(cfg->prot.i_lim_iq, 0); /* ilim_over's bound, once */
}
/* Internal to dtc_reset, the adoption of a reference set and dtc_reconfigure: the flux comparator's
 * squared bounds (hyst.h hyst2_sq_bounds) of the flux reference in force and h_flux's band, after
 * either changed; dtc_step compares |psi|^2 with them (hyst2_sq_step_b). */
static inline void dtc_flux_bounds(dtc_t *c)
{
    hyst2_sq_bounds(&c->h_flux, c->act.flux_ref_iq, &c->flux_sq);
}
/* Internal to dtc_step (low-pass correction factor, lpfcorr.h). */
void dtc_lpf_r(dtc_t *c);
/* Internal to dtc_step and dtc_reconfigure: the speed-dependent gains (dtc_lpf_r, the DC
 * suppression's, dtc_vmid_beta) of the last measured speed, due after a speed-loop step. */
void dtc_speed_gains(dtc_t *c);

#endif /* DTC_INTERNAL_H */
