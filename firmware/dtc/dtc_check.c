/* dtc_check.c - the PM DTC law's configuration check (dtc.h dtc_check): the common part
 * (dtc_config.c), then the law's part u.pm_dtc and the common settings as this law takes them.
 * Init-only code: its own file in the archive dtc_config, which the F2812 image keeps in flash
 * (firmware/CMakeLists.txt). */
#include "dtc.h"

#include <stddef.h>

static int16_t dtc_pm_part_check(const dtc_config_t *cfg, const char **f)
{
    const dtc_pm_dtc_cfg_t *p = &cfg->u.pm_dtc;
    /* the mid-point terms need a measured FSTP mid-point; the restoring term also the voltage
     * model and the mid-point calibration it corrects for (dtc.c dtc_vmid_beta) */
    const uint16_t mid = (uint16_t)(cfg->board.topology == DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U);

    DTC_REFUSE(p->part != DTC_PART_PM_DTC, DTC_ERR_PART, "u.pm_dtc.part");
    DTC_REFUSE(cfg->est.estimator > DTC_EST_CURRENT, DTC_ERR_VARIANT, "est.estimator");
    DTC_REFUSE(cfg->speed.sensor != DTC_SPEED_ENCODER, DTC_ERR_VARIANT, "speed.sensor");
    DTC_REFUSE(p->machine.ls_iq <= 0, DTC_ERR_MACHINE, "u.pm_dtc.machine.ls_iq");
    DTC_REFUSE(p->machine.psi_m_iq <= 0, DTC_ERR_MACHINE, "u.pm_dtc.machine.psi_m_iq");
    DTC_REFUSE(p->machine.inv_ls_iq <= 0, DTC_ERR_MACHINE, "u.pm_dtc.machine.inv_ls_iq");
    DTC_REFUSE(p->est.handover_speed_iq < 0, DTC_ERR_HANDOVER, "u.pm_dtc.est.handover_speed_iq");
    DTC_REFUSE(p->est.handover_hyst_iq < 0 || p->est.handover_hyst_iq > p->est.handover_speed_iq,
               DTC_ERR_HANDOVER, "u.pm_dtc.est.handover_hyst_iq");
    DTC_REFUSE(p->est.delay_comp > 1U, DTC_ERR_DELAY, "u.pm_dtc.est.delay_comp");
    DTC_REFUSE(p->est.polarity_mid > 1U, DTC_ERR_POLARITY, "u.pm_dtc.est.polarity_mid");
    DTC_REFUSE(p->est.lpf_comp > 1U, DTC_ERR_LPFCOMP, "u.pm_dtc.est.lpf_comp");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.wc_pu_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_dtc.est.wc_pu_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.lpf_wmin_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_dtc.est.lpf_wmin_iq");
    DTC_REFUSE(p->est.dc_supp > 1U, DTC_ERR_DCSUPP, "u.pm_dtc.est.dc_supp");
    DTC_REFUSE(p->est.dc_supp != 0U && p->est.dcs_k_iq <= 0, DTC_ERR_DCSUPP, "u.pm_dtc.est.dcs_k_iq");
    DTC_REFUSE(p->est.vmid_g_iq < 0 || (p->est.vmid_g_iq > 0 && mid == 0U), DTC_ERR_DCSUPP,
               "u.pm_dtc.est.vmid_g_iq");
    DTC_REFUSE(p->est.vmid_beta_s_iq < 0 ||
                   (p->est.vmid_beta_s_iq > 0 &&
                    (mid == 0U || cfg->est.estimator != DTC_EST_VOLTAGE || cfg->board.vmid_cal == 0U)),
               DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_beta_s_iq");
    DTC_REFUSE(p->sw.sstp_table > DTC_ST_D, DTC_ERR_VARIANT, "u.pm_dtc.sw.sstp_table");
    DTC_REFUSE(p->sw.flux_band_iq < 0, DTC_ERR_BAND, "u.pm_dtc.sw.flux_band_iq");
    DTC_REFUSE(p->sw.torque_band_iq < 0, DTC_ERR_BAND, "u.pm_dtc.sw.torque_band_iq");
    return DTC_OK;
}

int16_t dtc_check(const dtc_config_t *cfg, const char **field)
{
    return dtc_config_check_law(cfg, DTC_LAW_PM_DTC, DTC_LAW_PM_DTC, dtc_pm_part_check, field);
}
