/*
 * dtc_reconfig.c - live reconfiguration of the PM law from the SSTP to the FSTP after a leg failure
 * (dtc.h dtc_reconfigure). Runs once, in the ISR that found the failure: built into the
 * init-only archive dtc_init, which the F2812 image keeps in flash (firmware/CMakeLists.txt), so
 * it costs no zero-wait RAM; that one ISR runs it with the flash wait states.
 */
#include "dtc.h"
#include "dtc_internal.h"

#include <stddef.h>

/* Reconfiguration (dtc.h): what is frame-free carries over (speed measurement, speed PI and its
 * integrator, references, torque trim, the low-pass correction factor); the flux estimate and the
 * DC-suppression correction are turned into the new frame (clarke.h clarke_rot_phase), the encoder offset by
 * -x 120 deg (the same angle: theta_e' = theta_e - x 120 deg), so the current model and the
 * voltage model go on from the same flux; the leg history is taken into the new frame (b', c' =
 * the legs x+1, x+2; leg x is off); the comparators restart in the FSTP's state; the drop
 * compensation takes the FSTP's parameters; the hand-over re-decides with post's speeds; the
 * current model drives for a while (below). */
int16_t dtc_reconfigure(dtc_t *c, const dtc_config_t *post, uint16_t phase)
{
    if (phase > 2U || post == NULL || post->law != DTC_LAW_PM_DTC || post->board.topology != DTC_TOPO_FSTP ||
        dtc_check(post, NULL) != DTC_OK) {
        return DTC_ERR_RECONFIG;
    }
    if (c->gains_due != 0U) {
        dtc_speed_gains(c); /* with the configuration the speed was measured under */
    }
    swtab_legs_permute(&c->legs_1, phase);
    swtab_legs_permute(&c->legs_2, phase);
    swtab_legs_permute(&c->legs_3, phase);
    c->cfg = post;
    c->wts_iq = iq_mpy(c->speed_iq, post->board.ts_pu_iq); /* dtc_predict: w Ts of the new period */
    c->fe_p.estimator = post->est.estimator;
    c->fe_p.k_in_q31 = post->est.k_in_q31;
    c->fe_p.k_leak_q31 = post->est.k_leak_q31;
    c->fe_p.enc_offset = (angle_t)(post->board.enc_offset - clarke_phase_angle(phase)); /* -x 120 deg */
    clarke_rot_phase(&c->fe.psi_alpha_iq, &c->fe.psi_beta_iq, phase);
    clarke_rot_phase(&c->dcs_alpha_iq, &c->dcs_beta_iq, phase);
    vcomp_init(&c->vc_p, post->est.compensation, post->board.v_f_iq, post->board.v_ce_iq, post->board.v_d_iq,
               post->board.r_on_iq);
    vcomp_pt_init(&c->vc_pt, &c->vc_p);
    dtc_block_params(c, post);
    hyst2_init(&c->h_flux, post->u.pm_dtc.sw.flux_band_iq, 1U);
    dtc_flux_bounds(c);
    hyst2_init(&c->h_torque2, post->u.pm_dtc.sw.torque_band_iq, 1U);
    c->vec_1 = 1U;
    dtc_reset_currents(c);
    dtc_handover(c);
    /* The voltage model integrated the failed leg's voltage as if it reached the machine since
     * the failure, and until the relay has closed the FSTP's phase A' is not on the mid-point its
     * reconstruction assumes: the current model (encoder) drives, and seeds the low-pass every
     * period, for twice the relay's closing time (prot.relay_periods: the wait, and as long again
     * for the currents to settle on the FSTP); the voltage model then takes over from that flux
     * as at the start-up hand-over. A drive without the relay is not reconfigured. */
    c->cm_hold = (uint16_t)(post->prot.relay_periods > 0x7FFFU ? 0xFFFFU : 2U * post->prot.relay_periods);
    return DTC_OK;
}

