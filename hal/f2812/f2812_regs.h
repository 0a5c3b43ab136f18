/*
 * f2812_regs.h - the project's own TMS320F2812 register definitions (only the blocks the drive
 * uses). Written from the fact sheet ../shared/reference/f2812-facts.md (section numbers below),
 * not from TI's headers; no TI code is shipped.
 *
 * Placement. One struct per register block, one instance per block (f2812_regs.c). On the target
 * each instance sits in its own data section (F2812_REGBLOCK), which linker/f2812_regs.cmd maps
 * to the block's base address in the peripheral frame; on the host the instance is ordinary RAM,
 * so tests read back exactly what the binding wrote. Word offsets are checked at compile time in
 * f2812_regs.c against the fact-sheet addresses, on every compiler (C28x: 1 word per uint16_t;
 * host: 2 bytes).
 *
 * Access. Whole-register writes with the masks below (no C bit-fields: their layout is
 * implementation-defined, and a read-modify-write of a flag register clears every pending flag,
 * fact sheet 2.8). EALLOW-protected registers (marked [P]) are written through
 * f2812_wr_protected() between f2812_eallow()/f2812_edis() (f2812_target.h).
 *
 * Confidence marks copied from the fact sheet where a field is not fully confirmed: (~) recalled
 * or community-sourced, (x) conflicting; docs/f2812.md lists what was checked.
 */
#ifndef F2812_REGS_H
#define F2812_REGS_H

#include <stdint.h>

#include "f2812_target.h"

/* ------------------------------------------------------------------------------------------- */
/* Block base addresses (16-bit word addresses, C28x data space). Used by linker/f2812_regs.cmd
 * (which repeats them: the TI linker cannot include C) and by the docs; C code never forms a
 * pointer from them. Fact sheet 1.3 (DS, HDR ✔), 4.7 (flash).                                 */
#define F2812_FLASH_BASE 0x0A80u    /* PF0, EALLOW + CSM protected */
#define F2812_PIECTRL_BASE 0x0CE0u  /* PF0 */
#define F2812_PIEVECT_BASE 0x0D00u  /* PF0, EALLOW protected */
#define F2812_SYSCTRL_BASE 0x7010u  /* PF2, EALLOW protected */
#define F2812_SPIA_BASE 0x7040u     /* PF2, not protected (fact sheet 9.2) */
#define F2812_SCIA_BASE 0x7050u     /* PF2, not protected (fact sheet 9.1) */
#define F2812_GPIOMUX_BASE 0x70C0u  /* PF2, EALLOW protected */
#define F2812_GPIODATA_BASE 0x70E0u /* PF2, not protected */
#define F2812_ADC_BASE 0x7100u      /* PF2 */
#define F2812_EVA_BASE 0x7400u      /* PF2 */

/* ------------------------------------------------------------- flash control, 0x0A80 (4.7) -- */
struct f2812_flash_regs {
    uint16_t FOPT;        /* 0x0A80 [P] ENPIPE bit 0 */
    uint16_t rsvd1;       /* 0x0A81 */
    uint16_t FPWR;        /* 0x0A82 [P] */
    uint16_t FSTATUS;     /* 0x0A83 [P] */
    uint16_t FSTDBYWAIT;  /* 0x0A84 [P] */
    uint16_t FACTIVEWAIT; /* 0x0A85 [P] */
    uint16_t FBANKWAIT;   /* 0x0A86 [P] RANDWAIT 3:0, PAGEWAIT 11:8 */
    uint16_t FOTPWAIT;    /* 0x0A87 [P] OTPWAIT 4:0 */
};
#define F2812_FOPT_ENPIPE 0x0001u
#define F2812_FBANKWAIT(page, rand) ((uint16_t)(((uint16_t)(page) << 8) | (uint16_t)(rand)))

/* ------------------------------------------------------------ PIE control, 0x0CE0 (4.1) ---- */
struct f2812_pie_group {
    uint16_t IER; /* PIEIERg: bit (y-1) enables INTg.y */
    uint16_t IFR; /* PIEIFRg */
};
struct f2812_piectrl_regs {
    uint16_t PIECTRL;                  /* 0x0CE0 ENPIE bit 0, PIEVECT 15:1 (read-only) */
    uint16_t PIEACK;                   /* 0x0CE1 write 1 to bit (g-1) to re-arm group g */
    struct f2812_pie_group grp[12];    /* 0x0CE2 + 2(g-1): PIEIER1/PIEIFR1 .. PIEIER12/PIEIFR12 */
    uint16_t rsvd1[6];                 /* 0x0CFA..0x0CFF */
};
#define F2812_PIECTRL_ENPIE 0x0001u
#define F2812_PIEACK_GROUP1 0x0001u
#define F2812_PIEACK_GROUP2 0x0002u
#define F2812_PIEACK_ALL 0x0FFFu
#define F2812_PIE_INTX(y) ((uint16_t)(1u << ((y)-1u))) /* PIEIERg bit for INTg.y */
#define F2812_IER_INT1 0x0001u                         /* CPU IER bit (g-1) for PIE group g */
#define F2812_IER_INT2 0x0002u

/* ----------------------------------------------------- PIE vector table, 0x0D00 (4.1) [P] -- */
#define F2812_PIE_VECTORS 128u
/* Index of PIE interrupt g.y in the table: 32 + 8(g-1) + (y-1); address 0x0D00 + 2*index,
 * e.g. ADCINT 1.6 -> index 37 -> 0x0D4A (fact sheet 4.1 table). */
#define F2812_PIE_INDEX(g, y) (32u + 8u * ((g)-1u) + ((y)-1u))
#define F2812_PIE_INDEX_PDPINTA F2812_PIE_INDEX(1u, 1u) /* 0x0D40 */
#define F2812_PIE_INDEX_ADCINT F2812_PIE_INDEX(1u, 6u)  /* 0x0D4A */
#define F2812_PIE_INDEX_T1PINT F2812_PIE_INDEX(2u, 4u)  /* 0x0D56 (fact sheet 4.1 table) */
struct f2812_pievect_regs {
    f2812_isr_t vec[F2812_PIE_VECTORS]; /* 32-bit entries on the C28x */
};

/* --------------------------------------------------- system control, 0x7010 (4.3, 4.4) [P] -- */
struct f2812_sysctrl_regs {
    uint16_t rsvd1[10]; /* 0x7010..0x7019 */
    uint16_t HISPCP;    /* 0x701A HSPCLK = SYSCLKOUT / (2n), n = 0 -> /1 */
    uint16_t LOSPCP;    /* 0x701B LSPCLK = SYSCLKOUT / (2n) */
    uint16_t PCLKCR;    /* 0x701C peripheral clock enables */
    uint16_t rsvd2;     /* 0x701D */
    uint16_t LPMCR0;    /* 0x701E */
    uint16_t LPMCR1;    /* 0x701F */
    uint16_t rsvd3;     /* 0x7020 */
    uint16_t PLLCR;     /* 0x7021 DIV 3:0: SYSCLKOUT = OSCCLK * DIV / 2 */
    uint16_t SCSR;      /* 0x7022 write as a whole word only (WDOVERRIDE is write-1-to-clear) */
    uint16_t WDCNTR;    /* 0x7023 */
    uint16_t rsvd4;     /* 0x7024 */
    uint16_t WDKEY;     /* 0x7025 0x55 then 0xAA resets the counter */
    uint16_t rsvd5[3];  /* 0x7026..0x7028 */
    uint16_t WDCR;      /* 0x7029 WDFLAG 7, WDDIS 6, WDCHK 5:3 (must be 101b), WDPS 2:0 (~) */
    uint16_t rsvd6[6];  /* 0x702A..0x702F */
};
#define F2812_PCLKCR_EVAENCLK 0x0001u
#define F2812_PCLKCR_ADCENCLK 0x0008u
#define F2812_PCLKCR_SPIENCLK 0x0100u   /* bit 8 (4.3, HDR ✔) */
#define F2812_PCLKCR_SCIAENCLK 0x0400u  /* bit 10 (4.3, HDR ✔) */
#define F2812_WDCR_WDDIS 0x0040u
#define F2812_WDCR_WDCHK 0x0028u /* 101b in bits 5:3: every WDCR write must carry it */
#define F2812_WDCR_WDPS(p) ((uint16_t)((p)&7u))
#define F2812_WDKEY_1 0x0055u
#define F2812_WDKEY_2 0x00AAu

/* ----------------------------------------------------------- GPIO mux, 0x70C0 (4.8) [P] ---- */
struct f2812_gpiomux_regs {
    uint16_t GPAMUX;    /* 0x70C0 */
    uint16_t GPADIR;    /* 0x70C1 */
    uint16_t GPAQUAL;   /* 0x70C2 */
    uint16_t rsvd1;     /* 0x70C3 */
    uint16_t GPBMUX;    /* 0x70C4 */
    uint16_t GPBDIR;    /* 0x70C5 */
    uint16_t GPBQUAL;   /* 0x70C6 */
    uint16_t rsvd2[5];  /* 0x70C7..0x70CB (no port C) */
    uint16_t GPDMUX;    /* 0x70CC */
    uint16_t GPDDIR;    /* 0x70CD */
    uint16_t GPDQUAL;   /* 0x70CE */
    uint16_t rsvd3;     /* 0x70CF */
    uint16_t GPEMUX;    /* 0x70D0 */
    uint16_t GPEDIR;    /* 0x70D1 */
    uint16_t GPEQUAL;   /* 0x70D2 */
    uint16_t rsvd4;     /* 0x70D3 */
    uint16_t GPFMUX;    /* 0x70D4 */
    uint16_t GPFDIR;    /* 0x70D5 */
    uint16_t rsvd5[2];  /* 0x70D6..0x70D7 */
    uint16_t GPGMUX;    /* 0x70D8 */
    uint16_t GPGDIR;    /* 0x70D9 */
    uint16_t rsvd6[6];  /* 0x70DA..0x70DF */
};
#define F2812_GPAMUX_PWM1_6 0x003Fu     /* bits 0-5: PWM1..PWM6 */
#define F2812_GPAMUX_QEP 0x0700u        /* bits 8-10: CAP1_QEP1, CAP2_QEP2, CAP3_QEPI1 */
#define F2812_GPDMUX_PDPINTA 0x0001u    /* bit 0: T1CTRIP_PDPINTA */
#define F2812_GPFMUX_SCIA 0x0030u       /* bits 4, 5: SCITXDA (GPIOF4), SCIRXDA (GPIOF5) (9.1, HDR ✔) */
#define F2812_GPFMUX_SPIA 0x0007u       /* bits 0-2: SPISIMOA, SPISOMIA, SPICLKA (9.2, HDR ✔) */
#define F2812_GPF_SPISTE 0x0008u        /* bit 3: GPIOF3, the EEPROM's chip select driven as a GPIO */
/* MUX bit x = 0: pin GPIOxx is a GPIO; GPxDIR bit x = 1: output (4.8, HDR ✔). */

/* ------------------------------------------------------- GPIO data, 0x70E0 (4.8) ----------- */
/* Per port DAT (read: pin levels; write: output latch), SET / CLEAR / TOGGLE (write 1 to set /
 * clear / toggle that output's latch, 0 leaves it; HDR ✔ for the addresses, the write-1 semantics
 * ~ (TI's usual GPxSET/GPxCLEAR convention, not re-read here)). Bit x = pin GPIOxx. */
struct f2812_gpio_port {
    uint16_t DAT;
    uint16_t SET;
    uint16_t CLEAR;
    uint16_t TOGGLE;
};
struct f2812_gpiodata_regs {
    struct f2812_gpio_port A; /* 0x70E0 */
    struct f2812_gpio_port B; /* 0x70E4 */
    uint16_t rsvd1[4];        /* 0x70E8..0x70EB (no port C) */
    struct f2812_gpio_port D; /* 0x70EC */
    struct f2812_gpio_port E; /* 0x70F0 */
    struct f2812_gpio_port F; /* 0x70F4 */
    struct f2812_gpio_port G; /* 0x70F8 */
    uint16_t rsvd2[4];        /* 0x70FC..0x70FF */
};

/* ---------------------------------------------------------------- ADC, 0x7100 (3.1) -------- */
struct f2812_adc_regs {
    uint16_t ADCTRL1;       /* 0x7100 */
    uint16_t ADCTRL2;       /* 0x7101 */
    uint16_t ADCMAXCONV;    /* 0x7102 MAX_CONV1 3:0: conversions = value + 1 */
    uint16_t ADCCHSELSEQ[4]; /* 0x7103..0x7106 CONVnn = 4-bit channel codes, CONV00 = bits 3:0 */
    uint16_t ADCASEQSR;     /* 0x7107 read-only */
    uint16_t ADCRESULT[16]; /* 0x7108..0x7117 12-bit result LEFT-justified in bits 15:4 */
    uint16_t ADCTRL3;       /* 0x7118 */
    uint16_t ADCST;         /* 0x7119 */
    uint16_t rsvd1[6];      /* 0x711A..0x711F */
};
#define F2812_ADCTRL1_RESET 0x4000u
#define F2812_ADCTRL1_SUSMOD_FREE 0x0000u         /* 13:12 = 00: emulation halt ignored (~) */
#define F2812_ADCTRL1_ACQ_PS(n) ((uint16_t)(((n)&15u) << 8))
#define F2812_ADCTRL1_CPS 0x0080u                 /* core clock / 2 */
#define F2812_ADCTRL1_SEQ_CASC 0x0010u
#define F2812_ADCTRL2_RST_SEQ1 0x4000u
#define F2812_ADCTRL2_SOC_SEQ1 0x2000u
#define F2812_ADCTRL2_INT_ENA_SEQ1 0x0800u
#define F2812_ADCTRL2_INT_MOD_SEQ1 0x0400u
#define F2812_ADCTRL2_EVA_SOC_SEQ1 0x0100u
#define F2812_ADCTRL3_ADCBGRFDN 0x00C0u          /* bandgap and reference powered */
#define F2812_ADCTRL3_ADCPWDN 0x0020u            /* rest of the analog core powered */
#define F2812_ADCTRL3_ADCCLKPS(n) ((uint16_t)(((n)&15u) << 1))
#define F2812_ADCTRL3_SMODE_SEL 0x0001u
#define F2812_ADCST_INT_SEQ1 0x0001u
#define F2812_ADCST_INT_SEQ1_CLR 0x0010u
#define F2812_ADC_RESULT_SHIFT 4u                /* ADCRESULTn >> 4 = 12-bit count */

/* -------------------------------------------------------------- Event Manager A, 0x7400 (2) -- */
struct f2812_eva_regs {
    uint16_t GPTCONA;  /* 0x7400 */
    uint16_t T1CNT;    /* 0x7401 */
    uint16_t T1CMPR;   /* 0x7402 */
    uint16_t T1PR;     /* 0x7403 */
    uint16_t T1CON;    /* 0x7404 */
    uint16_t T2CNT;    /* 0x7405 */
    uint16_t T2CMPR;   /* 0x7406 */
    uint16_t T2PR;     /* 0x7407 */
    uint16_t T2CON;    /* 0x7408 */
    uint16_t EXTCONA;  /* 0x7409 */
    uint16_t rsvd1[7]; /* 0x740A..0x7410 */
    uint16_t COMCONA;  /* 0x7411 */
    uint16_t rsvd2;    /* 0x7412 */
    uint16_t ACTRA;    /* 0x7413 shadowed */
    uint16_t rsvd3;    /* 0x7414 */
    uint16_t DBTCONA;  /* 0x7415 */
    uint16_t rsvd4;    /* 0x7416 */
    uint16_t CMPR1;    /* 0x7417 shadowed */
    uint16_t CMPR2;    /* 0x7418 shadowed */
    uint16_t CMPR3;    /* 0x7419 shadowed */
    uint16_t rsvd5[6]; /* 0x741A..0x741F */
    uint16_t CAPCONA;  /* 0x7420 */
    uint16_t rsvd6;    /* 0x7421 */
    uint16_t CAPFIFOA; /* 0x7422 */
    uint16_t CAP1FIFO; /* 0x7423 */
    uint16_t CAP2FIFO; /* 0x7424 */
    uint16_t CAP3FIFO; /* 0x7425 */
    uint16_t rsvd7;    /* 0x7426 */
    uint16_t CAP1FBOT; /* 0x7427 */
    uint16_t CAP2FBOT; /* 0x7428 */
    uint16_t CAP3FBOT; /* 0x7429 */
    uint16_t rsvd8[2]; /* 0x742A..0x742B */
    uint16_t EVAIMRA;  /* 0x742C */
    uint16_t EVAIMRB;  /* 0x742D */
    uint16_t EVAIMRC;  /* 0x742E */
    uint16_t EVAIFRA;  /* 0x742F write 1 to clear */
    uint16_t EVAIFRB;  /* 0x7430 write 1 to clear */
    uint16_t EVAIFRC;  /* 0x7431 write 1 to clear */
    uint16_t rsvd9[14]; /* 0x7432..0x743F */
};

/* GPTCONA (2.2) */
#define F2812_GPTCONA_T1TOADC_UF 0x0080u   /* 8:7 = 01: T1 underflow starts the ADC (EVG, EX ✔) */
#define F2812_GPTCONA_T1STAT 0x2000u       /* read-only: T1 counting up */
#define F2812_GPTCONA_T2STAT 0x4000u       /* read-only: T2 (QEP) counting up */

/* TxCON (2.3) */
#define F2812_TXCON_FREE_SOFT 0xC000u      /* both bits: free run under either bit order (x, 8.1) */
#define F2812_TXCON_TMODE_UPDOWN 0x0800u   /* 12:11 = 01 continuous up/down */
#define F2812_TXCON_TMODE_DIRUPDOWN 0x1800u /* 12:11 = 11 directional up/down (QEP) */
#define F2812_TXCON_TPS(n) ((uint16_t)(((n)&7u) << 8))
#define F2812_TXCON_TENABLE 0x0040u
#define F2812_TXCON_TCLKS_QEP 0x0030u      /* 5:4 = 11 QEP circuit (T2/T4 only) */
#define F2812_TXCON_TCLD_ZERO 0x0000u      /* 3:2 = 00 compare reload at count 0 */
#define F2812_TXCON_TECMPR 0x0002u

/* COMCONA (2.4) */
#define F2812_COMCONA_CENABLE 0x8000u
#define F2812_COMCONA_CLD_UF 0x0000u       /* 14:13 = 00 CMPRx shadow -> active at T1CNT = 0 */
#define F2812_COMCONA_CLD_UF_PR 0x2000u    /* 14:13 = 01 ... at T1CNT = 0 or T1CNT = T1PR */
#define F2812_COMCONA_CLD_MASK 0x6000u
#define F2812_COMCONA_ACTRLD_UF 0x0000u    /* 11:10 = 00 ACTRA shadow -> active at T1CNT = 0 */
#define F2812_COMCONA_FCOMPOE 0x0200u      /* bit 9 (x 8.2 resolved to bit 9): 0 = PWM1-6 Hi-Z */
#define F2812_COMCONA_PDPINTASTATUS 0x0100u /* read-only pin level */

/* ACTRA (2.5): 2 bits per output, PWM1 = bits 1:0 ... PWM6 = bits 11:10 */
#define F2812_ACT_FORCED_LOW 0u
#define F2812_ACT_ACTIVE_LOW 1u
#define F2812_ACT_ACTIVE_HIGH 2u
#define F2812_ACT_FORCED_HIGH 3u
#define F2812_ACTRA_FIELD(pwm, act) ((uint16_t)((uint16_t)(act) << (2u * ((pwm)-1u))))
#define F2812_ACTRA_LEG_MASK(leg) ((uint16_t)(0x000Fu << (4u * (leg)))) /* leg 0 = A = PWM1/2 */

/* DBTCONA (2.6) */
#define F2812_DBTCONA_DBT(n) ((uint16_t)(((n)&15u) << 8))
#define F2812_DBTCONA_EDBT1 0x0020u
#define F2812_DBTCONA_EDBT2 0x0040u
#define F2812_DBTCONA_EDBT3 0x0080u
#define F2812_DBTCONA_DBTPS(n) ((uint16_t)(((n)&7u) << 2)) /* prescale 2^n, n = 0..5 */

/* EXTCONA (2.7): INDCOE = 0 so FCOMPOE (and PDPINTA) governs all six outputs. */
#define F2812_EXTCONA_INDCOE 0x0001u

/* EVAIMRA/EVAIFRA (2.8) */
#define F2812_EVA_INTA_PDPINTA 0x0001u
#define F2812_EVA_INTA_T1PINT 0x0080u /* bit 7: timer 1 period match (fact sheet 2.8) */
/* EVAIMRC/EVAIFRC */
#define F2812_EVA_INTC_CAP3 0x0004u

/* CAPCONA (2.9) */
#define F2812_CAPCONA_CAPRES 0x8000u       /* 0 written here resets the capture units (~) */
#define F2812_CAPCONA_CAP12EN_QEP 0x6000u  /* 14:13 = 11: QEP on, CAP1/2 off (x 8.3, see hal) */
#define F2812_CAPCONA_CAP3EN 0x1000u
#define F2812_CAPCONA_CAP3TSEL_T1 0x0400u  /* 0 = CAP3 time base is T2 (~) */
#define F2812_CAPCONA_CAP3EDGE_RISE 0x0004u /* 3:2 = 01 */
#define F2812_CAPFIFOA_CAP3FIFO 0x3000u    /* 13:12: CAP3 FIFO status (~) */

/* ---------------------------------------------------------- SPI-A, 0x7040 (9.2) ------------ */
/* Control registers use bits 7:0; TX data is left-justified for characters under 16 bits, RX data
 * right-justified (9.2, ~ for the alignment: TI example comments and community drivers). */
struct f2812_spi_regs {
    uint16_t SPICCR;   /* 0x7040 SPICHAR 3:0 (bits - 1), SPILBK 4, CLKPOLARITY 6, SPISWRESET 7 */
    uint16_t SPICTL;   /* 0x7041 SPIINTENA 0, TALK 1, MASTER_SLAVE 2, CLK_PHASE 3, OVERRUNINTENA 4 */
    uint16_t SPISTS;   /* 0x7042 BUFFULL_FLAG 5, INT_FLAG 6 (character done), OVERRUN_FLAG 7 */
    uint16_t rsvd1;    /* 0x7043 */
    uint16_t SPIBRR;   /* 0x7044 SPICLK = LSPCLK / (SPIBRR + 1), SPIBRR 3..127 */
    uint16_t rsvd2;    /* 0x7045 */
    uint16_t SPIRXEMU; /* 0x7046 */
    uint16_t SPIRXBUF; /* 0x7047 received character, right-justified; reading clears INT_FLAG */
    uint16_t SPITXBUF; /* 0x7048 */
    uint16_t SPIDAT;   /* 0x7049 shift register: a write starts a transfer (master) */
    uint16_t SPIFFTX;  /* 0x704A SPIRST 15, SPIFFENA 14, TXFIFO reset 13 */
    uint16_t SPIFFRX;  /* 0x704B */
    uint16_t SPIFFCT;  /* 0x704C */
    uint16_t rsvd3[2]; /* 0x704D..0x704E */
    uint16_t SPIPRI;   /* 0x704F FREE 4, SOFT 5 */
};
#define F2812_SPICCR_SWRESET 0x0080u
#define F2812_SPICCR_CLKPOL 0x0040u
#define F2812_SPICCR_CHAR(bits) ((uint16_t)(((bits)-1u) & 15u))
#define F2812_SPICTL_TALK 0x0002u
#define F2812_SPICTL_MASTER 0x0004u
#define F2812_SPICTL_PHASE 0x0008u
#define F2812_SPISTS_INT_FLAG 0x0040u
#define F2812_SPISTS_OVERRUN 0x0080u
#define F2812_SPIPRI_FREE 0x0010u

/* ---------------------------------------------------------- SCI-A, 0x7050 (9.1) ------------ */
/* Control registers use bits 7:0; the FIFO registers all 16 (9.1). One character per access. */
struct f2812_sci_regs {
    uint16_t SCICCR;   /* 0x7050 SCICHAR 2:0, ADDRIDLE 3, LOOPBKENA 4, PARITYENA 5, PARITY 6, STOPBITS 7 */
    uint16_t SCICTL1;  /* 0x7051 RXENA 0, TXENA 1, SLEEP 2, TXWAKE 3, SWRESET 5, RXERRINTENA 6 */
    uint16_t SCIHBAUD; /* 0x7052 BRR 15:8 */
    uint16_t SCILBAUD; /* 0x7053 BRR 7:0 */
    uint16_t SCICTL2;  /* 0x7054 TXINTENA 0, RXBKINTENA 1, TXEMPTY 6, TXRDY 7 */
    uint16_t SCIRXST;  /* 0x7055 PE 2, OE 3, FE 4, BRKDT 5, RXRDY 6, RXERROR 7 */
    uint16_t SCIRXEMU; /* 0x7056 */
    uint16_t SCIRXBUF; /* 0x7057 RXDT 7:0; FIFO mode: SCIFFPE 14, SCIFFFE 15 of that character */
    uint16_t rsvd1;    /* 0x7058 */
    uint16_t SCITXBUF; /* 0x7059 TX character, bits 7:0 */
    uint16_t SCIFFTX;  /* 0x705A TXFFIL 4:0, TXFFIENA 5, TXINTCLR 6, TXFFINT 7, TXFFST 12:8,
                        *        TXFIFOXRESET 13, SCIFFENA 14, SCIRST 15 */
    uint16_t SCIFFRX;  /* 0x705B RXFFIL 4:0, RXFFIENA 5, RXFFINTCLR 6, RXFFINT 7, RXFFST 12:8,
                        *        RXFIFORESET 13, RXFFOVRCLR 14, RXFFOVF 15 */
    uint16_t SCIFFCT;  /* 0x705C FFTXDLY 7:0, CDC 13, ABDCLR 14, ABD 15 */
    uint16_t rsvd2[2]; /* 0x705D..0x705E */
    uint16_t SCIPRI;   /* 0x705F FREE 3, SOFT 4 (x 9.5 #4 resolved: bits 4:3) */
};
#define F2812_SCICCR_8N1 0x0007u            /* 8 data bits, no parity, 1 stop, idle-line mode */
#define F2812_SCICTL1_RXENA 0x0001u
#define F2812_SCICTL1_TXENA 0x0002u
#define F2812_SCICTL1_SWRESET 0x0020u       /* 0 = SCI logic and flags held in reset */
#define F2812_SCIRXST_RXERROR 0x0080u
#define F2812_SCIRXBUF_DATA 0x00FFu
#define F2812_SCIRXBUF_FFPE 0x4000u
#define F2812_SCIRXBUF_FFFE 0x8000u
#define F2812_SCIFFTX_SCIRST 0x8000u
#define F2812_SCIFFTX_SCIFFENA 0x4000u
#define F2812_SCIFFTX_TXFIFOXRESET 0x2000u
#define F2812_SCIFFTX_TXINTCLR 0x0040u
#define F2812_SCIFFRX_RXFFOVF 0x8000u
#define F2812_SCIFFRX_RXFFOVRCLR 0x4000u
#define F2812_SCIFFRX_RXFIFORESET 0x2000u
#define F2812_SCIFFRX_RXFFINTCLR 0x0040u
#define F2812_SCIFF_ST(reg) ((uint16_t)(((reg) >> 8) & 0x1Fu)) /* TXFFST / RXFFST: words held */
#define F2812_SCI_FIFO_DEPTH 16u
#define F2812_SCIPRI_FREE 0x0018u           /* run free when the emulator halts the CPU */

/* ------------------------------------------------------------------- the block instances ---- */
extern volatile struct f2812_flash_regs f2812_flash;
extern volatile struct f2812_piectrl_regs f2812_piectrl;
extern volatile struct f2812_pievect_regs f2812_pievect;
extern volatile struct f2812_sysctrl_regs f2812_sysctrl;
extern volatile struct f2812_gpiomux_regs f2812_gpiomux;
extern volatile struct f2812_gpiodata_regs f2812_gpiodata;
extern volatile struct f2812_adc_regs f2812_adc;
extern volatile struct f2812_eva_regs f2812_eva;
extern volatile struct f2812_spi_regs f2812_spia;
extern volatile struct f2812_sci_regs f2812_scia;

#endif /* F2812_REGS_H */
