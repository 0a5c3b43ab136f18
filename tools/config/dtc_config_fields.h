/*
 * dtc_config_fields.h - every field of dtc_config_t (firmware/dtc/dtc_config.h), part by part, as
 * an X-macro list: the C emitter (dtc_config_emit_c), the round-trip check and the ISR
 * recording's configuration blob (hal/replay/pil_format.c, also built for the PIL targets) walk
 * the same list, so a field added to the struct and here is emitted, checked and replayed.
 * Macros only.
 *
 *   DTC_CFG_PART(part)              opens a part (a member struct of dtc_config_t)
 *   DTC_CFG_U(part, name)           unsigned integer
 *   DTC_CFG_IQ(part, name)          iq_t, printed with its pu value
 *   DTC_CFG_Q31(part, name)         q31_t gain
 *   DTC_CFG_Q15(part, name)         q15_t
 *   DTC_CFG_ARR3(part, name)        uint16_t[3]
 *   DTC_CFG_END(part)               closes it
 * Nested parts use a dotted path (machine.pm); the emitter opens and closes them by name.
 */
#define DTC_CONFIG_FIELDS(P, U, IQ, Q31, Q15, ARR3, END)                                           \
    P(board)                                                                                      \
    U(board, v_base_mv) U(board, i_base_ma) U(board, w_base_mrad_s) U(board, topology)             \
    U(board, fstp_vmid_measured) IQ(board, ts_pu_iq) Q15(board, td_ts_q15) IQ(board, v_f_iq)      \
    IQ(board, v_ce_iq) IQ(board, v_d_iq) IQ(board, r_on_iq) U(board, enc_counts)                   \
    U(board, enc_gain_q16) U(board, enc_offset) IQ(board, adc_i_gain_iq)                           \
    ARR3(board, adc_i_offset) IQ(board, adc_vdc_gain_iq) U(board, adc_vdc_offset)                   \
    IQ(board, adc_vmid_gain_iq) U(board, adc_vmid_offset) U(board, vmid_cal) U(board, i_sensors3)  \
    END(board)                                                                                    \
    P(prot)                                                                                       \
    IQ(prot, i_trip_iq) IQ(prot, vdc_max_iq) IQ(prot, vdc_min_iq) IQ(prot, i_lim_iq)               \
    U(prot, stall_speed_periods) IQ(prot, i_hold_iq) IQ(prot, i_sum_max_iq) IQ(prot, leg_i_min_iq) \
    IQ(prot, enc_freeze_speed_iq) U(prot, relay_periods) U(prot, i_plaus) IQ(prot, overspeed_iq)   \
    END(prot)                                                                                     \
    P(machine)                                                                                    \
    U(machine, pole_pairs) IQ(machine, rs_iq)                                                      \
    P(machine.pm)                                                                                 \
    IQ(machine.pm, ls_iq) IQ(machine.pm, psi_m_iq) IQ(machine.pm, inv_ls_iq)                       \
    END(machine.pm)                                                                               \
    P(machine.im)                                                                                 \
    IQ(machine.im, rr_iq) IQ(machine.im, sigma_ls_iq) IQ(machine.im, sigma_lr_iq)                  \
    IQ(machine.im, kr_iq) IQ(machine.im, ks_iq) IQ(machine.im, inv_ks_iq) IQ(machine.im, m_iq)     \
    END(machine.im)                                                                               \
    END(machine)                                                                                  \
    P(est)                                                                                        \
    U(est, estimator) U(est, compensation) Q31(est, k_in_q31) Q31(est, k_leak_q31)                 \
    IQ(est, handover_speed_iq) IQ(est, handover_hyst_iq) U(est, delay_comp) U(est, deadtime_comp)  \
    U(est, polarity_mid) U(est, lpf_comp) IQ(est, wc_pu_iq) IQ(est, lpf_wmin_iq) U(est, dc_supp)   \
    IQ(est, dcs_k_iq) IQ(est, vmid_g_iq) IQ(est, vmid_beta_s_iq)                                  \
    Q31(est, im_k_lo_q31) Q31(est, im_k_hi_q31) IQ(est, im_w_lo_iq) IQ(est, im_w_hi_iq)           \
    Q31(est, im_k_slope_q31)                                                                      \
    END(est)                                                                                      \
    P(sw)                                                                                         \
    U(sw, sstp_table) U(sw, scheme) IQ(sw, flux_band_iq) IQ(sw, torque_band_iq)                    \
    IQ(sw, im_table_speed_iq) U(sw, im_fw_on) U(sw, im_fw_window) IQ(sw, im_fw_step_down_iq)       \
    IQ(sw, im_fw_step_up_iq) IQ(sw, im_fw_psi_min_iq) IQ(sw, im_fw_inv_psi_rated_iq)              \
    IQ(sw, im_fw_kt_iq) U(sw, svm_mode) IQ(sw, sfvc_kp_iq) IQ(sw, dfoc_kp_iq)                     \
    IQ(sw, dfoc_ki_ts_iq) IQ(sw, dfoc_id_ref_iq) IQ(sw, dfoc_iq_per_t_iq)                         \
    IQ(sw, dsvm_torque_band2_iq)                                                                  \
    END(sw)                                                                                       \
    P(speed)                                                                                      \
    U(speed, mode) U(speed, sensor) U(speed, speed_div) IQ(speed, speed_k_iq)                      \
    U(speed, speed_min_counts) IQ(speed, kp_iq) IQ(speed, ki_ts_iq) IQ(speed, torque_limit_iq)     \
    Q15(speed, torque_trim_k_q15) IQ(speed, speed_limit_iq) IQ(speed, flux_ref_iq)                 \
    IQ(speed, speed_ref_iq) IQ(speed, torque_ref_iq) IQ(speed, psir_ref_iq)                        \
    IQ(speed, inv_psir_ref_iq) IQ(speed, inv_psir_sq_iq) IQ(speed, im_gain_w_iq)                   \
    Q31(speed, im_speed_filt_q31) U(speed, im_magn_periods) IQ(speed, im_magn_ramp_iq)             \
    Q31(speed, im_magn_k_q31)                                                                      \
    END(speed)
