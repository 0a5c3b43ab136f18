/*
 * f2812_sci.c - the serial line of hal.h on SCI-A (fact sheet 9.1): 8N1 at F2812_SCI_BAUD
 * (f2812_board.h), both 16-deep FIFOs on, no interrupts: the background loop polls through
 * hal_serial_read / hal_serial_write, neither of which waits.
 *
 * Receive errors. A character with a framing or parity error (SCIRXBUF.SCIFFFE/SCIFFPE) is still
 * handed on (the frame CRC rejects its frame) and counted. A receiver error (SCIRXST.RXERROR:
 * overrun, framing, parity, break) stops reception until the SCI is reset: the binding pulses
 * SWRESET, which clears the flags (9.1, ~) and keeps the FIFO contents. A FIFO overflow
 * (SCIFFRX.RXFFOVF: octets lost) is cleared with RXFFOVRCLR and counted.
 */
#include "hal.h"

#include "f2812_board.h"
#include "f2812_hal.h"
#include "f2812_regs.h"

#define SCICTL1_RUN ((uint16_t)(F2812_SCICTL1_SWRESET | F2812_SCICTL1_TXENA | F2812_SCICTL1_RXENA))
#define SCICTL1_RESET ((uint16_t)(F2812_SCICTL1_TXENA | F2812_SCICTL1_RXENA))
#define SCIFFTX_RUN                                                                                \
    ((uint16_t)(F2812_SCIFFTX_SCIRST | F2812_SCIFFTX_SCIFFENA | F2812_SCIFFTX_TXFIFOXRESET |       \
                F2812_SCIFFTX_TXINTCLR))
#define SCIFFRX_RUN ((uint16_t)(F2812_SCIFFRX_RXFIFORESET | F2812_SCIFFRX_RXFFINTCLR))

static f2812_sci_stats_t s_sci;

void f2812_sci_init(void)
{
    s_sci.rx_char_errors = 0u;
    s_sci.rx_resets = 0u;
    s_sci.rx_overflows = 0u;
    f2812_eallow();
    f2812_wr_protected(&f2812_sysctrl.PCLKCR, (uint16_t)(f2812_sysctrl.PCLKCR | F2812_PCLKCR_SCIAENCLK));
    f2812_wr_protected(&f2812_gpiomux.GPFMUX, (uint16_t)(f2812_gpiomux.GPFMUX | F2812_GPFMUX_SCIA));
    f2812_edis();
    /* 9.1 "8N1 + FIFO recipe": format and enables with the logic held in reset, baud, FIFOs,
     * then out of reset. */
    f2812_scia.SCICTL1 = SCICTL1_RESET;
    f2812_scia.SCICCR = F2812_SCICCR_8N1;
    f2812_scia.SCICTL2 = 0x0000u; /* no TX / RX-break interrupts */
    f2812_scia.SCIHBAUD = (uint16_t)(((uint32_t)F2812_SCI_BRR >> 8) & 0xFFu);
    f2812_scia.SCILBAUD = (uint16_t)((uint32_t)F2812_SCI_BRR & 0xFFu);
    f2812_scia.SCIFFTX = SCIFFTX_RUN;
    f2812_scia.SCIFFRX = SCIFFRX_RUN;
    f2812_scia.SCIFFCT = 0x0000u; /* no delay between FIFO characters, no autobaud */
    f2812_scia.SCIPRI = F2812_SCIPRI_FREE;
    f2812_scia.SCICTL1 = SCICTL1_RUN;
}

uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    uint16_t n;
    uint16_t i;
    if ((f2812_scia.SCIRXST & F2812_SCIRXST_RXERROR) != 0u) {
        f2812_scia.SCICTL1 = SCICTL1_RESET; /* SWRESET pulse: clears the receiver's error flags */
        f2812_scia.SCICTL1 = SCICTL1_RUN;
        s_sci.rx_resets++;
    }
    if ((f2812_scia.SCIFFRX & F2812_SCIFFRX_RXFFOVF) != 0u) {
        f2812_scia.SCIFFRX = (uint16_t)(SCIFFRX_RUN | F2812_SCIFFRX_RXFFOVRCLR);
        s_sci.rx_overflows++;
    }
    n = F2812_SCIFF_ST(f2812_scia.SCIFFRX);
    if (n > max) {
        n = max;
    }
    for (i = 0u; i < n; i++) {
        const uint16_t c = f2812_scia.SCIRXBUF;
        if ((c & (uint16_t)(F2812_SCIRXBUF_FFPE | F2812_SCIRXBUF_FFFE)) != 0u) {
            s_sci.rx_char_errors++;
        }
        buf[i] = (uint16_t)(c & F2812_SCIRXBUF_DATA);
    }
    return n;
}

uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    const uint16_t held = F2812_SCIFF_ST(f2812_scia.SCIFFTX);
    uint16_t room = held < F2812_SCI_FIFO_DEPTH ? (uint16_t)(F2812_SCI_FIFO_DEPTH - held) : 0u;
    uint16_t i;
    if (room > n) {
        room = n;
    }
    for (i = 0u; i < room; i++) {
        f2812_scia.SCITXBUF = (uint16_t)(buf[i] & 0x00FFu);
    }
    return room;
}

const f2812_sci_stats_t *f2812_sci_stats(void)
{
    return &s_sci;
}
