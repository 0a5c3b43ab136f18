/*
 * f2812_spi.c - SPI-A as the master of the parameter EEPROM (fact sheet 9.2): 8-bit characters,
 * F2812_SPIBRR clock, mode per F2812_SPI_CLKPOL / F2812_SPI_PHASE (f2812_board.h), FIFO off,
 * no interrupts; chip select on GPIOF3 as a GPIO, so it stays low across a multi-octet command
 * (SPISTEA may rise between characters, 9.2 ~). Background loop only.
 */
#include "f2812_board.h"
#include "f2812_hal.h"
#include "f2812_regs.h"

#define SPICCR_8BIT                                                                                \
    ((uint16_t)(F2812_SPICCR_CHAR(8u) | (F2812_SPI_CLKPOL != 0u ? F2812_SPICCR_CLKPOL : 0u)))
#define SPICTL_MASTER                                                                              \
    ((uint16_t)(F2812_SPICTL_MASTER | F2812_SPICTL_TALK |                                         \
                (F2812_SPI_PHASE != 0u ? F2812_SPICTL_PHASE : 0u)))

void f2812_spi_init(void)
{
    f2812_gpiodata.F.SET = F2812_GPF_SPISTE; /* chip select high (inactive) before it drives */
    f2812_eallow();
    f2812_wr_protected(&f2812_sysctrl.PCLKCR, (uint16_t)(f2812_sysctrl.PCLKCR | F2812_PCLKCR_SPIENCLK));
    f2812_wr_protected(&f2812_gpiomux.GPFMUX,
                       (uint16_t)((f2812_gpiomux.GPFMUX | F2812_GPFMUX_SPIA) & (uint16_t)~F2812_GPF_SPISTE));
    f2812_wr_protected(&f2812_gpiomux.GPFDIR, (uint16_t)(f2812_gpiomux.GPFDIR | F2812_GPF_SPISTE));
    f2812_edis();
    f2812_spia.SPICCR = SPICCR_8BIT; /* SPISWRESET = 0: held in reset while configured */
    f2812_spia.SPICTL = SPICTL_MASTER;
    f2812_spia.SPIBRR = (uint16_t)F2812_SPIBRR;
    f2812_spia.SPIFFTX = 0x8000u; /* SPIRST = 1, SPIFFENA = 0: the plain one-character buffer */
    f2812_spia.SPIPRI = F2812_SPIPRI_FREE;
    f2812_spia.SPICCR = (uint16_t)(SPICCR_8BIT | F2812_SPICCR_SWRESET);
}

void f2812_spi_cs(uint16_t active)
{
    if (active != 0u) {
        f2812_gpiodata.F.CLEAR = F2812_GPF_SPISTE;
    } else {
        f2812_gpiodata.F.SET = F2812_GPF_SPISTE;
    }
}

uint16_t f2812_spi_xfer(uint16_t tx, uint16_t *rx)
{
    uint16_t polls;
    f2812_spia.SPITXBUF = (uint16_t)((tx & 0x00FFu) << 8); /* left-justified 8-bit character */
    for (polls = 0u; polls < F2812_SPI_CHAR_POLLS; polls++) {
        if ((f2812_spia.SPISTS & F2812_SPISTS_INT_FLAG) != 0u) {
            *rx = (uint16_t)(f2812_spia.SPIRXBUF & 0x00FFu); /* reading clears INT_FLAG */
            return 1u;
        }
    }
    return 0u;
}
