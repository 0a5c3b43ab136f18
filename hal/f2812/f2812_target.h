/*
 * f2812_target.h - the ONE place where hal/f2812 differs between the TMS320F2812 (TI cl2000) and
 * a host/proxy compiler (gcc, arm-none-eabi-gcc, avr-gcc) that builds the same binding against
 * registers in RAM for the register-level tests (tests/hal) and the portability proxies.
 *
 * Everything target-specific is a macro or a static inline here:
 *   F2812_REGBLOCK(var, sect)  target: #pragma DATA_SECTION, so linker/f2812_regs.cmd places the
 *                              register struct at its peripheral-frame address (the pattern of
 *                              TI's DSP281x headers, fact sheet 1.3 "HDR"); host: nothing, the
 *                              struct is an ordinary zero-initialised global.
 *   F2812_RAMFUNC(fn)          target: #pragma CODE_SECTION(fn, "ramfuncs"), copied flash -> L0/L1
 *                              at start-up (fact sheet 1.4, 4.7); host: nothing.
 *   F2812_INTERRUPT            target: __interrupt (context save, IRET; CG 6.3); host: nothing.
 *   f2812_eallow()/f2812_edis()  target: EALLOW/EDIS instructions (fact sheet 4.2). Host: no
 *                              hardware effect; they only set the emulated ST1.EALLOW flag that
 *                              f2812_wr_protected() honours, so a forgotten EALLOW shows up in
 *                              the host tests exactly as on silicon: the write is lost.
 *   interrupt masks (IER, INTM) target: the cregister IER and the INTM intrinsics; host: fields
 *                              of f2812_host_cpu that the tests inspect.
 *
 * Nothing outside hal/f2812 includes this file.
 */
#ifndef F2812_TARGET_H
#define F2812_TARGET_H

#include <stdint.h>

/* A PIE vector: the address of an interrupt service routine (32 bits on the C28x). */
typedef void (*f2812_isr_t)(void);

/* Word copy used for the ramfuncs flash -> RAM copy (fact sheet 1.4 "Copy loop"). Copies the
 * words [begin, end) to dst. Defined in f2812_hal.c so the host tests exercise it. */
void f2812_memcopy(uint16_t *dst, const uint16_t *begin, const uint16_t *end);

#if defined(__TMS320C28XX__) || defined(__TMS320C2000__)
/* ---------------------------------------------------------------- TMS320F2812, TI cl2000 ---- */
#define F2812_ON_TARGET 1
#define F2812_PRAGMA_(x) _Pragma(#x)
#define F2812_REGBLOCK(var, sect) F2812_PRAGMA_(DATA_SECTION(var, sect))
#define F2812_RAMFUNC(fn) F2812_PRAGMA_(CODE_SECTION(fn, "ramfuncs"))
#define F2812_INTERRUPT __interrupt

/* CPU interrupt-enable register, a core register (fact sheet 4.1 "CPU side"; HDR declares it the
 * same way). The only 'unsigned int' in the project: it is the compiler's own type for it. */
extern cregister volatile unsigned int IER;
extern cregister volatile unsigned int IFR;

static inline void f2812_eallow(void) { __asm(" EALLOW"); }
static inline void f2812_edis(void) { __asm(" EDIS"); }
static inline void f2812_wr_protected(volatile uint16_t *reg, uint16_t value) { *reg = value; }
static inline void f2812_wr_protected_vec(volatile f2812_isr_t *slot, f2812_isr_t isr) { *slot = isr; }
static inline void f2812_ier_set(uint16_t mask) { IER |= mask; }
static inline void f2812_ier_ifr_clear(void) { IER = 0x0000u; IFR = 0x0000u; }
static inline void f2812_int_global_enable(void) { __asm(" CLRC INTM"); __asm(" CLRC DBGM"); }
static inline void f2812_int_global_disable(void) { __asm(" SETC INTM"); }
/* __disable_interrupts() returns the old ST1 (INTM is bit 0) and sets INTM; __restore_interrupts
 * writes INTM back (CG 6.3, recalled ~: check the compiler manual SPRU514 of your cl2000). */
static inline uint16_t f2812_irq_save(void) { return (uint16_t)__disable_interrupts(); }
static inline void f2812_irq_restore(uint16_t st1) { __restore_interrupts(st1); }
/* Flash-register writes take effect only after the pipeline drains: 8 cycles (fact sheet 4.7). */
static inline void f2812_pipeline_flush(void) { __asm(" RPT #7 || NOP"); }
/* Busy wait of AT LEAST min_cycles CPU cycles: every iteration costs >= 1 cycle (a NOP plus the
 * loop overhead), so the real wait is longer, never shorter, whatever the optimiser does. */
static inline void f2812_delay_cycles(uint32_t min_cycles)
{
    volatile uint32_t i;
    for (i = 0u; i < min_cycles; i++) {
        __asm(" NOP");
    }
}

/* Linker-defined symbols of the ramfuncs section (linker/f2812_flash.cmd, f2812_ram.cmd). COFF ABI:
 * the .cmd names them with a leading underscore. */
extern uint16_t f2812_ramfuncs_load_start;
extern uint16_t f2812_ramfuncs_load_end;
extern uint16_t f2812_ramfuncs_run_start;
extern uint16_t f2812_ramfuncs_h_load_start; /* ramfuncs_h: libdtc_fixmath.a and libdtc_app.a */
extern uint16_t f2812_ramfuncs_h_load_end;
extern uint16_t f2812_ramfuncs_h_run_start;
/* ramfuncs_m: the IM image's third zero-wait code block, M1 (linker/f2812_flash_im.cmd); the PM
 * image's .cmd files set its three symbols equal, so its copy moves no word. */
extern uint16_t f2812_ramfuncs_m_load_start;
extern uint16_t f2812_ramfuncs_m_load_end;
extern uint16_t f2812_ramfuncs_m_run_start;
static inline void f2812_ramfuncs_copy(void)
{
    f2812_memcopy(&f2812_ramfuncs_run_start, &f2812_ramfuncs_load_start, &f2812_ramfuncs_load_end);
    f2812_memcopy(&f2812_ramfuncs_h_run_start, &f2812_ramfuncs_h_load_start, &f2812_ramfuncs_h_load_end);
    f2812_memcopy(&f2812_ramfuncs_m_run_start, &f2812_ramfuncs_m_load_start, &f2812_ramfuncs_m_load_end);
}

#else
/* ------------------------------------------------- host / proxy: registers are plain RAM ---- */
#define F2812_ON_TARGET 0
#define F2812_REGBLOCK(var, sect)
#define F2812_RAMFUNC(fn)
#define F2812_INTERRUPT

/* Emulated CPU state the tests inspect. ST1.EALLOW, ST1.INTM, IER, IFR as on the C28x. */
struct f2812_host_cpu {
    uint16_t eallow;         /* 1 between f2812_eallow() and f2812_edis() */
    uint16_t intm;           /* 1 = maskable interrupts globally disabled (reset value) */
    uint16_t ier;            /* CPU interrupt enable register */
    uint16_t ifr;            /* CPU interrupt flag register */
    uint16_t lost_writes;    /* protected-register writes attempted with EALLOW clear */
    uint16_t pipeline_flushes; /* f2812_pipeline_flush() calls (after the flash set-up) */
    uint32_t delay_cycles;   /* total of the busy waits requested (PLL lock, ADC power-up) */
};
extern struct f2812_host_cpu f2812_host_cpu;

static inline void f2812_eallow(void) { f2812_host_cpu.eallow = 1u; }
static inline void f2812_edis(void) { f2812_host_cpu.eallow = 0u; }
static inline void f2812_wr_protected(volatile uint16_t *reg, uint16_t value)
{
    if (f2812_host_cpu.eallow != 0u) {
        *reg = value;
    } else {
        f2812_host_cpu.lost_writes++; /* silicon ignores the write (fact sheet 4.2) */
    }
}
static inline void f2812_wr_protected_vec(volatile f2812_isr_t *slot, f2812_isr_t isr)
{
    if (f2812_host_cpu.eallow != 0u) {
        *slot = isr;
    } else {
        f2812_host_cpu.lost_writes++;
    }
}
static inline void f2812_ier_set(uint16_t mask) { f2812_host_cpu.ier = (uint16_t)(f2812_host_cpu.ier | mask); }
static inline void f2812_ier_ifr_clear(void) { f2812_host_cpu.ier = 0u; f2812_host_cpu.ifr = 0u; }
static inline void f2812_int_global_enable(void) { f2812_host_cpu.intm = 0u; }
static inline void f2812_int_global_disable(void) { f2812_host_cpu.intm = 1u; }
static inline uint16_t f2812_irq_save(void)
{
    uint16_t old = f2812_host_cpu.intm;
    f2812_host_cpu.intm = 1u;
    return old;
}
static inline void f2812_irq_restore(uint16_t st1) { f2812_host_cpu.intm = (uint16_t)(st1 & 1u); }
static inline void f2812_pipeline_flush(void) { f2812_host_cpu.pipeline_flushes++; }
static inline void f2812_delay_cycles(uint32_t min_cycles) { f2812_host_cpu.delay_cycles += min_cycles; }
static inline void f2812_ramfuncs_copy(void) { /* host code runs where it was linked */ }
#endif

#endif /* F2812_TARGET_H */
