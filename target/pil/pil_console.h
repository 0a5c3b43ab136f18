/*
 * pil_console.h - the console image of processor-in-the-loop (docs/pil.md, "Console on the
 * emulated target"): the drive as the F2812 image runs it (target/f2812/f2812_main.c: the board's
 * compiled-in configuration, command arming, the serial protocol in the background loop, the
 * control ISR every period) on a bench without a machine: every period the HAL reads a healthy
 * drive at standstill (the current channels at their offsets, the DC link at the voltage base,
 * the mid-point at half of it, a still encoder, no trip) and the gate commands go nowhere.
 *
 * The same C runs in three bindings that give the same answers to the same session
 * (tests/pil/test_console_pil.py):
 *   pil_cm_console.elf  cross-cm0, qemu-system-arm -M mps2-an385: the line is the board's CMSDK
 *                       UART0, the ISR SysTick's (pil_console_cm.c);
 *   pil_avr_console.elf cross-avr, pil-simavr --console: the line is the ATmega2560's USART0, the
 *                       ISR Timer1's every 4 ms (pil_console_avr.c);
 *   pil-console-host    host: the line is hal/host's SerialLine at PROTO_BAUD in simulated time
 *                       on a pseudo-terminal, the ISR called once per period
 *                       (tools/pil/pil_console_host.cpp).
 * The storage medium is RAM of the F2812 board's EEPROM geometry (hal/f2812/f2812_board.h) on the
 * Cortex-M and the host, where a save lasts until the image stops; the AVR's own EEPROM on the AVR.
 */
#ifndef PIL_CONSOLE_H
#define PIL_CONSOLE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PIL_CONSOLE_STORE_WORDS 16384u /* F2812_EEPROM_WORDS */
#define PIL_CONSOLE_STORE_ERASE 32u    /* F2812_EEPROM_PAGE_OCTETS / 2 */

/* The bench's measurement, the application on the board configuration with command arming, the
 * protocol started (as f2812_main.c's main() before it enables the interrupt). Returns app_init's
 * code (0 = the configuration was accepted). */
int16_t pil_console_init(void);

/* One control period (the ISR) and one pass of the background loop. */
void pil_console_isr(void);
void pil_console_background(void);

/* ISR periods so far. */
uint32_t pil_console_ticks(void);

/* The Cortex-M and AVR bindings' store (pil_console_store.c implements hal.h's hal_store_read,
 * hal_store_write and hal_store_erase on it): an EEPROM-like array of hal_store_words() words,
 * rewritten in place, its slots aligned to hal_store_erase_words() (a power of two). The binding
 * supplies those two sizes and the access to one word at addr < hal_store_words(). */
uint16_t pil_console_store_get(uint16_t addr);
void pil_console_store_put(uint16_t addr, uint16_t value);

#ifdef __cplusplus
}
#endif

#endif /* PIL_CONSOLE_H */
