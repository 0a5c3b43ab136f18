/*
 * capture.c - triggered capture (capture.h).
 */
#include "capture.h"

/* What an unused source pointer of a selected channel points to (capture_t.ch). */
static const int32_t zero32 = 0;
static const uint16_t zero16 = 0u;

void capture_init(capture_t *c)
{
    uint16_t i;
    c->state = CAPTURE_OFF;
    for (i = 0u; i < (uint16_t)CAPTURE_Q_COUNT; i++) {
        c->src[i].p32 = 0;
        c->src[i].p16 = 0;
    }
    for (i = 0u; i < CAPTURE_CHANNELS; i++) {
        c->ch[i].p32 = 0;
        c->ch[i].p16 = 0;
        c->cfg.quantity[i] = 0u;
    }
    c->cfg.count = 0u;
    c->cfg.samples = 0u;
    c->cfg.pre = 0u;
    c->cfg.decim = 1u;
    c->cfg.trigger = CAPTURE_TRIG_NOW;
    c->cfg.trig_ch = 0u;
    c->cfg.level = 0;
    c->span = 0u;
    c->w = 0u;
    c->filled = 0u;
    c->post = 0u;
    c->dec_cnt = 0u;
    c->tch = 0u;
    c->may_fire = 0u;
    c->lvl = 0u;
    c->on_fault = 0u;
    c->tmask = 0;
    c->tlevel = 0;
    c->trig_tick = 0u;
}

uint16_t capture_bind(capture_t *c, uint16_t q, const volatile int32_t *p)
{
    if (q >= (uint16_t)CAPTURE_Q_COUNT) {
        return 1u;
    }
    c->src[q].p32 = p;
    c->src[q].p16 = 0;
    return 0u;
}

uint16_t capture_bind_u16(capture_t *c, uint16_t q, const volatile uint16_t *p)
{
    if (q >= (uint16_t)CAPTURE_Q_COUNT) {
        return 1u;
    }
    c->src[q].p32 = 0;
    c->src[q].p16 = p;
    return 0u;
}

static uint16_t check(const capture_t *c, const capture_setup_t *s)
{
    uint16_t i;
    if (s->count < 1u || s->count > CAPTURE_CHANNELS) {
        return CAPTURE_ERR_COUNT;
    }
    for (i = 0u; i < s->count; i++) {
        const uint16_t q = s->quantity[i];
        if (q >= (uint16_t)CAPTURE_Q_COUNT || (c->src[q].p32 == 0 && c->src[q].p16 == 0)) {
            return CAPTURE_ERR_QUANTITY;
        }
    }
    if (s->samples < 1u || (uint32_t)s->count * s->samples > (uint32_t)CAPTURE_BUF_WORDS32) {
        return CAPTURE_ERR_SAMPLES;
    }
    if (s->pre >= s->samples) {
        return CAPTURE_ERR_PRE;
    }
    if (s->decim < 1u) {
        return CAPTURE_ERR_DECIM;
    }
    if (s->trigger >= (uint16_t)CAPTURE_TRIG_COUNT ||
        (s->trigger >= (uint16_t)CAPTURE_TRIG_ABOVE && s->trigger <= (uint16_t)CAPTURE_TRIG_FALLING &&
         s->trig_ch >= s->count)) {
        return CAPTURE_ERR_TRIGGER;
    }
    return CAPTURE_OK;
}

uint16_t capture_setup(capture_t *c, const capture_setup_t *s)
{
    uint16_t i;
    const uint16_t err = check(c, s);
    c->state = CAPTURE_OFF; /* the ISR leaves it alone from here */
    if (err != CAPTURE_OK) {
        return err;
    }
    c->cfg = *s;
    for (i = 0u; i < CAPTURE_CHANNELS; i++) {
        const capture_src_t *b = &c->src[s->quantity[i < s->count ? i : 0u]];
        c->ch[i].p32 = (i < s->count && b->p32 != 0) ? b->p32 : &zero32;
        c->ch[i].p16 = (i < s->count && b->p16 != 0) ? b->p16 : &zero16;
    }
    c->span = (uint16_t)(s->count * s->samples);
    c->w = 0u;
    c->filled = 0u;
    c->post = (uint16_t)(s->samples - s->pre);
    c->dec_cnt = 1u; /* the first period after arming is recorded */
    /* The trigger as one test, hit(x) = (x ^ tmask) >= tlevel: with tmask = -1, x ^ tmask = ~x =
     * -x - 1 reverses the order of int32 without overflow, so x <= L <=> ~x >= ~L. An edge fires
     * on a hit after a miss (rising: prev < L <=> not prev >= L; falling: prev > L <=> not
     * ~prev >= ~L); now and fault hit always (x >= INT32_MIN). */
    c->tch = (s->trig_ch < s->count) ? s->trig_ch : 0u;
    c->tmask = (s->trigger == (uint16_t)CAPTURE_TRIG_BELOW || s->trigger == (uint16_t)CAPTURE_TRIG_FALLING) ? -1 : 0;
    c->tlevel = (s->trigger == (uint16_t)CAPTURE_TRIG_NOW || s->trigger == (uint16_t)CAPTURE_TRIG_FAULT)
                    ? INT32_MIN : (int32_t)(s->level ^ c->tmask);
    c->lvl = (uint16_t)(s->trigger <= (uint16_t)CAPTURE_TRIG_BELOW ? 1u : 0u);
    c->on_fault = (uint16_t)(s->trigger == (uint16_t)CAPTURE_TRIG_FAULT ? 1u : 0u);
    c->may_fire = c->lvl; /* an edge needs a recorded miss first, the fault trigger a fault */
    c->trig_tick = 0u;
    c->state = CAPTURE_ARMED; /* last: the set-up above is complete */
    return CAPTURE_OK;
}

void capture_stop(capture_t *c)
{
    c->state = CAPTURE_OFF;
}

uint16_t capture_state(const capture_t *c)
{
    return c->state;
}

void capture_isr_run(capture_t *c, uint32_t tick, uint16_t fault)
{
    const uint16_t n = c->cfg.count; /* >= 1 while armed (capture_setup) */
    const capture_src_t *s = c->ch;
    const capture_src_t *const end = &c->ch[n];
    int32_t *dst;
    int32_t *d;
    if (fault != 0u) {
        c->may_fire |= c->on_fault;
    }
    c->dec_cnt--;
    if (c->dec_cnt != 0u) {
        return;
    }
    c->dec_cnt = c->cfg.decim;
    dst = &c->buf[c->w];
    d = dst;
    do {
        /* one of the two points to a zero (capture_setup): the value of either type, no test */
        *d = *s->p32 + (int32_t)*s->p16;
        d++;
        s++;
    } while (s != end);
    c->w = (uint16_t)(c->w + n);
    if (c->w >= c->span) {
        c->w = 0u;
    }
    if (c->state == (uint16_t)CAPTURE_ARMED) {
        const uint16_t hit = (uint16_t)((dst[c->tch] ^ c->tmask) >= c->tlevel ? 1u : 0u);
        /* the trigger is tested only once the pre-trigger history is full */
        if (c->filled < c->cfg.pre) {
            c->filled++;
        } else if ((hit & c->may_fire) != 0u) {
            c->trig_tick = tick;
            c->state = CAPTURE_TRIGGERED;
        }
        c->may_fire = (uint16_t)((hit ^ 1u) | c->lvl);
        if (c->state == (uint16_t)CAPTURE_ARMED) {
            return;
        }
    }
    c->post--;
    if (c->post == 0u) {
        c->state = CAPTURE_DONE;
    }
}

int32_t capture_read(const capture_t *c, uint16_t k, uint16_t ch)
{
    uint16_t idx;
    if (c->state != (uint16_t)CAPTURE_DONE || k >= c->cfg.samples || ch >= c->cfg.count) {
        return 0;
    }
    /* done: the ring holds exactly the last `samples` samples; the oldest is at w */
    idx = (uint16_t)(c->w + (uint16_t)(k * c->cfg.count) + ch);
    if (idx >= c->span) {
        idx = (uint16_t)(idx - c->span);
    }
    return c->buf[idx];
}

uint32_t capture_first_tick(const capture_t *c)
{
    return c->trig_tick - (uint32_t)c->cfg.pre * c->cfg.decim;
}
