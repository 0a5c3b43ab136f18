/*
 * store.c - two-copy parameter store (store.h).
 */
#include "store.h"

#include "crc16.h"
#include "hal.h"

#define W_MAGIC 0u
#define W_VERSION 1u
#define W_SEQ_LO 2u
#define W_SEQ_HI 3u
#define W_N 4u
#define W_CRC 5u

static uint16_t slot_words(void)
{
    const uint16_t words = hal_store_words();
    const uint16_t unit = hal_store_erase_words();
    uint16_t half;
    if (words == 0u || unit == 0u || words < (uint16_t)(2u * unit)) {
        return 0u;
    }
    half = (uint16_t)(words >> 1);
    return (uint16_t)(half & (uint16_t)~(uint16_t)(unit - 1u)); /* whole erase units */
}

static uint16_t header_crc(const uint16_t *h)
{
    return crc16_words(CRC16_INIT, &h[W_VERSION], (uint16_t)(W_CRC - W_VERSION));
}

/* Checks the copy in slot s, reading its data into data (overwritten even when invalid, so the
 * caller reads into a scratch place or reloads). Returns 1 with *seq set when valid. */
static uint16_t slot_valid(uint16_t base, uint16_t version, uint16_t *data, uint16_t n, uint32_t *seq)
{
    uint16_t h[STORE_HEADER_WORDS];
    uint16_t crc;
    if (hal_store_read(base, h, STORE_HEADER_WORDS) != HAL_STORE_OK) {
        return 0u;
    }
    if (h[W_MAGIC] != STORE_MAGIC || h[W_VERSION] != version || h[W_N] != n) {
        return 0u;
    }
    if (hal_store_read((uint16_t)(base + STORE_HEADER_WORDS), data, n) != HAL_STORE_OK) {
        return 0u;
    }
    crc = crc16_words(header_crc(h), data, n);
    if (crc != h[W_CRC]) {
        return 0u;
    }
    *seq = (uint32_t)h[W_SEQ_LO] | ((uint32_t)h[W_SEQ_HI] << 16);
    return 1u;
}

/* a is newer than b, modulo 2^32 */
static uint16_t seq_newer(uint32_t a, uint32_t b)
{
    const uint32_t d = a - b;
    return (uint16_t)(d != 0u && d < 0x80000000u);
}

uint16_t store_boot(store_t *st, uint16_t version, uint16_t *data, const uint16_t *defaults, uint16_t n)
{
    uint32_t seq0 = 0u;
    uint32_t seq1 = 0u;
    uint16_t v0;
    uint16_t v1;
    uint16_t i;
    st->slot_words = slot_words();
    st->have_copy = 0u;
    st->newest = 0u;
    st->seq = 0u;
    if (st->slot_words == 0u || n > (uint16_t)(st->slot_words - STORE_HEADER_WORDS)) {
        v0 = 0u;
        v1 = 0u;
    } else {
        v0 = slot_valid(0u, version, data, n, &seq0);
        v1 = slot_valid(st->slot_words, version, data, n, &seq1);
    }
    if (v0 != 0u || v1 != 0u) {
        st->have_copy = 1u;
        if (v1 != 0u && (v0 == 0u || seq_newer(seq1, seq0) != 0u)) {
            st->newest = 1u;
            st->seq = seq1;
        } else {
            st->newest = 0u;
            st->seq = seq0;
        }
        /* reload the chosen copy (data holds whichever slot was read last) */
        if (slot_valid((uint16_t)(st->newest != 0u ? st->slot_words : 0u), version, data, n, &seq0) != 0u) {
            return STORE_OK;
        }
        st->have_copy = 0u; /* the medium changed under us: fall back */
    }
    if (data != defaults) {
        for (i = 0u; i < n; i++) {
            data[i] = defaults[i];
        }
    }
    return STORE_DEFAULTS;
}

uint16_t store_save(store_t *st, uint16_t armed, uint16_t version, const uint16_t *data, uint16_t n)
{
    static const uint16_t invalid = 0x0000u;
    const uint16_t magic = STORE_MAGIC;
    uint16_t h[STORE_HEADER_WORDS];
    uint16_t slot;
    uint16_t base;
    uint16_t i;
    uint32_t seq;
    if (armed != 0u) {
        return STORE_ERR_ARMED;
    }
    if (st->slot_words == 0u || n > (uint16_t)(st->slot_words - STORE_HEADER_WORDS)) {
        return STORE_ERR_SIZE;
    }
    slot = (st->have_copy != 0u) ? (uint16_t)(1u - st->newest) : 0u;
    base = (uint16_t)(slot != 0u ? st->slot_words : 0u);
    seq = (st->have_copy != 0u) ? (uint32_t)(st->seq + 1u) : 1u;
    h[W_MAGIC] = STORE_MAGIC;
    h[W_VERSION] = version;
    h[W_SEQ_LO] = (uint16_t)(seq & 0xFFFFu);
    h[W_SEQ_HI] = (uint16_t)(seq >> 16);
    h[W_N] = n;
    h[W_CRC] = crc16_words(header_crc(h), data, n);
    if (hal_store_write(base, &invalid, 1u) != HAL_STORE_OK ||
        hal_store_erase(base, st->slot_words) != HAL_STORE_OK ||
        hal_store_write((uint16_t)(base + W_VERSION), &h[W_VERSION], (uint16_t)(STORE_HEADER_WORDS - W_VERSION)) != HAL_STORE_OK ||
        hal_store_write((uint16_t)(base + STORE_HEADER_WORDS), data, n) != HAL_STORE_OK) {
        return STORE_ERR_MEDIUM;
    }
    /* read back before the record claims to be complete */
    for (i = 0u; i < (uint16_t)(STORE_HEADER_WORDS - W_VERSION + n); i++) {
        uint16_t w;
        const uint16_t want = (i < (uint16_t)(STORE_HEADER_WORDS - W_VERSION)) ? h[W_VERSION + i]
                                                                                 : data[i - (STORE_HEADER_WORDS - W_VERSION)];
        if (hal_store_read((uint16_t)(base + W_VERSION + i), &w, 1u) != HAL_STORE_OK) {
            return STORE_ERR_MEDIUM;
        }
        if (w != want) {
            return STORE_ERR_VERIFY;
        }
    }
    if (hal_store_write(base, &magic, 1u) != HAL_STORE_OK) {
        return STORE_ERR_MEDIUM;
    }
    if (hal_store_read(base, &i, 1u) != HAL_STORE_OK || i != STORE_MAGIC) {
        return STORE_ERR_VERIFY;
    }
    st->have_copy = 1u;
    st->newest = slot;
    st->seq = seq;
    return STORE_OK;
}
