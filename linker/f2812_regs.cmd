/*
 * f2812_regs.cmd - places the project's register-block structs (hal/f2812/f2812_regs.c, one data
 * section per block) at their peripheral-frame addresses. Link it together with f2812_flash.cmd
 * or f2812_ram.cmd. Addresses: ../shared/reference/f2812-facts.md 1.3 and 4.7 (DS, HDR ✔); the
 * same bases are F2812_*_BASE in hal/f2812/f2812_regs.h, whose layout is checked at compile time.
 * Lengths are the struct sizes in 16-bit words.
 *
 * The register sections are uninitialised (the C objects have no initialiser on the target), so
 * nothing is loaded into the peripheral frames; the linker only resolves the symbols.
 */
MEMORY
{
PAGE 1:
    REG_FLASH   : origin = 0x000A80, length = 0x000008   /* PF0 flash control (EALLOW, CSM) */
    REG_PIECTRL : origin = 0x000CE0, length = 0x000020   /* PF0 PIE control */
    REG_PIEVECT : origin = 0x000D00, length = 0x000100   /* PF0 PIE vector table (EALLOW) */
    REG_SYSCTRL : origin = 0x007010, length = 0x000020   /* PF2 system control (EALLOW) */
    REG_SPIA    : origin = 0x007040, length = 0x000010   /* PF2 SPI-A */
    REG_SCIA    : origin = 0x007050, length = 0x000010   /* PF2 SCI-A */
    REG_GPIOMUX : origin = 0x0070C0, length = 0x000020   /* PF2 GPIO mux (EALLOW) */
    REG_GPIODAT : origin = 0x0070E0, length = 0x000020   /* PF2 GPIO data */
    REG_ADC     : origin = 0x007100, length = 0x000020   /* PF2 ADC */
    REG_EVA     : origin = 0x007400, length = 0x000040   /* PF2 Event Manager A */
}

SECTIONS
{
    f2812_flash_regs   : > REG_FLASH,   PAGE = 1
    f2812_piectrl_regs : > REG_PIECTRL, PAGE = 1
    f2812_pievect_regs : > REG_PIEVECT, PAGE = 1
    f2812_sysctrl_regs : > REG_SYSCTRL, PAGE = 1
    f2812_spia_regs    : > REG_SPIA,    PAGE = 1
    f2812_scia_regs    : > REG_SCIA,    PAGE = 1
    f2812_gpiomux_regs : > REG_GPIOMUX, PAGE = 1
    f2812_gpiodata_regs : > REG_GPIODAT, PAGE = 1
    f2812_adc_regs     : > REG_ADC,     PAGE = 1
    f2812_eva_regs     : > REG_EVA,     PAGE = 1
}
