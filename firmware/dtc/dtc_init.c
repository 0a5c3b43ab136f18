/*
 * dtc_init.c - initialisation of the PM law (dtc.h dtc_init) and the PM laws' estimator
 * parameters (dtc_refs.h dtc_pm_est_params_from_config, for dtc_init and itc_init). Runs once,
 * from app_init in the background before the control interrupt starts: built into the init-only
 * archive dtc_init, which the F2812 image keeps in flash (firmware/CMakeLists.txt), so it costs
 * no zero-wait RAM.
 */
#include "dtc.h"
#include "dtc_internal.h"
#include "svm.h"

#include <stddef.h>

int16_t dtc_init(dtc_t *c, const dtc_config_t *cfg)
{
    dtc_refs_t r;
    const int16_t err = dtc_config_law_init_begin(c != NULL ? &c->cfg : NULL, cfg, dtc_check);

    if (err != DTC_OK) {
        return err;
    }
    c->cfg = cfg;

    dtc_pm_est_params_from_config(&c->fe_p, &c->vc_p, cfg, &cfg->u.pm_dtc.machine);
    vcomp_pt_init(&c->vc_pt, &c->vc_p);
    dtc_block_params(c, cfg);
    dtc_speed_params_from_config(&c->sm_p, &c->pi_p, cfg);

    dtc_refs_start(&c->act, &c->sh, &r, cfg);
    c->te_ref_iq = 0;
    dtc_refs_adopt(&c->act, &c->pi_p, &c->pi, &c->te_trim_iq, c->te_ref_iq, &r, cfg);

    flux_est_init(&c->fe, &c->fe_p);
    speed_meas_init(&c->sm, &c->sm_p, 0U);
    dtc_reset(c);
    return DTC_OK;
}

void dtc_pm_est_params_from_config(flux_est_params_t *fe_p, vcomp_params_t *vc_p, const dtc_config_t *cfg,
                                   const dtc_pm_machine_cfg_t *mach)
{
    fe_p->estimator = cfg->est.estimator;
    fe_p->k_in_q31 = cfg->est.k_in_q31;
    fe_p->k_leak_q31 = cfg->est.k_leak_q31;
    fe_p->rs_iq = cfg->machine.rs_iq;
    fe_p->ls_iq = mach->ls_iq;
    fe_p->psi_m_iq = mach->psi_m_iq;
    fe_p->dl_iq = fix_sub32(mach->lq_iq, mach->ls_iq); /* both > 0 (checked): no saturation */
    /* 1 / l_q by Newton steps (svm_recip: within a few IQ LSB, relative 2^-24; l_q >= 1/128 pu,
     * its row's bound, keeps 1/l_q <= 128 pu); init only: no division in the ISR */
    fe_p->inv_lq_iq = fe_p->dl_iq != 0 ? svm_recip(0, mach->lq_iq) : mach->inv_ls_iq;
    fe_p->enc_gain_q16 = cfg->board.enc_gain_q16;
    fe_p->enc_offset = cfg->board.enc_offset;
    vcomp_init(vc_p, cfg->est.compensation, cfg->board.v_f_iq, cfg->board.v_ce_iq, cfg->board.v_d_iq,
               cfg->board.r_on_iq);
}
