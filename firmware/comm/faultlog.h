/*
 * faultlog.h - the last FAULTLOG_ENTRIES faults with the ISR tick, the reason, its detail and a
 * snapshot of the measurement and the law's state at the trip.
 *
 * One writer, one reader. The ISR records (faultlog_record, when a fault latches); the
 * background loop reads (faultlog_get) and never writes. The log is a ring: the newest entry
 * overwrites the oldest once FAULTLOG_ENTRIES are held. It lives apart from the application's
 * state, so a fault clear does not touch it; only faultlog_init (at boot) empties it.
 *
 * Consistency without masking interrupts: the writer fills the slot, then increments
 * `recorded`. A reader copies the entry between two reads of `recorded`; if the count moved and
 * the slot it copied may have been rewritten meanwhile (k + moved >= FAULTLOG_ENTRIES), the copy
 * is discarded and FAULTLOG_BUSY returned (read again). On the C28x a 16-bit load or store is
 * atomic, so `recorded` itself is never torn.
 *
 * Formats: the snapshot's quantities are the firmware's per-unit IQ (int32, FIX_IQ_Q = 24
 * fraction bits, fixmath.h); the log copies them and does no arithmetic on them.
 */
#ifndef FAULTLOG_H
#define FAULTLOG_H

#include <stdint.h>

#define FAULTLOG_ENTRIES 8u /* power of two: the ring index is masked */

#if (FAULTLOG_ENTRIES & (FAULTLOG_ENTRIES - 1u)) != 0u
#error "FAULTLOG_ENTRIES must be a power of two"
#endif

/* What the application passes at the trip: the per-unit measurement of the sample that tripped
 * and the law's state of the step before (the estimates and references in force). */
typedef struct {
    int32_t ia_iq, ib_iq, ic_iq; /* phase currents, pu */
    int32_t vdc_iq;              /* DC-link voltage, pu */
    int32_t vmid_iq;             /* FSTP mid-point voltage, pu (0 on the SSTP) */
    int32_t speed_iq;            /* measured electrical speed, pu */
    int32_t psi_alpha_iq, psi_beta_iq; /* estimated stator flux, pu */
    int32_t te_iq;               /* estimated torque, pu */
    int32_t te_ref_iq;           /* torque reference in force, pu */
    int32_t speed_ref_iq;        /* speed reference in force, pu */
    uint16_t sector;             /* flux sector of the last step */
    uint16_t vector;             /* voltage vector of the last step */
    uint16_t state;              /* the application's state when the fault latched */
} faultlog_snapshot_t;

typedef struct {
    uint32_t tick;     /* ISR tick of the sample that tripped */
    uint16_t reason;   /* fault code (the application's fault enumeration) */
    int16_t detail;    /* the reason's detail (phase, channel, error code) */
    faultlog_snapshot_t snap;
} faultlog_entry_t;

typedef struct {
    volatile faultlog_entry_t e[FAULTLOG_ENTRIES]; /* volatile: the compiler keeps the entry's
                                                    * accesses on their side of `recorded`'s */
    volatile uint16_t recorded; /* faults recorded since faultlog_init (wraps at 2^16) */
} faultlog_t;

/* faultlog_get results. */
enum faultlog_status {
    FAULTLOG_OK = 0,
    FAULTLOG_EMPTY = 1, /* fewer than k + 1 entries held */
    FAULTLOG_BUSY = 2   /* the ISR recorded over the entry during the copy: read again */
};

/* Empties the log (boot only, never on a fault clear). */
void faultlog_init(faultlog_t *log);

/* ISR: records one fault. Copies the snapshot (about 30 words), no other work. */
void faultlog_record(faultlog_t *log, uint32_t tick, uint16_t reason, int16_t detail,
                     const faultlog_snapshot_t *snap);

/* Background: entries held (0..FAULTLOG_ENTRIES). */
uint16_t faultlog_count(const faultlog_t *log);

/* Background: copies entry k (0 = the newest) to *out. Returns enum faultlog_status. */
uint16_t faultlog_get(const faultlog_t *log, uint16_t k, faultlog_entry_t *out);

#endif /* FAULTLOG_H */
