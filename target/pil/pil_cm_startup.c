/*
 * pil_cm_startup.c - the smallest start-up of the Cortex-M PIL replay image: vector table with the
 * initial stack pointer and the reset handler, which zeroes .bss and calls main(). No C library
 * (mps2_an385.ld; qemu loads .data in place).
 */
#include <stdint.h>

int main(void);
void pil_cm_reset(void);
void pil_cm_fault(void);
/* SysTick's handler: the console image's control ISR (pil_console_cm.c); the replay images run
 * SysTick without its interrupt and link none (then a SysTick interrupt is a fault). */
void pil_cm_systick(void) __attribute__((weak, alias("pil_cm_fault")));

extern uint32_t __bss_start, __bss_end, __stack_top;

void pil_cm_reset(void)
{
    uint32_t *p;
    for (p = &__bss_start; p < &__bss_end; ++p) {
        *p = 0U;
    }
    (void)main();
    for (;;) {
    }
}

/* Any fault: stop qemu with a failing exit (semihosting SYS_EXIT, reason other than
 * ApplicationExit), so a crash is an error of the replay, never a hang. */
void pil_cm_fault(void)
{
    __asm volatile("movs r0, #0x18\n movs r1, #0\n bkpt 0xab\n" ::: "r0", "r1", "memory");
    for (;;) {
    }
}

__attribute__((section(".vectors"), used)) static void (*const g_vectors[16])(void) = {
    (void (*)(void))(uintptr_t)&__stack_top, pil_cm_reset, pil_cm_fault, pil_cm_fault,
    pil_cm_fault, pil_cm_fault, pil_cm_fault, 0, 0, 0, 0, pil_cm_fault, pil_cm_fault, 0,
    pil_cm_fault, pil_cm_systick};
