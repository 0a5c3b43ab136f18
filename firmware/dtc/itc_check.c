/* itc_check.c - the PM indirect torque control's configuration check (itc.h itc_check): the common
 * part (dtc_config.c), then the law's part u.pm_itc and the common settings as this law takes them.
 * Init-only code: its own file in the archive dtc_config, which the F2812 image keeps in flash
 * (firmware/CMakeLists.txt). */
#include "itc.h"

#include <stddef.h>

static int16_t itc_part_check(const dtc_config_t *cfg, const char **f)
{
    const dtc_pm_itc_cfg_t *p = &cfg->u.pm_itc;
    /* the mid-point regulation needs the FSTP with its mid-point measured (itc.h) */
    const uint16_t mid = (uint16_t)(cfg->board.topology == DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U);

    DTC_REFUSE(p->part != DTC_PART_PM_ITC, DTC_ERR_PART, "u.pm_itc.part");
    DTC_REFUSE(cfg->est.estimator > DTC_EST_CURRENT, DTC_ERR_VARIANT, "est.estimator");
    DTC_REFUSE(cfg->speed.sensor != DTC_SPEED_ENCODER, DTC_ERR_VARIANT, "speed.sensor");
    DTC_REFUSE(p->machine.ls_iq <= 0, DTC_ERR_MACHINE, "u.pm_itc.machine.ls_iq");
    DTC_REFUSE(p->machine.psi_m_iq <= 0, DTC_ERR_MACHINE, "u.pm_itc.machine.psi_m_iq");
    DTC_REFUSE(p->machine.inv_ls_iq <= 0, DTC_ERR_MACHINE, "u.pm_itc.machine.inv_ls_iq");
    DTC_REFUSE(p->cc.kp_iq <= 0, DTC_ERR_SVM, "u.pm_itc.cc.kp_iq");
    DTC_REFUSE(p->cc.ki_ts_iq <= 0, DTC_ERR_SVM, "u.pm_itc.cc.ki_ts_iq");
    DTC_REFUSE(p->cc.iq_per_t_iq <= 0, DTC_ERR_SVM, "u.pm_itc.cc.iq_per_t_iq");
    DTC_REFUSE(p->mid.g_iq < 0 || (p->mid.g_iq > 0 && mid == 0U), DTC_ERR_DCSUPP, "u.pm_itc.mid.g_iq");
    DTC_REFUSE(p->mid.g_iq > 0 && (p->mid.kf_iq <= 0 || p->mid.kf_iq >= ((iq_t)1 << FIX_IQ_Q)), DTC_ERR_DCSUPP,
               "u.pm_itc.mid.kf_iq");
    DTC_REFUSE(p->est.lpf_comp > 1U, DTC_ERR_LPFCOMP, "u.pm_itc.est.lpf_comp");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.wc_pu_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_itc.est.wc_pu_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.lpf_wmin_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_itc.est.lpf_wmin_iq");
    return DTC_OK;
}

int16_t itc_check(const dtc_config_t *cfg, const char **field)
{
    return dtc_config_check_law(cfg, DTC_LAW_PM_ITC, DTC_LAW_PM_ITC, itc_part_check, field);
}
