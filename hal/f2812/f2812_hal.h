/*
 * f2812_hal.h - F2812-specific entry points beyond hal/include/hal.h, used by the target's
 * start-up (target/f2812/f2812_main.c) and by the register-level tests (tests/hal). The firmware never
 * includes this file: it sees only hal.h.
 */
#ifndef F2812_HAL_H
#define F2812_HAL_H

#include <stdint.h>

#include "f2812_target.h"

/* ISR glue. f2812_adcint_isr is defined next to main() (target/f2812/f2812_main.c: it calls app_isr) and, in
 * the host tests, by the test itself; hal_init installs its address at PIE vector 1.6 (ADCINT).
 * f2812_pdpint_isr (PIE 1.1) and f2812_unexpected_isr (every other vector) are in the binding. */
F2812_INTERRUPT void f2812_adcint_isr(void);
F2812_INTERRUPT void f2812_pdpint_isr(void);
F2812_INTERRUPT void f2812_unexpected_isr(void);
/* Timer 1 period match (PIE 2.4): the PWM form's period-match reload (hal.h), body f2812_t1pint(). */
F2812_INTERRUPT void f2812_t1pint_isr(void);
void f2812_t1pint(void);

/* End of the ADC ISR, after app_isr(): counts the period, resets SEQ1 to CONV00, clears its
 * interrupt flag and re-arms PIE group 1 (fact sheet 3.3 step 7, 4.1 "ISR exit duties"). */
void f2812_adcint_done(void);

/* Leg A of a four-switch (FSTP) board is absent: phase A is tied to the capacitor mid-point
 * (Hoang et al. 2011, Fig. 1(b)). hal_init sets this from F2812_BOARD_FSTP; main()/tests may
 * override it after hal_init. With it set, hal_write ignores sa and keeps PWM1/PWM2 off. */
#ifndef F2812_BOARD_FSTP
#define F2812_BOARD_FSTP 0
#endif
void f2812_set_fstp(uint16_t fstp);

/* Direction of the encoder counter from GPTCONA.T2STAT: +1 counting up, -1 counting down
 * (after F2812_QEP_REVERSED is applied, i.e. +1 = positive speed). Diagnostics only: hal_meas_t
 * carries the count, and the application derives speed (and thus direction) from count deltas. */
int16_t f2812_qep_direction(void);

/* Starts the watchdog (about 4.4 ms timeout, f2812_board.h). Called by main() once app_init has
 * returned, so long initialisation cannot trip it; from then on app_background() must call
 * hal_watchdog_service(). */
void f2812_watchdog_start(void);

/* Start of operation, called by main() after app_init: starts EV-A timer 1 (the 50 us period and
 * the ADC trigger) with SEQ1 reset, then enables interrupts globally (INTM = 0, DBGM = 0). */
void f2812_interrupts_enable(void);

/* Worst-case ISR completion time since the start of its period, in HSPCLK periods (13.33 ns; a
 * period is 2 * T1PR = 3750). Read it with the debugger on the running drive: it must stay well
 * below 3750, or the switching state of period k is applied a period late. */
uint16_t f2812_isr_ticks_max(void);

/* SCI-A, the serial line of hal.h (f2812_sci.c). hal_init calls f2812_sci_init: clock, pins,
 * 8N1 at F2812_SCI_BAUD, FIFOs on, no interrupts. */
void f2812_sci_init(void);
typedef struct {
    uint16_t rx_char_errors; /* characters received with a framing or parity error */
    uint16_t rx_resets;      /* receiver errors cleared by a software reset */
    uint16_t rx_overflows;   /* receive FIFO overflows (octets lost) */
} f2812_sci_stats_t;
const f2812_sci_stats_t *f2812_sci_stats(void);

/* SPI-A master for the parameter EEPROM (f2812_spi.c); the storage medium of hal.h on it is
 * f2812_eeprom.c. hal_init calls f2812_spi_init. f2812_spi_cs(1) drives the chip select low
 * (active), (0) high. f2812_spi_xfer sends the octet tx and stores the octet received meanwhile
 * in *rx; returns 1, or 0 when the character never completed (bounded wait). */
void f2812_spi_init(void);
void f2812_spi_cs(uint16_t active);
uint16_t f2812_spi_xfer(uint16_t tx, uint16_t *rx);

#endif /* F2812_HAL_H */
