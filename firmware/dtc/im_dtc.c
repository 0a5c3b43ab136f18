#include "im_dtc_internal.h"

#include <stddef.h>

#include "clarke.h"
#include "sector.h"
#include "torque.h"
#include "vrec.h"

/* The rotor-flux reference of the improved estimator (Casadei eq. 20): the
 * constant rotor flux of Casadei eq. 19 when configured, else the no-load rotor flux of the stator-flux
 * reference, phi_r = (m/l_s) phi_s (the T model at zero slip). Rounded IQ products. */
void im_dtc_psir_ref(im_dtc_t *c, iq_t psi_s_ref_iq)
{
    const dtc_config_t *cfg = c->cfg;
    c->psir_ref_iq = cfg->u.im.ref.psir_ref_iq > 0 ? cfg->u.im.ref.psir_ref_iq
                                                 : iq_mpy(cfg->u.im.machine.inv_ks_iq, psi_s_ref_iq);
}

/* A reference set in force: references clamped to their limits, speed-PI gains; a change to
 * speed mode preloads the PI with the torque command (bumpless). */
void im_dtc_apply(im_dtc_t *c, const dtc_refs_t *r)
{
    dtc_refs_adopt(&c->act, &c->pi_p, &c->pi, &c->te_trim_iq, c->te_cmd_iq, r, c->cfg);
    im_dtc_psir_ref(c, r->flux_ref_iq);
}

void im_dtc_reset(im_dtc_t *c)
{
    static const swtab_legs_t off = {0U, 0U, 0U};
    const dtc_config_t *cfg = c->cfg;

    im_est_reset(&c->est);
    im_speed_reset(&c->isp);
    im_fw_reset(&c->fw, &c->fw_p);
    speed_meas_reset(&c->sm, 0U);
    c->speed_primed = 0U;
    speed_pi_reset(&c->pi, 0, cfg->speed.torque_limit_iq);
    hyst2_init(&c->h_flux, cfg->u.im.sw.flux_band_iq, 1U);
    hyst2_init(&c->h_torque2, cfg->u.im.sw.torque_band_iq, 1U);
    hyst3_init(&c->h_torque3, cfg->u.im.sw.torque_band_iq);
    hyst5_init(&c->h_torque5, cfg->u.im.sw.torque_band_iq, cfg->u.im.dsvm.torque_band2_iq);
    c->dsc.s[0] = 0U;
    c->dsc.s[1] = 0U;
    c->dsc.s[2] = 0U;
    c->dsc.ccw = 1U;
    c->dsc_on = 0U;
    c->div_cnt = 0U;
    c->magnetised = 0U;
    c->ein.start = 1U; /* the voltage model's start-up correction (im_est.h) */
    c->magn_n = 0U;
    c->magn_psir_iq = 0;
    c->ref_due = 1U;
    c->legs_1 = off;
    c->legs_2 = off;
    c->legs_3 = off;
    c->vec_1 = cfg->board.topology == DTC_TOPO_FSTP ? 1U : 0U; /* Hoang Table I's V_1 = legs off */
    c->tdem_1 = 0;
    c->te_cmd_iq = 0;
    c->te_trim_iq = 0;
    c->te_ref_iq = 0;
    c->psir_trim_iq = 0;
    im_sfvc_kpd(c);
    im_dfoc_id_ref(c);
    c->psi_ref_iq = c->act.flux_ref_iq;
    c->speed_iq = 0;
    c->enc_filt_iq = 0;
    c->plaus_err_iq = 0;
    c->plaus_on = 0U;
    /* SFVC: the gates were off, no voltage */
    svm_reset(&c->svm);
    c->svm_o.overmod = 0U; /* the DFOC's anti-windup reads the previous period's (im_dfoc.c) */
    c->v1_alpha_iq = 0;
    c->v1_beta_iq = 0;
    c->v2_alpha_iq = 0;
    c->v2_beta_iq = 0;
    c->vs_alpha_iq = 0;
    c->vs_beta_iq = 0;
    c->foc_id_int_iq = 0;
    c->foc_iq_int_iq = 0;
    c->sr_valid = 0U;
    c->i_limited = 0U;
    c->i_prev.ia_iq = 0;
    c->i_prev.ib_iq = 0;
    c->i_prev.ic_iq = 0;
    c->i_prev.i_alpha_iq = 0;
    c->i_prev.i_beta_iq = 0;
    c->open_wait = 0U;
    c->psir_fall = 0U;
    im_sup_reset(c);
}

/* Copies the shadow set and adopts it. External linkage on purpose (dtc.c dtc_shadow_adopt):
 * inlined, the copy would sit in im_dtc_step's frame. */
void im_dtc_adopt(im_dtc_t *c, uint16_t seq)
{
    dtc_refs_t r;
    dtc_shadow_take(&c->sh, seq, &r);
    im_dtc_apply(c, &r);
}

/* The estimator's input: the stator voltage of the period that ends now (legs returned two steps
 * ago, measured V_dc, Casadei eq. 2 / Hoang eqs. 1-5) with the drop (vcomp) and dead-time
 * compensations, the currents, the rotor-flux reference, the speed for tau, and whether the angle
 * and magnitude are wanted (speed-loop periods). (im_dtc_step then
 * calls the estimator itself: one call level less on the deepest stack path.) */
void im_dtc_estimate(im_dtc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    im_est_in_t *in = &c->ein;

    vrec_sstp(c->legs_2.sa, c->legs_2.sb, c->legs_2.sc, m->vdc_iq, &in->v_alpha_iq, &in->v_beta_iq);
    im_vcomp(c, c->legs_2.sa, c->legs_2.sb, c->legs_2.sc, 1U);
    in->v_alpha_iq = fix_add32(in->v_alpha_iq, c->dva_iq);
    in->v_beta_iq = fix_add32(in->v_beta_iq, c->dvb_iq);
    if (cfg->est.deadtime_comp != 0U &&
        (c->legs_3.sa != c->legs_2.sa || c->legs_3.sb != c->legs_2.sb || c->legs_3.sc != c->legs_2.sc)) {
        /* a leg changed at the start of the period: its dead-time error (none otherwise), the sign
         * of each phase current at that instant, the previous step's sample (vrec.h deadtime_leg).
         * The sample at the period's end has another sign whenever the period's ripple crosses
         * zero: near every zero crossing at low speed and light load, where the error then left
         * (measured, 4 kW IM, ideal devices, 72 rpm, 10 % rated torque, DTC) +3.1 % of mean
         * torque. */
        deadtime_error(&c->dt_p, m->vdc_iq, &c->i_prev, &c->legs_3, &c->legs_2, &c->dva_iq, &c->dvb_iq);
        in->v_alpha_iq = fix_add32(in->v_alpha_iq, c->dva_iq);
        in->v_beta_iq = fix_add32(in->v_beta_iq, c->dvb_iq);
    }
    c->i_prev = c->i;
    im_dtc_ein_common(c, m);
}

/* The encoder plausibility's comparison of a speed-loop period (im_dtc.h), run in the second
 * step on the speed-loop step's values (held since: est.theta_r, est.psir_mag_iq, speed_iq;
 * stored: the torque in plaus_err_iq, whether magnetised in sup.due bit 2): the sensorless speed (Casadei eqs. 16, 22: im_speed_step on that
 * step's rotor-flux angle and torque), the encoder's speed through the same filter, their
 * difference; before the rotor flux reaches plaus_psir_iq, and while the start-up magnetises (the
 * flux is built at DC: on a rotor that already turns its angle stands while the encoder's moves),
 * the filtered encoder speed is set to the sensorless one and nothing is compared.
 * Formats IQ pu; the difference saturates. */
void im_dtc_enc_plaus(im_dtc_t *c)
{
    im_speed_step(&c->isp, &c->isp_p, c->est.theta_r, c->plaus_err_iq, c->cfg->u.im.ref.inv_psir_sq_iq);
    if (c->est.psir_mag_iq < c->plaus_psir_iq || c->isp.primed == 0U || (c->sup.due & 4U) == 0U) {
        c->enc_filt_iq = c->isp.speed_iq;
        c->plaus_on = 0U;
        return;
    }
    c->enc_filt_iq = im_speed_lpf(c->enc_filt_iq, c->speed_iq, c->isp_p.k_filt_q31);
    c->plaus_err_iq = fix_sub32(c->isp.speed_iq, c->enc_filt_iq);
    c->plaus_on = 1U;
}

/* The speed-loop period's part of im_dtc_speed (im_dtc_internal.h): the encoder's speed (and the
 * values its plausibility compares later, im_dtc_enc_plaus), or the sensorless estimate (the rotor-flux angle's change over the speed period, Casadei eq. 22, minus
 * the slip of eq. 16 with the estimated torque te, im_ref.h), then the speed PI. The PI is held at
 * rest during the start-up magnetisation. */
void im_dtc_speed_tick(im_dtc_t *c, const dtc_meas_t *m, iq_t te)
{
    const dtc_config_t *cfg = c->cfg;
    uint16_t plaus = 0U;

    if (cfg->speed.sensor == DTC_SPEED_NONE) {
        im_speed_step(&c->isp, &c->isp_p, c->est.theta_r, te, cfg->u.im.ref.inv_psir_sq_iq);
        c->speed_iq = c->isp.speed_iq;
    } else {
        c->speed_iq = speed_meas_step(&c->sm, m->enc_count);
        /* the plausibility's values of this step, compared in the next step (im_dtc_speed, im_plaus_slot) */
        if (cfg->u.im.ref.enc_plaus_iq > 0) {
            c->plaus_err_iq = te;
            plaus = (uint16_t)(c->magnetised != 0U ? 6U : 2U);
        }
    }
    c->sup.due = (uint16_t)(1U | plaus);
    c->sup.compared = 0U;
    c->ref_due = 1U;
    if (c->act.mode == DTC_MODE_SPEED && c->magnetised != 0U) {
        c->te_cmd_iq = speed_pi_step(&c->pi, &c->pi_p, c->act.speed_ref_iq, c->speed_iq);
    }
}

/* The torque mode's command (im_dtc_speed): the torque reference with the mean-torque trim (as
 * the PM law), once torque is allowed. Not with flux weakening: there T_command is scaled by
 * Casadei eq. 33 and the torque is at the voltage limit by design, so a trim towards T_command (or
 * towards eq. 33's T*, which the machine cannot reach while the flux steps down) winds up to its
 * limit (measured: T* 29 % of T_command above Casadei eq. 33 towards T_command, 54 % towards T*);
 * T* is eqs. 33-34 as in section 12. */
void im_dtc_torque_cmd(im_dtc_t *c, iq_t te)
{
    const dtc_config_t *cfg = c->cfg;
    c->te_cmd_iq = c->magnetised != 0U && cfg->u.im.fw.on == 0U
                       ? dtc_trim_step(&c->te_trim_iq, c->act.torque_ref_iq, te,
                                       cfg->speed.torque_trim_k_q15, cfg->speed.torque_limit_iq)
                       : c->act.torque_ref_iq;
}

/* The rotor-flux trim of the IM laws (DTC, DSC, DSVM by |phi_s*| of Casadei eq. 19; SFVC by the
 * d component of Casadei eq. 18; DFOC by i_d*), with the constant rotor flux phi_r*: once per
 * speed period, after the speed loop's step (est.psir_mag_iq is that step's |phi_r|, Casadei eq. 21),
 *     trim += (T_sp / tau_r) (phi_r* - |phi_r|),   |trim| <= phi_r* / 8,
 * an integral with the rotor's time constant, which the caller adds to its flux command (times l_s/m
 * on |phi_s*|, the no-load ratio of Casadei eq. 19, and on the d component of the SFVC's Casadei
 * eq. 18; divided by m on i_d*). Returns 1 when the trim moved.
 * Why: Casadei eq. 20's correction (phi_r* e^{j theta} - phi_r)/tau is radial and vanishes only when
 * the law holds |phi_r| at phi_r*. A switching-table law holds the sampled |phi_s| a fraction of its
 * ripple off |phi_s*| (the zero-band comparator with the period's delay; DSC's hexagon has a mean
 * radius below phi_s*, 4 % measured at 72 rpm), the SFVC's deadbeat regulator leaves |phi_r| a
 * fraction of a mWb off phi_r* (one period's delay), and the DFOC holds i_d, whose rotor flux the
 * voltage model's error moves. The correction then stays at (phi_r* - |phi_r|)/tau, a radial voltage
 * that the estimator turns, at the stator frequency w_s, into a tangential flux error of
 * (phi_r* - |phi_r|)/(tau w_s): an angle error of the flux estimate, and a torque error
 * i_d/i_q times larger. Measured (4 kW IM, ideal inverter, 72 rpm, 10 % rated torque, tau 10 ms):
 * |phi_r| 0.31 mWb below phi_r* with DTC gave 2.7 mrad and -1.9 % torque; DSC 17 mWb below gave a
 * negative torque for a positive reference. The trim brings the mean |phi_r| to phi_r*, so that the
 * correction's mean is zero and the estimate is the voltage model's (Casadei eq. 1) in the mean.
 * The loop: DTC's |phi_r| follows |phi_s*| (m/l_s) within sigma tau_r, the DFOC's follows m i_d
 * within tau_r, so the integral's time constant tau_r settles it (damping 1/2 on the DFOC).
 * It integrates while motoring with |T*| >= T_lim / 32 and holds otherwise.
 * Formats: IQ pu; T_sp/tau_r Q31 (im_sup's k_cm); rounded product, saturating sum, clamped. */
uint16_t im_psir_trim(im_dtc_t *c)
{
    const iq_t lim = fix_rshift_rnd32(c->psir_ref_iq, 3U);
    if (fix_abs32(c->te_ref_iq) < c->sup.te_min_iq || (c->te_ref_iq > 0) != (c->speed_iq > 0)) {
        /* held below T_lim / 32 (im_sup's te_min): a trim found at no load (the null vectors' flux
         * droop at T* = 0) is not the loaded machine's; held while regenerating: there, at low
         * stator frequency, the improved estimator's own loop has its unstable region (Casadei
         * sec. 10.7, Fig. 21, eqs. 26-28), and the trim's integral in the flux loop moved map-stable
         * points out of it (measured, SFVC, ideal devices: at w_s = -30 rad/s, tau = 2 ms, the flux
         * lost, 101 % spread) */
        return 0U;
    }
    c->psir_trim_iq = fix_clamp32(
        iq_add(c->psir_trim_iq, q31_mul(c->sup.k_cm_q31, iq_sub(c->psir_ref_iq, c->est.psir_mag_iq))), -lim, lim);
    return 1U;
}

void im_sfvc_kpd(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    c->sfvc_kpd_iq = iq_mpy(cfg->u.im.sfvc.kp_iq,
                            iq_mpy(cfg->u.im.machine.ks_iq, iq_add(cfg->u.im.ref.psir_ref_iq, c->psir_trim_iq)));
}

/* References in force for this period:
 *   start-up (Casadei Fig. 17b): T* = 0 and phi_s* ramped to its no-load value for im_magn_periods;
 *   flux weakening (section 12, im_fw.h): phi_s* from the monitor of the torque comparator (the
 *     previous step's decision is the one acting now), T* by Casadei eqs. 33-34 without the mean-torque
 *     trim (im_dtc_speed); the estimator's rotor-flux
 *     reference follows phi_s* (no-load ratio m/l_s);
 *   constant rotor flux: phi_s* from T* by Casadei eq. 19, evaluated once per speed period (T* changes
 *     at that rate in speed mode; in torque mode phi_s* lags T* by at most speed_div periods);
 *   otherwise the stator-flux reference of the set in force. */
void im_dtc_refs(im_dtc_t *c)
{
    const dtc_config_t *cfg = c->cfg;
    const dtc_im_machine_cfg_t *im = &cfg->u.im.machine;
    iq_t te = c->te_cmd_iq;

    if (c->magnetised == 0U && ++c->magn_n >= cfg->u.im.ref.magn_periods) {
        c->magnetised = 1U;
        c->ein.start = 0U;
        im_dtc_psir_ref(c, c->act.flux_ref_iq); /* the estimator's reference of the set in force */
    }
    if (c->magnetised == 0U) {
        /* Casadei eq. 19 at T* = 0: phi_s* = (l_s/m) phi_r*, reached by the magnetising ramp (the host's
         * increment per period, the current below the rated one: im_dtc.h); the estimator's
         * rotor-flux reference follows the ramp at the no-load ratio m/l_s (the machine's rotor
         * flux lags it by sigma tau_r). magn_n <= 65535 times the increment in 64 bits. */
        const iq_t fin = cfg->u.im.ref.psir_ref_iq > 0 ? iq_mpy(im->ks_iq, cfg->u.im.ref.psir_ref_iq)
                                                     : c->act.flux_ref_iq;
        const int64_t ramp = (int64_t)cfg->u.im.ref.magn_ramp_iq * (int64_t)c->magn_n;
        /* The rotor flux the ramp builds, for the estimator's reference (Casadei eq. 20): the T model's
         * rotor equation in rotor-flux coordinates, tau_r d|phi_r|/dt = m i_d - |phi_r|
         * (Casadei eqs. A7, A9 in the frame of phi_r; im-facts.md: the current model of TI's ACI estimator),
         * i_d the current along the estimated rotor-flux direction e^{j theta} (Casadei eq. 22), forward
         * Euler with Ts/tau_r (< 1e-3). A fixed reference (the final phi_r*) would hold the
         * estimate there while the machine is still demagnetised. Formats: IQ pu, Ts/tau_r Q31;
         * rounded products, saturating sums. */
        const iq_t i_d = iq_add(iq_mpy(c->i.i_alpha_iq, c->est.u_alpha_iq), iq_mpy(c->i.i_beta_iq, c->est.u_beta_iq));
        c->magn_psir_iq = iq_add(c->magn_psir_iq,
                                 q31_mul(cfg->u.im.ref.magn_k_q31, iq_sub(iq_mpy(im->m_iq, i_d), c->magn_psir_iq)));
        te = 0;
        c->psi_ref_iq = ramp < (int64_t)fin ? (iq_t)ramp : fin;
        c->psir_ref_iq = c->magn_psir_iq > 0 ? c->magn_psir_iq : 0;
        c->ref_due = 1U;
    } else if (cfg->u.im.fw.on != 0U) {
        /* Section 12.2 watches the torque comparator: the torque demand was met in a period when
         * the comparator asked for less torque in the sense of T_command (the previous step's
         * decision, acting now). With ST-A/ST-B and a band that is the null vector of the text;
         * with Casadei Table 1 and a zero band the comparator goes from +1 straight to -1 (V_{k-1},
         * V_{k-2}) and never applies a null vector, at any speed. */
        const uint16_t met = (uint16_t)(te >= 0 ? (c->tdem_1 <= 0 ? 1U : 0U) : (c->tdem_1 >= 0 ? 1U : 0U));
        te = im_fw_step(&c->fw, &c->fw_p, met, te);
        c->psi_ref_iq = c->fw.psi_ref_iq;
        im_dtc_psir_ref(c, c->psi_ref_iq);
    } else if (cfg->u.im.ref.psir_ref_iq > 0) {
        /* the trim, then Casadei eq. 19 (a square root) with it, once per speed period, each in
         * a step that carries no other once-per-speed-period work (im_dtc_internal.h
         * im_trim_slot, im_dtc.h ref_slot; the same step with speed_div <= 6): ref_due 1 the
         * trim is due, 2 eq. 19 */
        if (c->ref_due == 1U && c->div_cnt == im_trim_slot(c)) {
            im_psir_trim(c);
            c->ref_due = 2U;
        }
        if (c->ref_due == 2U && c->div_cnt == c->ref_slot) {
            c->psi_ref_iq = iq_add(im_ref_stator_flux(im->ks_iq, im->sigma_lr_iq, cfg->u.im.ref.psir_ref_iq,
                                                      cfg->u.im.ref.inv_psir_ref_iq, te),
                                   iq_mpy(im->ks_iq, c->psir_trim_iq));
            c->ref_due = 0U;
        }
    } else {
        c->psi_ref_iq = c->act.flux_ref_iq;
    }
    c->te_ref_iq = te;
}

/* DSC's flux path by speed: Casadei sec. 9's hexagon above the speed at which sec. 8 hands ST-D over
 * to ST-A (u.im.table_speed_iq: half the speed at which the back-EMF reaches V_dc/sqrt3, so that
 * below it the null vectors fill more than half of each period), the circular path of ST-D below
 * it (Depenbrock's low-speed remedy for DSC, Casadei refs. [5], [6]: a DSC drive runs a circular
 * path at low speed), with a hysteresis of 1/16 of that speed either side, so that a speed held at
 * the threshold does not toggle. Why: with the long null intervals of low speed the hexagon's
 * path leaves Casadei eq. 20's correction a mean (phi_r* - |phi_r|)/tau that the estimator turns
 * into an angle error (im_psir_trim), and at light load the torque error is that angle times
 * i_d/i_q (docs/sil.md, the IM torque accuracy). Returns 1 while the hexagon runs; c->dsc_on is 0
 * on the circular path, so that the hexagon is re-seeded from the flux (dsc_reset) when it resumes.
 * Formats: speeds IQ pu; the threshold's 1/16 a rounded shift, the sums below 2^31 for any speed
 * limit the configuration accepts. */
static inline uint16_t im_dsc_hexagon(im_dtc_t *c)
{
    const iq_t ws = c->cfg->u.im.table_speed_iq, w = fix_abs32(c->speed_iq);
    const iq_t h = fix_rshift_rnd32(ws, 4U);
    const uint16_t hex = c->dsc_on != 0U ? (uint16_t)(w >= ws - h ? 1U : 0U) : (uint16_t)(w > ws + h ? 1U : 0U);
    if (hex == 0U) {
        c->dsc_on = 0U;
    }
    return hex;
}

/* Comparators and vector selection (Casadei sections 4-9), then the current limit (im_ilim).
 * Returns the SSTP vector 0..7. */
uint16_t im_dtc_select(im_dtc_t *c, iq_t te, dtc_out_t *o)
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t psi_a = c->est.psi_alpha_iq, psi_b = c->est.psi_beta_iq;
    const iq_t err = iq_sub(c->te_ref_iq, te);
    const uint16_t flux_up = hyst2_sq_step(&c->h_flux, c->psi_ref_iq, iq_sumsq_q48(psi_a, psi_b));
    const uint16_t sector = sector_sstp(psi_a, psi_b);
    uint16_t vec, table = cfg->u.im.sw.sstp_table;
    int16_t tdem;

    if (c->magnetised == 0U) {
        vec = im_magn_vector(c, sector, flux_up, err, &tdem);
    } else if (cfg->law == DTC_LAW_IM_DSC && im_dsc_hexagon(c) != 0U) {
        /* Section 9. The hexagon turns with the rotor (the sign of the speed; at standstill the
         * sign of T*): the flux then leads the rotor under the active vectors (torque up in the
         * sense of rotation) and falls back under the null vectors (torque down). The hexagon
         * keeps the flux's amplitude only while its active vectors run; under the long null
         * intervals of low speed and light load the machine's flux decays through R_s (to 0.045
         * Wb for 0.55 on the 4 kW IM at 72 rpm and 10 % torque, the torque of the wrong sign)
         * while Casadei eq. 20's correction holds the estimate's amplitude, so the hexagon's
         * comparators never see it. Where the null is asked for and the flux lies inside the
         * hexagon by more than the flux comparator's half band (flux_up), ST-D's vector that
         * raises the flux in the same torque sense replaces it (Casadei Table 3: V_k+1 / V_k-1):
         * section 9's DTC with a wide flux band, which reproduces DSC, holding the amplitude
         * there. On the hexagon |phi_s| >= phi_s* and flux_up stays 0: the hexagon runs as
         * before. */
        const uint16_t ccw = (uint16_t)(c->speed_iq > 0 || (c->speed_iq == 0 && c->te_ref_iq >= 0) ? 1U : 0U);
        const uint16_t up = hyst2_step(&c->h_torque2, err);
        uint16_t act;
        if (c->dsc_on == 0U || ccw != c->dsc.ccw) {
            dsc_reset(&c->dsc, ccw, psi_a, psi_b);
            c->dsc_on = 1U;
        }
        act = dsc_step(&c->dsc, psi_a, psi_b, c->psi_ref_iq);
        tdem = up != 0U ? 1 : -1;
        vec = (up != 0U) == (ccw != 0U) ? act : (flux_up != 0U ? swtab_sstp_st(DTC_ST_D, sector, 1U, up) : SWTAB_NULL);
    } else {
        if (cfg->law == DTC_LAW_IM_DSC) {
            table = DTC_ST_D; /* DSC's circular path (im_dsc_hexagon) */
        } else if (table == DTC_ST_SPEED) {
            /* Section 8: ST-D at low speed, ST-A at high speed. */
            table = fix_abs32(c->speed_iq) < cfg->u.im.table_speed_iq ? DTC_ST_D : DTC_ST_A;
        }
        if (table == DTC_ST_BASIC) {
            tdem = hyst3_step(&c->h_torque3, err);
            vec = swtab_sstp_basic(sector, flux_up, tdem);
        } else {
            const uint16_t up = hyst2_step(&c->h_torque2, err);
            tdem = up != 0U ? 1 : -1;
            vec = swtab_sstp_st(table, sector, flux_up, up);
        }
    }
    o->sector = sector;
    o->flux_up = flux_up;
    o->torque_dem = tdem;
    return im_ilim(c, swtab_null_choice(vec, c->vec_1));
}

void im_dtc_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    im_dtc_table_step(c, m, o, 0U);
}

void im_dtc_i_pred(const im_dtc_t *c, iq_t vdc_iq, iq_t i1[3])
{
    const dtc_config_t *cfg = c->cfg;
    const iq_t wa = iq_mpy(c->speed_iq, c->ip_a_iq); /* w a: the rotation's gain this period */
    /* (w Ts)^2 / 2 / (sigma l_s) = w a (w Ts) / 2: the rotation's second-order term */
    const iq_t h = fix_rshift_rnd32(iq_mpy(wa, iq_mpy(c->speed_iq, cfg->board.ts_pu_iq)), 1U);
    const iq_t ia = c->i.i_alpha_iq, ib = c->i.i_beta_iq;
    /* x = phi_s - sigma l_s i of this step: the estimator's (im_est_flux, the same sigma l_s,
     * flux and current), not formed again */
    const iq_t xa = c->est.x_alpha_iq, xb = c->est.x_beta_iq;
    iq_t va, vb;
    clarke_out_t o;

    if (cfg->board.topology == DTC_TOPO_FSTP) {
        /* the FSTP's legs B, C (im_dtc_fstp.c), leg A on the mid-point taken at V_dc/2 (Hoang eqs.
         * 17-19): the mid-point's slow swing is a bias the plausibility learns */
        vrec_fstp(c->legs_2.sb, c->legs_2.sc, vdc_iq, 0, 0U, &va, &vb);
    } else if (cfg->law == DTC_LAW_IM_DTC || cfg->law == DTC_LAW_IM_DSC) {
        /* the legs returned by the previous step act in the coming period (im_dtc.h timing) */
        vrec_sstp(c->legs_2.sa, c->legs_2.sb, c->legs_2.sc, vdc_iq, &va, &vb);
    } else {
        /* kept by im_pwm_out / im_dsvm_select for the coming period (d_eff: the dead time is in
         * it), with the device drops of this period's currents (im_sfvc_estimate: the SSTP's
         * equal drops do not depend on the legs) */
        va = fix_add32(c->v2_alpha_iq, c->dva_iq);
        vb = fix_add32(c->v2_beta_iq, c->dvb_iq);
    }
    /* i + a v - g i + b phi_s - (e^{j w Ts} - 1) x / (sigma l_s), x = phi_s - sigma l_s i
     * (Casadei eq. 21 over k_r), e^{j w Ts} - 1 ~ j w Ts - (w Ts)^2 / 2: - w a j x + h x,
     * j x = (-x_beta, x_alpha) (im_dtc.h) */
    clarke_inv(fix_add32(fix_add32(fix_sub32(fix_add32(ia, iq_mpy(c->ip_a_iq, va)), iq_mpy(c->ip_g_iq, ia)),
                                   iq_mpy(c->ip_b_iq, c->est.psi_alpha_iq)),
                         fix_add32(iq_mpy(wa, xb), iq_mpy(h, xa))),
               fix_add32(fix_sub32(fix_add32(ib, iq_mpy(c->ip_a_iq, vb)), iq_mpy(c->ip_g_iq, ib)),
                         fix_sub32(iq_mpy(c->ip_b_iq, c->est.psi_beta_iq), fix_sub32(iq_mpy(wa, xa), iq_mpy(h, xb)))),
               &o);
    i1[0] = o.ia_iq;
    i1[1] = o.ib_iq;
    i1[2] = o.ic_iq;
}
