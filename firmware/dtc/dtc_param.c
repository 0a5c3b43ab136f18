/* dtc_param.c - access to a configuration field through its description row (dtc_param.h).
 * Init and background code: 64-bit comparisons, no division, nothing in the 50 us path. */
#include "dtc_param.h"

#include <stddef.h>

#include "dtc_config.h"

int64_t dtc_param_raw(const struct dtc_config *cfg, const dtc_param_t *p)
{
    const void *a = (const char *)cfg + p->offset;
    switch (p->fmt) {
    case DTC_PF_U16:
    case DTC_PF_ANGLE:
        return (int64_t)*(const uint16_t *)a;
    case DTC_PF_U32:
        return (int64_t)*(const uint32_t *)a;
    case DTC_PF_Q15:
        return (int64_t)*(const int16_t *)a;
    default: /* DTC_PF_IQ, DTC_PF_Q31 */
        return (int64_t)*(const int32_t *)a;
    }
}

int16_t dtc_param_store(struct dtc_config *cfg, const dtc_param_t *p, int64_t raw)
{
    void *a = (char *)cfg + p->offset;
    switch (p->fmt) {
    case DTC_PF_U16:
    case DTC_PF_ANGLE:
        if (raw < 0 || raw > 65535) {
            return -1;
        }
        *(uint16_t *)a = (uint16_t)raw;
        return 0;
    case DTC_PF_U32:
        if (raw < 0 || raw > 4294967295LL) {
            return -1;
        }
        *(uint32_t *)a = (uint32_t)raw;
        return 0;
    case DTC_PF_Q15:
        if (raw < -32768 || raw > 32767) {
            return -1;
        }
        *(int16_t *)a = (int16_t)raw;
        return 0;
    default:
        if (raw < DTC_I32_MIN || raw > DTC_I32_MAX) {
            return -1;
        }
        *(int32_t *)a = (int32_t)raw;
        return 0;
    }
}

uint16_t dtc_param_in_range(const dtc_param_t *p, int64_t raw)
{
    return (uint16_t)(raw >= p->lo && raw <= p->hi ? 1U : 0U);
}

int16_t dtc_param_check_rows(const struct dtc_config *cfg, const dtc_param_list_t *list, const char **f)
{
    uint16_t k;
    for (k = 0U; k < list->n; k++) {
        const dtc_param_t *p = &list->rows[k];
        if (dtc_param_in_range(p, dtc_param_raw(cfg, p)) == 0U) {
            *f = p->name;
            return p->err;
        }
    }
    return DTC_OK;
}

const char *dtc_param_unit(uint16_t qty)
{
    static const char *const unit[DTC_PQ_COUNT] = {
        "", "", "pu", "V", "A", "rad/s", "Wb", "N.m", "ohm", "H", "1/H", "1/Wb", "s", "rad", "A/count",
        "V/count", "N.m s/rad"};
    return qty < (uint16_t)DTC_PQ_COUNT ? unit[qty] : "";
}
