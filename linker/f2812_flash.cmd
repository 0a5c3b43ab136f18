/*
 * f2812_flash.cmd - stand-alone flash image of the PM drive for the TMS320F2812 (target dtc_f2812,
 * the application of DTC_LAWS; boot mode "jump to flash", GPIOF4 = 1, the default through its
 * pull-up: fact sheet 1.5). Link with f2812_flash_mem.cmd (the memory map, from
 * ../shared/reference/f2812-facts.md 1.1-1.4) and f2812_regs.cmd. COFF ABI (C symbol X is _X
 * here), large memory model (.ebss/.econst). The IM image's is f2812_flash_im.cmd, the same
 * layout with its own lists.
 *
 * Placement by function: the ISR's hot functions (cl2000 --gen_func_subsections: one section
 * `.text:_NAME` per function, target/f2812/CMakeLists.txt) are named in three zero-wait blocks,
 * chosen by measurement with hal/f2812/hot_functions.py --image pm (callgrind inside app_isr on
 * the shipped PM scenarios: what runs every period or at the speed loop's rate; the lists between
 * the hot: markers are written by it); everything else of the control archives runs from flash
 * with its wait states (RANDWAIT = PAGEWAIT = 5 at 150 MHz, fact sheet 4.7), which
 * tools/pil/pil_profile.py --ram-cmd linker/f2812_flash.cmd counts per ISR. Placing whole
 * archives filled L0+L1 and H0 to 95-97 % by the pessimistic estimate and .ebss to 97 %
 * (hal/f2812/budget.sh), with no room for a change.
 *
 * Where things run
 *   codestart   BEGIN 0x3F7FF6: the long branch the boot ROM jumps to (f2812_codestart.asm)
 *   ramfuncs    loaded in flash, copied by hal_init() into L0+L1 (8K words, zero-wait) and run
 *               there: the HAL's ramfuncs (the ADC ISR glue, hal_read/hal_write/hal_gates_off, the
 *               PDPINTA ISR, the flash wait-state set-up, which must not run from flash), the hot
 *               functions of the first list (with the operation layer's ISR part, the capture's
 *               recording and the fault log's record) and the control archives' constant tables
 *               (.econst, .switch: the ISR reads them)
 *   ramfuncs_h  the same into H0's first 6.5K words: the second list
 *   ramfuncs_m  the same into M1 (1K words): the third list; the stack (--stack_size 0x400) has M0
 *   .ebss       H0's last 1.5K words (zero-wait): the controller state
 *   .stack      M0 (low 64K: the SP is 16 bits, fact sheet 1.1)
 *   opdata      the operation layer's data (libdtc_proto.a, libdtc_comm.a: the capture buffer, the
 *               fault log, the frame decoder's ring and the frames, the stored-set buffer, the
 *               configuration copy a parameter write is checked on; ~2.4K words, printed by
 *               hal/f2812/budget.sh) in external RAM on XINTF zone 6 (0x100000, fact sheet 1.1):
 *               the zero-wait blocks are the ISR path's, its state's and the stack's, and this
 *               data is the background's, except the capture's samples and the fault log's
 *               entries, which the ISR writes at the XINTF's wait states. BOARD FACT, UNVERIFIED:
 *               the Spectrum Digital eZdsp F2812 fits 64K words of SRAM on zone 6; a board without
 *               it must give opdata another block (docs/operate.md, "Where the operation layer's
 *               data lives").
 *   the rest    flash sectors J..C: the control code not named below (the start-up, the
 *               calibration, the faults' paths, rare branches), the configuration's validation,
 *               the laws' init, the application's init and background calls, the commissioning,
 *               the protocol. Sector B is left free for the user's parameter storage; sector A
 *               holds only codestart and the CSM words.
 * The CSM password words (0x3F7FF8..0x3F7FFF) and CSM_RSVD are deliberately NOT written: erased
 * flash (0xFFFF) leaves the device unsecured. Never program the password to all zeros.
 */
/* MEMORY: f2812_flash_mem.cmd (the blocks this file names) */

SECTIONS
{
    /* The hot functions by name before the generic .text rule claims them; the tables of the
     * control archives with them. Copied flash -> RAM by hal_init() before any of it is called. */
    ramfuncs  : {
                    *(ramfuncs)
                    /* hot:ramfuncs begin (hal/f2812/hot_functions.py --write) */
                    *(.text:_app_core_step)
                    *(.text:_capture_isr_run)
                    *(.text:_dtc_step)
                    *(.text:_faultlog_record)
                    /* hot:ramfuncs end */
                    -l=libdtc_firmware.a (.econst)
                    -l=libdtc_firmware.a (.switch)
                    -l=libdtc_fixmath.a (.econst)
                    -l=libdtc_fixmath.a (.switch)
                    -l=libdtc_im.a (.econst)
                    -l=libdtc_im.a (.switch)
                    -l=libdtc_app.a (.econst)
                    -l=libdtc_app.a (.switch)
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
                    *(.text:_app_core_latch)
                    *(.text:_app_enc_check)
                    *(.text:_app_fault_one_way)
                    *(.text:_app_fault_open_phase)
                    *(.text:_app_fault_stall)
                    *(.text:_app_fault_trips)
                    *(.text:_app_isr)
                    *(.text:_app_plaus_step)
                    *(.text:_app_pwm_encode)
                    *(.text:_calibrate_step)
                    *(.text:_check_hw_trip)
                    *(.text:_check_trips)
                    *(.text:_deadtime_apply)
                    *(.text:_deadtime_code)
                    *(.text:_deadtime_leg)
                    *(.text:_dtc_dcsupp_in)
                    *(.text:_dtc_handover)
                    *(.text:_dtc_lpf_r)
                    *(.text:_dtc_pol_mid)
                    *(.text:_dtc_predict_in)
                    *(.text:_dtc_reset_currents)
                    *(.text:_dtc_speed_gains)
                    *(.text:_dtc_vmid_beta)
                    *(.text:_fix_add32)
                    *(.text:_fix_sector6)
                    *(.text:_fix_sincos)
                    *(.text:_fix_sub32)
                    *(.text:_flux_est_cm_surface)
                    *(.text:_flux_est_reset)
                    *(.text:_flux_est_seed)
                    *(.text:_hyst2_init)
                    *(.text:_hyst3_init)
                    *(.text:_iq_mpy)
                    *(.text:_iq_recip_newton)
                    *(.text:_law_enc_angle)
                    *(.text:_law_i_pred)
                    *(.text:_law_reset)
                    *(.text:_law_speed_ref)
                    *(.text:_law_speed_ref_ptr)
                    *(.text:_law_step)
                    *(.text:_law_warnings)
                    *(.text:_plaus_judge)
                    *(.text:_q32_integrate)
                    *(.text:_speed_meas_reset)
                    *(.text:_speed_meas_step)
                    *(.text:_speed_pi_reset)
                    *(.text:_speed_pi_step)
                    *(.text:_swtab_null_choice)
                    *(.text:_swtab_rot6)
                    *(.text:_swtab_sstp_basic)
                    *(.text:_swtab_sstp_legs)
                    *(.text:_vcomp_leg_drop_lin)
                    *(.text:_vcomp_points_pos)
                    *(.text:_vcomp_step_lin)
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
                    *(.text:_calibrate_finish)
                    *(.text:_dtc_reset)
                    *(.text:_hyst2_sq_bounds)
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
                    -l=libdtc_proto.a (.ebss)
                    -l=libdtc_comm.a (.ebss)
                }
                > XRAM,    PAGE = 1
    .ebss     : > RAMH0D,  PAGE = 1
    .esysmem  : > RAMH0D,  PAGE = 1   /* the firmware allocates nothing; heap size 0 */

    .reset    : > RESET,   PAGE = 0, TYPE = DSECT   /* the boot ROM owns the reset vector */
}
