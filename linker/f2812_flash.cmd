/*
 * f2812_flash.cmd - stand-alone flash image for the TMS320F2812 (boot mode "jump to flash",
 * GPIOF4 = 1, the default through its pull-up: fact sheet 1.5). Link with f2812_regs.cmd.
 * Written for this project from the memory map in ../shared/reference/f2812-facts.md 1.1-1.4;
 * COFF ABI (C symbol X is _X here), large memory model (.ebss/.econst).
 *
 * Where things run
 *   codestart   BEGIN 0x3F7FF6: the long branch the boot ROM jumps to (target/f2812/f2812_codestart.asm)
 *   ramfuncs    loaded in flash, copied at start-up by hal_init() into L0+L1 (8K words, zero-wait)
 *               and run there: the ADC ISR glue, hal_read/hal_write/hal_gates_off, the PDPINTA ISR,
 *               the flash wait-state set-up (must not run from flash), and ALL of the control
 *               firmware's shared blocks, PM law and small IM blocks (libdtc_firmware.a: code and
 *               its fixed-point tables), so the 50 us path never waits on flash (5 wait states at 150 MHz, fact
 *               sheet 4.7). The configuration's validation (libdtc_config.a) runs at init only
 *               and stays in flash (.text), as do the application's init and background calls
 *               (libdtc_app_init.a), the parameters by id, the commissioning and the calibration's
 *               rotor hold (libdtc_app_flash.a: ISR parts that run only in place of the law) and
 *               the serial protocol (libdtc_proto.a, libdtc_comm.a: the
 *               capture and the fault log that the ISR calls run from flash too, docs/operate.md).
 *   ramfuncs_h  the same for the fixed-point core, the induction-machine law and the application
 *               (libdtc_fixmath.a, libdtc_im.a, libdtc_app.a), copied into the first 7K words of
 *               H0: the ISR path has 15K words of
 *               zero-wait RAM, not 8K.
 *   .stack      M0+M1 (low 64K: the SP is 16 bits, fact sheet 1.1)
 *   .ebss       the last 1K words of H0 (zero-wait): controller state
 *   opdata      the operation layer's data (libdtc_proto.a, libdtc_comm.a: the capture buffer, the
 *               fault log, the frame decoder's ring and the frames, the stored-set buffer, the
 *               configuration copy a parameter write is checked on; ~2.4K words, printed by
 *               hal/f2812/budget.sh) in external RAM on XINTF zone 6 (0x100000, fact sheet 1.1):
 *               every zero-wait block is taken by the ISR path and its state (L0+L1, H0 by the
 *               pessimistic estimate) or the stack (M0+M1), and this data is the background's,
 *               except the capture's samples and the fault log's entries, which the ISR writes at
 *               the XINTF's wait states (a few words per sample while a capture records, one
 *               entry per fault). BOARD FACT, UNVERIFIED: the Spectrum Digital eZdsp F2812 fits
 *               64K words of SRAM on zone 6; a board without it must give opdata another block
 *               (docs/operate.md, "Where the operation layer's data lives").
 *   the rest    flash sectors J..C. Sector B is left free for the user's parameter storage;
 *               sector A holds only codestart and the CSM words.
 * The CSM password words (0x3F7FF8..0x3F7FFF) and CSM_RSVD are deliberately NOT written: erased
 * flash (0xFFFF) leaves the device unsecured. Never program the password to all zeros.
 */
MEMORY
{
PAGE 0:    /* program */
    RAML0L1   : origin = 0x008000, length = 0x002000   /* L0 + L1 SARAM, zero-wait: ramfuncs run */
    RAMH0P    : origin = 0x3F8000, length = 0x001C00   /* H0 SARAM (first 7K), zero-wait: ramfuncs_h */
    FLASH_JC  : origin = 0x3D8000, length = 0x01C000   /* sectors J, I, H, G, F, E, D, C */
    FLASHB    : origin = 0x3F4000, length = 0x002000   /* sector B: free (user parameters) */
    FLASHA    : origin = 0x3F6000, length = 0x001F80   /* sector A below the CSM words: free */
    CSM_RSVD  : origin = 0x3F7F80, length = 0x000076   /* zeros only when the CSM is used */
    BEGIN     : origin = 0x3F7FF6, length = 0x000002   /* boot-to-flash entry */
    CSM_PWL   : origin = 0x3F7FF8, length = 0x000008   /* CSM password: left erased */
    RESET     : origin = 0x3FFFC0, length = 0x000002   /* boot ROM's reset vector */
PAGE 1:    /* data */
    RAMM0M1   : origin = 0x000000, length = 0x000800   /* M0 + M1 SARAM, low 64K */
    RAMH0D    : origin = 0x3F9C00, length = 0x000400   /* H0 SARAM (last 1K), zero-wait: state */
    XRAM      : origin = 0x100000, length = 0x010000   /* XINTF zone 6: external SRAM (board fact) */
}

SECTIONS
{
    /* Control path first: the library-member specifications must claim the firmware's sections
     * before the generic .text/.econst rules below. Copied flash -> RAM by hal_init() before any
     * of it is called. The archive is named as CMake builds it (firmware/libdtc_firmware.a; the
     * link adds --search_path for it). */
    ramfuncs  : {
                    *(ramfuncs)
                    -l=libdtc_firmware.a (.text)
                    -l=libdtc_firmware.a (.econst)
                    -l=libdtc_firmware.a (.switch)
                }
                LOAD = FLASH_JC,
                RUN = RAML0L1,
                LOAD_START(_f2812_ramfuncs_load_start),
                LOAD_END(_f2812_ramfuncs_load_end),
                RUN_START(_f2812_ramfuncs_run_start),
                PAGE = 0

    ramfuncs_h : {
                    -l=libdtc_fixmath.a (.text)
                    -l=libdtc_fixmath.a (.econst)
                    -l=libdtc_fixmath.a (.switch)
                    -l=libdtc_im.a (.text)
                    -l=libdtc_im.a (.econst)
                    -l=libdtc_im.a (.switch)
                    -l=libdtc_app.a (.text)
                    -l=libdtc_app.a (.econst)
                    -l=libdtc_app.a (.switch)
                }
                LOAD = FLASH_JC,
                RUN = RAMH0P,
                LOAD_START(_f2812_ramfuncs_h_load_start),
                LOAD_END(_f2812_ramfuncs_h_load_end),
                RUN_START(_f2812_ramfuncs_h_run_start),
                PAGE = 0

    codestart : > BEGIN,    PAGE = 0
    .text     : > FLASH_JC, PAGE = 0
    .cinit    : > FLASH_JC, PAGE = 0
    .pinit    : > FLASH_JC, PAGE = 0
    .switch   : > FLASH_JC, PAGE = 0
    .econst   : > FLASH_JC, PAGE = 0   /* flash, PAGE 0 (TI note for flash programmers) */

    .stack    : > RAMM0M1, PAGE = 1
    /* the operation layer's data before the generic .ebss rule claims it: uninitialised, its
     * init calls (app_proto_start) set it up */
    opdata    : {
                    -l=libdtc_proto.a (.ebss)
                    -l=libdtc_comm.a (.ebss)
                }
                > XRAM,    PAGE = 1
    .ebss     : > RAMH0D,  PAGE = 1
    .esysmem  : > RAMH0D,  PAGE = 1   /* the firmware allocates nothing; heap size 0 */

    .reset    : > RESET,   PAGE = 0, TYPE = DSECT   /* the boot ROM owns the reset vector */
}
