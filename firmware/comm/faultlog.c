/*
 * faultlog.c - the fault ring (faultlog.h).
 */
#include "faultlog.h"

#define FAULTLOG_MASK ((uint16_t)(FAULTLOG_ENTRIES - 1u))

void faultlog_init(faultlog_t *log)
{
    static const faultlog_entry_t zero;
    uint16_t i;
    for (i = 0u; i < FAULTLOG_ENTRIES; i++) {
        log->e[i] = zero;
    }
    log->recorded = 0u;
}

void faultlog_record(faultlog_t *log, uint32_t tick, uint16_t reason, int16_t detail,
                     const faultlog_snapshot_t *snap)
{
    const uint16_t n = log->recorded;
    volatile faultlog_entry_t *e = &log->e[n & FAULTLOG_MASK];
    e->tick = tick;
    e->reason = reason;
    e->detail = detail;
    e->snap = *snap;
    log->recorded = (uint16_t)(n + 1u); /* published after the entry is complete */
}

uint16_t faultlog_count(const faultlog_t *log)
{
    const uint16_t n = log->recorded;
    return (n < FAULTLOG_ENTRIES) ? n : (uint16_t)FAULTLOG_ENTRIES;
}

uint16_t faultlog_get(const faultlog_t *log, uint16_t k, faultlog_entry_t *out)
{
    const uint16_t n1 = log->recorded;
    uint16_t n2;
    const uint16_t held = (n1 < FAULTLOG_ENTRIES) ? n1 : (uint16_t)FAULTLOG_ENTRIES;
    if (k >= held) {
        return FAULTLOG_EMPTY;
    }
    *out = log->e[(uint16_t)(n1 - 1u - k) & FAULTLOG_MASK];
    n2 = log->recorded;
    /* entry k's slot is rewritten by the (FAULTLOG_ENTRIES - k)-th record after n1 */
    if ((uint16_t)(n2 - n1) >= (uint16_t)(FAULTLOG_ENTRIES - k)) {
        return FAULTLOG_BUSY;
    }
    return FAULTLOG_OK;
}
