#include "dtc_config.h"

#include <limits.h>
#include <stddef.h>

/* The part's parameter rows (DTC_PARAMS_COMMON, dtc_param.h). */
#define DTC_PARAMS_COMMON_ROW(...) DTC_PARAM_ROW(DTC_PP_COMMON, __VA_ARGS__)
DTC_PARAM_TABLE(dtc_params_common, DTC_PARAMS_COMMON, DTC_PARAMS_COMMON_ROW);

/* Trip levels the ADC can see. The trips fire on a reading strictly above the level (app_core.c),
 * so a level at or above the largest reading never fires: the reading clamps first. Current:
 * the largest |i| a measured channel reads is its gain times the smaller side of its offset, in
 * counts, less the calibration's tolerance DTC_ADC_OFFSET_TOL_COUNTS (the calibrated offset may
 * sit that far off nominal); the channels are the measured ones (all three, or SSTP A and B,
 * FSTP B and C). DC link: the gain times the counts above its offset. Init only; 64-bit products
 * of a gain (IQ) and a count (< 2^12) cannot overflow. */
static int16_t dtc_range_check(const dtc_config_t *c, const char **f)
{
    const dtc_board_cfg_t *b = &c->board;
    uint16_t k;
    int64_t head = 4095;
    for (k = 0U; k < 3U; k++) {
        const int64_t lo = (int64_t)b->adc_i_offset[k], hi = 4095 - (int64_t)b->adc_i_offset[k];
        const uint16_t measured =
            (uint16_t)(b->i_sensors3 != 0U || (b->topology == DTC_TOPO_FSTP ? k != 0U : k != 2U));
        if (measured != 0U) {
            head = lo < head ? lo : head;
            head = hi < head ? hi : head;
        }
    }
    head -= DTC_ADC_OFFSET_TOL_COUNTS;
    DTC_REFUSE((int64_t)c->prot.i_trip_iq >= (int64_t)b->adc_i_gain_iq * head, DTC_ERR_LIMIT, "prot.i_trip_iq");
    DTC_REFUSE((int64_t)c->prot.vdc_max_iq >= (int64_t)b->adc_vdc_gain_iq * (4095 - (int64_t)b->adc_vdc_offset),
               DTC_ERR_LIMIT, "prot.vdc_max_iq");
    return DTC_OK;
}

/* The relations between fields of the common part; each field's own range is its row's. */
static int16_t dtc_common_relations(const dtc_config_t *cfg, const char **f)
{
    const dtc_protect_cfg_t *p = &cfg->prot;
    const dtc_speed_cfg_t *s = &cfg->speed;
    const uint16_t topology = cfg->board.topology, comp = cfg->est.compensation;
    DTC_REFUSE(p->vdc_min_iq >= p->vdc_max_iq, DTC_ERR_LIMIT, "prot.vdc_min_iq");
    DTC_REFUSE(p->i_lim_iq > 0 && p->i_lim_iq >= p->i_trip_iq, DTC_ERR_ILIM, "prot.i_lim_iq");
    DTC_REFUSE(p->i_hold_iq >= p->i_trip_iq, DTC_ERR_ILIM, "prot.i_hold_iq");
    DTC_REFUSE(p->i_plaus != 0U && p->leg_i_min_iq <= 0, DTC_ERR_FAULTDET, "prot.i_plaus");
    /* at or below the speed limit a permitted reference would trip */
    DTC_REFUSE(p->overspeed_iq > 0 && p->overspeed_iq <= s->speed_limit_iq, DTC_ERR_LIMIT, "prot.overspeed_iq");
    /* the sum of two measured and one derived current is 0 */
    DTC_REFUSE(p->i_sum_max_iq > 0 && cfg->board.i_sensors3 == 0U, DTC_ERR_FAULTDET, "prot.i_sum_max_iq");
    DTC_REFUSE((topology == DTC_TOPO_SSTP && (comp == DTC_COMP_FSTP_SIMPLE || comp == DTC_COMP_FSTP_PROPOSED)) ||
                   (topology == DTC_TOPO_FSTP && (comp == DTC_COMP_SSTP || comp == DTC_COMP_SSTP_PROPOSED)),
               DTC_ERR_COMPENSATION, "est.compensation");
    DTC_REFUSE(s->speed_ref_iq > s->speed_limit_iq || s->speed_ref_iq < -s->speed_limit_iq, DTC_ERR_REFERENCE,
               "speed.speed_ref_iq");
    DTC_REFUSE(s->torque_ref_iq > s->torque_limit_iq || s->torque_ref_iq < -s->torque_limit_iq,
               DTC_ERR_REFERENCE, "speed.torque_ref_iq");
    return DTC_OK;
}

int16_t dtc_config_check_common(const dtc_config_t *cfg, const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    int16_t err;

    *f = "";
    if (cfg == NULL) {
        return DTC_ERR_NULL;
    }
    /* version first, then law: the rows of the law's part are read only for a known law */
    err = dtc_param_check_rows(cfg, &dtc_params_common, f);
    if (err == DTC_OK) {
        err = dtc_common_relations(cfg, f);
    }
    if (err == DTC_OK) {
        err = dtc_range_check(cfg, f);
    }
    return err;
}

int16_t dtc_config_check_law(const dtc_config_t *cfg, uint16_t first, uint16_t last,
                             int16_t (*part)(const dtc_config_t *cfg, const char **f), const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    const int16_t err = dtc_config_check_common(cfg, f);
    if (err != DTC_OK) {
        return err;
    }
    DTC_REFUSE(cfg->law < first || cfg->law > last, DTC_ERR_VARIANT, "law");
    return part(cfg, f);
}

int16_t dtc_config_law_init_begin(const dtc_config_t **law_cfg, const dtc_config_t *cfg,
                                  int16_t (*check)(const dtc_config_t *cfg, const char **field))
{
    if (law_cfg == NULL) {
        return DTC_ERR_NULL;
    }
    *law_cfg = NULL;
    return check(cfg, NULL);
}
