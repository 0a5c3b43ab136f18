/*
 * dtc_config.h - the firmware's configuration: a common part every law uses
 * (dtc_config_common.h) and one part per control law (u), selected by the one enum dtc_law, in
 * per-unit Q formats (dtc_base.h).
 *
 * The struct is produced on the host from SI values by tools/config (dtc_config_from_si(), which
 * also precomputes every reciprocal so the firmware never divides) and may be emitted as a C
 * source file for a target build (dtc_config_emit_c(), designated initialisers of the law's
 * member only). The firmware re-checks it at init: dtc_config_check_common() here, then the law's
 * own check (dtc_check, im_dtc_check), both reached through law_check / law_init (app/law.h); a
 * corrupted or hand-edited struct is refused with a code from enum dtc_err.
 *
 * The laws' parts exist only for the laws linked into the image (DTC_LAW_PM_LINKED,
 * DTC_LAW_IM_LINKED, DTC_LAW_ITC_LINKED from DTC_LAWS, firmware/CMakeLists.txt; all when not defined): a PM image
 * carries no IM field and the reverse. The union is the struct's last member, so each law's part
 * sits at the same offset whichever laws a translation unit sees, and a law's code reads its part
 * only after law.c has checked that the configuration is that law's and that the law is linked.
 */
#ifndef DTC_CONFIG_H
#define DTC_CONFIG_H

#include <stdint.h>

#include "dtc_config_common.h"
#include "dtc_param.h"
#include "im_cfg.h"
#include "pm_dtc_cfg.h"
#include "pm_itc_cfg.h"

#ifndef DTC_LAW_PM_LINKED
#define DTC_LAW_PM_LINKED 1
#endif
#ifndef DTC_LAW_IM_LINKED
#define DTC_LAW_IM_LINKED 1
#endif
#ifndef DTC_LAW_ITC_LINKED
#define DTC_LAW_ITC_LINKED 1
#endif
#if !DTC_LAW_PM_LINKED && !DTC_LAW_IM_LINKED && !DTC_LAW_ITC_LINKED
#error "DTC_LAWS links no control law"
#endif

struct dtc_config {
    uint16_t version;          /* DTC_CONFIG_VERSION */
    uint16_t law;              /* enum dtc_law: selects the member of u */
    dtc_board_cfg_t board;
    dtc_protect_cfg_t prot;
    dtc_machine_cfg_t machine;
    dtc_est_cfg_t est;
    dtc_speed_cfg_t speed;
    union {
#if DTC_LAW_PM_LINKED
        dtc_pm_dtc_cfg_t pm_dtc; /* DTC_LAW_PM_DTC */
#endif
#if DTC_LAW_IM_LINKED
        dtc_im_cfg_t im;         /* DTC_LAW_IM_DTC .. DTC_LAW_IM_DSVM */
#endif
#if DTC_LAW_ITC_LINKED
        dtc_pm_itc_cfg_t pm_itc; /* DTC_LAW_PM_ITC */
#endif
    } u;
};

typedef struct dtc_config dtc_config_t;

/* Checks the common part: version, the law's value (a known enum dtc_law), board, protection,
 * the ADC's view of the trip levels, machine, estimator and speed loop, each as every law needs
 * it. Returns DTC_OK, DTC_ERR_NULL for a null cfg, or the first enum dtc_err code found; *field
 * (if not null) then names the offending field as "part.field" (a string constant), "" on
 * DTC_OK. Pure, init only. Each law's check calls it first, then checks its own part. */
int16_t dtc_config_check_common(const dtc_config_t *cfg, const char **field);
/* A law's check: dtc_config_check_common, then DTC_ERR_VARIANT ("law") unless first <= cfg->law <=
 * last (the laws of the checking module), then part(cfg) (the law's part, DTC_REFUSE style).
 * *field as above. */
int16_t dtc_config_check_law(const dtc_config_t *cfg, uint16_t first, uint16_t last,
                             int16_t (*part)(const dtc_config_t *cfg, const char **f), const char **field);
/* The start of a law's init (dtc_init, im_dtc_init, itc_init): DTC_ERR_NULL when there is no law
 * state (law_cfg null); else the law's configuration pointer *law_cfg is cleared, so that a law
 * whose init is refused is never stepped, and cfg goes through the law's check. Returns DTC_OK
 * or the check's code; the law sets *law_cfg itself once its init has succeeded. Init only. */
int16_t dtc_config_law_init_begin(const dtc_config_t **law_cfg, const dtc_config_t *cfg,
                                  int16_t (*check)(const dtc_config_t *cfg, const char **field));

#endif /* DTC_CONFIG_H */
