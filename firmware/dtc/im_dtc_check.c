/* im_dtc_check.c - the IM laws' configuration check (im_dtc.h im_dtc_check): the common part
 * (dtc_config.c), then the part u.im, each scheme's sub-struct for its law, and the common
 * settings as these laws take them. Init-only code: its own file in the archive dtc_config, which
 * the F2812 image keeps in flash (firmware/CMakeLists.txt). */
#include "im_dtc.h"

#include <limits.h>
#include <stddef.h>

/* The part's parameter rows (DTC_PARAMS_IM, dtc_param.h). */
#define DTC_PARAMS_IM_ROW(...) DTC_PARAM_ROW(DTC_PP_IM, __VA_ARGS__)
DTC_PARAM_TABLE(dtc_params_im, DTC_PARAMS_IM, DTC_PARAMS_IM_ROW);

static int16_t im_part_check(const dtc_config_t *cfg, const char **f)
{
    const dtc_im_cfg_t *p = &cfg->u.im;
    const uint16_t law = cfg->law;
    const uint16_t svm = (uint16_t)(law == DTC_LAW_IM_SFVC || law == DTC_LAW_IM_DFOC);
    const int16_t err = dtc_param_check_rows(cfg, &dtc_params_im, f); /* the part's tag first */

    if (err != DTC_OK) {
        return err;
    }
    /* Casadei's tables, DSC, DSVM's 19 vectors and the SVM schemes are written for the six-switch
     * inverter; the switching-table DTC also runs the four-switch inverter with Hoang Table II
     * (im_dtc_fstp.c). Section 12's flux weakening watches a comparator with a null vector, which
     * the FSTP has not. */
    DTC_REFUSE(cfg->board.topology != DTC_TOPO_SSTP &&
                   !(cfg->board.topology == DTC_TOPO_FSTP && law == DTC_LAW_IM_DTC && p->fw.on == 0U),
               DTC_ERR_VARIANT, "board.topology");
    DTC_REFUSE(cfg->est.estimator != DTC_EST_VOLTAGE && cfg->est.estimator != DTC_EST_IMPROVED,
               DTC_ERR_VARIANT, "est.estimator");
    /* the low-speed gain of Casadei eq. 20 also corrects the voltage model during the start-up
     * (im_est.h) */
    DTC_REFUSE(p->est.k_lo_q31 <= 0, DTC_ERR_FLUX_EST, "u.im.est.k_lo_q31");
    if (cfg->est.estimator == DTC_EST_IMPROVED) {
        DTC_REFUSE(p->est.k_hi_q31 <= 0, DTC_ERR_FLUX_EST, "u.im.est.k_hi_q31");
        DTC_REFUSE(p->est.w_hi_iq < p->est.w_lo_iq, DTC_ERR_FLUX_EST, "u.im.est.w_hi_iq");
    }
    if (p->fw.on != 0U) {
        /* Casadei section 12's flux weakening watches the three-level torque comparator, which
         * SFVC and DFOC have not and DSVM replaces by a five-level one (hyst5_t) */
        DTC_REFUSE(svm != 0U || law == DTC_LAW_IM_DSVM, DTC_ERR_VARIANT, "u.im.fw.on");
        DTC_REFUSE(p->fw.window < 20U, DTC_ERR_WEAKENING, "u.im.fw.window");
        DTC_REFUSE(p->fw.step_down_iq <= 0, DTC_ERR_WEAKENING, "u.im.fw.step_down_iq");
        DTC_REFUSE(p->fw.step_up_iq <= 0, DTC_ERR_WEAKENING, "u.im.fw.step_up_iq");
        DTC_REFUSE(p->fw.psi_min_iq <= 0, DTC_ERR_WEAKENING, "u.im.fw.psi_min_iq");
        DTC_REFUSE(p->fw.inv_psi_rated_iq <= 0, DTC_ERR_WEAKENING, "u.im.fw.inv_psi_rated_iq");
        DTC_REFUSE(p->fw.kt_iq <= 0, DTC_ERR_WEAKENING, "u.im.fw.kt_iq");
    }
    /* SFVC (Casadei eq. 18) and DFOC take the rotor-flux command (and its reciprocal) */
    DTC_REFUSE(svm != 0U && p->ref.psir_ref_iq <= 0, DTC_ERR_REFERENCE, "u.im.ref.psir_ref_iq");
    DTC_REFUSE(p->ref.psir_ref_iq > 0 && p->ref.inv_psir_ref_iq <= 0, DTC_ERR_REFERENCE,
               "u.im.ref.inv_psir_ref_iq");
    if (law == DTC_LAW_IM_SFVC) {
        /* 0 < K_p Ts <= 1 (a larger gain overshoots the flux error every period) */
        DTC_REFUSE(p->sfvc.kp_iq <= 0 || iq_mpy(p->sfvc.kp_iq, cfg->board.ts_pu_iq) > IQ(1.0), DTC_ERR_SVM,
                   "u.im.sfvc.kp_iq");
    }
    if (law == DTC_LAW_IM_DFOC) {
        DTC_REFUSE(p->dfoc.kp_iq <= 0, DTC_ERR_SVM, "u.im.dfoc.kp_iq");
        DTC_REFUSE(p->dfoc.id_ref_iq <= 0, DTC_ERR_SVM, "u.im.dfoc.id_ref_iq");
        DTC_REFUSE(p->dfoc.iq_per_t_iq <= 0, DTC_ERR_SVM, "u.im.dfoc.iq_per_t_iq");
    }
    if (law == DTC_LAW_IM_DSVM) {
        DTC_REFUSE(p->dsvm.torque_band2_iq < p->sw.torque_band_iq, DTC_ERR_BAND, "u.im.dsvm.torque_band2_iq");
    }
    return DTC_OK;
}

int16_t im_dtc_check(const dtc_config_t *cfg, const char **field)
{
    return dtc_config_check_law(cfg, DTC_LAW_IM_DTC, DTC_LAW_IM_DSVM, im_part_check, field);
}
