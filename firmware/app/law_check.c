/* law_check.c - law.h law_check: the check of a configuration by its law's module, dispatched on
 * the law as law.c dispatches the rest. Init-only and host code (the converter), in its own file
 * so that an image links it only where it is called. */
#include "law.h"

#include <stddef.h>

int16_t law_check(const dtc_config_t *cfg, const char **field)
{
    const char *dummy = "";
    const char **f = field != NULL ? field : &dummy;
    *f = "";
    if (cfg == NULL) {
        return DTC_ERR_NULL;
    }
    switch (cfg->law) {
#if DTC_LAW_PM_LINKED
    case DTC_LAW_PM_DTC:
        return dtc_check(cfg, f);
#endif
#if DTC_LAW_IM_LINKED
    DTC_LAW_IM_CASES:
        return im_dtc_check(cfg, f);
#endif
#if DTC_LAW_ITC_LINKED
    case DTC_LAW_PM_ITC:
        return itc_check(cfg, f);
#endif
    default:
        break;
    }
    /* a law not linked, or no law: the common part's code if it has one, else the law's */
    {
        const int16_t err = dtc_config_check_common(cfg, f);
        if (err != DTC_OK) {
            return err;
        }
    }
    *f = "law";
    return DTC_ERR_VARIANT;
}
