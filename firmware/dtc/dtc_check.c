/* dtc_check.c - the PM DTC law's configuration check (dtc.h dtc_check): the common part
 * (dtc_config.c), then the law's part u.pm_dtc and the common settings as this law takes them.
 * Init-only code: its own file in the archive dtc_config, which the F2812 image keeps in flash
 * (firmware/CMakeLists.txt). */
#include "dtc.h"

#include <limits.h>
#include <stddef.h>

/* The part's parameter rows (DTC_PARAMS_PM_DTC, dtc_param.h). */
#define DTC_PARAMS_PM_DTC_ROW(...) DTC_PARAM_ROW(DTC_PP_PM_DTC, __VA_ARGS__)
DTC_PARAM_TABLE(dtc_params_pm_dtc, DTC_PARAMS_PM_DTC, DTC_PARAMS_PM_DTC_ROW);

static int16_t dtc_pm_part_check(const dtc_config_t *cfg, const char **f)
{
    const dtc_pm_dtc_cfg_t *p = &cfg->u.pm_dtc;
    /* the mid-point terms need a measured FSTP mid-point; the restoring term also the voltage
     * model and the mid-point calibration it corrects for (dtc.c dtc_vmid_beta) */
    const uint16_t mid = (uint16_t)(cfg->board.topology == DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U);
    const int16_t err = dtc_param_check_rows(cfg, &dtc_params_pm_dtc, f); /* the part's tag first */

    if (err != DTC_OK) {
        return err;
    }
    DTC_REFUSE(cfg->est.estimator > DTC_EST_CURRENT, DTC_ERR_VARIANT, "est.estimator");
    DTC_REFUSE(cfg->speed.sensor != DTC_SPEED_ENCODER, DTC_ERR_VARIANT, "speed.sensor");
    DTC_REFUSE(p->est.handover_hyst_iq > p->est.handover_speed_iq, DTC_ERR_HANDOVER, "u.pm_dtc.est.handover_hyst_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.wc_pu_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_dtc.est.wc_pu_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.lpf_wmin_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_dtc.est.lpf_wmin_iq");
    DTC_REFUSE(p->est.dc_supp != 0U && p->est.dcs_k_iq <= 0, DTC_ERR_DCSUPP, "u.pm_dtc.est.dcs_k_iq");
    DTC_REFUSE(p->est.vmid_g_iq > 0 && mid == 0U, DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_g_iq");
    DTC_REFUSE(p->est.vmid_beta_s_iq > 0 &&
                   (mid == 0U || cfg->est.estimator != DTC_EST_VOLTAGE || cfg->board.vmid_cal == 0U),
               DTC_ERR_DCSUPP, "u.pm_dtc.est.vmid_beta_s_iq");
    return DTC_OK;
}

int16_t dtc_check(const dtc_config_t *cfg, const char **field)
{
    return dtc_config_check_law(cfg, DTC_LAW_PM_DTC, DTC_LAW_PM_DTC, dtc_pm_part_check, field);
}
