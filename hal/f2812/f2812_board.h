/*
 * f2812_board.h - clock tree, control-period timing, dead band, ADC channel map and encoder of
 * the drive board, with every register value derived (and checked by the preprocessor) from the
 * physical quantity it sets. Board-specific values can be overridden with -D on the command line.
 *
 * Clock tree (fact sheet 4.3, DS ✔):
 *   OSCCLK 30 MHz crystal; PLLCR.DIV = 10: SYSCLKOUT = 30 MHz * 10 / 2 = 150 MHz.
 *   HISPCP = 1: HSPCLK = 150 MHz / 2 = 75 MHz (EV-A timers, dead band, ADC). 75 MHz rather than
 *     150 MHz: the drive only applies 0 %/100 % duty per period (see f2812_hal.c), so the finer PWM
 *     resolution of 150 MHz buys nothing, while 75 MHz is TI's own default (HDR InitSysCtrl ✔),
 *     halves EV/ADC clock power and lets the ADC reach 12.5 MHz with CPS = 0.
 *   LOSPCP = 2: LSPCLK = 37.5 MHz (SCI-A: the serial line; SPI-A: the parameter EEPROM; unused by
 *     the control path).
 *
 * Control period (fact sheet 2.3, EVG ✔: continuous up/down period = 2 * TxPR * T_clk):
 *   T1PR = 50 us * 75 MHz / 2 = 1875. Underflow (T1CNT = 0) once per period starts the ADC and is
 *   the instant the shadowed compare/action registers load, i.e. the period boundary.
 */
#ifndef F2812_BOARD_H
#define F2812_BOARD_H

#include <stdint.h>

/* ------------------------------------------------------------------------ clocks ----------- */
#define F2812_OSCCLK_HZ 30000000L
#define F2812_PLLCR_DIV 10
#define F2812_SYSCLK_HZ (F2812_OSCCLK_HZ * F2812_PLLCR_DIV / 2)
#define F2812_HISPCP 1
#define F2812_HSPCLK_HZ (F2812_SYSCLK_HZ / (2 * F2812_HISPCP))
#define F2812_LOSPCP 2
#define F2812_LSPCLK_HZ (F2812_SYSCLK_HZ / (2 * F2812_LOSPCP))

#if F2812_SYSCLK_HZ != 150000000L
#error "SYSCLKOUT must be 150 MHz (30 MHz crystal, PLLCR = 10)"
#endif

/* PLL lock: 131072 OSCCLK cycles = 4.37 ms at 30 MHz (fact sheet 4.3, HDR ✔). */
#define F2812_PLL_LOCK_US 4370L

/* ----------------------------------------------------------- control period, EV-A T1 ------- */
#define F2812_CONTROL_FREQ_HZ 20000L /* 1 / 50 us */
#define F2812_T1PR_VALUE (F2812_HSPCLK_HZ / (2L * F2812_CONTROL_FREQ_HZ))
#if F2812_T1PR_VALUE != 1875L || F2812_T1PR_VALUE * 2L * F2812_CONTROL_FREQ_HZ != F2812_HSPCLK_HZ
#error "T1PR for an exact 50 us up/down period at HSPCLK = 75 MHz must be 1875"
#endif
#define F2812_T1PR ((uint16_t)F2812_T1PR_VALUE)

/* Compare values that hold a leg in one state for a whole period (see f2812_hal.c "How legs are
 * driven"). With ACTRA 'active high' on the upper output, the compare output is active from the
 * up-count match to the down-count match (SPRU065, symmetric PWM; ~ at the two extremes):
 *   CMPRx = 0         -> active for the whole period: upper switch on, lower off.
 *   CMPRx = T1PR + 1  -> never matched, inactive the whole period: upper off, lower on.
 * These two constants are the single place to swap if the scope shows the opposite sense. */
#define F2812_CMPR_UPPER_ON ((uint16_t)0u)
#define F2812_CMPR_UPPER_OFF ((uint16_t)(F2812_T1PR + 1u))

/* ------------------------------------------------------------------------ dead band -------- */
/* Dead time of the gate drive (board and power-switch specific; override with -D). The unit
 * inserts DBT * 2^DBTPS HSPCLK periods (fact sheet 2.6; clock source HSPCLK is ~, item 8.10).
 * The smallest prescaler that fits DBT <= 15 is chosen, rounding up: never shorter than asked. */
#ifndef F2812_DEADBAND_NS
#define F2812_DEADBAND_NS 2000L
#endif
#define F2812_DB_TICKS ((F2812_DEADBAND_NS * (F2812_HSPCLK_HZ / 1000000L) + 999L) / 1000L)
#define F2812_DB_CEIL_(p) ((F2812_DB_TICKS + (1L << (p)) - 1L) >> (p))
#if F2812_DB_CEIL_(0) <= 15
#define F2812_DBTPS 0
#elif F2812_DB_CEIL_(1) <= 15
#define F2812_DBTPS 1
#elif F2812_DB_CEIL_(2) <= 15
#define F2812_DBTPS 2
#elif F2812_DB_CEIL_(3) <= 15
#define F2812_DBTPS 3
#elif F2812_DB_CEIL_(4) <= 15
#define F2812_DBTPS 4
#elif F2812_DB_CEIL_(5) <= 15
#define F2812_DBTPS 5
#else
#error "F2812_DEADBAND_NS exceeds 15 * 32 HSPCLK periods (6.4 us at 75 MHz)"
#endif
#define F2812_DBT F2812_DB_CEIL_(F2812_DBTPS)
#if F2812_DBT < 1
#error "a zero dead band is not allowed"
#endif
/* Dead time actually inserted, in ns (2 us requested -> DBT = 10, /16 -> 160 ticks = 2133 ns). */
#define F2812_DEADBAND_ACTUAL_NS (((long)F2812_DBT << F2812_DBTPS) * 1000L / (F2812_HSPCLK_HZ / 1000000L))

/* --------------------------------------------------------------------------------- ADC ----- */
/* ADCCLK = HSPCLK / (2 * ADCCLKPS) / (CPS + 1) = 75 MHz / 6 = 12.5 MHz (fact sheet 3.2, ~ formula;
 * 25 MHz max). S/H window (1 + ACQ_PS) = 2 ADCCLK = 160 ns. Five sequential conversions take about
 * 4t + 4 * 3t = 16 * 80 ns = 1.3 us after the underflow: the ISR starts ~1.5 us into the period. */
#define F2812_ADCCLKPS 3u
#define F2812_ADC_CPS 0u
#define F2812_ADC_ACQ_PS 1u
/* ADC power-up waits (DS ✔): bandgap/reference 7..10 ms, analog core 20..50 us. */
#define F2812_ADC_BGR_DELAY_US 10000L
#define F2812_ADC_PWD_DELAY_US 50L

/* Input channel of each measurement, in hal.h order (code 0..7 = ADCINA0..7, 8..15 = ADCINB0..7).
 * The sequencer converts them in this order, so ADCRESULTn holds hal.h channel n. */
#ifndef F2812_ADCIN_IA
#define F2812_ADCIN_IA 0u   /* ADCINA0 */
#endif
#ifndef F2812_ADCIN_IB
#define F2812_ADCIN_IB 1u   /* ADCINA1 */
#endif
#ifndef F2812_ADCIN_IC
#define F2812_ADCIN_IC 2u   /* ADCINA2 */
#endif
#ifndef F2812_ADCIN_VDC
#define F2812_ADCIN_VDC 3u  /* ADCINA3 */
#endif
#ifndef F2812_ADCIN_VMID
#define F2812_ADCIN_VMID 4u /* ADCINA4 */
#endif

/* --------------------------------------------------------------------------------- QEP ----- */
/* 2000-line encoder (Hoang et al. 2011, Fig. 9(b)): the QEP circuit counts every edge of both
 * channels, 4 * 2000 = 8000 counts per mechanical turn, T2 wraps inside 0..T2PR (EVG ✔). */
#ifndef F2812_QEP_LINES
#define F2812_QEP_LINES 2000u
#endif
#define F2812_QEP_COUNTS (4u * F2812_QEP_LINES)
#define F2812_T2PR ((uint16_t)(F2812_QEP_COUNTS - 1u))
/* 1 if the encoder wiring makes T2 count DOWN for positive speed: hal_read then reports
 * T2PR - T2CNT, so qep_count always rises for positive speed (hal.h contract). */
#ifndef F2812_QEP_REVERSED
#define F2812_QEP_REVERSED 0
#endif

/* ------------------------------------------- fault tolerance: relay and desaturation pins */
/* Port B is EV-B's (PWM7-12, T3/T4, CAP4-6); the drive uses EV-A only, so its pins are free of
 * EV-A, ADC and QEP use and of the boot-mode pins (GPIOF2/3/4/12, fact sheet 1.5). The peripheral
 * names of the port-B pins are by analogy with port A's table (fact sheet 4.8 lists GPAMUX only: ~);
 * used as GPIOs (MUX bit 0, the reset value) only the bit -> GPIOBx numbering matters (✔).
 *   GPIOB0..2 (PWM7-9 when muxed): outputs, relay coil drivers for phases A, B, C; 1 = coil on.
 *   GPIOB8..10 (CAP4-6 when muxed): inputs, the gate drivers' desaturation FAULT outputs of legs
 *   A, B, C, open-drain and active low with pull-ups (as HCPL-316J / ACPL-332J style drivers;
 *   the board's choice, F2812_DESAT_ACTIVE_LOW). The same FAULT lines pull PDPINTA (wired-OR). */
#define F2812_RELAY_GPB_SHIFT 0u
#define F2812_RELAY_GPB_MASK ((uint16_t)(7u << F2812_RELAY_GPB_SHIFT))
#define F2812_DESAT_GPB_SHIFT 8u
#define F2812_DESAT_GPB_MASK ((uint16_t)(7u << F2812_DESAT_GPB_SHIFT))
#ifndef F2812_DESAT_ACTIVE_LOW
#define F2812_DESAT_ACTIVE_LOW 1
#endif

/* ------------------------------------------------------------- serial line, SCI-A --------- */
/* 8N1 at F2812_SCI_BAUD. Baud = LSPCLK / ((BRR + 1) * 8) for BRR >= 1 (fact sheet 9.1, FAM ✔), so
 * BRR = LSPCLK / (8 baud) - 1, rounded to the nearest: 115200 baud -> BRR = 40, 114329 baud
 * (-0.76 %, the fact sheet's table). The preprocessor refuses a rate more than 2 % off (a UART
 * receiver samples mid-bit: the two ends together tolerate about 4 % over a 10-bit character). */
#ifndef F2812_SCI_BAUD
#define F2812_SCI_BAUD 115200L
#endif
#define F2812_SCI_BRR ((F2812_LSPCLK_HZ + 4L * F2812_SCI_BAUD) / (8L * F2812_SCI_BAUD) - 1L)
#if F2812_SCI_BRR < 1L || F2812_SCI_BRR > 65535L
#error "F2812_SCI_BAUD outside what SCI-A reaches from LSPCLK (BRR 1..65535)"
#endif
#define F2812_SCI_BAUD_ACTUAL (F2812_LSPCLK_HZ / ((F2812_SCI_BRR + 1L) * 8L))
#if (F2812_SCI_BAUD_ACTUAL - F2812_SCI_BAUD) * 50L > F2812_SCI_BAUD || \
    (F2812_SCI_BAUD - F2812_SCI_BAUD_ACTUAL) * 50L > F2812_SCI_BAUD
#error "F2812_SCI_BAUD is more than 2 % off what SCI-A can make from LSPCLK"
#endif

/* ----------------------------------------------------- parameter EEPROM, SPI-A ------------- */
/* A 25LC256-class SPI EEPROM (32 KiB: 16384 16-bit words, 64-octet pages, 5 ms write cycle; fact
 * sheet 9.2, EE ✔) on SPISIMOA/SPISOMIA/SPICLKA, chip select on GPIOF3 driven as a GPIO.
 * SPICLK = LSPCLK / (SPIBRR + 1): SPIBRR = 7 -> 4.69 MHz, inside the part's ~5 MHz at 3.3 V
 * (fact sheet 9.2, ~). Mode 0 (data latched on the rising clock edge, the part's mode 0 or 3):
 * CLKPOLARITY = 0 with CLK_PHASE = 1, the reading of fact sheet 9.5 #1 (x: scope it on the bench;
 * F2812_SPI_CLKPOL / F2812_SPI_PHASE are the single place to swap). */
#ifndef F2812_EEPROM_WORDS
#define F2812_EEPROM_WORDS 16384u
#endif
#define F2812_EEPROM_PAGE_OCTETS 64u
#ifndef F2812_SPIBRR
#define F2812_SPIBRR 7u
#endif
#ifndef F2812_SPI_CLKPOL
#define F2812_SPI_CLKPOL 0u
#endif
#ifndef F2812_SPI_PHASE
#define F2812_SPI_PHASE 1u
#endif
/* Write cycle: 5 ms max (EE ✔). The status register is read (RDSR, two characters, about 4 us at
 * 4.69 MHz) at most F2812_EEPROM_WIP_POLLS times, about 80 ms, servicing the watchdog between
 * reads. A character's done flag is polled at most F2812_SPI_CHAR_POLLS times (a character takes
 * 1.7 us = 256 CPU cycles; every poll is several cycles): a missing part or clock ends in
 * HAL_STORE_ERR_DEVICE, never in a hang. */
#define F2812_EEPROM_WIP_POLLS 20000u
#define F2812_SPI_CHAR_POLLS 2000u

/* ---------------------------------------------------------------------------- watchdog ----- */
/* WDCLK = OSCCLK / 512 = 58.6 kHz, 8-bit counter; WDPS = 1 (/1): timeout 256 / 58.6 kHz = 4.4 ms
 * (fact sheet 4.4, ~ layout; the 0x0068 disable value is ✔). The background loop must service
 * it at least every 4.4 ms; it is started by main() after app_init, not by hal_init. */
#define F2812_WDPS 1u

#endif /* F2812_BOARD_H */
