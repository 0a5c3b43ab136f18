/* dtc_params.c - the parameter rows of the image's linked parts by id (dtc_params.h). Compiled
 * with the image's DTC_LAW_*_LINKED, so it names the law parts' row tables only for linked laws.
 * Background code: linear searches over about 150 rows, no division. */
#include "dtc_params.h"

#include <stddef.h>

static const dtc_param_list_t *const dtc_param_lists[] = {
    &dtc_params_common,
#if DTC_LAW_PM_LINKED
    &dtc_params_pm_dtc,
#endif
#if DTC_LAW_IM_LINKED
    &dtc_params_im,
#endif
#if DTC_LAW_ITC_LINKED
    &dtc_params_pm_itc,
#endif
};
#define DTC_PARAM_NLISTS ((uint16_t)(sizeof dtc_param_lists / sizeof dtc_param_lists[0]))

uint16_t dtc_param_count(void)
{
    uint16_t k, n = 0U;
    for (k = 0U; k < DTC_PARAM_NLISTS; k++) {
        n = (uint16_t)(n + dtc_param_lists[k]->n);
    }
    return n;
}

const dtc_param_t *dtc_param_at(uint16_t i)
{
    uint16_t k;
    for (k = 0U; k < DTC_PARAM_NLISTS; k++) {
        if (i < dtc_param_lists[k]->n) {
            return &dtc_param_lists[k]->rows[i];
        }
        i = (uint16_t)(i - dtc_param_lists[k]->n);
    }
    return NULL;
}

const dtc_param_t *dtc_param_find(uint16_t id)
{
    uint16_t k, j;
    for (k = 0U; k < DTC_PARAM_NLISTS; k++) {
        for (j = 0U; j < dtc_param_lists[k]->n; j++) {
            if (dtc_param_lists[k]->rows[j].id == id) {
                return &dtc_param_lists[k]->rows[j];
            }
        }
    }
    return NULL;
}

const dtc_param_list_t *dtc_param_law_list(uint16_t law)
{
#if DTC_LAW_PM_LINKED
    if (law == (uint16_t)DTC_LAW_PM_DTC) {
        return &dtc_params_pm_dtc;
    }
#endif
#if DTC_LAW_IM_LINKED
    if (dtc_law_is_im(law) != 0U) {
        return &dtc_params_im;
    }
#endif
#if DTC_LAW_ITC_LINKED
    if (law == (uint16_t)DTC_LAW_PM_ITC) {
        return &dtc_params_pm_itc;
    }
#endif
    (void)law;
    return NULL;
}

uint16_t dtc_param_of_law(const dtc_param_t *p, uint16_t law)
{
    const dtc_param_list_t *l = dtc_param_law_list(law);
    if (p->part == (uint16_t)DTC_PP_COMMON) {
        return 1U;
    }
    return (uint16_t)(l != NULL && l->n > 0U && l->rows[0].part == p->part ? 1U : 0U);
}

int16_t dtc_param_get(const dtc_config_t *cfg, const dtc_param_t *p, int32_t *raw)
{
    if (cfg == NULL || p == NULL || raw == NULL) {
        return DTC_ERR_NULL;
    }
    if (dtc_param_of_law(p, cfg->law) == 0U) {
        return DTC_ERR_PART;
    }
    *raw = p->fmt == (uint16_t)DTC_PF_U32 ? (int32_t)(uint32_t)dtc_param_raw(cfg, p) : (int32_t)dtc_param_raw(cfg, p);
    return DTC_OK;
}

int16_t dtc_param_set(dtc_config_t *cfg, const dtc_param_t *p, int32_t raw)
{
    const int64_t v = p != NULL && p->fmt == (uint16_t)DTC_PF_U32 ? (int64_t)(uint32_t)raw : (int64_t)raw;
    if (cfg == NULL || p == NULL) {
        return DTC_ERR_NULL;
    }
    if ((p->flags & DTC_PARAM_RO) != 0U) {
        return DTC_ERR_READONLY;
    }
    if (dtc_param_of_law(p, cfg->law) == 0U) {
        return DTC_ERR_PART;
    }
    if (dtc_param_in_range(p, v) == 0U || dtc_param_store(cfg, p, v) != 0) {
        return p->err;
    }
    return DTC_OK;
}
