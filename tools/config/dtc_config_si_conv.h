/*
 * dtc_config_si_conv.h - the converter's internals shared by its common part (dtc_config_si.c)
 * and the laws' parts (law_pm_dtc_si.c, law_pm_itc_si.c, law_im_si.c): the error state of one conversion, the
 * pu-to-Q conversions that refuse what does not fit, and each law part's entry points. Host code,
 * not for the converter's users (dtc_config_si.h).
 */
#ifndef DTC_CONFIG_SI_CONV_H
#define DTC_CONFIG_SI_CONV_H

#include <stddef.h>

#include "dtc_config_si.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* One conversion's error state: the first failure's code, field and message win. */
typedef struct {
    char *msg;
    size_t len;
    int code;
    const char *field; /* the refused member (a row name of dtc_si_params.h), "" if none */
} dtc_si_conv_t;

/* Records the failure (the first one only) of the dtc_config_si_t member field (its row of
 * dtc_si_params.h names it in the error; "" when no one member is at fault) and returns code. */
int dtc_si_fail(dtc_si_conv_t *c, int code, const char *field, const char *fmt, ...);
/* The plain range checks of every row of dtc_si_params.h that applies to si's law and switches,
 * in row order (dtc_si_params.c); returns the first failure's code, or DTC_SI_OK. */
int dtc_si_params_check(dtc_si_conv_t *c, const dtc_config_si_t *si);
/* value (in pu) -> IQ, refusing overflow and a non-zero value that rounds to zero (field: the
 * SI member the value comes from, optionally followed by what was derived from it, "ls_h (1/l_s)";
 * value its SI value, for the message). */
iq_t dtc_si_to_iq(dtc_si_conv_t *c, const char *field, double value, double pu);
/* A gain in (0, 1) -> Q31, refusing what is not representable. */
q31_t dtc_si_to_q31(dtc_si_conv_t *c, const char *field, double v);

/* The PM DTC law's part (law_pm_dtc_si.c): its range checks of the SI fields it reads (returns
 * the first failure's code, or DTC_SI_OK), and its conversion into cfg->u.pm_dtc plus the
 * protection levels only this law uses (the current limit, the rotor-hold current; board.vmid_cal
 * and the common part already converted). */
int dtc_si_pm_dtc_check(dtc_si_conv_t *c, const dtc_config_si_t *si);
void dtc_si_pm_dtc_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg);
/* The PM DTC law's protection levels (law_pm_dtc_si.c), shared with the ITC, which drives the
 * same machine on the same board: the current limit prot.i_lim_iq and the rotor-hold current
 * prot.i_hold_iq. */
/* The current limit's conversion (prot.i_lim_iq: current_limit_a, or dtc_ilim_default_a when
 * derived), every law. Returns the limit in use, A (0 = off). */
double dtc_si_ilim_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg);
void dtc_si_pm_prot_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg);
/* The PM ITC's part (law_pm_itc_si.c): as above, into cfg->u.pm_itc. */
int dtc_si_pm_itc_check(dtc_si_conv_t *c, const dtc_config_si_t *si);
void dtc_si_pm_itc_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg);
/* The IM laws' part (law_im_si.c): as above, into cfg->u.im. */
int dtc_si_im_check(dtc_si_conv_t *c, const dtc_config_si_t *si);
void dtc_si_im_convert(dtc_si_conv_t *c, const dtc_config_si_t *si, const dtc_bases_t *b, dtc_config_t *cfg);

#endif /* DTC_CONFIG_SI_CONV_H */
