/*
 * pil_format.c - encoding and decoding of the ISR recording (pil_format.h). Byte by byte, so
 * the result does not depend on the target's endianness, int width or struct padding.
 */
#include "pil_format.h"


static void put16(uint8_t **p, uint16_t v)
{
    (*p)[0] = (uint8_t)(v & 0xFFU);
    (*p)[1] = (uint8_t)(v >> 8);
    *p += 2;
}

static void put32(uint8_t **p, uint32_t v)
{
    (*p)[0] = (uint8_t)(v & 0xFFUL);
    (*p)[1] = (uint8_t)((v >> 8) & 0xFFUL);
    (*p)[2] = (uint8_t)((v >> 16) & 0xFFUL);
    (*p)[3] = (uint8_t)(v >> 24);
    *p += 4;
}

static uint16_t get16(const uint8_t **p)
{
    const uint16_t v = (uint16_t)((uint16_t)(*p)[0] | (uint16_t)((uint16_t)(*p)[1] << 8));
    *p += 2;
    return v;
}

static uint32_t get32(const uint8_t **p)
{
    const uint32_t v = (uint32_t)(*p)[0] | ((uint32_t)(*p)[1] << 8) | ((uint32_t)(*p)[2] << 16) |
                       ((uint32_t)(*p)[3] << 24);
    *p += 4;
    return v;
}

/* A configuration field of 2 or 4 bytes as its bit pattern, zero-extended (signed and unsigned
 * variants of a type may alias each other). */
static uint32_t field_bits(const void *f, uint16_t size)
{
    return size == 2U ? (uint32_t)*(const uint16_t *)f : *(const uint32_t *)f;
}

static void field_set(void *f, uint16_t size, uint32_t bits)
{
    if (size == 2U) {
        *(uint16_t *)f = (uint16_t)(bits & 0xFFFFUL);
    } else {
        *(uint32_t *)f = bits;
    }
}

/* The blob holds every configuration field in the order of the parameter rows (dtc_param.h): the
 * common part's, then the part of the configuration's law, then zero fields up to the longest
 * law's part, so that every blob has pil_config_fields() fields whatever its law. */
static const dtc_param_list_t *pil_law_rows(uint16_t law)
{
#if DTC_LAW_ITC_LINKED
    if (law == DTC_LAW_PM_ITC) {
        return &dtc_params_pm_itc;
    }
#endif
    return dtc_law_is_im(law) != 0U ? &dtc_params_im : &dtc_params_pm_dtc;
}

uint16_t pil_config_fields(void)
{
    /* the ITC's part is shorter than the IM laws' (unit test test_dtc_param): it does not set the length */
    return (uint16_t)(dtc_params_common.n + (dtc_params_pm_dtc.n > dtc_params_im.n ? dtc_params_pm_dtc.n
                                                                                      : dtc_params_im.n));
}

/* A row's field as stored: 2 or 4 bytes. */
static uint16_t pil_row_size(const dtc_param_t *r)
{
    return (uint16_t)(r->fmt == DTC_PF_U16 || r->fmt == DTC_PF_Q15 || r->fmt == DTC_PF_ANGLE ? 2U : 4U);
}

void pil_config_encode(const dtc_config_t *c, uint8_t *blob)
{
    const dtc_param_list_t *lists[2] = {&dtc_params_common, pil_law_rows(c->law)};
    uint8_t *p = blob;
    uint16_t n = 0U, l, k;
    for (l = 0U; l < 2U; l++) {
        for (k = 0U; k < lists[l]->n; k++, n++) {
            put32(&p, field_bits((const char *)c + lists[l]->rows[k].offset, pil_row_size(&lists[l]->rows[k])));
        }
    }
    for (; n < pil_config_fields(); n++) {
        put32(&p, 0U);
    }
}

void pil_config_decode(const uint8_t *blob, dtc_config_t *c)
{
    const uint8_t *p = blob;
    uint16_t l, k;
    for (l = 0U; l < 2U; l++) {
        /* the common part first: it holds the law, which selects the second list */
        const dtc_param_list_t *rows = l == 0U ? &dtc_params_common : pil_law_rows(c->law);
        for (k = 0U; k < rows->n; k++) {
            field_set((char *)c + rows->rows[k].offset, pil_row_size(&rows->rows[k]), get32(&p));
        }
    }
}

static const uint8_t k_magic[4] = {0x44U, 0x50U, 0x49U, 0x4CU}; /* "DPIL" */

void pil_header_encode(const pil_header_t *h, uint8_t b[PIL_HEADER_BYTES])
{
    uint8_t *p = b;
    uint16_t i;
    for (i = 0U; i < 4U; ++i) {
        *p++ = k_magic[i];
    }
    put16(&p, h->version);
    put16(&p, h->config_fields);
    put16(&p, h->in_bytes);
    put16(&p, h->out_bytes);
    put16(&p, h->t1pr);
    put16(&p, 0U);
    put32(&p, h->isr_count);
}

int16_t pil_header_decode(const uint8_t b[PIL_HEADER_BYTES], pil_header_t *h)
{
    const uint8_t *p = b + 4;
    uint16_t i;
    for (i = 0U; i < 4U; ++i) {
        if (b[i] != k_magic[i]) {
            return PIL_ERR_MAGIC;
        }
    }
    h->version = get16(&p);
    h->config_fields = get16(&p);
    h->in_bytes = get16(&p);
    h->out_bytes = get16(&p);
    h->t1pr = get16(&p);
    (void)get16(&p);
    h->isr_count = get32(&p);
    if (h->version != PIL_VERSION) {
        return PIL_ERR_VERSION;
    }
    if (h->config_fields != pil_config_fields() || h->in_bytes != PIL_IN_BYTES ||
        h->out_bytes != PIL_OUT_BYTES) {
        return PIL_ERR_LAYOUT;
    }
    return PIL_OK;
}

void pil_in_encode(const hal_meas_t *m, uint8_t b[PIL_IN_BYTES])
{
    uint8_t *p = b;
#define E16(n, mem) put16(&p, m->mem);
#define E32(n, mem) put32(&p, m->mem);
    PIL_IN_FIELDS(E16, E32)
#undef E16
#undef E32
}

void pil_in_decode(const uint8_t b[PIL_IN_BYTES], hal_meas_t *m)
{
    static const hal_meas_t zero = {{0U, 0U, 0U, 0U, 0U}, 0U, 0U, 0U, 0U, 0U, 0U};
    const uint8_t *p = b;
    *m = zero; /* a field the record does not carry reads 0 (never a stack leftover) */
#define D16(n, mem) m->mem = get16(&p);
#define D32(n, mem) m->mem = get32(&p);
    PIL_IN_FIELDS(D16, D32)
#undef D16
#undef D32
}

void pil_out_fill(pil_out_t *o, const pil_hal_obs_t *obs, const app_status_t *st)
{
    const hal_cmd_t *c = &obs->written;
    o->sa = c->sa;
    o->sb = c->sb;
    o->sc = c->sc;
    o->enable = c->enable;
    o->form = c->form;
    /* The compare values and polarities command something only in the PWM form (hal.h); in the
     * leg-state form the application leaves them unset, so they are recorded as 0. */
    if (c->form == (uint16_t)HAL_CMD_PWM) {
        o->cmpr_up0 = c->cmpr_up[0];
        o->cmpr_up1 = c->cmpr_up[1];
        o->cmpr_up2 = c->cmpr_up[2];
        o->cmpr_dn0 = c->cmpr_dn[0];
        o->cmpr_dn1 = c->cmpr_dn[1];
        o->cmpr_dn2 = c->cmpr_dn[2];
        o->act0 = c->act[0];
        o->act1 = c->act[1];
        o->act2 = c->act[2];
    } else {
        o->cmpr_up0 = 0U;
        o->cmpr_up1 = 0U;
        o->cmpr_up2 = 0U;
        o->cmpr_dn0 = 0U;
        o->cmpr_dn1 = 0U;
        o->cmpr_dn2 = 0U;
        o->act0 = 0U;
        o->act1 = 0U;
        o->act2 = 0U;
    }
    o->relay = c->relay; /* a GPIO output in either form (hal.h) */
    o->writes = obs->writes;
    o->gates_off = obs->gates_off;
    o->trip_clear = obs->trip_clear;
    o->state = st->state;
    o->fault = st->fault;
    o->fault_detail = (uint16_t)st->fault_detail;
    o->st_tick = st->tick;
    o->fault_tick = st->fault_tick;
    o->reconfigured = st->reconfigured;
    o->ia_iq = (uint32_t)st->meas.ia_iq;
    o->ib_iq = (uint32_t)st->meas.ib_iq;
    o->ic_iq = (uint32_t)st->meas.ic_iq;
    o->vdc_iq = (uint32_t)st->meas.vdc_iq;
    o->vmid_iq = (uint32_t)st->meas.vmid_iq;
    o->enc_count = st->meas.enc_count;
    o->vector = st->out.vector;
    o->sector = st->out.sector;
    o->flux_up = st->out.flux_up;
    o->torque_dem = (uint16_t)st->out.torque_dem;
    o->speed_tick = st->out.speed_tick;
    o->on_cm = st->out.on_cm;
    o->i_limited = st->out.i_limited;
    o->theta_e = st->out.theta_e;
    o->psi_alpha_iq = (uint32_t)st->out.psi_alpha_iq;
    o->psi_beta_iq = (uint32_t)st->out.psi_beta_iq;
    o->te_iq = (uint32_t)st->out.te_iq;
    o->te_ref_iq = (uint32_t)st->out.te_ref_iq;
    o->speed_iq = (uint32_t)st->out.speed_iq;
    o->psi_ref_iq = (uint32_t)st->out.psi_ref_iq;
    o->psir_mag_iq = (uint32_t)st->out.psir_mag_iq;
}

void pil_out_encode(const pil_out_t *o, uint8_t b[PIL_OUT_BYTES])
{
    uint8_t *p = b;
#define E16(n) put16(&p, o->n);
#define E32(n) put32(&p, o->n);
    PIL_OUT_FIELDS(E16, E32)
#undef E16
#undef E32
}
