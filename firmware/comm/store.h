/*
 * store.h - the parameter set kept across a reset: two copies on the HAL's storage medium
 * (hal.h, hal_store_*), each with a layout version, a sequence number and a CRC; at boot the
 * newest valid copy, else the compiled-in configuration.
 *
 * The set itself is an array of 16-bit words whose layout the caller owns (the parameter table's
 * stored parameters in id order); `version` names that layout (it changes whenever the layout
 * does), so a copy written by another layout is never loaded.
 *
 * Medium layout. The medium is split into two slots of equal size (slot 0 at word 0, slot 1 at
 * half the medium), each a whole number of erase units. A slot holds one record:
 *   word 0        STORE_MAGIC once the record is complete, anything else otherwise
 *   word 1        version
 *   words 2, 3    sequence number, low word first (uint32; the newest copy has the larger one,
 *                 compared modulo 2^32)
 *   word 4        n, data words
 *   word 5        CRC-16/CCITT-FALSE (crc16.h) over words 1..4 and the data, each word high
 *                 octet first
 *   words 6..     the data
 * A copy is valid when word 0 is STORE_MAGIC, version and n are the expected ones and the CRC
 * matches.
 *
 * Saving (store_save), only while the drive is disarmed, always into the slot that does NOT hold
 * the newest valid copy:
 *   1. word 0 := 0x0000 (the slot no longer claims a record; a flash medium can always clear bits),
 *   2. erase the slot,
 *   3. write words 1..5 and the data,
 *   4. read it all back and compare,
 *   5. word 0 := STORE_MAGIC.
 * A power cut at any point leaves the other slot, the newest valid copy, untouched; the slot being
 * written claims a record only after step 5, the last word written. So every boot finds the newest
 * completed copy, or the one before it if the cut came before step 5 ended; never a mix.
 * tests/unit/test_comm_store.c cuts the power at every word written and checks exactly that.
 */
#ifndef STORE_H
#define STORE_H

#include <stdint.h>

#define STORE_MAGIC 0x5A17u
#define STORE_HEADER_WORDS 6u

enum store_status {
    STORE_OK = 0,         /* store_boot: the stored copy was loaded; store_save: written */
    STORE_DEFAULTS = 1,   /* store_boot: no valid copy; the compiled-in set was loaded */
    STORE_ERR_ARMED = 2,  /* store_save refused: the drive is armed */
    STORE_ERR_SIZE = 3,   /* the set does not fit a slot (or the medium is absent) */
    STORE_ERR_MEDIUM = 4, /* the medium reported an error */
    STORE_ERR_VERIFY = 5  /* the copy read back differs from what was written */
};

typedef struct {
    uint16_t slot_words;  /* words per slot (half the medium, whole erase units) */
    uint16_t newest;      /* slot holding the newest valid copy (valid only if have_copy) */
    uint16_t have_copy;   /* 1: a valid copy is on the medium */
    uint32_t seq;         /* its sequence number */
} store_t;

/* Boot: finds the newest valid copy of layout `version` with n words and copies it into data;
 * without one, copies defaults[0..n-1] into data. Returns STORE_OK (stored copy loaded) or
 * STORE_DEFAULTS (none valid, or no medium). data and defaults may be the same array. */
uint16_t store_boot(store_t *st, uint16_t version, uint16_t *data, const uint16_t *defaults, uint16_t n);

/* Background, disarmed only (armed != 0: STORE_ERR_ARMED, nothing written): writes data[0..n-1]
 * as the newest copy, into the slot without the newest valid copy. Returns enum store_status;
 * on STORE_OK st->seq is the new copy's sequence number. */
uint16_t store_save(store_t *st, uint16_t armed, uint16_t version, const uint16_t *data, uint16_t n);

#endif /* STORE_H */
