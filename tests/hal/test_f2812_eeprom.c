/*
 * test_f2812_eeprom.c - the storage medium of hal.h on a 25LC256-class SPI EEPROM
 * (hal/f2812/f2812_eeprom.c), against a model of the part written here from its datasheet (fact
 * sheet 9.2, EE ✔): the SPI master (f2812_spi_*) is replaced by this model, so the test sees
 * every octet on the bus.
 *
 * The model: 32768 octets; a command starts at chip select low; WREN (0x06) sets the write-enable
 * latch when chip select rises; WRITE (0x02) + 16-bit address + data is accepted only with the
 * latch set and no write in progress, its address wraps inside the 64-octet page, and the write
 * cycle (WIP) begins at the rising chip select and lasts for a number of status reads; the latch
 * clears after it; READ (0x03) + address returns octets sequentially; RDSR (0x05) returns WIP in
 * bit 0 and the latch in bit 1.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "f2812_hal.h"
#include "f2812_regs.h"
#include "hal.h"

F2812_INTERRUPT void f2812_adcint_isr(void) {}

#define EE_OCTETS 32768u
#define EE_PAGE 64u
static struct {
    uint16_t mem[EE_OCTETS];
    int cs;            /* 1 = selected */
    int pos;           /* octets of this command so far */
    uint16_t op;
    uint16_t addr;
    int wel;
    int wip_reads;     /* status reads until the write cycle ends */
    int busy_per_write;
    uint16_t page_buf_base;
    uint16_t pending[EE_PAGE];
    int pending_n;
    uint16_t pending_addr;
    int violations;    /* WRITE without WREN, or during a write cycle */
    int writes;        /* write cycles */
    int rdsr;          /* status reads */
    int dead;          /* no part: transfers never complete */
} ee;

void f2812_spi_init(void) {}

void f2812_spi_cs(uint16_t active)
{
    if (active && !ee.cs) {
        ee.cs = 1;
        ee.pos = 0;
        ee.pending_n = 0;
    } else if (!active && ee.cs) {
        ee.cs = 0;
        if (ee.op == 0x06u && ee.pos == 1) {
            ee.wel = 1;
        }
        if (ee.op == 0x02u && ee.pos >= 3) {
            if (!ee.wel || ee.wip_reads > 0) {
                ee.violations++;
            } else {
                for (int i = 0; i < ee.pending_n; i++) {
                    const uint16_t page = (uint16_t)(ee.pending_addr & ~(EE_PAGE - 1u));
                    const uint16_t a = (uint16_t)(page + ((ee.pending_addr + i) & (EE_PAGE - 1u)));
                    ee.mem[a] = ee.pending[i];
                }
                ee.wip_reads = ee.busy_per_write;
                ee.writes++;
            }
            ee.wel = 0;
        }
        ee.op = 0;
    }
}

uint16_t f2812_spi_xfer(uint16_t tx, uint16_t *rx)
{
    tx &= 0xFFu;
    *rx = 0xFFu;
    if (ee.dead) {
        return 0u;
    }
    assert_true(ee.cs); /* every octet inside a chip-select frame */
    if (ee.pos == 0) {
        ee.op = tx;
    } else if ((ee.op == 0x02u || ee.op == 0x03u) && ee.pos <= 2) {
        ee.addr = ee.pos == 1 ? (uint16_t)(tx << 8) : (uint16_t)(ee.addr | tx);
        if (ee.pos == 2) {
            ee.pending_addr = (uint16_t)(ee.addr & (EE_OCTETS - 1u));
        }
    } else if (ee.op == 0x03u) {
        *rx = ee.mem[ee.addr & (EE_OCTETS - 1u)];
        ee.addr++;
    } else if (ee.op == 0x02u) {
        if (ee.pending_n < (int)EE_PAGE) {
            ee.pending[ee.pending_n] = tx;
        }
        ee.pending_n++;
        assert_true(ee.pending_n <= (int)EE_PAGE); /* never more than a page per write */
    } else if (ee.op == 0x05u) {
        ee.rdsr++;
        *rx = (uint16_t)((ee.wip_reads > 0 ? 1u : 0u) | (ee.wel ? 2u : 0u));
        if (ee.wip_reads > 0) {
            ee.wip_reads--;
        }
    }
    ee.pos++;
    return 1u;
}

static int setup(void **state)
{
    (void)state;
    memset(&ee, 0, sizeof ee);
    for (unsigned i = 0; i < EE_OCTETS; i++) {
        ee.mem[i] = 0xFFu;
    }
    ee.busy_per_write = 3;
    memset((void *)&f2812_sysctrl, 0, sizeof f2812_sysctrl);
    return 0;
}

static void test_geometry(void **state)
{
    (void)state;
    assert_int_equal(hal_store_words(), 16384); /* 32 KiB */
    assert_int_equal(hal_store_erase_words(), 32); /* a 64-octet page */
}

static void test_write_read_across_pages(void **state)
{
    (void)state;
    uint16_t w[100];
    uint16_t r[100];
    for (int i = 0; i < 100; i++) {
        w[i] = (uint16_t)(0xA500u + (unsigned)i * 0x0103u);
    }
    /* 100 words from word 20: octets 40..239, touching pages 0..3: four write commands */
    assert_int_equal(hal_store_write(20u, w, 100u), HAL_STORE_OK);
    assert_int_equal(ee.writes, 4);
    assert_int_equal(ee.violations, 0);
    /* each write cycle was waited out (status read until WIP = 0) with the watchdog serviced */
    assert_int_equal(ee.rdsr, 4 * (3 + 1));
    assert_int_equal(f2812_sysctrl.WDKEY, 0x00AA);
    /* big-endian words in the part */
    assert_int_equal(ee.mem[40], 0xA5);
    assert_int_equal(ee.mem[41], 0x00);
    assert_int_equal(hal_store_read(20u, r, 100u), HAL_STORE_OK);
    assert_memory_equal(w, r, sizeof w);
    /* neighbours untouched */
    assert_int_equal(ee.mem[39], 0xFF);
    assert_int_equal(ee.mem[240], 0xFF);
    /* rewrite in place (no erase needed): a second write over the same words */
    for (int i = 0; i < 100; i++) {
        w[i] = (uint16_t)~w[i];
    }
    assert_int_equal(hal_store_erase(0u, 128u), HAL_STORE_OK);
    assert_int_equal(hal_store_write(20u, w, 100u), HAL_STORE_OK);
    assert_int_equal(hal_store_read(20u, r, 100u), HAL_STORE_OK);
    assert_memory_equal(w, r, sizeof w);
    /* the last word of the part */
    const uint16_t last = 0x1234u;
    assert_int_equal(hal_store_write(16383u, &last, 1u), HAL_STORE_OK);
    assert_int_equal(hal_store_read(16383u, r, 1u), HAL_STORE_OK);
    assert_int_equal(r[0], 0x1234);
}

static void test_range_and_missing_part(void **state)
{
    (void)state;
    uint16_t r[2] = {0, 0};
    assert_int_equal(hal_store_read(16383u, r, 2u), HAL_STORE_ERR_RANGE);
    assert_int_equal(hal_store_write(16384u, r, 1u), HAL_STORE_ERR_RANGE);
    assert_int_equal(hal_store_erase(16u, 32u), HAL_STORE_ERR_RANGE); /* not on a page */
    assert_int_equal(hal_store_erase(0u, 16u), HAL_STORE_ERR_RANGE);
    assert_int_equal(hal_store_erase(16352u, 64u), HAL_STORE_ERR_RANGE); /* past the end */
    /* a part that never finishes its write cycle: a bounded wait, then an error */
    ee.busy_per_write = 1000000;
    assert_int_equal(hal_store_write(0u, r, 1u), HAL_STORE_ERR_DEVICE);
    /* no part / no SPI clock: errors, no hang */
    ee.dead = 1;
    assert_int_equal(hal_store_read(0u, r, 2u), HAL_STORE_ERR_DEVICE);
    assert_int_equal(hal_store_write(0u, r, 2u), HAL_STORE_ERR_DEVICE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_geometry, setup),
        cmocka_unit_test_setup(test_write_read_across_pages, setup),
        cmocka_unit_test_setup(test_range_and_missing_part, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
