/*
 * f2812_regs.c - the register block instances and a compile-time check of their layout.
 *
 * Target: each instance is in its own data section; linker/f2812_regs.cmd maps the section to the
 * block's base address (F2812_*_BASE in f2812_regs.h). Host: plain zero-initialised globals.
 */
#include <stddef.h>

#include "f2812_regs.h"

F2812_REGBLOCK(f2812_flash, "f2812_flash_regs")
volatile struct f2812_flash_regs f2812_flash;
F2812_REGBLOCK(f2812_piectrl, "f2812_piectrl_regs")
volatile struct f2812_piectrl_regs f2812_piectrl;
F2812_REGBLOCK(f2812_pievect, "f2812_pievect_regs")
volatile struct f2812_pievect_regs f2812_pievect;
F2812_REGBLOCK(f2812_sysctrl, "f2812_sysctrl_regs")
volatile struct f2812_sysctrl_regs f2812_sysctrl;
F2812_REGBLOCK(f2812_gpiomux, "f2812_gpiomux_regs")
volatile struct f2812_gpiomux_regs f2812_gpiomux;
F2812_REGBLOCK(f2812_gpiodata, "f2812_gpiodata_regs")
volatile struct f2812_gpiodata_regs f2812_gpiodata;
F2812_REGBLOCK(f2812_adc, "f2812_adc_regs")
volatile struct f2812_adc_regs f2812_adc;
F2812_REGBLOCK(f2812_eva, "f2812_eva_regs")
volatile struct f2812_eva_regs f2812_eva;
F2812_REGBLOCK(f2812_spia, "f2812_spia_regs")
volatile struct f2812_spi_regs f2812_spia;
F2812_REGBLOCK(f2812_scia, "f2812_scia_regs")
volatile struct f2812_sci_regs f2812_scia;

#if !F2812_ON_TARGET
struct f2812_host_cpu f2812_host_cpu = {0u, 1u, 0u, 0u, 0u, 0u, 0u}; /* INTM = 1 after reset */
#endif

/* ---- layout: word offset of every register = its fact-sheet address minus the block base ---- */
#define F2812_WORD_OFFSET(type, member) (offsetof(type, member) / sizeof(uint16_t))
#define F2812_CHECK(name, cond) typedef char f2812_layout_##name[(cond) ? 1 : -1]
#define F2812_AT(type, member, addr, base)                                                         \
    F2812_CHECK(type##_##member, F2812_WORD_OFFSET(struct type, member) == ((addr) - (base)))

F2812_AT(f2812_flash_regs, FOPT, 0x0A80u, F2812_FLASH_BASE);
F2812_AT(f2812_flash_regs, FBANKWAIT, 0x0A86u, F2812_FLASH_BASE);
F2812_AT(f2812_flash_regs, FOTPWAIT, 0x0A87u, F2812_FLASH_BASE);

F2812_AT(f2812_piectrl_regs, PIEACK, 0x0CE1u, F2812_PIECTRL_BASE);
F2812_AT(f2812_piectrl_regs, grp, 0x0CE2u, F2812_PIECTRL_BASE); /* PIEIER1 */
F2812_CHECK(piectrl_size, sizeof(struct f2812_piectrl_regs) == 0x20u * sizeof(uint16_t));

F2812_AT(f2812_sysctrl_regs, HISPCP, 0x701Au, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, LOSPCP, 0x701Bu, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, PCLKCR, 0x701Cu, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, LPMCR0, 0x701Eu, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, PLLCR, 0x7021u, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, SCSR, 0x7022u, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, WDCNTR, 0x7023u, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, WDKEY, 0x7025u, F2812_SYSCTRL_BASE);
F2812_AT(f2812_sysctrl_regs, WDCR, 0x7029u, F2812_SYSCTRL_BASE);
F2812_CHECK(sysctrl_size, sizeof(struct f2812_sysctrl_regs) == 0x20u * sizeof(uint16_t));

F2812_AT(f2812_gpiomux_regs, GPAMUX, 0x70C0u, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPBMUX, 0x70C4u, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPDMUX, 0x70CCu, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPEMUX, 0x70D0u, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPFMUX, 0x70D4u, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPGMUX, 0x70D8u, F2812_GPIOMUX_BASE);
F2812_AT(f2812_gpiomux_regs, GPGDIR, 0x70D9u, F2812_GPIOMUX_BASE);
F2812_CHECK(gpiomux_size, sizeof(struct f2812_gpiomux_regs) == 0x20u * sizeof(uint16_t));
F2812_CHECK(gpiodata_A_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, A.DAT) == (0x70E0u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_B_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, B.DAT) == (0x70E4u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_B_SET, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, B.SET) == (0x70E5u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_B_CLEAR, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, B.CLEAR) == (0x70E6u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_D_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, D.DAT) == (0x70ECu - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_E_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, E.DAT) == (0x70F0u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_F_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, F.DAT) == (0x70F4u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_G_DAT, F2812_WORD_OFFSET(struct f2812_gpiodata_regs, G.DAT) == (0x70F8u - F2812_GPIODATA_BASE));
F2812_CHECK(gpiodata_size, sizeof(struct f2812_gpiodata_regs) == 0x20u * sizeof(uint16_t));

F2812_AT(f2812_adc_regs, ADCTRL2, 0x7101u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCMAXCONV, 0x7102u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCCHSELSEQ, 0x7103u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCASEQSR, 0x7107u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCRESULT, 0x7108u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCTRL3, 0x7118u, F2812_ADC_BASE);
F2812_AT(f2812_adc_regs, ADCST, 0x7119u, F2812_ADC_BASE);
F2812_CHECK(adc_size, sizeof(struct f2812_adc_regs) == 0x20u * sizeof(uint16_t));

F2812_AT(f2812_eva_regs, T1CNT, 0x7401u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, T1PR, 0x7403u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, T1CON, 0x7404u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, T2CNT, 0x7405u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, T2PR, 0x7407u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, T2CON, 0x7408u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, EXTCONA, 0x7409u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, COMCONA, 0x7411u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, ACTRA, 0x7413u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, DBTCONA, 0x7415u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CMPR1, 0x7417u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CMPR3, 0x7419u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CAPCONA, 0x7420u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CAPFIFOA, 0x7422u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CAP3FIFO, 0x7425u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, CAP1FBOT, 0x7427u, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, EVAIMRA, 0x742Cu, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, EVAIMRC, 0x742Eu, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, EVAIFRA, 0x742Fu, F2812_EVA_BASE);
F2812_AT(f2812_eva_regs, EVAIFRC, 0x7431u, F2812_EVA_BASE);
F2812_CHECK(eva_size, sizeof(struct f2812_eva_regs) == 0x40u * sizeof(uint16_t));

F2812_AT(f2812_spi_regs, SPISTS, 0x7042u, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPIBRR, 0x7044u, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPIRXBUF, 0x7047u, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPITXBUF, 0x7048u, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPIDAT, 0x7049u, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPIFFTX, 0x704Au, F2812_SPIA_BASE);
F2812_AT(f2812_spi_regs, SPIPRI, 0x704Fu, F2812_SPIA_BASE);
F2812_CHECK(spia_size, sizeof(struct f2812_spi_regs) == 0x10u * sizeof(uint16_t));

F2812_AT(f2812_sci_regs, SCICTL1, 0x7051u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIHBAUD, 0x7052u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCILBAUD, 0x7053u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCICTL2, 0x7054u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIRXST, 0x7055u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIRXBUF, 0x7057u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCITXBUF, 0x7059u, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIFFTX, 0x705Au, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIFFRX, 0x705Bu, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIFFCT, 0x705Cu, F2812_SCIA_BASE);
F2812_AT(f2812_sci_regs, SCIPRI, 0x705Fu, F2812_SCIA_BASE);
F2812_CHECK(scia_size, sizeof(struct f2812_sci_regs) == 0x10u * sizeof(uint16_t));

#if F2812_ON_TARGET
/* A PIE vector is a 32-bit code address: 2 words, 128 entries = 0x100 words (fact sheet 4.1). */
F2812_CHECK(pievect_size, sizeof(struct f2812_pievect_regs) == 0x100u);
#endif
