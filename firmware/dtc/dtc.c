#include "dtc.h"

#include <stddef.h>

#include "clarke.h"
#include "dtc_internal.h"
#include "ilim.h"
#include "lpfcorr.h"
#include "sector.h"
#include "torque.h"
#include "vrec.h"

static void dtc_adopt(dtc_t *c, const dtc_refs_t *r)
{
    dtc_refs_adopt(&c->act, &c->pi_p, &c->pi, &c->te_trim_iq, c->te_ref_iq, r, c->cfg);
    dtc_flux_bounds(c);
}

void dtc_reset_currents(dtc_t *c)
{
    c->i_prev.ia_iq = 0;
    c->i_prev.ib_iq = 0;
    c->i_prev.ic_iq = 0;
    c->i_prev.i_alpha_iq = 0;
    c->i_prev.i_beta_iq = 0;
    c->i_mid = c->i_prev;
    c->i1 = c->i_prev;
    c->i_limited = 0U;
    c->dt_code = DEADTIME_CODE_NONE; /* i_prev is no longer the sample it was formed on */
    c->fwd_ok = 0U;                  /* nor of c->fwd_* */
}

/* Current limit and ripple-robust polarity (ilim.h, dtc_config.h polarity_mid): state at reset. */
static void dtc_reset_ilim_pol(dtc_t *c)
{
    dtc_reset_currents(c);
    c->lpf_y_iq = 0;
    c->lpf_r_iq = 0;
    c->dcs_alpha_iq = 0;
    c->dcs_beta_iq = 0;
    c->dcs_kw_iq = 0;
    c->vmid_beta_iq = 0;
    c->vmid_dev_iq = 0;
    c->gains_due = 0U;
}

void dtc_reset(dtc_t *c)
{
    static const swtab_legs_t off = {0U, 0U, 0U};
    const dtc_config_t *cfg = c->cfg;

    flux_est_reset(&c->fe);
    speed_meas_reset(&c->sm, 0U);
    c->speed_primed = 0U; /* the first step takes the encoder position as the reference */
    speed_pi_reset(&c->pi, 0, cfg->speed.torque_limit_iq);
    c->te_trim_iq = 0;
    hyst2_init(&c->h_flux, cfg->u.pm_dtc.sw.flux_band_iq, 1U);
    dtc_flux_bounds(c);
    hyst2_init(&c->h_torque2, cfg->u.pm_dtc.sw.torque_band_iq, 1U);
    hyst3_init(&c->h_torque3, cfg->u.pm_dtc.sw.torque_band_iq);
    c->div_cnt = 0U;
    c->legs_1 = off;
    c->legs_2 = off;
    c->legs_3 = off;
    c->vec_1 = cfg->board.topology == DTC_TOPO_FSTP ? 1U : 0U;
    c->te_ref_iq = c->act.mode == DTC_MODE_TORQUE ? c->act.torque_ref_iq : 0;
    c->speed_iq = 0;
    c->wts_iq = 0;
    c->on_cm = cfg->u.pm_dtc.est.handover_speed_iq > 0 ? 1U : 0U;
    c->cm_hold = 0U;
    dtc_reset_ilim_pol(c);
}

/* Copies the shadow set (complete: the caller checked the sequence number) and adopts it.
 * External linkage on purpose: a static function called once is inlined, and its copy of the
 * set would then sit in dtc_step's frame on the deepest stack path. */
void dtc_shadow_adopt(dtc_t *c, uint16_t seq)
{
    dtc_refs_t r;
    dtc_shadow_take(&c->sh, seq, &r);
    dtc_adopt(c, &r);
}

/* Torque mode: the reference in force, with the mean-torque trim. External linkage on purpose
 * (as dtc_shadow_adopt): inlined, its 64-bit temporaries would sit in dtc_step's frame on the
 * deepest stack path (budget: tools/bench, <= 256 bytes on the Cortex-M0 proxy).
 *
 * Mean-torque trim. With zero (or small) bands the torque rises and falls at different rates
 * within a period, and without the delay compensation the comparator's decision also acts one
 * period late (hal.h), so the bang-bang loop settles with a mean offset from the reference (Table
 * VIII machine, FSTP, 1500 rpm, tests/unit/test_dtc_step.c: -22 % without, -12 % with the delay
 * compensation; the rate asymmetry is what the prediction does not remove). In speed mode the speed PI absorbs it; in torque mode a
 * slow integrator on the estimated-torque error does: trim += k * (T* - T_est), k = Ts/tau,
 * limited to a quarter of the torque limit, reset on every mode change and at reset; the trimmed
 * reference still respects the torque limit.
 * Scaling and overflow: the error is IQ pu, times a Q15 gain < 1; the sum saturates and is
 * clamped to +-torque_limit/4 (torque_limit > 0, validated). */
void dtc_torque_trim(dtc_t *c, iq_t te)
{
    const dtc_config_t *cfg = c->cfg;
    c->te_ref_iq = dtc_trim_step(&c->te_trim_iq, c->act.torque_ref_iq, te,
                                 cfg->speed.torque_trim_k_q15, cfg->speed.torque_limit_iq);
}

/* Hand-over between the current and the voltage model (dtc_config.h), on the measured speed
 * at the speed-loop rate: up above handover_speed, back below handover_speed - hyst. Speed and
 * thresholds IQ pu; |speed| saturates (fix_abs32 of INT32_MIN), the difference cannot overflow
 * (0 <= hyst <= speed, validated). */
/* DC-current suppression (dtc_config.h dc_supp). In steady state the true stator flux of a PM
 * machine has no DC part in the stationary frame (psi = l_s i + psi_m e^{j theta}, Hoang eqs.
 * 6-9, with currents that carry none), and the DTC holds the ESTIMATE on a circle centred on the
 * origin (|psi| regulated, eq. 13). A DC error delta of the estimate (a DC voltage error E
 * integrated by the low-pass: delta = E / w_c, flux_est.h) therefore moves the TRUE flux circle
 * by -delta, i.e. the machine carries a DC current -delta / l_s; on the FSTP that DC current is
 * phase A's and charges the split capacitors (mid-point drift), and with the estimated torque
 * (Hoang eq. 10) it makes the torque ripple at f and the currents at 2f (SIL: a 3 mWb offset,
 * 0.5 A of DC and 2f current at 700 rpm). The correction c added to the estimate integrates the
 * measured current, dc/dt = w_d l_s i: with the estimate plus c held on the circle, the DC
 * current is (-delta - c)/l_s, so c -> -delta at the rate w_d and the DC current -> 0, which is
 * the suppression of the DC current (and of the FSTP mid-point's DC charge). The fundamental
 * (and any negative sequence) passes into c rotated by 90 deg and attenuated by w_d/w, so w_d
 * follows the measured speed, w_d = |w|/20: 5 % at every speed (a fixed w_d = w_c = 5 rad/s is
 * 24 % at 200 rpm and takes the proposed scheme's imbalance there from 21 to 64 %, SIL), and
 * 7.9 rad/s (tau 0.13 s) at 1500 rpm. Off (reset to zero) while the current model drives.
 * Formats: k = Ts l_s / 20 (IQ pu, configuration) times |w| (IQ; at the speed-loop rate, as |w|
 * is measured there); the state c is kept with 8
 * more fractional bits than IQ (Q32 pu, +-0.5 pu, saturating) because one period's increment
 * k i is below an IQ LSB for |i| < 2.4e-3 pu at 1500 rpm (an IQ state would stop 5 mA short);
 * it is added to the flux rounded back to IQ (fixmath q32_integrate).
 * FSTP mid-point regulation (vmid_g_iq > 0, the mid-point measured): phase A's current is the
 * split capacitors' only DC path, dV_lo/dt = -i_a / (2 C), and with balancing resistors alone
 * a mid-point charged away from V_dc/2 (a low-speed acceleration leaves it 15 V off, SIL,
 * 4.7 mF) returns only with R_bal C (47 s for 10 kohm). So the suppression's DC target for
 * phase A is i_a = g (vmid - V_dc/2) instead of zero, g = 2 C w_m, w_m = w_c / 2: the deviation
 * then decays as exp(-w_m t), slower than the suppression itself at speed (w_d = |w|/20 >= w_m
 * above 480 rpm; damping sqrt(w_d/w_m)/2 of the cascade). */
static inline void dtc_dcsupp_in(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b)
{
    iq_t ia = i->i_alpha_iq;
    if (c->on_cm != 0U || c->speed_primed == 0U) {
        c->dcs_alpha_iq = 0;
        c->dcs_beta_iq = 0;
        return;
    }
    const iq_t k = c->dcs_kw_iq;
    if (c->cfg->u.pm_dtc.est.vmid_g_iq > 0) {
        /* FSTP mid-point regulation: phase A (alpha) is to carry g (vmid - V_dc/2) of DC */
        ia = iq_sub(ia, iq_mpy(c->cfg->u.pm_dtc.est.vmid_g_iq, c->vmid_dev_iq));
    }
    *psi_a = iq_add(*psi_a, q32_integrate(&c->dcs_alpha_iq, k, ia));
    *psi_b = iq_add(*psi_b, q32_integrate(&c->dcs_beta_iq, k, i->i_beta_iq));
}

/* dtc_dcsupp_in, external (dtc_internal.h); dtc_step takes the inline body: a call, with the
 * flux through memory, costs a quarter of the work. */
void dtc_dcsupp(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b) { dtc_dcsupp_in(c, i, psi_a, psi_b); }

/* Restoring mid-point reconstruction (FSTP, voltage model, mid-point measured and calibrated:
 * u.pm_dtc.est.vmid_beta_s_iq > 0). The calibration (app_core.c app_vmid_cal_set) makes the two voltage
 * sensors agree at vmid = V_dc/2 only: with a remaining link error g_eff = g + o/V_dc (gain g,
 * offset o of the link sensor, as the calibration leaves them) the reconstruction (vrec.h, Hoang
 * eqs. 1-5 with phase A on the mid-point; the legs' mean (S_b + S_c)/2 is vmid/V_dc) carries
 * E = -(2/3) g_eff d of DC on v_alpha, d = vmid - V_dc/2. That closes a loop: E -> flux offset of
 * the low-pass (1/(s + w_c)) -> DC current of phase A (-offset / l_s) -> mid-point
 * (dd/dt = -i_a/(2 C)), i.e. d'' + w_c d' + K g_eff d = 0 with K = (2/3)/(2 C l_s) (22 000 s^-2
 * for Hoang Table VIII, 2 x 4.7 mF). For g_eff < 0 (link read low) it is unstable (a real pole near
 * sqrt(K |g_eff|): +19 rad/s at -2 %; with the DC suppression, dtc_dcsupp, +14 rad/s at
 * 1500 rpm), which the SIL shows as the mid-point running away and a stall. So d reaches the
 * reconstruction scaled by (1 - beta): the DC error becomes -(2/3)(g_eff + beta) d, which
 * restores the mid-point for every g_eff > -beta. beta_max = 1/16 covers the datasheet-grade
 * link sensor (|g| <= 2 %, |o| <= 1 V at 70 V: |g_eff| <= 3.4 %).
 * The price is the mid-point's own swing: phase A's fundamental I at w moves the mid-point by
 * d = I / (2 C w) (dd/dt = -i_a/(2 C)), which beta turns into a flux error -beta i_a / (3 C w^2)
 * on phase A, in phase opposition to i_a: an inductance error beta / (3 C w^2) on that phase. At
 * 1500 rpm that is small (0.4 % of psi_m at rated current with 1/16); at 200 rpm it is 6 % at a
 * quarter of the rated current and 50 % while the speed loop accelerates at its limit, and
 * K (g_eff + beta) puts a lightly damped resonance (37 rad/s, damping w_c / 74 at g_eff = 0) next
 * to the electrical frequency: a fixed 1/16 makes the proposed FSTP limit-cycle between 40 and
 * 240 rpm around a 200 rpm reference (SIL). So beta follows the speed: beta =
 * min(1/16, k w^2), k = 3 C l_s / 8 from the host (tools/config dtc_vmid_beta_k): the inductance
 * error stays within l_s / 8 at every speed (Hoang Table VIII: 5.62e-6 s^2, the cap from 1007 rpm up;
 * the loop's own resonance then sits at sqrt(K k) |w| = 0.35 |w|, below the electrical
 * frequency). An allowance of l_s / 2.4 instead (k three times larger) leaves the proposed FSTP's
 * imbalance at 200 rpm between 27 and 104 % over six noise seeds, l_s / 8 between 25 and 89 %
 * (SIL). Below sqrt(|g_eff| / k) the mid-point is not restored against a
 * link-sensor error; the derived hand-over keeps the voltage model above that speed for the
 * datasheet tolerance down to its hand-back speed (dtc_handover_default_rpm), so only a
 * hand-over set lower by hand (control.handover_rpm) takes the voltage model there.
 * Formats: IQ pu; the configuration holds s = sqrt(k) (pu: k w_base^2 would overflow IQ for a
 * many-pole machine, its root does not), beta = (s |w|)^2; products rounded and saturating
 * (iq_mpy: a large s |w| saturates and the square with it, beyond the cap), beta in [0, 1/16]. */
void dtc_vmid_beta(dtc_t *c)
{
    const iq_t bmax = fix_rshift_rnd32(iq_from_int(1), DTC_VMID_BETA_MAX_LOG2);
    const iq_t sw = iq_mpy(c->cfg->u.pm_dtc.est.vmid_beta_s_iq, fix_abs32(c->speed_iq));
    const iq_t b = iq_mpy(sw, sw);
    c->vmid_beta_iq = b > bmax ? bmax : b;
}

/* Low-pass correction factor r = w_c / w from the measured speed (lpfcorr.h), at the speed-loop
 * rate. External linkage on purpose (as dtc_shadow_adopt): keeps its temporaries out of
 * dtc_step's frame. */
void dtc_lpf_r(dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    iq_t r;
    c->lpf_y_iq = lpfcorr_recip(c->lpf_y_iq, c->speed_iq, cfg->u.pm_dtc.est.lpf_wmin_iq);
    r = iq_mpy(cfg->u.pm_dtc.est.wc_pu_iq, c->lpf_y_iq);
    c->lpf_r_iq = c->speed_iq < 0 ? fix_neg32(r) : r;
}

/* The estimator's speed-dependent gains (low-pass correction r, DC-suppression gain, mid-point
 * beta) from the speed measured at the last speed-loop step. Called at the start of the step after
 * that speed-loop step: every one of them is first read by the step after the one that measured
 * the speed (dtc_vmid_dev, the estimator's input, dtc_dcsupp all come before the speed loop in
 * dtc_step), so forming them there gives the same values at the same steps, and the speed-loop
 * step, the longest, no longer carries them. Formats as in dtc_lpf_r, dtc_vmid_beta; the DC
 * suppression's gain Ts l_s |w| / 20 is a rounded, saturating IQ product. */
void dtc_speed_gains(dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    c->gains_due = 0U;
    if (cfg->u.pm_dtc.est.lpf_comp != 0U) {
        dtc_lpf_r(c);
    }
    c->dcs_kw_iq = iq_mpy(cfg->u.pm_dtc.est.dcs_k_iq, fix_abs32(c->speed_iq)); /* dtc_dcsupp: Ts l_s |w|/20 */
    if (cfg->u.pm_dtc.est.vmid_beta_s_iq > 0) {
        dtc_vmid_beta(c);
    }
}

void dtc_handover(dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    iq_t w = fix_abs32(c->speed_iq);
    if (cfg->u.pm_dtc.est.handover_speed_iq <= 0) {
        c->on_cm = 0U;
    } else if (c->on_cm != 0U) {
        if (w > cfg->u.pm_dtc.est.handover_speed_iq) {
            c->on_cm = 0U;
        }
    } else if (w < iq_sub(cfg->u.pm_dtc.est.handover_speed_iq, cfg->u.pm_dtc.est.handover_hyst_iq)) {
        c->on_cm = 1U;
    }
}

/* Actuation-delay compensation. The leg states legs_1 (returned by the previous step) act
 * during the period that starts now, so the vector chosen here acts from k+1 on: the
 * comparators and the sector must see the machine at k+1. Prediction over one period Ts:
 *   stator flux (Hoang eqs. 15-16, 37-38 when compensated, over one period with the committed
 *   vector; dead time as in deadtime_error when on): dpsi = Ts (v(legs_1) + v_f - r_s i),
 *   psi(k+1) = psi + dpsi;
 *   current (PM machine, Hoang eqs. 6-9 with L_d = L_q: psi = l_s i + psi_r, the rotor flux
 *   psi_r = psi_m e^{j theta} turning at w): psi_r = psi - l_s i, dpsi_r = w Ts j psi_r,
 *   i(k+1) = i + (dpsi - dpsi_r) / l_s;
 *   torque (Hoang eq. 10) of psi(k+1), i(k+1);
 *   a salient PM (l_q != l_d, l_s = l_d): the rotor-frame step of dtc_predict_salient.
 * w is the measured electrical speed (speed-loop rate; it changes little within 500 us).
 * dtc_step reconstructs v(legs_1) into c->v1_* and the drop (c->v1f_*) and dead-time (c->v1d_*)
 * compensations in force, and forms r_s i (c->ri_*) once for the estimator and this prediction;
 * dtc_predict does the rest (split for the stack: no call chain holds
 * two of these frames).
 * Formats: IQ pu throughout; ts_pu (~0.016) and 1/l_s (~32 pu for Hoang Table VIII) from the config.
 * Scaling and overflow: every product is a rounded iq_mpy (64-bit intermediate), every sum
 * saturates: |dpsi| <= Ts_pu (|v| + r_s |i|) stays far below 1 pu for any measured input; the
 * current step (dpsi - dpsi_r)/l_s saturates at +-128 pu in the worst case (no wrap). */
static inline void dtc_predict_in(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te)
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t wts = c->wts_iq; /* w Ts: at the speed-loop rate, as w (dtc_step) */
    iq_t dpa, dpb, ia1, ib1;

    dtc_predict_dpsi(c, &dpa, &dpb);
    /* psi_r = psi - l_s i;  j psi_r w Ts = (-w Ts psi_rb, w Ts psi_ra) */
    ia1 = iq_add(i->i_alpha_iq,
                 iq_mpy(cfg->u.pm_dtc.machine.inv_ls_iq,
                        fix_add32(dpa, iq_mpy(wts, iq_sub(*psi_b, iq_mpy(cfg->u.pm_dtc.machine.ls_iq, i->i_beta_iq))))));
    ib1 = iq_add(i->i_beta_iq,
                 iq_mpy(cfg->u.pm_dtc.machine.inv_ls_iq,
                        iq_sub(dpb, iq_mpy(wts, iq_sub(*psi_a, iq_mpy(cfg->u.pm_dtc.machine.ls_iq, i->i_alpha_iq))))));
    dtc_predict_end(c, psi_a, psi_b, te, dpa, dpb, ia1, ib1);
}

/* dtc_predict_in, external (dtc_internal.h). dtc_step takes the inline body where the compiler
 * inlines it (the host: a call with the flux and torque through memory costs a tenth of it); the
 * Cortex-M0 build (-Os) keeps it out of line, as the stack budget needs. */
void dtc_predict(dtc_t *c, const clarke_out_t *i, iq_t *psi_a, iq_t *psi_b, iq_t *te) { dtc_predict_in(c, i, psi_a, psi_b, te); }

/* Ripple-robust polarity (dtc_config.h polarity_mid): the mean current of period [k-1, k],
 * i(k-1)/2 + i(k)/2, each halved and rounded first (the halves of two full-scale values round up
 * to 2^30 each, so the sum saturates) (the current is piecewise linear within a period: one vector, back-EMF
 * nearly constant), into c->i_mid for the R_on terms of that period's drop compensation (Hoang
 * eqs. 37-38, linear in the current); the forward drops (Hoang Tables V-VI decide per leg by the
 * current's sign) are averaged over the line from i(k-1) to i(k) (vcomp_step_lin): with 2-3 A
 * pk-pk ripple on a 0.6 A fundamental the sign of one sample at the period's end is often not the
 * sign the period had, and at 0.55 A pk-pk per period on a 0.8 A fundamental (Hoang Table VIII,
 * 50 us, 700 rpm, 25 % load) a leg current crosses zero inside a third of the periods. IQ pu; the
 * sum saturates, the halving rounds. Only alpha and beta are formed: the R_on terms read nothing
 * else (the phases of i_mid stay as dtc_reset_currents left them). */
void dtc_pol_mid(dtc_t *c, const clarke_out_t *i)
{
    c->i_mid.i_alpha_iq =
        fix_add32(fix_rshift_rnd32(c->i_prev.i_alpha_iq, 1U), fix_rshift_rnd32(i->i_alpha_iq, 1U));
    c->i_mid.i_beta_iq =
        fix_add32(fix_rshift_rnd32(c->i_prev.i_beta_iq, 1U), fix_rshift_rnd32(i->i_beta_iq, 1U));
}

/* The estimator's drop compensation of legs_2 (applied during the period [k-1, k]): vcomp_step_lin
 * of the legs over i0 -> i with the R_on terms at i_r (vcomp.h). Its forward drops are those the
 * last step's prediction formed for the same legs (then legs_1) on its sample (now i_prev),
 * c->fwd_*, when no phase current changed sign from i_prev to i: a leg whose current keeps its
 * sign over a period has the drop of that sign (vcomp_leg_drop_lin), the same at i_prev, over
 * i_prev -> i and at i (i0 is i_prev or i). Bit for bit the value vcomp_step_lin forms; the
 * forward drops are formed here only in a period with a zero crossing, or after a reset (fwd_ok).
 * Signs compared by the sign bit of the exclusive or (0 counts as positive, as in vcomp.h). */
static void dtc_vcomp_est(dtc_t *c, const clarke_out_t *i0, const clarke_out_t *i, const clarke_out_t *i_r,
                          iq_t *vfa, iq_t *vfb)
{
    const clarke_out_t *ip = &c->i_prev;
    iq_t fa, fb;
    if (c->vc_p.mode == (uint16_t)DTC_COMP_NONE) {
        *vfa = 0;
        *vfb = 0;
        return;
    }
    if (c->fwd_ok != 0U && ((ip->ia_iq ^ i->ia_iq) | (ip->ib_iq ^ i->ib_iq) | (ip->ic_iq ^ i->ic_iq)) >= 0) {
        fa = c->fwd_alpha_iq;
        fb = c->fwd_beta_iq;
    } else {
        vcomp_fwd_lin(&c->vc_p, c->legs_2.sa, c->legs_2.sb, c->legs_2.sc, i0, i, &fa, &fb);
    }
    vcomp_ron(&c->vc_p, i_r, fa, fb, vfa, vfb);
}

void dtc_step(dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    const dtc_config_t *cfg = c->cfg;
    clarke_out_t *const i = &c->i_k; /* in the state, not the frame: see dtc.h */
    flux_est_in_t *const fin = &c->fin;
    iq_t psi_a, psi_b, te;
    uint64_t mag2;
    uint16_t sector, flux_up, vec, vm;
    int16_t tdem;
    swtab_legs_t legs;
    iq_t vmid_r; /* the mid-point the reconstruction takes (dtc_vmid_dev) */

    /* 1. Shadow set: adopt a complete, not yet adopted set (sequence number even). */
    {
        uint16_t seq = dtc_shadow_pending(&c->sh);
        if (seq != 0U) {
            dtc_shadow_adopt(c, seq);
        }
    }

    if (c->gains_due != 0U) {
        dtc_speed_gains(c);
    }

    vmid_r = m->vmid_iq;
    if (cfg->board.fstp_vmid_measured != 0U && cfg->est.estimator == DTC_EST_VOLTAGE) {
        c->vmid_dev_iq = dtc_vmid_dev(c, m);
        vmid_r = iq_add(fix_rshift_rnd32(m->vdc_iq, 1U), c->vmid_dev_iq);
    }

    /* 2. Clarke (Hoang eqs. 4-5) from the two measured currents. */
    clarke_meas(cfg->board.topology == DTC_TOPO_FSTP ? 1U : 0U, m->ia_iq, m->ib_iq, m->ic_iq, i);

    /* 3. Flux estimator. */
    /* the voltage model's voltage follows; r: 0 unless lpf_comp (dtc_lpf_r) */
    flux_est_in_set(fin, 0, 0, i->i_alpha_iq, i->i_beta_iq, m->enc_count, c->lpf_r_iq);
    if (cfg->est.estimator == DTC_EST_VOLTAGE) {
        iq_t vfa, vfb;
        /* the reconstruction of legs_2 goes through c->v1_*: the delay compensation below takes
         * it as that of legs_1 when the legs did not change (same link and mid-point samples) */
        if (cfg->board.topology == DTC_TOPO_FSTP) {
            vrec_fstp(c->legs_2.sb, c->legs_2.sc, m->vdc_iq, vmid_r, cfg->board.fstp_vmid_measured,
                      &c->v1_alpha_iq, &c->v1_beta_iq);
        } else {
            vrec_sstp(c->legs_2.sa, c->legs_2.sb, c->legs_2.sc, m->vdc_iq, &c->v1_alpha_iq,
                      &c->v1_beta_iq);
        }
        fin->v_alpha_iq = c->v1_alpha_iq;
        fin->v_beta_iq = c->v1_beta_iq;
        {
            /* polarity_mid: the period [k-1, k], drops over the current's line from i(k-1) to
             * i(k), R_on at its mean; else the drops and R_on at i(k). One call: inlined. */
            const uint16_t pm = cfg->u.pm_dtc.est.polarity_mid;
            if (pm != 0U) {
                dtc_pol_mid(c, i);
            }
            dtc_vcomp_est(c, pm != 0U ? &c->i_prev : i, i, pm != 0U ? &c->i_mid : i, &vfa, &vfb);
        }
        fin->v_alpha_iq = fix_add32(fin->v_alpha_iq, vfa);
        fin->v_beta_iq = fix_add32(fin->v_beta_iq, vfb);
        if (cfg->est.deadtime_comp != 0U) {
            /* legs_3 -> legs_2 on i_prev (polarity_mid) is the change the last step's prediction
             * formed on its sample (c->dt_code); without polarity_mid it is judged on i */
            uint16_t code = c->dt_code;
            if (code == DEADTIME_CODE_NONE || cfg->u.pm_dtc.est.polarity_mid == 0U) {
                code = deadtime_code(&c->dt_p, cfg->u.pm_dtc.est.polarity_mid != 0U ? &c->i_prev : i, &c->legs_3,
                                     &c->legs_2);
            }
            deadtime_apply(&c->dt_p, m->vdc_iq, code, &vfa, &vfb);
            fin->v_alpha_iq = fix_add32(fin->v_alpha_iq, vfa);
            fin->v_beta_iq = fix_add32(fin->v_beta_iq, vfb);
        }
    }
    if (c->cm_hold != 0U) {
        c->cm_hold--; /* after a reconfiguration (dtc_reconfigure): the current model drives */
        c->on_cm = 1U;
    }
    vm = cfg->est.estimator == DTC_EST_VOLTAGE && c->speed_primed != 0U && c->on_cm == 0U ? 1U : 0U;
    if (vm != 0U || cfg->u.pm_dtc.est.delay_comp != 0U) {
        /* r_s i (Hoang eqs. 15-16): one product for the voltage model and the prediction */
        c->ri_alpha_iq = iq_mpy(cfg->machine.rs_iq, i->i_alpha_iq);
        c->ri_beta_iq = iq_mpy(cfg->machine.rs_iq, i->i_beta_iq);
    }
    if (vm != 0U) {
        flux_est_vm_step(&c->fe, fin, c->ri_alpha_iq, c->ri_beta_iq); /* low-pass correction: lpfcorr.h */
    } else {
        /* The current model (Hoang eqs. 8-9): the estimator, or with the voltage model the first
         * step after a reset and every step below the hand-over speed, written into the low-pass
         * state so that the voltage model starts from it when the hand-over comes (dtc_config.h).
         * flux_est_seed is flux_est_step of a current-model estimator. */
        flux_est_seed(&c->fe, fin);
    }
    psi_a = c->fe.psi_alpha_iq;
    psi_b = c->fe.psi_beta_iq;
    if (cfg->u.pm_dtc.est.dc_supp != 0U && cfg->est.estimator == DTC_EST_VOLTAGE) {
        dtc_dcsupp_in(c, i, &psi_a, &psi_b);
    }

    /* 4. Torque (Hoang eq. 10); the estimate at k is reported as it is. */
    te = torque_eq10(psi_a, psi_b, i->i_alpha_iq, i->i_beta_iq);
    o->psi_alpha_iq = psi_a;
    o->psi_beta_iq = psi_b;
    o->te_iq = te;

    /* 5. Speed loop every speed_div-th call (the first call of each group). */
    o->speed_tick = 0U;
    if (speed_loop_due(&c->sm, &c->speed_primed, &c->div_cnt, m->enc_count) != 0U) {
        o->speed_tick = 1U;
        c->speed_iq = speed_meas_step(&c->sm, m->enc_count);
        c->wts_iq = iq_mpy(c->speed_iq, cfg->board.ts_pu_iq); /* dtc_predict's rotation per period */
        dtc_handover(c);
        c->gains_due = 1U; /* dtc_speed_gains, at the start of the next step */
        if (c->act.mode == DTC_MODE_SPEED) {
            c->te_ref_iq = speed_pi_step(&c->pi, &c->pi_p, c->act.speed_ref_iq, c->speed_iq);
        }
    }
    speed_loop_advance(&c->div_cnt, cfg->speed.speed_div);
    if (c->act.mode == DTC_MODE_TORQUE) {
        dtc_torque_trim(c, te);
    }

    /* 6. Flux and torque for the comparators: the prediction for k+1 when the delay
     *    compensation is on (dtc_predict), else the estimate at k; |psi|^2 (Hoang eq. 11 squared: the
     *    flux comparator works on it, so the ISR takes no square root), sector.
     *    Hysteresis comparators (Hoang eqs. 13-14, Casadei section 4). */
    if (cfg->u.pm_dtc.est.delay_comp != 0U) {
        if (cfg->est.estimator == DTC_EST_VOLTAGE && c->legs_1.sa == c->legs_2.sa && c->legs_1.sb == c->legs_2.sb &&
            c->legs_1.sc == c->legs_2.sc) {
            /* legs_1 = legs_2: c->v1_* holds their reconstruction (step 3) */
        } else if (cfg->board.topology == DTC_TOPO_FSTP) {
            vrec_fstp(c->legs_1.sb, c->legs_1.sc, m->vdc_iq, vmid_r, cfg->board.fstp_vmid_measured,
                      &c->v1_alpha_iq, &c->v1_beta_iq);
        } else {
            vrec_sstp(c->legs_1.sa, c->legs_1.sb, c->legs_1.sc, m->vdc_iq, &c->v1_alpha_iq,
                      &c->v1_beta_iq);
        }
        if (c->vc_p.mode != (uint16_t)DTC_COMP_NONE) {
            /* vcomp_step in its two parts: the forward drops are kept for the next step (dtc_vcomp_est);
             * on the FSTP from the table of vcomp_fwd_lin's values at a sample (vcomp_pt_t) */
            if (c->vc_pt.ok != 0U) {
                const uint16_t k = vcomp_pt_index(c->legs_1.sb, c->legs_1.sc, i);
                c->fwd_alpha_iq = c->vc_pt.fa_iq[k];
                c->fwd_beta_iq = c->vc_pt.fb_iq[k];
            } else {
                /* vcomp_fwd_lin: vcomp_step_lin with no R_on current (its R_on terms are 0); the
                 * estimator's call of vcomp_fwd_lin stays the only one, inlined */
                static const clarke_out_t no_current = {0, 0, 0, 0, 0};
                vcomp_step_lin(&c->vc_p, c->legs_1.sa, c->legs_1.sb, c->legs_1.sc, &no_current, i, i,
                               &c->fwd_alpha_iq, &c->fwd_beta_iq);
            }
            c->fwd_ok = 1U;
            vcomp_ron(&c->vc_p, i, c->fwd_alpha_iq, c->fwd_beta_iq, &c->v1f_alpha_iq, &c->v1f_beta_iq);
        } else {
            c->v1f_alpha_iq = 0;
            c->v1f_beta_iq = 0;
        }
        c->v1d_alpha_iq = 0;
        c->v1d_beta_iq = 0;
        if (cfg->est.deadtime_comp != 0U) {
            c->dt_code = deadtime_code(&c->dt_p, i, &c->legs_2, &c->legs_1); /* the next step's estimator takes it */
            deadtime_apply(&c->dt_p, m->vdc_iq, c->dt_code, &c->v1d_alpha_iq, &c->v1d_beta_iq);
        }
        if (c->fe_p.dl_iq != 0) {
            dtc_predict_salient(c, i, &psi_a, &psi_b, &te); /* a salient PM: l_q != l_d */
        } else {
            dtc_predict_in(c, i, &psi_a, &psi_b, &te);
        }
    }
    mag2 = iq_sumsq_q48(psi_a, psi_b);
    sector = cfg->board.topology == DTC_TOPO_FSTP ? sector_fstp(psi_a, psi_b) : sector_sstp(psi_a, psi_b);
    flux_up = hyst2_sq_step_b(&c->h_flux, &c->flux_sq, mag2); /* hyst2_sq_step of act.flux_ref_iq */
    if (cfg->board.topology == DTC_TOPO_SSTP && cfg->u.pm_dtc.sw.sstp_table == DTC_ST_BASIC) {
        tdem = hyst3_step(&c->h_torque3, iq_sub(c->te_ref_iq, te));
    } else {
        tdem = hyst2_step(&c->h_torque2, iq_sub(c->te_ref_iq, te)) != 0U ? 1 : -1;
    }

    /* 7. Switching table. */
    if (cfg->board.topology == DTC_TOPO_FSTP) {
        vec = swtab_fstp(sector, flux_up, tdem > 0 ? 1U : 0U);
        legs = swtab_fstp_legs(vec);
    } else {
        if (cfg->u.pm_dtc.sw.sstp_table == DTC_ST_BASIC) {
            vec = swtab_sstp_basic(sector, flux_up, tdem);
        } else {
            vec = swtab_sstp_st(cfg->u.pm_dtc.sw.sstp_table, sector, flux_up, tdem > 0 ? 1U : 0U);
        }
        vec = swtab_null_choice(vec, c->vec_1);
        legs = swtab_sstp_legs(vec);
    }
    if (cfg->prot.i_lim_iq > 0) {
        /* Current limit (ilim.h ilim_select) on the current predicted for k+1, or on i(k) without
         * the delay compensation (the host's margin covers the second period then): |i|^2 against
         * I_lim^2 squared at init (ilim_over's exact comparison), then ilim_pick. */
        const clarke_out_t *il = cfg->u.pm_dtc.est.delay_comp != 0U ? &c->i1 : i;
        c->i_limited = iq_sumsq_q48(il->i_alpha_iq, il->i_beta_iq) > c->ilim2_q48 ? 1U : 0U;
        if (c->i_limited != 0U) {
            vec = ilim_pick(&c->il_p, il);
            legs = cfg->board.topology == DTC_TOPO_FSTP ? swtab_fstp_legs(vec) : swtab_sstp_legs(vec);
        }
    }
    c->i_prev.ia_iq = i->ia_iq; /* the sample at k is the previous one for the next step */
    c->i_prev.ib_iq = i->ib_iq;
    c->i_prev.ic_iq = i->ic_iq;
    c->i_prev.i_alpha_iq = i->i_alpha_iq;
    c->i_prev.i_beta_iq = i->i_beta_iq;
    swtab_legs_shift(&c->legs_3, &c->legs_2, &c->legs_1, &legs);
    c->vec_1 = vec;

    /* 8. Outputs. */
    o->sa = legs.sa;
    o->sb = legs.sb;
    o->sc = legs.sc;
    o->vector = vec;
    o->sector = sector;
    o->flux_up = flux_up;
    o->torque_dem = tdem;
    law_out_state(o, c->te_ref_iq, c->speed_iq, c->fe.theta_e,
                  cfg->est.estimator == DTC_EST_CURRENT ? 1U : c->on_cm, c->act.flux_ref_iq);
    o->psir_mag_iq = 0;
    o->i_limited = c->i_limited;
}
