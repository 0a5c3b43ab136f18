; f2812_codestart.asm - first code executed after the boot ROM's "boot to flash" jump.
;
; The boot ROM branches to 0x3F7FF6 (fact sheet 1.1, 1.5), where linker/f2812_flash.cmd places the
; section "codestart": two words, one long branch. The watchdog is on after reset with a ~4.4 ms
; timeout, and C auto-initialisation (.cinit) can take longer, so the watchdog is disabled here
; (WDCR <- 0x0068: WDDIS = 1 with the mandatory WDCHK = 101b, fact sheet 1.4, 4.4) before the C
; run-time start-up _c_int00 (COFF ABI name) runs and calls main(). main() re-enables it.
; The RAM build places the same section at the start of H0 (0x3F8000, "boot to H0").

WDCR_ADDR       .set    0x7029
WDCR_DISABLE    .set    0x0068

        .ref    _c_int00
        .def    f2812_code_start

        .sect   "codestart"
f2812_code_start:
        LB      f2812_wd_disable        ; 2 words: fills 0x3F7FF6..0x3F7FF7

        .text
f2812_wd_disable:
        SETC    OBJMODE                 ; C28x object mode (the boot ROM leaves C27x mode)
        EALLOW
        MOVZ    DP, #(WDCR_ADDR >> 6)
        MOV     @(WDCR_ADDR & 0x3F), #WDCR_DISABLE
        EDIS
        LB      _c_int00
