/*
 * f2812_flash_im.cmd - stand-alone flash image of the induction-machine drive for the TMS320F2812
 * (target dtc_f2812_im: the IM-only application libdtc_app_im.a; boot mode "jump to flash",
 * GPIOF4 = 1). Link with f2812_flash_mem.cmd (the memory map, from
 * ../shared/reference/f2812-facts.md 1.1-1.4) and f2812_regs.cmd. COFF ABI (C symbol X is _X
 * here), large memory model.
 *
 * The layout is the PM image's (f2812_flash.cmd: placement by function) with the IM image's
 * archives and lists. The IM law's code (five schemes, the estimator, the start-up, the flux
 * weakening) is about 14K words nominal and 21K pessimistic on the cross-cm0 proxy (hal/f2812/
 * budget.sh --im), more than the zero-wait RAM holds, so only the ISR's hot functions are named
 * (cl2000 --gen_func_subsections: one section `.text:_NAME` per function, target/f2812/
 * CMakeLists.txt), chosen by measurement with hal/f2812/hot_functions.py --image im (callgrind
 * inside app_isr on the shipped IM scenario, every IM scheme, and the Cortex-M0 replay's counts:
 * what runs every period or at the speed loop's rate; the lists between the hot: markers are
 * written by it), and everything else of the control archives runs from flash with its wait states
 * (RANDWAIT = PAGEWAIT = 5 at 150 MHz, fact sheet 4.7), which tools/pil/pil_profile.py --ram-cmd
 * linker/f2812_flash_im.cmd counts per ISR.
 *
 * Where things run
 *   codestart   BEGIN 0x3F7FF6: the long branch the boot ROM jumps to (f2812_codestart.asm)
 *   ramfuncs    loaded in flash, copied by hal_init() into L0+L1 (8K words, zero-wait) and run
 *               there: the HAL's ramfuncs (the ADC ISR glue, hal_read/hal_write/hal_gates_off, the
 *               PDPINTA ISR, the flash wait-state set-up), the hot functions of the first list and
 *               the control archives' constant tables (.econst, .switch: the ISR reads them)
 *   ramfuncs_h  the same into H0's first 6.5K words: the hot functions of the second list
 *   ramfuncs_m  the same into M1 (1K words): the third list; the stack (--stack_size 0x400) has M0
 *   .ebss       H0's last 1.5K words (zero-wait): the controller state, about 1.2K words with the
 *               IM law (law_t with im_dtc_t, the application): more than a 1K-word .ebss, so H0 is
 *               split 6.5K code / 1.5K state (budget.sh --im checks both with its 5 % margin)
 *   .stack      M0 (low 64K: the SP is 16 bits, fact sheet 1.1)
 *   opdata      the operation layer's data in external RAM on XINTF zone 6, as in f2812_flash.cmd
 *               (BOARD FACT, UNVERIFIED: 64K words of SRAM on zone 6 of the eZdsp F2812)
 *   the rest    flash sectors J..C: the control code not named below (the start-up, the other
 *               schemes' rare paths, the faults' paths), the init and validation code, the
 *               protocol. Sector B is left free for the user's parameter storage.
 * The CSM password words are deliberately NOT written (erased flash leaves the device unsecured).
 */
/* MEMORY: f2812_flash_mem.cmd (the blocks this file names) */

SECTIONS
{
    /* The hot functions by name before the generic .text rule claims them; the tables of the
     * control archives with them. Copied flash -> RAM by hal_init() before any of it is called. */
    ramfuncs  : {
                    *(ramfuncs)
                    /* hot:ramfuncs begin (hal/f2812/hot_functions.py --write) */
                    *(.text:_app_core_latch)
                    *(.text:_app_core_step)
                    *(.text:_app_fault_open_phase)
                    *(.text:_app_fault_stall)
                    *(.text:_app_fault_trips)
                    *(.text:_capture_isr_run)
                    *(.text:_check_hw_trip)
                    *(.text:_clarke_sstp)
                    *(.text:_hyst2_init)
                    *(.text:_hyst3_init)
                    *(.text:_ilim_select)
                    *(.text:_im_dfoc_id_ref)
                    *(.text:_im_dsvm_select)
                    *(.text:_im_dsvm_step)
                    *(.text:_im_dtc_refs)
                    *(.text:_im_dtc_select)
                    *(.text:_im_est_reset)
                    *(.text:_im_fw_reset)
                    *(.text:_im_speed_reset)
                    *(.text:_im_sup_step)
                    *(.text:_law_pwm)
                    *(.text:_speed_meas_reset)
                    /* hot:ramfuncs end */
                    -l=libdtc_firmware.a (.econst)
                    -l=libdtc_firmware.a (.switch)
                    -l=libdtc_fixmath.a (.econst)
                    -l=libdtc_fixmath.a (.switch)
                    -l=libdtc_im.a (.econst)
                    -l=libdtc_im.a (.switch)
                    -l=libdtc_app_im.a (.econst)
                    -l=libdtc_app_im.a (.switch)
                }
                LOAD = FLASH_JC,
                RUN = RAML0L1,
                LOAD_START(_f2812_ramfuncs_load_start),
                LOAD_END(_f2812_ramfuncs_load_end),
                RUN_START(_f2812_ramfuncs_run_start),
                PAGE = 0

    ramfuncs_h : {
                    /* hot:ramfuncs_h begin (hal/f2812/hot_functions.py --write) */
                    *(.text:_app_adc_to_pu)
                    *(.text:_app_core_convert)
                    *(.text:_app_enc_check)
                    *(.text:_app_enc_flux_check)
                    *(.text:_app_fault_one_way)
                    *(.text:_app_isr)
                    *(.text:_app_plaus_step)
                    *(.text:_app_pwm_encode)
                    *(.text:_check_trips)
                    *(.text:_deadtime_error)
                    *(.text:_deadtime_leg)
                    *(.text:_dsc_step)
                    *(.text:_dsvm_leg_duty)
                    *(.text:_dsvm_rotate)
                    *(.text:_faultlog_record)
                    *(.text:_fix_add32)
                    *(.text:_fix_isqrt_rnd)
                    *(.text:_fix_polar_begin)
                    *(.text:_fix_polar_end)
                    *(.text:_fix_polar_iter)
                    *(.text:_fix_sector6)
                    *(.text:_fix_sub32)
                    *(.text:_ilim_over)
                    *(.text:_im_dtc_enc_plaus)
                    *(.text:_im_dtc_estimate)
                    *(.text:_im_dtc_i_pred)
                    *(.text:_im_dtc_speed_tick)
                    *(.text:_im_dtc_step)
                    *(.text:_im_psir_trim)
                    *(.text:_im_sfvc_kpd)
                    *(.text:_im_speed_lpf)
                    *(.text:_im_speed_step)
                    *(.text:_im_sup_cm_ref)
                    *(.text:_iq_mag)
                    *(.text:_iq_mpy)
                    *(.text:_law_i_pred)
                    *(.text:_law_speed_ref)
                    *(.text:_law_speed_ref_ptr)
                    *(.text:_law_warnings)
                    *(.text:_plaus_judge)
                    *(.text:_speed_meas_step)
                    *(.text:_speed_pi_step)
                    *(.text:_svm_leg_dt)
                    *(.text:_svm_legs)
                    *(.text:_swtab_null_choice)
                    *(.text:_swtab_rot6)
                    *(.text:_swtab_sstp_basic)
                    *(.text:_swtab_sstp_legs)
                    *(.text:_swtab_sstp_st)
                    *(.text:_vcomp_tab_step)
                    *(.text:_vrec_from_legs)
                    /* hot:ramfuncs_h end */
                }
                LOAD = FLASH_JC,
                RUN = RAMH0P,
                LOAD_START(_f2812_ramfuncs_h_load_start),
                LOAD_END(_f2812_ramfuncs_h_load_end),
                RUN_START(_f2812_ramfuncs_h_run_start),
                PAGE = 0

    ramfuncs_m : {
                    /* hot:ramfuncs_m begin (hal/f2812/hot_functions.py --write) */
                    *(.text:_im_est_flux)
                    *(.text:_law_reset)
                    *(.text:_law_step)
                    *(.text:_svm_reset)
                    /* hot:ramfuncs_m end */
                }
                LOAD = FLASH_JC,
                RUN = RAMM1P,
                LOAD_START(_f2812_ramfuncs_m_load_start),
                LOAD_END(_f2812_ramfuncs_m_load_end),
                RUN_START(_f2812_ramfuncs_m_run_start),
                PAGE = 0

    codestart : > BEGIN,    PAGE = 0
    .text     : > FLASH_JC, PAGE = 0
    .cinit    : > FLASH_JC, PAGE = 0
    .pinit    : > FLASH_JC, PAGE = 0
    .switch   : > FLASH_JC, PAGE = 0
    .econst   : > FLASH_JC, PAGE = 0   /* flash, PAGE 0 (TI note for flash programmers) */

    .stack    : > RAMM0,   PAGE = 1   /* --stack_size=0x400: all of M0 */
    opdata    : {
                    -l=libdtc_proto_im.a (.ebss)
                    -l=libdtc_comm.a (.ebss)
                }
                > XRAM,    PAGE = 1
    .ebss     : > RAMH0D,  PAGE = 1
    .esysmem  : > RAMH0D,  PAGE = 1   /* the firmware allocates nothing; heap size 0 */

    .reset    : > RESET,   PAGE = 0, TYPE = DSECT   /* the boot ROM owns the reset vector */
}
