/*
 * app_params.c - the dispatcher's parameter commands (app_proto_param.h): the protocol's
 * parameter table is the configuration's parameter description (dtc_params.h) followed by the
 * application's own parameters (APP_PARAM_LIST).
 *
 * A write is range-checked by its row, made on a copy of the configuration in force, the whole
 * copy checked by its law's check (law_check), and only then applied: while disarmed the
 * application restarts on the copy (app_reconfigure: calibration, then READY); while armed only a
 * live row (DTC_PARAM_LIVE) is written, through the shadow set (app_config_live). Background only.
 *
 * Stored parameters (PARAMS_SAVE, PARAMS_RESTORE, app_params_boot; store.h): the set is every
 * writable configuration row's and every stored derived row's (DTC_PARAM_STORED: those the
 * identification's apply writes, app_ident_apply.c) raw value (two words, low first) in table
 * order, then the application's rows; its layout version is the table's hash (app_param_table_hash), so a set
 * written by another table is never loaded. A stored set is loaded row by row into a copy of the
 * compiled-in configuration (each value range-checked by its row) and the copy checked by its
 * law's check: a set that fails either is not used.
 */
#include "app_proto_param.h"

#include "app.h"
#include "crc16.h"
#include "dtc_params.h"
#include "proto.h"
#include "store.h"

#include <stddef.h>

/* The application's parameters: X(ID, id, name, unit, base, lo, hi, default). Their ids are above
 * the configuration's (APP_PARAM_ID_BASE). comm_timeout_s: the command timeout (app_core.h), in ms
 * (SI seconds = raw * 1e-3), 0 = off; live: it may be changed while armed. */
#define APP_PARAM_ID_BASE 0xF000u
#define APP_PARAM_LIST(X) X(COMM_TIMEOUT, 0xF001u, "comm_timeout_s", "s", PROTO_BASE_MILLI, 0, 60000, 0)

#define APP_PARAM_ROW_(id_, num, name, unit, base, lo, hi, dflt) {num, name, unit, base, lo, hi, dflt},
typedef struct {
    uint16_t id;
    const char *name;
    const char *unit;
    uint16_t base;
    int32_t lo, hi, dflt;
} app_param_t;
static const app_param_t k_app_params[] = {APP_PARAM_LIST(APP_PARAM_ROW_)};
#undef APP_PARAM_ROW_
#define APP_PARAM_N ((uint16_t)(sizeof k_app_params / sizeof k_app_params[0]))

static dtc_config_t g_copy; /* background only: the configuration being changed */

/* 1 when row p is in the stored set: writable, or derived and marked stored. */
static uint16_t row_stored(const dtc_param_t *p)
{
    return (p->flags & DTC_PARAM_RO) == 0U || (p->flags & DTC_PARAM_STORED) != 0U ? 1U : 0U;
}

/* PARAM_DESC's base (enum proto_base) of a configuration row's quantity (enum dtc_param_qty). */
static uint16_t qty_base(uint16_t qty)
{
    switch (qty) {
    case DTC_PQ_V:
    case DTC_PQ_V_COUNT: return PROTO_BASE_V;
    case DTC_PQ_A:
    case DTC_PQ_A_COUNT: return PROTO_BASE_I;
    case DTC_PQ_W: return PROTO_BASE_W;
    case DTC_PQ_PSI: return PROTO_BASE_PSI;
    case DTC_PQ_T: return PROTO_BASE_T;
    case DTC_PQ_Z: return PROTO_BASE_Z;
    case DTC_PQ_L: return PROTO_BASE_L;
    case DTC_PQ_INV_L: return PROTO_BASE_INV_L;
    case DTC_PQ_INV_PSI: return PROTO_BASE_INV_PSI;
    case DTC_PQ_TIME: return PROTO_BASE_S;
    case DTC_PQ_ANGLE: return PROTO_BASE_TURN;
    case DTC_PQ_T_W: return PROTO_BASE_T_W;
    default: return PROTO_BASE_ONE; /* NONE, RATIO, PU */
    }
}

/* Fraction bits of a configuration row's raw value (enum dtc_param_fmt). */
static uint16_t fmt_frac(uint16_t fmt)
{
    switch (fmt) {
    case DTC_PF_IQ: return 24U;
    case DTC_PF_Q15: return 15U;
    case DTC_PF_Q31: return 31U;
    case DTC_PF_ANGLE: return 16U;
    default: return 0U;
    }
}

/* The protocol's configuration rows: those of the configuration in force (the common part's, then
 * its law's part's; dtc_params.h), by position and by id. */
static uint16_t cfg_law(void)
{
    const dtc_config_t *c = app_config();
    return c != NULL ? c->law : 0xFFFFU;
}

static uint16_t cfg_rows(void)
{
    const dtc_param_list_t *l = dtc_param_law_list(cfg_law());
    return (uint16_t)(dtc_params_common.n + (l != NULL ? l->n : 0U));
}

static const dtc_param_t *cfg_row(uint16_t k)
{
    const dtc_param_list_t *l = dtc_param_law_list(cfg_law());
    if (k < dtc_params_common.n) {
        return &dtc_params_common.rows[k];
    }
    k = (uint16_t)(k - dtc_params_common.n);
    return l != NULL && k < l->n ? &l->rows[k] : NULL;
}

static const dtc_param_t *cfg_find(uint16_t id)
{
    const dtc_param_t *p = dtc_param_find(id);
    return p != NULL && dtc_param_of_law(p, cfg_law()) != 0U ? p : NULL;
}

uint16_t app_param_count(void)
{
    return (uint16_t)(cfg_rows() + APP_PARAM_N);
}

static void put_str(uint16_t *o, const char *s, uint16_t max, uint16_t *n)
{
    uint16_t k = 0U;
    while (s[k] != '\0' && k < max) {
        o[k] = (uint16_t)((uint16_t)(unsigned char)s[k] & 0xFFU);
        k++;
    }
    *n = k;
}

static uint16_t crc_str(uint16_t crc, const char *s)
{
    uint16_t k;
    for (k = 0U; s[k] != '\0'; k++) {
        crc = crc16_update(crc, (uint16_t)((uint16_t)(unsigned char)s[k] & 0xFFU));
    }
    return crc;
}

static uint16_t crc_u32(uint16_t crc, uint32_t v)
{
    uint16_t k;
    for (k = 0U; k < 4U; k++) {
        crc = crc16_update(crc, (uint16_t)(v & 0xFFU));
        v >>= 8;
    }
    return crc;
}

/* The table's CRC, computed once (the table is constant). */
static uint32_t table_hash(void)
{
    uint16_t crc = CRC16_INIT;
    uint16_t i;
    for (i = 0U; i < cfg_rows(); i++) {
        const dtc_param_t *p = cfg_row(i);
        crc = crc_u32(crc, (uint32_t)p->id | ((uint32_t)p->fmt << 16));
        crc = crc_u32(crc, (uint32_t)p->qty | ((uint32_t)p->flags << 16));
        crc = crc_u32(crc, (uint32_t)p->lo);
        crc = crc_u32(crc, (uint32_t)p->hi);
        crc = crc_str(crc, p->name);
    }
    for (i = 0U; i < APP_PARAM_N; i++) {
        crc = crc_u32(crc, k_app_params[i].id);
        crc = crc_u32(crc, (uint32_t)k_app_params[i].lo);
        crc = crc_u32(crc, (uint32_t)k_app_params[i].hi);
        crc = crc_str(crc, k_app_params[i].name);
    }
    return crc;
}

uint32_t app_param_table_hash(void)
{
    static uint32_t hash;
    static uint16_t have;
    if (have == 0U) {
        hash = table_hash();
        have = 1U;
    }
    return hash;
}

static const app_param_t *app_row(uint16_t id)
{
    uint16_t i;
    for (i = 0U; i < APP_PARAM_N; i++) {
        if (k_app_params[i].id == id) {
            return &k_app_params[i];
        }
    }
    return NULL;
}

static void do_desc(const frame_t *rq, frame_t *rs)
{
    const uint16_t i = frame_get_u16(&rq->payload[0]);
    const uint16_t n_cfg = cfg_rows();
    uint16_t *o = rs->payload;
    uint16_t base, n, m;
    const char *unit;
    const char *name;
    if (i >= app_param_count()) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, 0);
        return;
    }
    frame_put_u16(&o[0], i);
    if (i < n_cfg) {
        const dtc_param_t *p = cfg_row(i);
        const dtc_config_t *dflt = app_config_default();
        int32_t d = 0;
        uint16_t flags = 0U;
        if (dflt != NULL) {
            (void)dtc_param_get(dflt, p, &d);
        }
        if ((p->flags & DTC_PARAM_RO) != 0U) {
            flags |= PROTO_PARAM_READ_ONLY;
            if ((p->flags & DTC_PARAM_STORED) != 0U) {
                flags |= PROTO_PARAM_STORED;
            }
        } else {
            flags |= PROTO_PARAM_STORED;
            if ((p->flags & DTC_PARAM_LIVE) == 0U) {
                flags |= PROTO_PARAM_DISARMED_ONLY;
            }
        }
        base = qty_base(p->qty);
        unit = dtc_param_unit(p->qty);
        name = p->name;
        frame_put_u16(&o[2], p->id);
        frame_put_u16(&o[4], fmt_frac(p->fmt));
        frame_put_u16(&o[6], flags);
        frame_put_i32(&o[8], p->lo);
        frame_put_i32(&o[12], p->hi);
        frame_put_i32(&o[16], d);
    } else {
        const app_param_t *a = &k_app_params[i - n_cfg];
        base = a->base;
        unit = a->unit;
        name = a->name;
        frame_put_u16(&o[2], a->id);
        frame_put_u16(&o[4], 0U);
        frame_put_u16(&o[6], 0U);
        frame_put_i32(&o[8], a->lo);
        frame_put_i32(&o[12], a->hi);
        frame_put_i32(&o[16], a->dflt);
    }
    frame_put_u16(&o[20], base);
    put_str(&o[24], name, (uint16_t)(FRAME_MAX_PAYLOAD - 24U), &n);
    frame_put_u16(&o[22], n);
    put_str(&o[24U + n], unit, (uint16_t)(FRAME_MAX_PAYLOAD - 24U - n), &m);
    rs->len = (uint16_t)(24U + n + m);
}

/* The value in force of parameter id into *raw; 0, or PROTO_ERR_PARAM_ID. */
static uint16_t read_raw(const app_proto_t *p, uint16_t id, int32_t *raw)
{
    const dtc_param_t *c = cfg_find(id);
    if (c != NULL) {
        const dtc_config_t *cfg = app_config();
        if (cfg == NULL || dtc_param_get(cfg, c, raw) != DTC_OK) {
            return PROTO_ERR_PARAM_ID;
        }
        return 0U;
    }
    if (id == 0xF001u) {
        *raw = (int32_t)app_proto_timeout_ms(p);
        return 0U;
    }
    return PROTO_ERR_PARAM_ID;
}

static void do_read(const app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    const uint16_t id = frame_get_u16(&rq->payload[0]);
    int32_t raw = 0;
    const uint16_t e = read_raw(p, id, &raw);
    if (e != 0U) {
        app_proto_error(rq, rs, e, 0);
        return;
    }
    frame_put_u16(&rs->payload[0], id);
    frame_put_i32(&rs->payload[2], raw);
    rs->len = 6U;
}

static void do_write(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    const uint16_t id = frame_get_u16(&rq->payload[0]);
    const int32_t raw = frame_get_i32(&rq->payload[2]);
    const dtc_param_t *c = cfg_find(id);
    const app_param_t *a = app_row(id);
    const dtc_config_t *cfg = app_config();
    app_status_t s;
    int16_t rc;
    int32_t now = 0;
    if (a != NULL) {
        if (raw < a->lo || raw > a->hi) {
            app_proto_error(rq, rs, PROTO_ERR_RANGE, 2);
            return;
        }
        app_proto_set_timeout_ms(p, (uint16_t)raw);
    } else if (c == NULL || cfg == NULL) {
        app_proto_error(rq, rs, PROTO_ERR_PARAM_ID, 0);
        return;
    } else {
        app_get_status(&s);
        if ((c->flags & DTC_PARAM_RO) != 0U) {
            app_proto_error(rq, rs, PROTO_ERR_READ_ONLY, 0);
            return;
        }
        if (s.state == APP_STATE_RUN && (c->flags & DTC_PARAM_LIVE) == 0U) {
            app_proto_error(rq, rs, PROTO_ERR_ARMED, 0);
            return;
        }
        g_copy = *cfg;
        rc = dtc_param_set(&g_copy, c, raw);
        if (rc == DTC_OK) {
            rc = law_check(&g_copy, NULL);
        }
        if (rc != DTC_OK) {
            app_proto_error(rq, rs, PROTO_ERR_RANGE, rc);
            return;
        }
        rc = s.state == APP_STATE_RUN ? app_config_live(&g_copy) : app_reconfigure(&g_copy);
        if (rc == APP_ERR_ARMED) {
            app_proto_error(rq, rs, PROTO_ERR_ARMED, 0); /* armed between the check and the write */
            return;
        }
        if (rc != 0) {
            app_proto_error(rq, rs, PROTO_ERR_REFUSED, PROTO_REFUSE_CONFIG);
            return;
        }
    }
    (void)read_raw(p, id, &now);
    frame_put_u16(&rs->payload[0], id);
    frame_put_i32(&rs->payload[2], now);
    rs->len = 6U;
}

/* Words of the stored set (two per writable row), at most APP_STORE_WORDS. */
#define APP_STORE_WORDS 256u
static uint16_t g_set[APP_STORE_WORDS];   /* background only */
static store_t g_store;

static void put_raw(uint16_t *w, int32_t raw)
{
    const uint32_t u = (uint32_t)raw;
    w[0] = (uint16_t)(u & 0xFFFFu);
    w[1] = (uint16_t)(u >> 16);
}

static int32_t get_raw(const uint16_t *w)
{
    const uint32_t u = (uint32_t)w[0] | ((uint32_t)w[1] << 16);
    /* two's complement without an implementation-defined conversion */
    return (u & 0x80000000UL) != 0U ? -(int32_t)(~u) - 1 : (int32_t)u;
}

/* The stored set of configuration cfg and timeout ms into w; returns its words (0: too large). */
static uint16_t serialize(const dtc_config_t *cfg, uint16_t ms, uint16_t *w)
{
    uint16_t i, n = 0U;
    for (i = 0U; i < cfg_rows(); i++) {
        const dtc_param_t *p = cfg_row(i);
        int32_t raw = 0;
        if (row_stored(p) == 0U) {
            continue;
        }
        if (n + 2U > APP_STORE_WORDS) {
            return 0U;
        }
        (void)dtc_param_get(cfg, p, &raw);
        put_raw(&w[n], raw);
        n = (uint16_t)(n + 2U);
    }
    if (n + 2U > APP_STORE_WORDS) {
        return 0U;
    }
    put_raw(&w[n], (int32_t)ms);
    return (uint16_t)(n + 2U);
}

/* A stored set w into *cfg (a copy of the compiled-in configuration) and *ms: DTC_OK, or the first
 * row's (or the law check's) refusal. */
static int16_t deserialize(const uint16_t *w, dtc_config_t *cfg, uint16_t *ms)
{
    uint16_t i, n = 0U;
    int16_t rc;
    int32_t t;
    for (i = 0U; i < cfg_rows(); i++) {
        const dtc_param_t *p = cfg_row(i);
        int32_t now = 0;
        const int32_t raw = get_raw(&w[n]);
        if (row_stored(p) == 0U) {
            continue;
        }
        n = (uint16_t)(n + 2U);
        (void)dtc_param_get(cfg, p, &now);
        if (raw != now) {
            /* a stored derived row is read-only by id: its range check and store directly */
            const int64_t v = p->fmt == (uint16_t)DTC_PF_U32 ? (int64_t)(uint32_t)raw : (int64_t)raw;
            rc = (p->flags & DTC_PARAM_RO) == 0U ? dtc_param_set(cfg, p, raw)
                 : (dtc_param_in_range(p, v) != 0U && dtc_param_store(cfg, p, v) == 0 ? (int16_t)DTC_OK : p->err);
            if (rc != DTC_OK) {
                return rc;
            }
        }
    }
    t = get_raw(&w[n]);
    *ms = (uint16_t)(t < 0 ? 0 : t > 60000 ? 60000 : t);
    return law_check(cfg, NULL);
}

/* Loads the newest valid stored set (source 0) or the compiled-in one (source 1) into the drive;
 * disarmed only. Returns 0 or a PROTO_ERR_* code, *detail its detail. */
static uint16_t restore(app_proto_t *pr, uint16_t source, int16_t *detail)
{
    const dtc_config_t *dflt = app_config_default();
    uint16_t ms = 0U, n;
    int16_t rc;
    *detail = 0;
    if (dflt == NULL) {
        return PROTO_ERR_STATE;
    }
    g_copy = *dflt;
    if (source == 0U) {
        n = serialize(dflt, 0U, g_set);
        if (n == 0U) {
            *detail = STORE_ERR_SIZE;
            return PROTO_ERR_STORE;
        }
        if (store_boot(&g_store, (uint16_t)app_param_table_hash(), g_set, g_set, n) != STORE_OK) {
            *detail = STORE_DEFAULTS;
            return PROTO_ERR_STORE; /* no valid stored copy */
        }
        rc = deserialize(g_set, &g_copy, &ms);
        if (rc != DTC_OK) {
            *detail = rc;
            return PROTO_ERR_RANGE;
        }
    }
    rc = app_reconfigure(&g_copy);
    if (rc == APP_ERR_ARMED) {
        return PROTO_ERR_ARMED;
    }
    if (rc != 0) {
        *detail = rc;
        return PROTO_ERR_REFUSED;
    }
    app_proto_set_timeout_ms(pr, ms);
    return 0U;
}

void app_params_boot(app_proto_t *p)
{
    int16_t detail;
    (void)restore(p, 0U, &detail); /* no valid stored set: the compiled-in configuration stays */
}

static void do_save(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    app_status_t s;
    const dtc_config_t *cfg = app_config();
    uint16_t n, st;
    app_get_status(&s);
    if (s.state == APP_STATE_RUN) {
        app_proto_error(rq, rs, PROTO_ERR_ARMED, 0);
        return;
    }
    n = cfg != NULL ? serialize(cfg, app_proto_timeout_ms(p), g_set) : 0U;
    if (n == 0U) {
        app_proto_error(rq, rs, PROTO_ERR_STORE, STORE_ERR_SIZE);
        return;
    }
    /* g_store: the medium as app_params_boot (or the last save) left it */
    st = store_save(&g_store, 0U, (uint16_t)app_param_table_hash(), g_set, n);
    if (st != STORE_OK) {
        app_proto_error(rq, rs, PROTO_ERR_STORE, (int16_t)st);
        return;
    }
    frame_put_u32(&rs->payload[0], g_store.seq);
    rs->len = 4U;
}

static void do_restore(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    int16_t detail;
    const uint16_t src = frame_get_u16(&rq->payload[0]);
    uint16_t e;
    if (src > 1U) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, 0);
        return;
    }
    e = restore(p, src, &detail);
    if (e != 0U) {
        app_proto_error(rq, rs, e, detail);
        return;
    }
    frame_put_u16(&rs->payload[0], src);
    rs->len = 2U;
}

void app_proto_param(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    switch (rq->cmd) {
    case PROTO_PARAM_DESC:
        do_desc(rq, rs);
        break;
    case PROTO_PARAM_READ:
        do_read(p, rq, rs);
        break;
    case PROTO_PARAM_WRITE:
        do_write(p, rq, rs);
        break;
    case PROTO_PARAMS_SAVE:
        do_save(p, rq, rs);
        break;
    case PROTO_PARAMS_RESTORE:
        do_restore(p, rq, rs);
        break;
    default:
        app_proto_error(rq, rs, PROTO_ERR_UNKNOWN_CMD, 0);
        break;
    }
}
