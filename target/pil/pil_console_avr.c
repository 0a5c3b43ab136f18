/*
 * pil_console_avr.c - the AVR binding of the console image (pil_console.h) on an ATmega2560 at
 * 16 MHz with external SRAM on its XMEM interface, run by tools/pil/pil-simavr --console: the
 * serial line is USART0, the control ISR Timer/Counter1's compare match A, the interrupt mask
 * SREG's I bit, the storage medium the on-chip EEPROM. main() is f2812_main.c's: init, then the
 * background loop for ever.
 *
 * RAM. The image needs more than the part's 8 KB of internal SRAM (docs/pil.md, "AVR console":
 * static data plus the stack's peak, measured by pil-simavr), so it is linked for the part with
 * 32 KB of external SRAM (data space 0x0200..0x7FFF, target/pil/CMakeLists.txt); the external
 * SRAM is enabled (XMCRA.SRE, datasheet 9.4) in .init3, before the C start-up copies .data.
 *
 * USART0 (ATmega2560 datasheet, 22. USART): UDR0 data, UCSR0A (RXC0 receive complete, UDRE0 data
 * register empty, U2X0 double speed), UCSR0B (RXCIE0, RXEN0, TXEN0), UCSR0C (UCSZ01:0 = 3: 8 data
 * bits, no parity, 1 stop bit), UBRR0 = f / (8 baud) - 1 with U2X0 (16: 117,647 baud, +2.1 %).
 * The part holds two received octets and a third in the shift register (22.7.4); at 115200 baud
 * that is 3 x 1389 cycles, less than one control ISR (~3,600 cycles disarmed, ~55,700 armed,
 * measured). So reception is the receive-complete interrupt into a ring the background loop
 * empties (hal_serial_read), and the control ISR runs with interrupts enabled (its own compare
 * interrupt masked until it returns) so that the receive interrupt preempts it. Sending is polled
 * (UDRE0) by the background loop: an octet waiting to be sent loses nothing.
 *
 * Timer/Counter1 (datasheet 17.): CTC mode (WGM13:0 = 4, TOP = OCR1A), clock f / 1, interrupt on
 * compare match A every PIL_AVR_ISR_CYCLES cycles: 64,000 cycles = 4 ms, above the longest ISR
 * measured in the console session (55,681 cycles, armed) with 13 % left for the background loop.
 * The application's time base is its configured 50 us period (APP_ISR_PERIOD_NS): on this part
 * every control period lasts 80 times longer, and so does every time counted in ISR periods
 * (PROTO_IDLE_MS, comm_timeout_s, the capture's sample rate).
 *
 * EEPROM (datasheet 8.3): 4096 octets, each write 3.4 ms; avr-libc's eeprom_*_word wait for the
 * previous write. A word of the store is two octets, little-endian.
 */
#include <avr/eeprom.h>
#include <avr/interrupt.h>
#include <avr/io.h>

#include "hal.h"
#include "pil_avr_channel.h"
#include "pil_console.h"

#define PIL_AVR_ISR_CYCLES 64000U
#define PIL_AVR_F_CPU 16000000UL
#define PIL_AVR_BAUD 115200UL
#define PIL_AVR_STORE_WORDS 2048U /* (E2END + 1) / 2 */
#define PIL_AVR_STORE_ERASE 32U   /* the unit the store's slots are aligned to (an EEPROM: no erase) */
#define PIL_AVR_RX_RING 64U       /* a power of two */

static volatile uint8_t g_rx[PIL_AVR_RX_RING];
static volatile uint8_t g_rx_head; /* written by the receive interrupt only */
static uint8_t g_rx_tail;          /* background only */

/* External SRAM on, no wait states, the whole data space above the internal SRAM (XMCRB = 0). */
void pil_avr_xmem(void) __attribute__((naked, used, section(".init3")));
void pil_avr_xmem(void)
{
    XMCRA = (uint8_t)(1U << SRE);
}

/* An octet received: into the ring; dropped when the ring is full (the frame's CRC then rejects
 * its frame, as a line error would). */
ISR(USART0_RX_vect)
{
    const uint8_t c = UDR0;
    const uint8_t next = (uint8_t)((g_rx_head + 1U) & (PIL_AVR_RX_RING - 1U));
    if (next != g_rx_tail) {
        g_rx[g_rx_head] = c;
        g_rx_head = next;
    }
}

/* The control ISR with interrupts enabled (the receive interrupt preempts it), its own compare
 * interrupt masked meanwhile (no re-entry when it overruns its period), between the markers
 * pil-simavr --console times it by (GPIOR2 is a general-purpose register: on the part the writes
 * do nothing else). */
ISR(TIMER1_COMPA_vect)
{
    TIMSK1 = 0U;
    sei();
    GPIOR2 = PIL_AVR_ISR_BEGIN;
    pil_console_isr();
    GPIOR2 = PIL_AVR_ISR_END;
    cli();
    TIMSK1 = (uint8_t)(1U << OCIE1A);
}

uint16_t hal_irq_save(void)
{
    const uint16_t sreg = SREG;
    cli();
    return (uint16_t)((sreg >> SREG_I) & 1U);
}

void hal_irq_restore(uint16_t state)
{
    if (state != 0U) {
        sei();
    }
}

uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    uint16_t n = 0U;
    while (n < max && g_rx_tail != g_rx_head) {
        buf[n] = g_rx[g_rx_tail];
        g_rx_tail = (uint8_t)((g_rx_tail + 1U) & (PIL_AVR_RX_RING - 1U));
        n++;
    }
    return n;
}

uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    uint16_t k = 0U;
    while (k < n && (UCSR0A & (1U << UDRE0)) != 0U) {
        UDR0 = (uint8_t)(buf[k] & 0xFFU);
        k++;
    }
    return k;
}

uint16_t hal_store_words(void) { return PIL_AVR_STORE_WORDS; }
uint16_t hal_store_erase_words(void) { return PIL_AVR_STORE_ERASE; }

uint16_t pil_console_store_get(uint16_t addr)
{
    return eeprom_read_word((const uint16_t *)(uintptr_t)(2U * addr));
}

void pil_console_store_put(uint16_t addr, uint16_t value)
{
    eeprom_update_word((uint16_t *)(uintptr_t)(2U * addr), value);
}

int main(void)
{
    (void)pil_console_init();
    UBRR0 = (uint16_t)((PIL_AVR_F_CPU + 4UL * PIL_AVR_BAUD) / (8UL * PIL_AVR_BAUD) - 1UL);
    UCSR0A = (uint8_t)(1U << U2X0);
    UCSR0C = (uint8_t)(3U << UCSZ00);
    UCSR0B = (uint8_t)((1U << RXCIE0) | (1U << RXEN0) | (1U << TXEN0));
    OCR1A = (uint16_t)(PIL_AVR_ISR_CYCLES - 1U);
    TCCR1A = 0U;
    TCCR1B = (uint8_t)((1U << WGM12) | (1U << CS10));
    TIMSK1 = (uint8_t)(1U << OCIE1A);
    sei();
    for (;;) {
        pil_console_background();
    }
}
