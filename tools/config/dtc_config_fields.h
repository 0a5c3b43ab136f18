/*
 * dtc_config_fields.h - every field of dtc_config_t (firmware/dtc/dtc_config.h), part by part, as
 * X-macro lists: the common part (DTC_CONFIG_COMMON_FIELDS) and one list per law's part of the
 * union u (DTC_CONFIG_PM_DTC_FIELDS for u.pm_dtc, DTC_CONFIG_IM_FIELDS for u.im,
 * DTC_CONFIG_PM_ITC_FIELDS for u.pm_itc). The C emitter
 * (dtc_config_emit_c), the round-trip check and the ISR recording's configuration blob
 * (hal/replay/pil_format.c, also built for the PIL targets) walk the common list and the list of
 * the configuration's law, so a field added to the struct and here is emitted, checked and
 * replayed. Macros only.
 *
 *   DTC_CFG_PART(part)              opens a part (a member struct of dtc_config_t)
 *   DTC_CFG_U(part, name)           unsigned integer
 *   DTC_CFG_IQ(part, name)          iq_t, printed with its pu value
 *   DTC_CFG_Q31(part, name)         q31_t gain
 *   DTC_CFG_Q15(part, name)         q15_t
 *   DTC_CFG_ARR3(part, name)        uint16_t[3]
 *   DTC_CFG_END(part)               closes it
 * Nested parts use a dotted path (u.pm_dtc.machine); the emitter opens and closes them by name.
 */
#define DTC_CONFIG_COMMON_FIELDS(P, U, IQ, Q31, Q15, ARR3, END)                                    \
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
    END(machine)                                                                                  \
    P(est)                                                                                        \
    U(est, estimator) U(est, compensation) Q31(est, k_in_q31) Q31(est, k_leak_q31)                 \
    U(est, deadtime_comp)                                                                         \
    END(est)                                                                                      \
    P(speed)                                                                                      \
    U(speed, mode) U(speed, sensor) U(speed, speed_div) IQ(speed, speed_k_iq)                      \
    U(speed, speed_min_counts) IQ(speed, kp_iq) IQ(speed, ki_ts_iq) IQ(speed, torque_limit_iq)     \
    Q15(speed, torque_trim_k_q15) IQ(speed, speed_limit_iq) IQ(speed, flux_ref_iq)                 \
    IQ(speed, speed_ref_iq) IQ(speed, torque_ref_iq)                                               \
    END(speed)

/* u.pm_dtc (law DTC_LAW_PM_DTC). */
#define DTC_CONFIG_PM_DTC_FIELDS(P, U, IQ, Q31, Q15, ARR3, END)                                    \
    U(u.pm_dtc, part)                                                                             \
    P(u.pm_dtc.sw)                                                                                \
    U(u.pm_dtc.sw, sstp_table) IQ(u.pm_dtc.sw, flux_band_iq) IQ(u.pm_dtc.sw, torque_band_iq)       \
    END(u.pm_dtc.sw)                                                                              \
    P(u.pm_dtc.est)                                                                               \
    U(u.pm_dtc.est, delay_comp) U(u.pm_dtc.est, polarity_mid) U(u.pm_dtc.est, lpf_comp)            \
    U(u.pm_dtc.est, dc_supp) IQ(u.pm_dtc.est, handover_speed_iq) IQ(u.pm_dtc.est, handover_hyst_iq) \
    IQ(u.pm_dtc.est, wc_pu_iq) IQ(u.pm_dtc.est, lpf_wmin_iq) IQ(u.pm_dtc.est, dcs_k_iq)            \
    IQ(u.pm_dtc.est, vmid_g_iq) IQ(u.pm_dtc.est, vmid_beta_s_iq)                                  \
    END(u.pm_dtc.est)                                                                             \
    P(u.pm_dtc.machine)                                                                           \
    IQ(u.pm_dtc.machine, ls_iq) IQ(u.pm_dtc.machine, psi_m_iq) IQ(u.pm_dtc.machine, inv_ls_iq)     \
    END(u.pm_dtc.machine)

/* u.im (laws DTC_LAW_IM_DTC .. DTC_LAW_IM_DSVM). */
#define DTC_CONFIG_IM_FIELDS(P, U, IQ, Q31, Q15, ARR3, END)                                        \
    U(u.im, part)                                                                                 \
    P(u.im.machine)                                                                               \
    IQ(u.im.machine, rr_iq) IQ(u.im.machine, sigma_ls_iq) IQ(u.im.machine, sigma_lr_iq)            \
    IQ(u.im.machine, kr_iq) IQ(u.im.machine, ks_iq) IQ(u.im.machine, inv_ks_iq)                    \
    IQ(u.im.machine, m_iq)                                                                        \
    END(u.im.machine)                                                                             \
    P(u.im.est)                                                                                   \
    Q31(u.im.est, k_lo_q31) Q31(u.im.est, k_hi_q31) IQ(u.im.est, w_lo_iq) IQ(u.im.est, w_hi_iq)    \
    Q31(u.im.est, k_slope_q31)                                                                    \
    END(u.im.est)                                                                                 \
    P(u.im.sw)                                                                                    \
    U(u.im.sw, sstp_table) IQ(u.im.sw, flux_band_iq) IQ(u.im.sw, torque_band_iq)                   \
    END(u.im.sw)                                                                                  \
    IQ(u.im, table_speed_iq)                                                                      \
    P(u.im.fw)                                                                                    \
    U(u.im.fw, on) U(u.im.fw, window) IQ(u.im.fw, step_down_iq) IQ(u.im.fw, step_up_iq)            \
    IQ(u.im.fw, psi_min_iq) IQ(u.im.fw, inv_psi_rated_iq) IQ(u.im.fw, kt_iq)                       \
    END(u.im.fw)                                                                                  \
    P(u.im.ref)                                                                                   \
    IQ(u.im.ref, psir_ref_iq) IQ(u.im.ref, inv_psir_ref_iq) IQ(u.im.ref, inv_psir_sq_iq)           \
    IQ(u.im.ref, gain_w_iq) Q31(u.im.ref, speed_filt_q31) U(u.im.ref, magn_periods)               \
    IQ(u.im.ref, magn_ramp_iq) Q31(u.im.ref, magn_k_q31)                                          \
    END(u.im.ref)                                                                                 \
    U(u.im, svm_mode)                                                                             \
    P(u.im.sfvc)                                                                                  \
    IQ(u.im.sfvc, kp_iq)                                                                          \
    END(u.im.sfvc)                                                                                \
    P(u.im.dfoc)                                                                                  \
    IQ(u.im.dfoc, kp_iq) IQ(u.im.dfoc, ki_ts_iq) IQ(u.im.dfoc, id_ref_iq) IQ(u.im.dfoc, iq_per_t_iq) \
    END(u.im.dfoc)                                                                                \
    P(u.im.dsvm)                                                                                  \
    IQ(u.im.dsvm, torque_band2_iq)                                                                \
    END(u.im.dsvm)

/* u.pm_itc (law DTC_LAW_PM_ITC). */
#define DTC_CONFIG_PM_ITC_FIELDS(P, U, IQ, Q31, Q15, ARR3, END)                                    \
    U(u.pm_itc, part)                                                                             \
    P(u.pm_itc.cc)                                                                                \
    IQ(u.pm_itc.cc, kp_iq) IQ(u.pm_itc.cc, ki_ts_iq) IQ(u.pm_itc.cc, iq_per_t_iq)                  \
    END(u.pm_itc.cc)                                                                              \
    P(u.pm_itc.mid)                                                                               \
    IQ(u.pm_itc.mid, g_iq) IQ(u.pm_itc.mid, kf_iq)                                                 \
    END(u.pm_itc.mid)                                                                             \
    P(u.pm_itc.est)                                                                               \
    U(u.pm_itc.est, lpf_comp) IQ(u.pm_itc.est, wc_pu_iq) IQ(u.pm_itc.est, lpf_wmin_iq)             \
    END(u.pm_itc.est)                                                                             \
    P(u.pm_itc.machine)                                                                           \
    IQ(u.pm_itc.machine, ls_iq) IQ(u.pm_itc.machine, psi_m_iq) IQ(u.pm_itc.machine, inv_ls_iq)     \
    END(u.pm_itc.machine)
