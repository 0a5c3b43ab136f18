/*
 * app_proto.c - the serial protocol's dispatcher (see app_proto.h, proto.h for the layouts).
 */
#include "app_proto.h"

#include "app.h"
#include "app_proto_param.h"
#include "capture.h"
#include "faultlog.h"
#include "hal.h"
#include "proto.h"
#include "torque.h"

#include <stddef.h>

/* The drive's protocol instance and what it serves (app_proto_start): background-owned, except
 * the capture's samples and the fault log's entries, which the ISR writes. */
static app_proto_t g_proto;
static capture_t g_cap;
static faultlog_t g_flog;

void app_proto_start(uint32_t period_ns)
{
    capture_init(&g_cap);
    faultlog_init(&g_flog);
    app_attach(&g_cap, &g_flog);
    app_proto_init(&g_proto, period_ns);
    app_params_boot(&g_proto);
}

void app_proto_background(void)
{
    app_proto_poll(&g_proto);
}

capture_t *app_capture(void)
{
    return &g_cap;
}

const faultlog_t *app_faultlog(void)
{
    return &g_flog;
}

void app_proto_init(app_proto_t *p, uint32_t period_ns)
{
    frame_dec_init(&p->dec);
    p->tx_len = 0U;
    p->tx_pos = 0U;
    p->period_ns = period_ns > 0U ? period_ns : 1U;
    /* background, init: a division is fine here */
    p->idle_ticks = (uint32_t)(((uint32_t)PROTO_IDLE_MS * 1000000UL + p->period_ns - 1U) / p->period_ns);
    p->last_rx_tick = 0U;
    p->rx_seen = 0U;
    p->timeout_ms = 0U;
    p->tm_on = 0U;
    p->tm_seq = 0U;
    p->tm_decim = 1U;
    p->tm_count = 0U;
    p->tm_next = 0U;
}

uint16_t app_proto_timeout_ms(const app_proto_t *p)
{
    return p->timeout_ms;
}

void app_proto_set_timeout_ms(app_proto_t *p, uint16_t ms)
{
    p->timeout_ms = ms;
    /* periods = ms * 1e6 / period_ns, rounded up (background: a division is fine) */
    app_set_comm_timeout(ms == 0U ? 0U : (uint32_t)(((uint64_t)ms * 1000000U + p->period_ns - 1U) / p->period_ns));
}

void app_proto_error(const frame_t *rq, frame_t *rs, uint16_t code, int16_t detail)
{
    rs->cmd = PROTO_ERROR;
    rs->len = 6U;
    frame_put_u16(&rs->payload[0], rq->cmd);
    frame_put_u16(&rs->payload[2], code);
    frame_put_u16(&rs->payload[4], (uint16_t)detail);
}

/* A quantity (enum capture_quantity) from a status copy and the references published last. */
APP_NOINLINE static int32_t quantity(const app_status_t *s, const dtc_refs_t *r, uint16_t q)
{
    switch (q) {
    case CAPTURE_Q_I_A: return s->meas.ia_iq;
    case CAPTURE_Q_I_B: return s->meas.ib_iq;
    case CAPTURE_Q_I_C: return s->meas.ic_iq;
    case CAPTURE_Q_PSI_ALPHA_EST: return s->out.psi_alpha_iq;
    case CAPTURE_Q_PSI_BETA_EST: return s->out.psi_beta_iq;
    case CAPTURE_Q_TORQUE_EST: return s->out.te_iq;
    case CAPTURE_Q_SPEED: return s->out.speed_iq;
    case CAPTURE_Q_SPEED_REF: return r->speed_ref_iq;
    case CAPTURE_Q_TORQUE_REF: return s->out.te_ref_iq;
    case CAPTURE_Q_PSI_REF: return s->out.psi_ref_iq;
    case CAPTURE_Q_VDC: return s->meas.vdc_iq;
    case CAPTURE_Q_VMID: return s->meas.vmid_iq;
    case CAPTURE_Q_SECTOR: return (int32_t)s->out.sector;
    case CAPTURE_Q_VECTOR: return (int32_t)s->out.vector;
    default: return 0;
    }
}

APP_NOINLINE static void do_hello(frame_t *rs, const app_proto_t *p)
{
    const dtc_config_t *c = app_config();
    uint16_t *o = rs->payload;
    frame_put_u16(&o[0], PROTO_VERSION);
    frame_put_u16(&o[2], APP_FW_VERSION);
    frame_put_u32(&o[4], app_param_table_hash());
    frame_put_u16(&o[8], app_param_count());
    frame_put_u16(&o[10], c != NULL ? c->law : 0xFFFFU);
    frame_put_u32(&o[12], p->period_ns);
    frame_put_u16(&o[16], FIX_IQ_Q);
    frame_put_u16(&o[18], CAPTURE_BUF_WORDS32);
    frame_put_u16(&o[20], CAPTURE_CHANNELS);
    frame_put_u16(&o[22], FRAME_MAX_PAYLOAD);
    frame_put_u16(&o[24], FAULTLOG_ENTRIES);
    frame_put_u32(&o[26], c != NULL ? c->board.v_base_mv : 0U);
    frame_put_u32(&o[30], c != NULL ? c->board.i_base_ma : 0U);
    frame_put_u32(&o[34], c != NULL ? c->board.w_base_mrad_s : 0U);
    frame_put_u16(&o[38], c != NULL ? c->machine.pole_pairs : 0U);
    rs->len = 40U;
}

APP_NOINLINE static void do_status(frame_t *rs, const frame_dec_t *dec)
{
    app_status_t s;
    dtc_refs_t r;
    uint16_t *o = rs->payload;
    app_get_status(&s);
    app_get_refs(&r);
    frame_put_u16(&o[0], s.state);
    frame_put_u16(&o[2], (uint16_t)(s.state == APP_STATE_RUN ? 1U : 0U));
    frame_put_u16(&o[4], s.fault);
    frame_put_u16(&o[6], (uint16_t)s.fault_detail);
    frame_put_u32(&o[8], s.tick);
    frame_put_i32(&o[12], s.out.speed_iq);
    frame_put_i32(&o[16], r.speed_ref_iq);
    frame_put_i32(&o[20], s.out.te_iq);
    frame_put_i32(&o[24], s.out.te_ref_iq);
    frame_put_i32(&o[28], torque_flux_mag(s.out.psi_alpha_iq, s.out.psi_beta_iq));
    frame_put_i32(&o[32], s.meas.vdc_iq);
    frame_put_i32(&o[36], s.meas.vmid_iq);
    frame_put_u16(&o[40], r.mode == (uint16_t)DTC_MODE_TORQUE ? PROTO_MODE_TORQUE : PROTO_MODE_SPEED);
    frame_put_u16(&o[42], app_faultlog()->recorded);
    frame_put_u16(&o[44], dec->stats.frames);
    frame_put_u16(&o[46], dec->stats.crc_errors);
    rs->len = 48U;
}

/* SPEED_REF / TORQUE_REF: the reference and its mode through the shadow set. */
APP_NOINLINE static void do_ref(const frame_t *rq, frame_t *rs, uint16_t mode)
{
    dtc_refs_t r;
    int16_t rc;
    const int32_t v = frame_get_i32(&rq->payload[0]);
    app_get_refs(&r);
    r.mode = mode;
    if (mode == (uint16_t)DTC_MODE_SPEED) {
        r.speed_ref_iq = v;
    } else {
        r.torque_ref_iq = v;
    }
    rc = app_set_refs(&r);
    if (rc != DTC_OK) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, rc);
        return;
    }
    frame_put_i32(&rs->payload[0], v);
    rs->len = 4U;
}

APP_NOINLINE static void do_capture_setup(const frame_t *rq, frame_t *rs)
{
    capture_setup_t s;
    uint16_t k, rc;
    const uint16_t *i = rq->payload;
    s.count = frame_get_u16(&i[0]);
    for (k = 0U; k < CAPTURE_CHANNELS; k++) {
        s.quantity[k] = frame_get_u16(&i[2U + 2U * k]);
    }
    s.samples = frame_get_u16(&i[10]);
    s.pre = frame_get_u16(&i[12]);
    s.decim = frame_get_u16(&i[14]);
    s.trigger = frame_get_u16(&i[16]);
    s.trig_ch = frame_get_u16(&i[18]);
    s.level = frame_get_i32(&i[20]);
    rc = capture_setup(app_capture(), &s);
    if (rc != CAPTURE_OK) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, (int16_t)rc);
    }
}

APP_NOINLINE static void do_capture_status(frame_t *rs)
{
    const capture_t *c = app_capture();
    const uint16_t st = capture_state(c);
    uint16_t *o = rs->payload;
    frame_put_u16(&o[0], st);
    frame_put_u16(&o[2], c->cfg.samples);
    frame_put_u16(&o[4], c->cfg.count);
    frame_put_u32(&o[6], st == (uint16_t)CAPTURE_DONE ? capture_first_tick(c) : 0U);
    frame_put_u16(&o[10], c->cfg.decim);
    rs->len = 12U;
}

APP_NOINLINE static void do_capture_read(const frame_t *rq, frame_t *rs)
{
    const capture_t *c = app_capture();
    const uint16_t first = frame_get_u16(&rq->payload[0]);
    uint16_t n = frame_get_u16(&rq->payload[2]);
    uint16_t k, ch, at = 4U;
    const uint16_t per = (uint16_t)(4U * c->cfg.count);
    if (capture_state(c) != (uint16_t)CAPTURE_DONE) {
        app_proto_error(rq, rs, PROTO_ERR_STATE, 0);
        return;
    }
    if (first >= c->cfg.samples) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, 0);
        return;
    }
    if (n > (uint16_t)(c->cfg.samples - first)) {
        n = (uint16_t)(c->cfg.samples - first);
    }
    while (n > 0U && (uint32_t)n * per + 4U > FRAME_MAX_PAYLOAD) {
        n--; /* at most 29 steps (one channel): background */
    }
    for (k = 0U; k < n; k++) {
        for (ch = 0U; ch < c->cfg.count; ch++) {
            frame_put_i32(&rs->payload[at], capture_read(c, (uint16_t)(first + k), ch));
            at = (uint16_t)(at + 4U);
        }
    }
    frame_put_u16(&rs->payload[0], first);
    frame_put_u16(&rs->payload[2], n);
    rs->len = at;
}

APP_NOINLINE static void do_faultlog(const frame_t *rq, frame_t *rs)
{
    faultlog_entry_t e;
    uint16_t rc = FAULTLOG_BUSY, tries;
    uint16_t *o = rs->payload;
    const uint16_t k = frame_get_u16(&rq->payload[0]);
    for (tries = 0U; tries < 4U && rc == (uint16_t)FAULTLOG_BUSY; tries++) {
        rc = faultlog_get(app_faultlog(), k, &e);
    }
    if (rc == (uint16_t)FAULTLOG_EMPTY) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, 0);
        return;
    }
    if (rc != (uint16_t)FAULTLOG_OK) {
        app_proto_error(rq, rs, PROTO_ERR_STATE, 0);
        return;
    }
    frame_put_u16(&o[0], k);
    frame_put_u16(&o[2], app_faultlog()->recorded);
    frame_put_u32(&o[4], e.tick);
    frame_put_u16(&o[8], e.reason);
    frame_put_u16(&o[10], (uint16_t)e.detail);
    frame_put_i32(&o[12], e.snap.ia_iq);
    frame_put_i32(&o[16], e.snap.ib_iq);
    frame_put_i32(&o[20], e.snap.ic_iq);
    frame_put_i32(&o[24], e.snap.vdc_iq);
    frame_put_i32(&o[28], e.snap.vmid_iq);
    frame_put_i32(&o[32], e.snap.speed_iq);
    frame_put_i32(&o[36], e.snap.psi_alpha_iq);
    frame_put_i32(&o[40], e.snap.psi_beta_iq);
    frame_put_i32(&o[44], e.snap.te_iq);
    frame_put_i32(&o[48], e.snap.te_ref_iq);
    frame_put_i32(&o[52], e.snap.speed_ref_iq);
    frame_put_u16(&o[56], e.snap.sector);
    frame_put_u16(&o[58], e.snap.vector);
    frame_put_u16(&o[60], e.snap.state);
    rs->len = 62U;
}

/* IDENTIFY (proto.h): start from READY, or the progress and the results so far. */
APP_NOINLINE static void do_identify(const frame_t *rq, frame_t *rs)
{
    const uint16_t sub = frame_get_u16(&rq->payload[0]);
    uint16_t *o = rs->payload;
    uint16_t k;
    app_ident_view_t d;
    app_status_t s;
    frame_put_u16(&o[0], sub);
    rs->len = 2U;
    if (sub == (uint16_t)PROTO_IDENT_START) {
        const dtc_config_t *c = app_config();
        uint16_t why;
        app_get_status(&s);
        if (s.state == APP_STATE_RUN || s.state == APP_STATE_IDENT) {
            app_proto_error(rq, rs, PROTO_ERR_ARMED, 0);
            return;
        }
        if (c == NULL || (c->law != (uint16_t)DTC_LAW_PM_DTC && c->law != (uint16_t)DTC_LAW_PM_ITC &&
                          dtc_law_is_im(c->law) == 0U)) {
            app_proto_error(rq, rs, PROTO_ERR_REFUSED, PROTO_REFUSE_LAW);
            return;
        }
        why = app_identify();
        if (why != (uint16_t)APP_ARM_OK) {
            app_proto_error(rq, rs, PROTO_ERR_REFUSED, (int16_t)why);
        }
        return;
    }
    if (sub != (uint16_t)PROTO_IDENT_STATUS && sub != (uint16_t)PROTO_IDENT_RESULT) {
        app_proto_error(rq, rs, PROTO_ERR_RANGE, 0);
        return;
    }
    app_get_ident_view(&d);
    frame_put_u16(&o[2], d.step);
    if (sub == (uint16_t)PROTO_IDENT_STATUS) {
        app_get_status(&s);
        frame_put_u16(&o[4], d.fail);
        frame_put_u16(&o[6], d.fail_step);
        frame_put_u16(&o[8], (uint16_t)d.fail_detail);
        frame_put_u16(&o[10], s.state);
        rs->len = 12U;
        return;
    }
    frame_put_u16(&o[4], d.res.axis);
    frame_put_i32(&o[6], d.res.r_iq);
    frame_put_i32(&o[10], d.res.v0_iq);
    frame_put_i32(&o[14], d.res.l_ts_iq);
    frame_put_u16(&o[18], d.res.pole_pairs);
    frame_put_u16(&o[20], d.res.enc_reversed);
    frame_put_u16(&o[22], d.res.enc_offset);
    frame_put_i32(&o[24], d.res.counts_per_turn);
    for (k = 0U; k < 3U; k++) {
        frame_put_u32(&o[28U + 4U * k], d.res.ticks[k + 1U]);
    }
    for (k = 0U; k < APP_IDENT_R_LEVELS; k++) {
        frame_put_i32(&o[40U + 4U * k], d.res.level_i_iq[k]);
        frame_put_i32(&o[56U + 4U * k], d.res.level_v_iq[k]);
    }
    frame_put_i32(&o[72], d.res.psi_iq);
    frame_put_i32(&o[76], d.res.j_q12);
    frame_put_i32(&o[80], d.res.b_iq);
    frame_put_i32(&o[84], d.res.tc_iq);
    frame_put_u32(&o[88], d.res.ticks[APP_IDENT_SPIN]);
    frame_put_u16(&o[92], d.im_on);
    frame_put_i32(&o[94], d.res.im.ls_ts_iq);
    frame_put_i32(&o[98], d.res.im.lsig_ts_iq);
    frame_put_i32(&o[102], d.res.im.taur_q4);
    frame_put_i32(&o[106], d.res.im.rr_iq);
    frame_put_i32(&o[110], d.res.im.id_iq);
    frame_put_u16(&o[114], d.res.lq_q12);
    frame_put_u16(&o[116], d.res.salient);
    rs->len = 118U;
}

/* FAULT_CLEAR (proto.h): refused while the configuration is the fault. */
APP_NOINLINE static void do_fault_clear(const frame_t *rq, frame_t *rs)
{
    app_status_t s;
    app_get_status(&s);
    if (s.state == APP_STATE_FAULT && s.fault == (uint16_t)APP_FAULT_CONFIG) {
        app_proto_error(rq, rs, PROTO_ERR_REFUSED, PROTO_REFUSE_CONFIG);
    } else {
        app_request_fault_clear();
    }
}

/* IDENT_APPLY (proto.h): the finished identification into the parameters in force. */
APP_NOINLINE static void do_ident_apply(const frame_t *rq, frame_t *rs)
{
    int16_t detail = 0;
    uint16_t n = 0U;
    const int16_t rc = app_ident_apply(&n, &detail);
    switch (rc) {
    case APP_IDENT_APPLY_OK:
        break;
    case APP_IDENT_APPLY_ARMED:
        app_proto_error(rq, rs, PROTO_ERR_ARMED, 0);
        return;
    case APP_IDENT_APPLY_NOT_DONE:
        app_proto_error(rq, rs, PROTO_ERR_STATE, rc);
        return;
    case APP_IDENT_APPLY_LAW:
        app_proto_error(rq, rs, PROTO_ERR_REFUSED, PROTO_REFUSE_LAW);
        return;
    case APP_IDENT_APPLY_CHECK:
        app_proto_error(rq, rs, PROTO_ERR_RANGE, detail);
        return;
    default:
        app_proto_error(rq, rs, PROTO_ERR_RANGE, rc);
        return;
    }
    frame_put_u16(&rs->payload[0], n);
    rs->len = 2U;
}

APP_NOINLINE static void do_telemetry_start(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    uint16_t k;
    const uint16_t count = frame_get_u16(&rq->payload[2]);
    uint16_t decim = frame_get_u16(&rq->payload[0]);
    uint32_t min_decim;
    if (count > 4U || rq->len < (uint16_t)(4U + 2U * count)) {
        app_proto_error(rq, rs, count > 4U ? PROTO_ERR_RANGE : PROTO_ERR_LENGTH, 2);
        return;
    }
    for (k = 0U; k < count; k++) {
        p->tm_q[k] = frame_get_u16(&rq->payload[4U + 2U * k]);
        if (p->tm_q[k] >= (uint16_t)CAPTURE_Q_COUNT) {
            app_proto_error(rq, rs, PROTO_ERR_RANGE, (int16_t)(4U + 2U * k));
            return;
        }
    }
    /* at most half the line: a frame of FRAME_OVERHEAD + 4 + 4 count octets, 10 bits each, at
     * PROTO_BAUD, in control periods (background: division fine) */
    min_decim = (uint32_t)(((uint64_t)(FRAME_OVERHEAD + 4U + 4U * count) * 10U * 2U * 1000000000U / (uint64_t)PROTO_BAUD +
                            p->period_ns - 1U) / p->period_ns);
    if ((uint32_t)decim < min_decim) {
        decim = (uint16_t)(min_decim > 0xFFFFU ? 0xFFFFU : min_decim);
    }
    p->tm_decim = decim;
    p->tm_count = count;
    p->tm_seq = rq->seq;
    p->tm_on = 1U;
    p->tm_next = 0U;
    frame_put_u16(&rs->payload[0], decim);
    rs->len = 2U;
}

/* Minimum request length of each command (proto.h layouts); 0xFFFF: unknown command. */
static uint16_t min_len(uint16_t cmd)
{
    switch (cmd) {
    case PROTO_HELLO:
    case PROTO_STATUS:
    case PROTO_ARM:
    case PROTO_DISARM:
    case PROTO_FAULT_CLEAR:
    case PROTO_TELEMETRY_STOP:
    case PROTO_CAPTURE_STATUS:
    case PROTO_CAPTURE_STOP:
    case PROTO_PARAMS_SAVE:
    case PROTO_IDENT_APPLY:
        return 0U;
    case PROTO_PARAM_DESC:
    case PROTO_PARAM_READ:
    case PROTO_FAULTLOG_READ:
    case PROTO_PARAMS_RESTORE:
    case PROTO_IDENTIFY:
        return 2U;
    case PROTO_SPEED_REF:
    case PROTO_TORQUE_REF:
    case PROTO_TELEMETRY_START:
    case PROTO_CAPTURE_READ:
        return 4U;
    case PROTO_PARAM_WRITE:
        return 6U;
    case PROTO_CAPTURE_SETUP:
        return 24U;
    default:
        return 0xFFFFU;
    }
}

void app_proto_handle(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    const uint16_t need = min_len(rq->cmd);
    rs->seq = rq->seq;
    rs->cmd = (uint16_t)(rq->cmd | PROTO_RESPONSE);
    rs->len = 0U;
    if (need == 0xFFFFU) {
        app_proto_error(rq, rs, PROTO_ERR_UNKNOWN_CMD, 0);
        return;
    }
    if (rq->len < need) {
        app_proto_error(rq, rs, PROTO_ERR_LENGTH, (int16_t)need);
        return;
    }
    switch (rq->cmd) {
    case PROTO_HELLO:
        do_hello(rs, p);
        break;
    case PROTO_STATUS:
        do_status(rs, &p->dec);
        break;
    case PROTO_ARM: {
        const uint16_t why = app_arm();
        if (why != (uint16_t)APP_ARM_OK) {
            app_proto_error(rq, rs, PROTO_ERR_REFUSED, (int16_t)why);
        }
        break;
    }
    case PROTO_DISARM:
        app_disarm();
        break;
    case PROTO_SPEED_REF:
        do_ref(rq, rs, DTC_MODE_SPEED);
        break;
    case PROTO_TORQUE_REF:
        do_ref(rq, rs, DTC_MODE_TORQUE);
        break;
    case PROTO_FAULT_CLEAR:
        do_fault_clear(rq, rs);
        break;
    case PROTO_TELEMETRY_START:
        do_telemetry_start(p, rq, rs);
        break;
    case PROTO_TELEMETRY_STOP:
        p->tm_on = 0U;
        break;
    case PROTO_CAPTURE_SETUP:
        do_capture_setup(rq, rs);
        break;
    case PROTO_CAPTURE_STATUS:
        do_capture_status(rs);
        break;
    case PROTO_CAPTURE_READ:
        do_capture_read(rq, rs);
        break;
    case PROTO_CAPTURE_STOP:
        capture_stop(app_capture());
        break;
    case PROTO_FAULTLOG_READ:
        do_faultlog(rq, rs);
        break;
    case PROTO_IDENTIFY:
        do_identify(rq, rs);
        break;
    case PROTO_IDENT_APPLY:
        do_ident_apply(rq, rs);
        break;
    default: /* the parameter commands, save and restore */
        app_proto_param(p, rq, rs);
        break;
    }
}

/* Starts sending frame f (the transmit buffer is free). */
static void send(app_proto_t *p, const frame_t *f)
{
    p->tx_len = frame_encode(p->tx, FRAME_MAX_OCTETS, f->cmd, f->seq, f->payload, f->len);
    p->tx_pos = 0U;
}

static void flush(app_proto_t *p)
{
    if (p->tx_pos < p->tx_len) {
        p->tx_pos = (uint16_t)(p->tx_pos + hal_serial_write(&p->tx[p->tx_pos], (uint16_t)(p->tx_len - p->tx_pos)));
    }
}

APP_NOINLINE static void telemetry(app_proto_t *p, uint32_t tick)
{
    frame_t *const f = &p->out;
    app_status_t s;
    dtc_refs_t r;
    uint16_t k;
    if ((int32_t)(tick - p->tm_next) < 0) {
        return;
    }
    p->tm_next = tick + p->tm_decim;
    app_get_status(&s);
    app_get_refs(&r);
    f->cmd = PROTO_TELEMETRY;
    f->seq = p->tm_seq;
    frame_put_u32(&f->payload[0], s.tick);
    for (k = 0U; k < p->tm_count; k++) {
        frame_put_i32(&f->payload[4U + 4U * k], quantity(&s, &r, p->tm_q[k]));
    }
    f->len = (uint16_t)(4U + 4U * p->tm_count);
    send(p, f);
}

/* The drive's tick (its status copy off the stack of the request's handling) */
APP_NOINLINE static uint32_t status_tick(void)
{
    app_status_t s;
    app_get_status(&s);
    return s.tick;
}

void app_proto_poll(app_proto_t *p)
{
    uint16_t buf[APP_PROTO_RX_OCTETS];
    uint16_t n, k;
    uint32_t tick;

    flush(p);
    tick = status_tick();
    n = frame_dec_room(&p->dec);
    n = hal_serial_read(buf, n < APP_PROTO_RX_OCTETS ? n : APP_PROTO_RX_OCTETS);
    for (k = 0U; k < n; k++) {
        (void)frame_dec_put(&p->dec, buf[k]);
    }
    if (n > 0U) {
        p->last_rx_tick = tick;
        p->rx_seen = 1U;
    } else if (p->rx_seen != 0U && tick - p->last_rx_tick >= p->idle_ticks) {
        /* a truncated frame can wait no longer: only once the queued octets are parsed */
        if (frame_dec_pending(&p->dec) == 0U) {
            frame_dec_idle(&p->dec);
            p->rx_seen = 0U;
        }
    }
    if (p->tx_pos < p->tx_len) {
        return; /* the line is busy: the request waits in the decoder */
    }
    if (frame_dec_poll(&p->dec, APP_PROTO_PARSE_STEPS) != 0U) {
        app_comm_seen();
        app_proto_handle(p, &p->dec.frame, &p->out);
        send(p, &p->out);
        flush(p);
        return;
    }
    if (p->tm_on != 0U) {
        telemetry(p, tick);
        flush(p);
    }
}
