/*
 * dtc_si_params.h - the SI inputs of the configuration converter (dtc_config_si_t,
 * dtc_config_si.h), described once: member, type, unit, plain range, owning law(s), the
 * converter's error code, the scenario key(s) that set it, the plant key a firmware.* belief key
 * falls back to, and one line of meaning. Host code.
 *
 * Derived from it: the converter's plain range checks (dtc_si_params_check, the first refusal in
 * row order wins; relations between fields stay in the converter's code), the field a refusal
 * carries (dtc_si_error_t.field is a row's name), the scenario keys a refusal names
 * (tools/sil), the firmware.* scenario keys (tools/sil scenario_schema.cpp: unit, range, help) and
 * the SI table of docs/firmware-core.md (dtc_config_gen --si-params-doc).
 *
 * One row: X(name, type, unit, lo, hi, bounds, laws, when, err, keys, belief, meaning)
 *   name    the dtc_config_si_t member
 *   type    DTC_SIP_DOUBLE, DTC_SIP_INT, DTC_SIP_INT3 (int[3], each element checked)
 *   unit    SI unit ("" for counts, flags and enums)
 *   lo, hi  the plain range's ends (+-DTC_SIP_INF: open-ended)
 *   bounds  DTC_SIP_ANY (any finite value: only relations apply), DTC_SIP_CLOSED [lo, hi],
 *           DTC_SIP_LO_OPEN (lo, hi], DTC_SIP_HI_OPEN [lo, hi), DTC_SIP_OPEN (lo, hi),
 *           DTC_SIP_FLAG (0 or 1), DTC_SIP_ENUM (the integers lo..hi)
 *   laws    the enum dtc_law values whose conversion checks it (DTC_SIP_ALL, _PM, _IM, ...)
 *   when    DTC_SIP_ALWAYS, or the switch under which the value is used (e.g. the PI gains only
 *           when they are not derived from the bandwidth)
 *   err     the enum dtc_si_err code of a refusal
 *   keys    the scenario key(s) the SIL runner sets it from ("" = the converter's default)
 *   belief  a firmware.* scenario key (the value the firmware believes about the machine or the
 *           inverter): the plant key it falls back to when not given; NULL otherwise
 *   meaning one line
 */
#ifndef DTC_SI_PARAMS_H
#define DTC_SI_PARAMS_H

#include <stddef.h>
#include <stdio.h>

#include "dtc_config_si.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DTC_SIP_INF 1e300

enum dtc_sip_type { DTC_SIP_DOUBLE, DTC_SIP_INT, DTC_SIP_INT3 };
enum dtc_sip_bounds {
    DTC_SIP_ANY,
    DTC_SIP_CLOSED,
    DTC_SIP_LO_OPEN,
    DTC_SIP_HI_OPEN,
    DTC_SIP_OPEN,
    DTC_SIP_FLAG,
    DTC_SIP_ENUM
};
enum dtc_sip_when {
    DTC_SIP_ALWAYS,
    DTC_SIP_IF_HANDOVER_GIVEN, /* handover_auto == 0 */
    DTC_SIP_IF_ILIM_GIVEN,     /* current_limit_auto == 0 */
    DTC_SIP_IF_PI_BW,          /* pi_from_bandwidth != 0 */
    DTC_SIP_IF_PI_GAINS,       /* pi_from_bandwidth == 0 */
    DTC_SIP_IF_RELAY           /* reconfig_relay == 1 */
};

#define DTC_SIP_LAW(l) (1U << (l))
#define DTC_SIP_ALL ((1U << DTC_LAW_COUNT) - 1U)
#define DTC_SIP_PM (DTC_SIP_LAW(DTC_LAW_PM_DTC) | DTC_SIP_LAW(DTC_LAW_PM_ITC))
#define DTC_SIP_IM                                                                                  \
    (DTC_SIP_LAW(DTC_LAW_IM_DTC) | DTC_SIP_LAW(DTC_LAW_IM_DSC) | DTC_SIP_LAW(DTC_LAW_IM_SFVC) |    \
     DTC_SIP_LAW(DTC_LAW_IM_DFOC) | DTC_SIP_LAW(DTC_LAW_IM_DSVM))
#define DTC_SIP_IM_SVM (DTC_SIP_LAW(DTC_LAW_IM_SFVC) | DTC_SIP_LAW(DTC_LAW_IM_DFOC))
#define DTC_SIP_IM_SFVC DTC_SIP_LAW(DTC_LAW_IM_SFVC)
#define DTC_SIP_IM_DSVM DTC_SIP_LAW(DTC_LAW_IM_DSVM)
#define DTC_SIP_IM_DFOC DTC_SIP_LAW(DTC_LAW_IM_DFOC)

/* clang-format off */
#define DTC_SI_PARAMS(X) \
    X(law, DTC_SIP_INT, "", 0, DTC_LAW_COUNT - 1, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.scheme, motor.type", NULL, "the control law: enum dtc_law (machine, law and scheme)") \
    X(v_base_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_BASE, "inverter.vdc_v", NULL, "per-unit voltage base (the nominal DC link)") \
    X(i_base_a, DTC_SIP_DOUBLE, "A", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_BASE, "motor.rated_current_a", NULL, "per-unit current base (the rated peak current)") \
    X(w_base_rad_s, DTC_SIP_DOUBLE, "rad/s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_BASE, "motor.rated_speed_rpm, motor.pole_pairs", NULL, "per-unit electrical speed base (the rated speed)") \
    X(rs_ohm, DTC_SIP_DOUBLE, "ohm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.rs_ohm or firmware.rs_ohm (per unit of inverter.vdc_v / motor.rated_current_a)", "motor.rs_ohm", "stator resistance the firmware uses (PM: voltage model, prediction; IM: both estimators)") \
    X(ls_h, DTC_SIP_DOUBLE, "H", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_PM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.ls_h or firmware.ls_h (per unit of inverter.vdc_v, motor.rated_current_a, motor.rated_speed_rpm)", "motor.ls_h", "PM: inductance the firmware uses (current model, prediction)") \
    X(lq_h, DTC_SIP_DOUBLE, "H", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_PM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.lq_h or firmware.lq_h (0: ls_h)", "firmware.ls_h when that is given, else motor.lq_h", "PM: q-axis inductance L_q the firmware uses (salient current model, prediction, ITC decoupling); 0 = ls_h, a surface PM") \
    X(psi_m_wb, DTC_SIP_DOUBLE, "Wb", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_PM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.psi_m_wb or firmware.psi_m_wb (per unit of inverter.vdc_v / rated electrical speed)", "motor.psi_m_wb", "PM: magnet flux linkage the firmware uses (current model, hand-over)") \
    X(pole_pairs, DTC_SIP_INT, "", 1, 16, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.pole_pairs", NULL, "pole pairs") \
    X(rated_speed_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.rated_speed_rpm", NULL, "rated (mechanical) speed") \
    X(rated_torque_nm, DTC_SIP_DOUBLE, "N*m", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.rated_torque_nm", NULL, "rated torque") \
    X(rated_current_a, DTC_SIP_DOUBLE, "A", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.rated_current_a", NULL, "rated peak phase current") \
    X(inertia_kgm2, DTC_SIP_DOUBLE, "kg*m^2", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_IF_PI_BW, DTC_SI_ERR_GAIN, "motor.j_kgm2", NULL, "inertia the speed PI is designed for (pi_from_bandwidth)") \
    X(rr_ohm, DTC_SIP_DOUBLE, "ohm", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.rr_ohm or firmware.rr_ohm", "motor.rr_ohm", "IM: rotor resistance the firmware uses (the slip of Casadei eq. 16: sensorless speed, SFVC; the start-up's rotor time constant)") \
    X(lls_h, DTC_SIP_DOUBLE, "H", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.lls_h or firmware.lls_h", "motor.lls_h", "IM: stator leakage inductance the firmware uses") \
    X(llr_h, DTC_SIP_DOUBLE, "H", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.llr_h or firmware.llr_h", "motor.llr_h", "IM: rotor leakage inductance the firmware uses") \
    X(lm_h, DTC_SIP_DOUBLE, "H", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_MACHINE, "motor.lm_h or firmware.lm_h", "motor.lm_h", "IM: magnetising inductance the firmware uses") \
    X(topology, DTC_SIP_INT, "", DTC_TOPO_SSTP, DTC_TOPO_FSTP, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "inverter.topology", NULL, "inverter: enum dtc_topology (SSTP, FSTP)") \
    X(vdc_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "inverter.vdc_v", NULL, "nominal DC-link voltage") \
    X(v_ce_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "inverter.v_ce_v or firmware.v_ce_v", "inverter.v_ce_v", "transistor drop the compensation assumes") \
    X(v_d_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "inverter.v_d_v or firmware.v_d_v", "inverter.v_d_v", "diode drop the compensation assumes") \
    X(v_f_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "control.v_f_v", NULL, "equal drop of the simple compensations (SSTP [29], Hoang Table V)") \
    X(r_on_ohm, DTC_SIP_DOUBLE, "ohm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "inverter.r_on_ohm or firmware.r_on_ohm", "inverter.r_on_ohm", "on-state resistance the compensation assumes") \
    X(fstp_vmid_measured, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "sensors.vmid_fitted", NULL, "1: the FSTP's capacitor mid-point voltage is measured") \
    X(ts_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_TIMING, "ts_s", NULL, "control period") \
    X(speed_div, DTC_SIP_INT, "", 1, 1000, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_TIMING, "control.speed_loop_divider", NULL, "the speed loop runs every speed_div-th period") \
    X(enc_lines, DTC_SIP_INT, "", 1, 16383, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ENCODER, "sensors.encoder_lines", NULL, "encoder lines per turn (4 lines * 4 counts fit 16 bits)") \
    X(enc_offset_rad, DTC_SIP_DOUBLE, "rad", -DTC_SIP_INF, DTC_SIP_INF, DTC_SIP_ANY, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ENCODER, "sensors.encoder_offset_rad", NULL, "electrical angle at encoder count 0") \
    X(enc_reversed, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ENCODER, "sensors.encoder_reversed or firmware.encoder_reversed", NULL, "1: the count runs down for forward rotation of the field (a reversed encoder or two motor leads exchanged)") \
    X(speed_min_counts, DTC_SIP_INT, "", 1, 16000, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ENCODER, "", NULL, "speed window: the shortest holding at least this many counts") \
    X(flux_band_wb, DTC_SIP_DOUBLE, "Wb", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_BAND, "control.flux_band_wb", NULL, "flux hysteresis band (full width)") \
    X(torque_band_nm, DTC_SIP_DOUBLE, "N*m", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_BAND, "control.torque_band_nm", NULL, "torque hysteresis band (full width)") \
    X(lpf_cutoff_rad_s, DTC_SIP_DOUBLE, "rad/s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_CUTOFF, "control.lpf_cutoff_rad_s", NULL, "voltage model's low-pass cut-off (a pure integrator drifts); below pi/ts_s") \
    X(handover_auto, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_HANDOVER, "control.handover_rpm", NULL, "1: the hand-over speed is derived (dtc_handover_default_rpm)") \
    X(handover_speed_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_IF_HANDOVER_GIVEN, DTC_SI_ERR_HANDOVER, "control.handover_rpm, control.handover_hyst_frac", NULL, "PM: current model below it, voltage model above (0 = voltage model from standstill)") \
    X(handover_hyst_frac, DTC_SIP_DOUBLE, "", 0, 1, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_HANDOVER, "control.handover_rpm, control.handover_hyst_frac", NULL, "back to the current model below (1 - frac) times the hand-over speed") \
    X(delay_comp, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_DELAY, "control.delay_comp", NULL, "1: actuation-delay compensation (comparators on the k+1 prediction)") \
    X(deadtime_comp, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_DEADTIME, "control.deadtime_comp", NULL, "1: dead-time compensation of the reconstructed voltage") \
    X(dead_time_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_DEADTIME, "inverter.dead_time_s (or firmware.dead_time_s) against ts_s", "inverter.dead_time_s", "dead time the dead-time compensation assumes; below ts_s / 2") \
    X(pi_from_bandwidth, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_GAIN, "", NULL, "1: the speed PI's gains from speed_bw_rad_s and inertia_kgm2") \
    X(speed_bw_rad_s, DTC_SIP_DOUBLE, "rad/s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_IF_PI_BW, DTC_SI_ERR_GAIN, "control.speed_bw_hz", NULL, "speed-loop crossover (PI zero at a quarter of it)") \
    X(kp_nm_s_rad, DTC_SIP_DOUBLE, "N*m*s/rad", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_IF_PI_GAINS, DTC_SI_ERR_GAIN, "", NULL, "speed PI proportional gain, per mechanical rad/s") \
    X(ki_nm_rad, DTC_SIP_DOUBLE, "N*m/rad", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_IF_PI_GAINS, DTC_SI_ERR_GAIN, "", NULL, "speed PI integral gain, per mechanical rad/s per s") \
    X(torque_limit_nm, DTC_SIP_DOUBLE, "N*m", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "control.torque_limit_nm", NULL, "torque limit of the speed PI's output") \
    X(torque_trim_tau_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_GAIN, "", NULL, "torque mode: mean-torque trim time constant, longer than ts_s (0 = off)") \
    X(stall_time_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_GAIN, "protection.stall_time_s (with ts_s, control.speed_loop_divider)", NULL, "speed mode: stall fault after this long at the torque limit (0 = derived; 20..65535 speed periods)") \
    X(speed_limit_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "control.speed_ref_rpm", NULL, "limit of the speed reference") \
    X(flux_ref_wb, DTC_SIP_DOUBLE, "Wb", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_REFERENCE, "control.flux_ref_wb", NULL, "stator-flux reference") \
    X(speed_ref_rpm, DTC_SIP_DOUBLE, "rpm", -DTC_SIP_INF, DTC_SIP_INF, DTC_SIP_ANY, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_REFERENCE, "control.speed_ref_rpm", NULL, "speed reference, within speed_limit_rpm") \
    X(torque_ref_nm, DTC_SIP_DOUBLE, "N*m", -DTC_SIP_INF, DTC_SIP_INF, DTC_SIP_ANY, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_REFERENCE, "control.torque_ref_nm", NULL, "torque reference (torque mode), within torque_limit_nm") \
    X(psir_ref_wb, DTC_SIP_DOUBLE, "Wb", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.rotor_flux_ref_wb", NULL, "IM: constant rotor flux (Casadei eq. 19); 0: from flux_ref_wb") \
    X(tau_lo_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.observer_tau_s", NULL, "IM: improved estimator's tau at low speed (Casadei eq. 20), longer than ts_s") \
    X(tau_hi_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.observer_tau_high_s", NULL, "IM: its tau at high speed (Casadei section 10.2), longer than ts_s") \
    X(tau_w_lo_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.observer_tau_lo_rpm, control.observer_tau_hi_rpm", NULL, "IM: |speed| up to which tau_lo_s applies") \
    X(tau_w_hi_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.observer_tau_hi_rpm, control.observer_tau_lo_rpm", NULL, "IM: |speed| from which tau_hi_s applies, at least tau_w_lo_rpm") \
    X(speed_sensor, DTC_SIP_INT, "", DTC_SPEED_ENCODER, DTC_SPEED_NONE, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.speed_sensor", NULL, "enum dtc_speed_sensor (encoder; none: IM only)") \
    X(table_speed_rpm, DTC_SIP_DOUBLE, "rpm", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.table_speed_rpm", NULL, "IM, DTC_ST_SPEED: ST-D below, ST-A above (0 = derived)") \
    X(speed_filter_s, DTC_SIP_DOUBLE, "s", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "ts_s, control.speed_loop_divider", NULL, "IM sensorless: speed filter time constant, longer than the speed period") \
    X(rr_track, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.rr_tracking", NULL, "IM, encoder: the slip uses the rotor resistance tracked on line and r_s follows it (firmware/dtc/im_sup.h)") \
    X(cm_ref, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.current_model_ref", NULL, "IM, encoder, improved estimator (not DSVM): Casadei eq. 20's reference from the rotor-flux current model at low speed (firmware/dtc/im_sup.h)") \
    X(magn_frac, DTC_SIP_DOUBLE, "", 0, 1, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.magnetise_frac (with motor.rr_ohm, motor.llr_h, motor.lm_h, ts_s)", NULL, "IM start-up: torque once the rotor flux reaches this fraction of its reference") \
    X(flux_weakening, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.flux_weakening", NULL, "IM: 1 = flux weakening (Casadei section 12)") \
    X(fw_window, DTC_SIP_INT, "", 20, 65535, DTC_SIP_CLOSED, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.flux_weakening", NULL, "IM: control periods per flux-reference decision (section 12.3: at least 20)") \
    X(fw_step_frac, DTC_SIP_DOUBLE, "", 0, 1, DTC_SIP_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.flux_weakening", NULL, "IM: flux-reference step per decision, fraction of flux_ref_wb") \
    X(fw_psi_min_frac, DTC_SIP_DOUBLE, "", 0, 1, DTC_SIP_LO_OPEN, DTC_SIP_IM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.flux_weakening", NULL, "IM: lowest flux reference, fraction of flux_ref_wb") \
    X(carrier_hz, DTC_SIP_DOUBLE, "Hz", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM_SVM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.carrier_hz, ts_s", NULL, "IM SFVC, DFOC: SVM carrier, equal to 1/ts_s (0 = 1/ts_s)") \
    X(svm_mode, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_IM_SVM, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.modulation", NULL, "IM SFVC, DFOC: enum svm_mode, 0 symmetric, 1 two-phase") \
    X(sfvc_kp_per_s, DTC_SIP_DOUBLE, "1/s", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM_SFVC, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.sfvc_kp_per_s (with ts_s)", NULL, "IM SFVC: flux-regulator gain of Casadei eq. 24, at most 1/ts_s (0 = derived)") \
    X(dfoc_bw_hz, DTC_SIP_DOUBLE, "Hz", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM_DFOC, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.dfoc_bw_hz (with ts_s)", NULL, "IM DFOC: current-loop crossover, below 1/(6 ts_s) (0 = derived, 0.2/ts_s)") \
    X(dfoc_zeta, DTC_SIP_DOUBLE, "", 0, 10, DTC_SIP_CLOSED, DTC_SIP_IM_DFOC, DTC_SIP_ALWAYS, DTC_SI_ERR_IM, "control.dfoc_zeta (with control.dfoc_bw_hz, motor.rs_ohm)", NULL, "IM DFOC: 0 = the PI zero on the stator pole; > 0 = both poles at w_c with this damping") \
    X(dsvm_torque_band2_nm, DTC_SIP_DOUBLE, "N*m", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_IM_DSVM, DTC_SIP_ALWAYS, DTC_SI_ERR_BAND, "control.dsvm_torque_band2_nm", NULL, "IM DSVM: outer torque band (full width), at least torque_band_nm (0 = derived)") \
    X(estimator, DTC_SIP_INT, "", DTC_EST_VOLTAGE, DTC_EST_IMPROVED, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.estimator", NULL, "enum dtc_estimator (voltage; current: PM; improved: IM)") \
    X(compensation, DTC_SIP_INT, "", DTC_COMP_NONE, DTC_COMP_SSTP_PROPOSED, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.compensation", NULL, "enum dtc_compensation, one available on the topology") \
    X(sstp_table, DTC_SIP_INT, "", DTC_ST_BASIC, DTC_ST_SPEED, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.table", NULL, "enum dtc_sstp_table (DTC_ST_SPEED: IM only)") \
    X(mode, DTC_SIP_INT, "", DTC_MODE_SPEED, DTC_MODE_TORQUE, DTC_SIP_ENUM, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_VARIANT, "control.mode", NULL, "enum dtc_mode (speed, torque)") \
    X(adc_i_a_per_count, DTC_SIP_DOUBLE, "A", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "sensors.current_range_a (per unit of motor.rated_current_a)", NULL, "phase-current ADC gain per count") \
    X(adc_i_offset, DTC_SIP_INT3, "", 0, 4095, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "", NULL, "phase-current ADC codes at zero current (nominal; calibrated at start-up)") \
    X(adc_vdc_v_per_count, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "sensors.voltage_range_v (per unit of inverter.vdc_v)", NULL, "DC-link ADC gain per count") \
    X(adc_vdc_offset, DTC_SIP_INT, "", 0, 4095, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "", NULL, "DC-link ADC code at 0 V") \
    X(adc_vmid_v_per_count, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "sensors.voltage_range_v (per unit of inverter.vdc_v)", NULL, "FSTP mid-point ADC gain per count") \
    X(adc_vmid_offset, DTC_SIP_INT, "", 0, 4095, DTC_SIP_CLOSED, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ADC, "", NULL, "FSTP mid-point ADC code at 0 V") \
    X(i_trip_a, DTC_SIP_DOUBLE, "A", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "protection.overcurrent_a", NULL, "firmware over-current trip on |i|") \
    X(vdc_max_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "protection.vdc_max_v, protection.vdc_min_v", NULL, "DC-link over-voltage trip, above vdc_min_v") \
    X(vdc_min_v, DTC_SIP_DOUBLE, "V", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "protection.vdc_min_v, protection.vdc_max_v", NULL, "DC-link under-voltage trip") \
    X(current_limit_auto, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ILIM, "control.current_limit_a", NULL, "1: the current limit is derived (dtc_ilim_default_a)") \
    X(current_limit_a, DTC_SIP_DOUBLE, "A", 0, DTC_SIP_INF, DTC_SIP_HI_OPEN, DTC_SIP_ALL, DTC_SIP_IF_ILIM_GIVEN, DTC_SI_ERR_ILIM, "control.current_limit_a (derived from protection.overcurrent_a, inverter.vdc_v, motor.*, ts_s, control.delay_comp)", NULL, "current-limit override on |i|, below i_trip_a (0 = off)") \
    X(polarity_mid, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ILIM, "control.polarity_mid", NULL, "1: drops averaged over the period's current, dead-time polarity at the switching instant") \
    X(lpf_comp, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_CUTOFF, "control.lpf_comp", NULL, "voltage model: 1 = low-pass gain and phase correction") \
    X(dc_supp, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_CUTOFF, "control.dc_supp", NULL, "voltage model: 1 = DC-current suppression (and the FSTP mid-point regulation)") \
    X(c_dc_f, DTC_SIP_DOUBLE, "F", 0, DTC_SIP_INF, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_INVERTER, "inverter.c_dc_f", NULL, "each split DC-link capacitor") \
    X(vmid_cal, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ILIM, "control.vmid_cal", NULL, "FSTP, mid-point measured: 1 = calibrated against V_dc/2 before the start") \
    X(cal_hold, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_ILIM, "control.cal_hold (the hold current is derived from control.torque_limit_nm, motor.psi_m_wb and the current limit)", NULL, "with vmid_cal: 1 = the rotor is held by a phase-B/C current meanwhile") \
    X(i_sensors3, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "sensors.current_sensors", NULL, "1: all three phase currents measured (their sum is checked)") \
    X(fault_detect, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "control.fault_detect", NULL, "1: open-phase and lost-encoder detection") \
    X(reconfig_relay, DTC_SIP_INT, "", 0, 1, DTC_SIP_FLAG, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "inverter.reconfig_relay", NULL, "1: a relay per phase ties a failed leg's phase to the mid-point") \
    X(relay_delay_s, DTC_SIP_DOUBLE, "s", 0, 1, DTC_SIP_OPEN, DTC_SIP_ALL, DTC_SIP_IF_RELAY, DTC_SI_ERR_LIMIT, "inverter.relay_delay_s", NULL, "the relay's closing time") \
    X(overspeed_rpm, DTC_SIP_DOUBLE, "rpm", -DTC_SIP_INF, DTC_SIP_INF, DTC_SIP_ANY, DTC_SIP_ALL, DTC_SIP_ALWAYS, DTC_SI_ERR_LIMIT, "protection.overspeed_rpm", NULL, "overspeed trip above speed_limit_rpm (0 = derived, < 0 = off)")
/* clang-format on */

/* One row of DTC_SI_PARAMS, with the member's offset in dtc_config_si_t. */
typedef struct {
    const char *name;
    int type;      /* enum dtc_sip_type */
    const char *unit;
    double lo, hi;
    int bounds;    /* enum dtc_sip_bounds */
    unsigned laws; /* DTC_SIP_LAW bits */
    int when;      /* enum dtc_sip_when */
    int err;       /* enum dtc_si_err */
    const char *keys;
    const char *belief;
    const char *meaning;
    size_t offset;
} dtc_si_param_t;

extern const dtc_si_param_t dtc_si_params[];
extern const size_t dtc_si_param_count;

/* The row named name, or NULL. */
const dtc_si_param_t *dtc_si_param_find(const char *name);
/* The row whose name is the leading identifier of label ("ls_h (1/l_s)" -> ls_h), or NULL. */
const dtc_si_param_t *dtc_si_param_of_label(const char *label);
/* 1 when the row's value is checked and used for si (its law and switch), else 0. */
int dtc_si_param_applies(const dtc_si_param_t *p, const dtc_config_si_t *si);
/* 1 when v is inside the row's plain range (finite, within its ends; whole and in range for the
 * integer kinds), else 0. */
int dtc_si_param_in_range(const dtc_si_param_t *p, double v);
/* The plain range as text for messages and docs: "> 0", "[0, 1)", "0 or 1", "1..16", ... */
const char *dtc_si_param_range_text(const dtc_si_param_t *p, char *buf, size_t n);
/* The row's value in si (element k of an int[3]). */
double dtc_si_param_value(const dtc_si_param_t *p, const dtc_config_si_t *si, int k);
/* Writes the SI parameters as a Markdown table (the docs' section between the markers
 * <!-- si-params:begin --> and <!-- si-params:end -->). Returns 0, or -1 on an I/O error. */
int dtc_si_params_markdown(FILE *f);

#ifdef __cplusplus
}
#endif

#endif /* DTC_SI_PARAMS_H */
