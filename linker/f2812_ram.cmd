/*
 * f2812_ram.cmd - RAM image for debugging with the user's emulator (loaded by CCS/UniFlash into
 * SARAM, nothing written to flash). Boot mode "jump to H0" (GPIOF4,F12,F3,F2 = 0,0,1,0: fact sheet
 * 1.5) or start at f2812_code_start from the debugger. Link with f2812_regs.cmd.
 *
 *   codestart  H0 0x3F8000 (the H0 boot entry)
 *   ramfuncs   the rest of H0 (8190 words), LOAD = RUN: hal_init()'s copy finds load == run
 *   ramfuncs_h the fixed-point core, the induction-machine law and the application
 *              (libdtc_fixmath.a, libdtc_im.a, libdtc_app.a): L1 (4K words), LOAD = RUN
 *   .text/.cinit/.econst (start-up code, RTS, constants outside the firmware library)  L0 (3K)
 *   .ebss      the last 1K words of L0
 *   .stack     M0 + M1 (low 64K)
 *   opdata     the operation layer's data in external RAM on XINTF zone 6 (as in f2812_flash.cmd)
 * Every block is zero-wait SARAM, so timing equals the flash build's ISR timing. The control path
 * (the whole firmware library) gets the largest block, H0, as in the flash build it gets L0+L1,
 * and the fixed-point core L1 (4K words; 7K in the flash build): hal/f2812/budget.sh checks the
 * smaller figures.
 */
MEMORY
{
PAGE 0:    /* program */
    BEGINH0   : origin = 0x3F8000, length = 0x000002   /* boot-to-H0 entry */
    RAMH0     : origin = 0x3F8002, length = 0x001FFE   /* H0 SARAM: ramfuncs */
    RAML0     : origin = 0x008000, length = 0x000C00   /* L0 SARAM: start-up code, constants */
    RAML1     : origin = 0x009000, length = 0x001000   /* L1 SARAM: ramfuncs_h */
    RESET     : origin = 0x3FFFC0, length = 0x000002
PAGE 1:    /* data */
    RAMM0M1   : origin = 0x000000, length = 0x000800   /* M0 + M1, low 64K: stack */
    RAML0D    : origin = 0x008C00, length = 0x000400   /* L0 (last 1K): controller state */
    XRAM      : origin = 0x100000, length = 0x010000   /* XINTF zone 6: external SRAM (board fact) */
}

/* The IM image's third code block (ramfuncs_m, f2812_flash_im.cmd) does not exist here: its copy
 * (hal_init, f2812_target.h f2812_ramfuncs_copy) moves no word. */
_f2812_ramfuncs_m_load_start = 0;
_f2812_ramfuncs_m_load_end = 0;
_f2812_ramfuncs_m_run_start = 0;

SECTIONS
{
    /* Control path first, so the library-member specifications claim the firmware's sections
     * before the generic rules below. */
    ramfuncs  : {
                    *(ramfuncs)
                    -l=libdtc_firmware.a (.text)
                    -l=libdtc_firmware.a (.econst)
                    -l=libdtc_firmware.a (.switch)
                }
                > RAMH0,
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
                > RAML1,
                LOAD_START(_f2812_ramfuncs_h_load_start),
                LOAD_END(_f2812_ramfuncs_h_load_end),
                RUN_START(_f2812_ramfuncs_h_run_start),
                PAGE = 0

    codestart : > BEGINH0, PAGE = 0
    .text     : > RAML0,   PAGE = 0
    .cinit    : > RAML0,   PAGE = 0
    .pinit    : > RAML0,   PAGE = 0
    .switch   : > RAML0,   PAGE = 0
    .econst   : > RAML0,   PAGE = 0

    .stack    : > RAMM0M1, PAGE = 1
    opdata    : {
                    -l=libdtc_proto.a (.ebss)
                    -l=libdtc_comm.a (.ebss)
                }
                > XRAM,    PAGE = 1
    .ebss     : > RAML0D,  PAGE = 1
    .esysmem  : > RAML0D,  PAGE = 1

    .reset    : > RESET,   PAGE = 0, TYPE = DSECT
}
