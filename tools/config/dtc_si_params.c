/* dtc_si_params.c - the table of the converter's SI inputs (dtc_si_params.h), its plain range
 * checks and its Markdown table. Host code. */
#include "dtc_si_params.h"
#include "dtc_config_si_conv.h"

#include <math.h>
#include <string.h>

#define DTC_SIP_ROW_(name, type, unit, lo, hi, bounds, laws, when, err, keys, belief, meaning) \
    {#name, type, unit, lo, hi, bounds, laws, when, err, keys, belief, meaning, offsetof(dtc_config_si_t, name)},
const dtc_si_param_t dtc_si_params[] = {DTC_SI_PARAMS(DTC_SIP_ROW_)};
#undef DTC_SIP_ROW_
const size_t dtc_si_param_count = sizeof dtc_si_params / sizeof dtc_si_params[0];

const dtc_si_param_t *dtc_si_param_find(const char *name)
{
    for (size_t i = 0; i < dtc_si_param_count; i++) {
        if (strcmp(dtc_si_params[i].name, name) == 0) {
            return &dtc_si_params[i];
        }
    }
    return NULL;
}

const dtc_si_param_t *dtc_si_param_of_label(const char *label)
{
    size_t n = strcspn(label, " ([/,=:");
    for (size_t i = 0; i < dtc_si_param_count; i++) {
        if (strlen(dtc_si_params[i].name) == n && strncmp(dtc_si_params[i].name, label, n) == 0) {
            return &dtc_si_params[i];
        }
    }
    return NULL;
}

int dtc_si_param_applies(const dtc_si_param_t *p, const dtc_config_si_t *si)
{
    const int law_ok = si->law >= 0 && si->law < DTC_LAW_COUNT;
    if (law_ok ? (p->laws & DTC_SIP_LAW((unsigned)si->law)) == 0U : p->laws != DTC_SIP_ALL) {
        return 0;
    }
    switch (p->when) {
    case DTC_SIP_IF_HANDOVER_GIVEN: return si->handover_auto == 0;
    case DTC_SIP_IF_ILIM_GIVEN: return si->current_limit_auto == 0;
    case DTC_SIP_IF_PI_BW: return si->pi_from_bandwidth != 0;
    case DTC_SIP_IF_PI_GAINS: return si->pi_from_bandwidth == 0;
    case DTC_SIP_IF_RELAY: return si->reconfig_relay == 1;
    default: return 1;
    }
}

int dtc_si_param_in_range(const dtc_si_param_t *p, double v)
{
    if (!isfinite(v)) {
        return 0;
    }
    switch (p->bounds) {
    case DTC_SIP_CLOSED:
    case DTC_SIP_FLAG:
    case DTC_SIP_ENUM: return v >= p->lo && v <= p->hi;
    case DTC_SIP_LO_OPEN: return v > p->lo && v <= p->hi;
    case DTC_SIP_HI_OPEN: return v >= p->lo && v < p->hi;
    case DTC_SIP_OPEN: return v > p->lo && v < p->hi;
    default: return 1;
    }
}

const char *dtc_si_param_range_text(const dtc_si_param_t *p, char *buf, size_t n)
{
    const int lo_inf = p->lo <= -DTC_SIP_INF, hi_inf = p->hi >= DTC_SIP_INF;
    const int lo_open = p->bounds == DTC_SIP_LO_OPEN || p->bounds == DTC_SIP_OPEN;
    const int hi_open = p->bounds == DTC_SIP_HI_OPEN || p->bounds == DTC_SIP_OPEN;
    if (p->bounds == DTC_SIP_ANY || (lo_inf && hi_inf)) {
        snprintf(buf, n, "any finite value");
    } else if (p->bounds == DTC_SIP_FLAG) {
        snprintf(buf, n, "0 or 1");
    } else if (p->type != DTC_SIP_DOUBLE || p->bounds == DTC_SIP_ENUM) {
        snprintf(buf, n, "%g..%g", p->lo, p->hi);
    } else if (hi_inf) {
        snprintf(buf, n, "%s %g", lo_open ? ">" : ">=", p->lo);
    } else if (lo_inf) {
        snprintf(buf, n, "%s %g", hi_open ? "<" : "<=", p->hi);
    } else {
        snprintf(buf, n, "%s%g, %g%s", lo_open ? "(" : "[", p->lo, p->hi, hi_open ? ")" : "]");
    }
    return buf;
}

double dtc_si_param_value(const dtc_si_param_t *p, const dtc_config_si_t *si, int k)
{
    const char *at = (const char *)si + p->offset;
    if (p->type == DTC_SIP_DOUBLE) {
        double v;
        memcpy(&v, at, sizeof v);
        return v;
    }
    {
        int v;
        memcpy(&v, at + (size_t)k * sizeof(int), sizeof v);
        return (double)v;
    }
}

int dtc_si_params_check(dtc_si_conv_t *c, const dtc_config_si_t *si)
{
    for (size_t i = 0; i < dtc_si_param_count; i++) {
        const dtc_si_param_t *p = &dtc_si_params[i];
        const int n = p->type == DTC_SIP_INT3 ? 3 : 1;
        if (!dtc_si_param_applies(p, si)) {
            continue;
        }
        for (int k = 0; k < n; k++) {
            const double v = dtc_si_param_value(p, si, k);
            char range[64];
            if (dtc_si_param_in_range(p, v)) {
                continue;
            }
            dtc_si_param_range_text(p, range, sizeof range);
            if (fabs(v) >= DTC_SIP_INF && v == v) {
                /* an open end of the range stops at +-DTC_SIP_INF, which the range text leaves out */
                return dtc_si_fail(c, p->err, p->name, "%s = %g: beyond the largest value any conversion takes (|x| < %g)", p->name, v, DTC_SIP_INF);
            }
            if (n > 1) {
                return dtc_si_fail(c, p->err, p->name, "%s[%d] = %g: must be %s%s", p->name, k, v, range[0] == '(' || range[0] == '[' ? "in " : "", range);
            }
            return dtc_si_fail(c, p->err, p->name, "%s = %g: must be %s%s", p->name, v, range[0] == '(' || range[0] == '[' ? "in " : "", range);
        }
    }
    return DTC_SI_OK;
}

int dtc_si_params_markdown(FILE *f)
{
    static const struct {
        unsigned mask;
        const char *text;
    } laws[] = {{DTC_SIP_ALL, "all"},           {DTC_SIP_PM, "PM (DTC, ITC)"}, {DTC_SIP_IM, "IM"},
                {DTC_SIP_IM_SVM, "IM SFVC, DFOC"}, {DTC_SIP_IM_SFVC, "IM SFVC"},   {DTC_SIP_IM_DSVM, "IM DSVM"}};
    static const char *const codes[] = {"BASE",      "MACHINE", "INVERTER", "TIMING",    "ENCODER",  "BAND",
                                        "CUTOFF",    "GAIN",    "LIMIT",    "REFERENCE", "VARIANT",  "ADC",
                                        "RANGE",     "FIRMWARE", "HANDOVER", "DELAY",    "DEADTIME", "IM",
                                        "ILIM"};
    int rc = fprintf(f, "| member | unit | range | laws | error | scenario key(s) | meaning |\n"
                        "|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < dtc_si_param_count && rc >= 0; i++) {
        const dtc_si_param_t *p = &dtc_si_params[i];
        const char *law = "?";
        char range[64];
        const int code = -(p->err) - 101;
        for (size_t k = 0; k < sizeof laws / sizeof laws[0]; k++) {
            if (laws[k].mask == p->laws) {
                law = laws[k].text;
            }
        }
        dtc_si_param_range_text(p, range, sizeof range);
        rc = fprintf(f, "| `%s%s` | %s | %s | %s | %s | %s | %s |\n", p->name, p->type == DTC_SIP_INT3 ? "[3]" : "",
                     p->unit, range, law, code >= 0 && code < (int)(sizeof codes / sizeof codes[0]) ? codes[code] : "?",
                     p->keys[0] != '\0' ? p->keys : "(the converter's default)", p->meaning);
    }
    return rc < 0 ? -1 : 0;
}
