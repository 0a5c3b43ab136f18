/*
 * test_f2812_sci.c - register-level tests of the serial line (SCI-A, hal/f2812/f2812_sci.c) and
 * the EEPROM's SPI master (SPI-A, f2812_spi.c) on the host, registers in RAM.
 *
 * Expected values are written out here from the fact sheet (../shared/reference/f2812-facts.md
 * section 9) and the quantity they set, not taken from the binding's macros. What RAM cannot do
 * (FIFO status counts, a character arriving, a transfer completing) the test sets by hand and
 * says so; a RAM SCIRXBUF returns the same character on every read, so a test of several octets
 * reads that one character several times.
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

static void reset_device(void)
{
    memset((void *)&f2812_sysctrl, 0, sizeof f2812_sysctrl);
    memset((void *)&f2812_gpiomux, 0, sizeof f2812_gpiomux);
    memset((void *)&f2812_gpiodata, 0, sizeof f2812_gpiodata);
    memset((void *)&f2812_spia, 0, sizeof f2812_spia);
    memset((void *)&f2812_scia, 0, sizeof f2812_scia);
    memset(&f2812_host_cpu, 0, sizeof f2812_host_cpu);
    f2812_host_cpu.intm = 1u;
}

static int setup_init(void **state)
{
    (void)state;
    reset_device();
    hal_init();
    return 0;
}

static void test_sci_init_registers(void **state)
{
    (void)state;
    /* clock and pins: PCLKCR.SCIAENCLK bit 10; GPFMUX bits 4 (SCITXDA) and 5 (SCIRXDA) (9.1) */
    assert_int_equal(f2812_sysctrl.PCLKCR & 0x0400, 0x0400);
    assert_int_equal(f2812_gpiomux.GPFMUX & 0x0030, 0x0030);
    assert_int_equal(f2812_host_cpu.lost_writes, 0);
    /* 8 data bits (SCICHAR = 111), no parity, one stop bit, idle-line mode: 0x0007 */
    assert_int_equal(f2812_scia.SCICCR, 0x0007);
    /* out of reset (SWRESET bit 5) with TX (bit 1) and RX (bit 0) enabled: 0x0023 */
    assert_int_equal(f2812_scia.SCICTL1, 0x0023);
    assert_int_equal(f2812_scia.SCICTL2, 0x0000); /* no interrupts: polled */
    /* baud = LSPCLK / ((BRR + 1) 8), LSPCLK = 150 MHz / 4 = 37.5 MHz: 115200 -> BRR 40 = 0x0028,
     * 114329 baud, -0.76 % (9.1 table) */
    const uint16_t brr = (uint16_t)((f2812_scia.SCIHBAUD << 8) | f2812_scia.SCILBAUD);
    assert_int_equal(f2812_scia.SCIHBAUD, 0x0000);
    assert_int_equal(f2812_scia.SCILBAUD, 0x0028);
    const double baud = 37.5e6 / ((brr + 1.0) * 8.0);
    assert_true(baud > 115200.0 * 0.98 && baud < 115200.0 * 1.02);
    /* FIFOs: SCIFFTX = SCIRST 15 | SCIFFENA 14 | TXFIFOXRESET 13 | TXINTCLR 6 = 0xE040;
     * SCIFFRX = RXFIFORESET 13 | RXFFINTCLR 6 = 0x2040, no FIFO interrupts (9.1 recipe) */
    assert_int_equal(f2812_scia.SCIFFTX, 0xE040);
    assert_int_equal(f2812_scia.SCIFFRX, 0x2040);
    assert_int_equal(f2812_scia.SCIFFCT, 0x0000);
    /* free run under an emulation halt: FREE/SOFT bits 4:3 = 0x0018 (9.5 #4) */
    assert_int_equal(f2812_scia.SCIPRI, 0x0018);
}

static void test_sci_read_nonblocking(void **state)
{
    (void)state;
    uint16_t buf[32];
    /* empty FIFO: nothing, no wait */
    assert_int_equal(hal_serial_read(buf, 32u), 0);
    /* RXFFST (SCIFFRX 12:8) = 3 characters held; the character reads 0x41 */
    f2812_scia.SCIFFRX = (uint16_t)(0x2040u | (3u << 8));
    f2812_scia.SCIRXBUF = 0x0041u;
    assert_int_equal(hal_serial_read(buf, 32u), 3);
    assert_int_equal(buf[0], 0x41);
    assert_int_equal(buf[2], 0x41);
    /* at most max */
    f2812_scia.SCIFFRX = (uint16_t)(0x2040u | (16u << 8));
    assert_int_equal(hal_serial_read(buf, 5u), 5);
    assert_int_equal(hal_serial_read(buf, 0u), 0);
    /* a character with a framing error (bit 15) or parity error (bit 14): handed on as its
     * octet, bits 15:8 cleared, and counted */
    const uint16_t before = f2812_sci_stats()->rx_char_errors;
    f2812_scia.SCIFFRX = (uint16_t)(0x2040u | (2u << 8));
    f2812_scia.SCIRXBUF = 0x80A5u;
    assert_int_equal(hal_serial_read(buf, 32u), 2);
    assert_int_equal(buf[0], 0xA5);
    assert_int_equal(f2812_sci_stats()->rx_char_errors, before + 2u);
}

static void test_sci_receiver_error_recovery(void **state)
{
    (void)state;
    uint16_t buf[4];
    /* RXERROR (SCIRXST bit 7): the binding pulses SWRESET and leaves the SCI running (0x0023) */
    f2812_scia.SCIRXST = 0x0080u;
    f2812_scia.SCICTL1 = 0x0003u; /* mark: the binding must write the running value back */
    (void)hal_serial_read(buf, 4u);
    assert_int_equal(f2812_scia.SCICTL1, 0x0023);
    assert_int_equal(f2812_sci_stats()->rx_resets, 1);
    f2812_scia.SCIRXST = 0u; /* the reset cleared the flags (hardware) */
    /* RXFFOVF (SCIFFRX bit 15): cleared by writing RXFFOVRCLR (bit 14), FIFO kept running */
    f2812_scia.SCIFFRX = 0xA040u;
    (void)hal_serial_read(buf, 4u);
    assert_int_equal(f2812_scia.SCIFFRX, 0x6040);
    assert_int_equal(f2812_sci_stats()->rx_overflows, 1);
}

static void test_sci_write_nonblocking(void **state)
{
    (void)state;
    const uint16_t out[5] = {0x101, 0x02, 0x03, 0x04, 0x1A5};
    /* TXFFST (SCIFFTX 12:8) = 14 of 16: two accepted, the caller keeps the rest */
    f2812_scia.SCIFFTX = (uint16_t)(0xE040u | (14u << 8));
    assert_int_equal(hal_serial_write(out, 5u), 2);
    assert_int_equal(f2812_scia.SCITXBUF, 0x02); /* the last one written, bits 7:0 only */
    /* full FIFO: nothing accepted, no wait */
    f2812_scia.SCIFFTX = (uint16_t)(0xE040u | (16u << 8));
    assert_int_equal(hal_serial_write(out, 5u), 0);
    /* empty FIFO: all five, the last masked to its octet */
    f2812_scia.SCIFFTX = 0xE040u;
    assert_int_equal(hal_serial_write(out, 5u), 5);
    assert_int_equal(f2812_scia.SCITXBUF, 0xA5);
}

static void test_spi_init_registers(void **state)
{
    (void)state;
    /* clock PCLKCR.SPIENCLK bit 8; GPFMUX bits 0-2 SPISIMOA/SOMIA/CLKA, bit 3 left a GPIO and
     * made an output (chip select), driven high = inactive (9.2) */
    assert_int_equal(f2812_sysctrl.PCLKCR & 0x0100, 0x0100);
    assert_int_equal(f2812_gpiomux.GPFMUX & 0x000F, 0x0007);
    assert_int_equal(f2812_gpiomux.GPFDIR & 0x0008, 0x0008);
    assert_int_equal(f2812_gpiodata.F.SET & 0x0008, 0x0008);
    /* 8-bit characters (SPICHAR = 7), clock polarity 0, out of reset (bit 7): 0x0087 */
    assert_int_equal(f2812_spia.SPICCR, 0x0087);
    /* master (bit 2), TALK (bit 1), CLK_PHASE 1 (bit 3): 0x000E */
    assert_int_equal(f2812_spia.SPICTL, 0x000E);
    /* SPICLK = 37.5 MHz / (SPIBRR + 1) = 4.69 MHz <= 5 MHz for a 25LC256 at 3.3 V (9.2) */
    assert_int_equal(f2812_spia.SPIBRR, 7);
    assert_true(37.5e6 / (f2812_spia.SPIBRR + 1.0) <= 5e6);
    assert_int_equal(f2812_spia.SPIPRI, 0x0010);
}

static void test_spi_transfer(void **state)
{
    (void)state;
    uint16_t rx = 0u;
    /* the character is written left-justified; the done flag (SPISTS bit 6) set by hand, as the
     * hardware would after 8 clocks; the received octet is right-justified */
    f2812_spia.SPISTS = 0x0040u;
    f2812_spia.SPIRXBUF = 0x005Au;
    assert_int_equal(f2812_spi_xfer(0x1C3u, &rx), 1);
    assert_int_equal(f2812_spia.SPITXBUF, 0xC300);
    assert_int_equal(rx, 0x5A);
    /* a transfer that never completes (no clock): bounded wait, failure reported */
    f2812_spia.SPISTS = 0u;
    assert_int_equal(f2812_spi_xfer(0x00u, &rx), 0);
    /* chip select: active = GPIOF3 cleared, inactive = set */
    f2812_gpiodata.F.SET = 0u;
    f2812_gpiodata.F.CLEAR = 0u;
    f2812_spi_cs(1u);
    assert_int_equal(f2812_gpiodata.F.CLEAR, 0x0008);
    f2812_spi_cs(0u);
    assert_int_equal(f2812_gpiodata.F.SET, 0x0008);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_sci_init_registers, setup_init),
        cmocka_unit_test_setup(test_sci_read_nonblocking, setup_init),
        cmocka_unit_test_setup(test_sci_receiver_error_recovery, setup_init),
        cmocka_unit_test_setup(test_sci_write_nonblocking, setup_init),
        cmocka_unit_test_setup(test_spi_init_registers, setup_init),
        cmocka_unit_test_setup(test_spi_transfer, setup_init),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
