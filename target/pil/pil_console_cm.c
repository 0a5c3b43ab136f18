/*
 * pil_console_cm.c - the Cortex-M binding of the console image (pil_console.h) on
 * qemu-system-arm -M mps2-an385: the serial line is the board's CMSDK APB UART0 (0x40004000,
 * qemu's first -serial), the control ISR SysTick's interrupt every 50 us of the 25 MHz processor
 * clock (under -icount the clock is the instruction count), the interrupt mask PRIMASK, the
 * storage medium RAM. main() is f2812_main.c's: init, then the background loop for ever.
 *
 * CMSDK APB UART (ARM DDI 0479 "Cortex-M System Design Kit", APB UART; qemu hw/char/
 * cmsdk-apb-uart.c): DATA +0x00, STATE +0x04 (bit 0 TX buffer full, bit 1 RX buffer full), CTRL
 * +0x08 (bit 0 TX enable, bit 1 RX enable), BAUDDIV +0x10 (at least 16). One octet each way, no
 * FIFO: the background loop polls it on every pass.
 */
#include <stdint.h>

#include "hal.h"
#include "pil_console.h"

#define UART0_BASE 0x40004000UL
#define UART_DATA (*(volatile uint32_t *)(UART0_BASE + 0x00UL))
#define UART_STATE (*(volatile uint32_t *)(UART0_BASE + 0x04UL))
#define UART_CTRL (*(volatile uint32_t *)(UART0_BASE + 0x08UL))
#define UART_BAUDDIV (*(volatile uint32_t *)(UART0_BASE + 0x10UL))
#define UART_STATE_TXFULL 0x1UL
#define UART_STATE_RXFULL 0x2UL

#define SYST_CSR (*(volatile uint32_t *)0xE000E010UL)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014UL)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018UL)
#define CPU_HZ 25000000UL
#define ISR_HZ 20000UL /* 1 / APP_ISR_PERIOD_NS */

static uint16_t g_store[PIL_CONSOLE_STORE_WORDS];

void pil_cm_systick(void);
void pil_cm_systick(void)
{
    pil_console_isr();
}

uint16_t hal_irq_save(void)
{
    uint32_t primask;
    __asm volatile("mrs %0, primask\n cpsid i" : "=r"(primask)::"memory");
    return (uint16_t)(primask & 1U);
}

void hal_irq_restore(uint16_t state)
{
    if (state == 0U) {
        __asm volatile("cpsie i" ::: "memory");
    }
}

uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    uint16_t n = 0U;
    while (n < max && (UART_STATE & UART_STATE_RXFULL) != 0U) {
        buf[n] = (uint16_t)(UART_DATA & 0xFFU);
        n++;
    }
    return n;
}

uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    uint16_t k = 0U;
    while (k < n && (UART_STATE & UART_STATE_TXFULL) == 0U) {
        UART_DATA = (uint32_t)(buf[k] & 0xFFU);
        k++;
    }
    return k;
}

uint16_t hal_store_words(void) { return (uint16_t)PIL_CONSOLE_STORE_WORDS; }
uint16_t hal_store_erase_words(void) { return (uint16_t)PIL_CONSOLE_STORE_ERASE; }

uint16_t pil_console_store_get(uint16_t addr)
{
    return g_store[addr];
}

void pil_console_store_put(uint16_t addr, uint16_t value)
{
    g_store[addr] = value;
}

int main(void)
{
    uint32_t k;
    for (k = 0U; k < PIL_CONSOLE_STORE_WORDS; k++) {
        g_store[k] = 0xFFFFU; /* erased */
    }
    UART_BAUDDIV = CPU_HZ / 115200UL;
    UART_CTRL = 0x3UL; /* TX and RX enabled, no interrupts */
    (void)pil_console_init();
    SYST_RVR = CPU_HZ / ISR_HZ - 1UL;
    SYST_CVR = 0U;
    SYST_CSR = 7U; /* enabled, interrupt, processor clock */
    for (;;) {
        pil_console_background();
    }
}
