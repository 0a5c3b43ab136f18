/*
 * f2812_flash_mem.cmd - the memory map of the F2812's flash images (f2812_flash.cmd, the PM image;
 * f2812_flash_im.cmd, the IM image): link it with either, and f2812_regs.cmd. Written for this
 * project from ../shared/reference/f2812-facts.md 1.1-1.4 (16-bit word addresses).
 *   RAML0L1   ramfuncs: the HAL's ISR path, the first list of hot functions, the control tables
 *   RAMH0P    ramfuncs_h: H0's first 6.5K words, the second list
 *   RAMM1P    ramfuncs_m: M1, the third list (M1 is program and data SARAM, fact sheet 1.1)
 *   RAMM0     the stack: --stack_size 0x400 (cmake/toolchain-cl2000.cmake), all of M0; the SP is
 *             16 bits, so the stack lives in the low 64K
 *   RAMH0D    .ebss: H0's last 1.5K words, the controller state
 *   XRAM      opdata: external SRAM on XINTF zone 6 (BOARD FACT, UNVERIFIED: the eZdsp F2812's)
 *   FLASH_JC  the load images of the RAM sections and everything that runs from flash; sector B
 *             is left free for the user's parameter storage, sector A holds codestart and the
 *             CSM words
 * hal/f2812/budget.sh and hot_functions.py read the blocks' lengths here.
 */
MEMORY
{
PAGE 0:    /* program */
    RAML0L1   : origin = 0x008000, length = 0x002000   /* L0 + L1 SARAM, zero-wait: ramfuncs run */
    RAMH0P    : origin = 0x3F8000, length = 0x001A00   /* H0 SARAM (first 6.5K), zero-wait: ramfuncs_h */
    FLASH_JC  : origin = 0x3D8000, length = 0x01C000   /* sectors J, I, H, G, F, E, D, C */
    FLASHB    : origin = 0x3F4000, length = 0x002000   /* sector B: free (user parameters) */
    FLASHA    : origin = 0x3F6000, length = 0x001F80   /* sector A below the CSM words: free */
    CSM_RSVD  : origin = 0x3F7F80, length = 0x000076   /* zeros only when the CSM is used */
    BEGIN     : origin = 0x3F7FF6, length = 0x000002   /* boot-to-flash entry */
    CSM_PWL   : origin = 0x3F7FF8, length = 0x000008   /* CSM password: left erased */
    RESET     : origin = 0x3FFFC0, length = 0x000002   /* boot ROM's reset vector */
    RAMM1P    : origin = 0x000400, length = 0x000400   /* M1 SARAM, zero-wait: ramfuncs_m */
PAGE 1:    /* data */
    RAMM0     : origin = 0x000000, length = 0x000400   /* M0 SARAM, low 64K: the stack (0x400) */
    RAMH0D    : origin = 0x3F9A00, length = 0x000600   /* H0 SARAM (last 1.5K), zero-wait: state */
    XRAM      : origin = 0x100000, length = 0x010000   /* XINTF zone 6: external SRAM (board fact) */
}
