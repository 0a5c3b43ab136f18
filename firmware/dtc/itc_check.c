/* itc_check.c - the PM indirect torque control's configuration check (itc.h itc_check): the common
 * part (dtc_config.c), then the law's part u.pm_itc and the common settings as this law takes them.
 * Init-only code: its own file in the archive dtc_config, which the F2812 image keeps in flash
 * (firmware/CMakeLists.txt). */
#include "itc.h"

#include <limits.h>
#include <stddef.h>

/* The part's parameter rows (DTC_PARAMS_PM_ITC, dtc_param.h). */
#define DTC_PARAMS_PM_ITC_ROW(...) DTC_PARAM_ROW(DTC_PP_PM_ITC, __VA_ARGS__)
DTC_PARAM_TABLE(dtc_params_pm_itc, DTC_PARAMS_PM_ITC, DTC_PARAMS_PM_ITC_ROW);

static int16_t itc_part_check(const dtc_config_t *cfg, const char **f)
{
    const dtc_pm_itc_cfg_t *p = &cfg->u.pm_itc;
    /* the mid-point regulation needs the FSTP with its mid-point measured (itc.h) */
    const uint16_t mid = (uint16_t)(cfg->board.topology == DTC_TOPO_FSTP && cfg->board.fstp_vmid_measured != 0U);
    const int16_t err = dtc_param_check_rows(cfg, &dtc_params_pm_itc, f); /* the part's tag first */

    if (err != DTC_OK) {
        return err;
    }
    DTC_REFUSE(cfg->est.estimator > DTC_EST_CURRENT, DTC_ERR_VARIANT, "est.estimator");
    DTC_REFUSE(cfg->speed.sensor != DTC_SPEED_ENCODER, DTC_ERR_VARIANT, "speed.sensor");
    DTC_REFUSE(p->mid.g_iq > 0 && mid == 0U, DTC_ERR_DCSUPP, "u.pm_itc.mid.g_iq");
    DTC_REFUSE(p->mid.g_iq > 0 && p->mid.kf_iq <= 0, DTC_ERR_DCSUPP, "u.pm_itc.mid.kf_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.wc_pu_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_itc.est.wc_pu_iq");
    DTC_REFUSE(p->est.lpf_comp != 0U && p->est.lpf_wmin_iq <= 0, DTC_ERR_LPFCOMP, "u.pm_itc.est.lpf_wmin_iq");
    return DTC_OK;
}

int16_t itc_check(const dtc_config_t *cfg, const char **field)
{
    return dtc_config_check_law(cfg, DTC_LAW_PM_ITC, DTC_LAW_PM_ITC, itc_part_check, field);
}
