// firmware_si.cpp - the scenario's firmware configuration in SI units (tools/config
// dtc_config_si_t), as the SIL runner hands it to the converter, and the converter's refusals
// named by scenario key (the keys column of tools/config/dtc_si_params.h).
#include "firmware_si.hpp"
#include "sil_constants.hpp"

#include <cmath>
#include <cstring>

extern "C" {
#include "dtc_si_params.h"
#include "plant_defaults.h"
}

namespace sil {

namespace {

int topology_of(Topology t)
{
    return t == Topology::Fstp ? DTC_TOPO_FSTP : DTC_TOPO_SSTP;
}

int compensation_of(Compensation c, Topology t)
{
    switch (c) {
    case Compensation::None: return DTC_COMP_NONE;
    case Compensation::Simple: return t == Topology::Fstp ? DTC_COMP_FSTP_SIMPLE : DTC_COMP_SSTP;
    case Compensation::Proposed: return t == Topology::Fstp ? DTC_COMP_FSTP_PROPOSED : DTC_COMP_SSTP_PROPOSED;
    }
    return DTC_COMP_NONE;
}

int estimator_of(Estimator e)
{
    switch (e) {
    case Estimator::Voltage: return DTC_EST_VOLTAGE;
    case Estimator::Current: return DTC_EST_CURRENT;
    case Estimator::Improved: return DTC_EST_IMPROVED;
    }
    return DTC_EST_CURRENT;
}

// SwitchingTable lists the tables in the order of enum dtc_sstp_table.
static_assert(static_cast<int>(SwitchingTable::Basic) == DTC_ST_BASIC && static_cast<int>(SwitchingTable::StA) == DTC_ST_A &&
                  static_cast<int>(SwitchingTable::StB) == DTC_ST_B && static_cast<int>(SwitchingTable::StC) == DTC_ST_C &&
                  static_cast<int>(SwitchingTable::StD) == DTC_ST_D &&
                  static_cast<int>(SwitchingTable::SpeedDependent) == DTC_ST_SPEED,
              "SwitchingTable follows enum dtc_sstp_table");

} // namespace

dtc_config_si_t firmware_si_config(const Scenario& sc)
{
    dtc_config_si_t si;
    dtc_config_si_defaults(&si);
    const MotorCfg& m = sc.motor;
    const InverterCfg& inv = sc.inverter;
    const ControlCfg& c = sc.control;
    // Per-unit bases (firmware/dtc/dtc_base.h): nominal DC link, rated peak current, rated
    // electrical speed.
    si.v_base_v = inv.vdc_v;
    si.i_base_a = m.rated_current_a;
    // The pole pairs and the encoder offset as the firmware believes them (firmware.*, dtc-sil identify).
    const std::int64_t pole_pairs = sc.firmware.pole_pairs.value_or(m.pole_pairs);
    si.w_base_rad_s = m.rated_speed_rpm * kPi / 30.0 * static_cast<double>(pole_pairs);
    // Machine and inverter as the firmware believes them: the plant's values here, the
    // firmware.* keys given override them at the end.
    si.rs_ohm = m.rs_ohm;
    si.ls_h = m.ls_h;
    // L_q: the plant's, unless the firmware was given its own L_d (firmware.ls_h): then a surface
    // PM's (0 = ls_h) unless firmware.lq_h says otherwise, so that no plant value joins a belief.
    si.lq_h = sc.firmware.value.count("ls_h") != 0 ? 0.0 : m.lq_h;
    si.psi_m_wb = m.psi_m_wb;
    si.pole_pairs = static_cast<int>(pole_pairs);
    si.rated_speed_rpm = m.rated_speed_rpm;
    si.rated_torque_nm = m.rated_torque_nm;
    si.rated_current_a = m.rated_current_a;
    si.inertia_kgm2 = sc.firmware.j_kgm2.value_or(m.j_kgm2);
    // Inverter, timing.
    si.topology = topology_of(inv.topology);
    si.vdc_v = inv.vdc_v;
    si.v_ce_v = inv.v_ce_v;
    si.v_d_v = inv.v_d_v;
    si.v_f_v = c.v_f_v;
    si.r_on_ohm = inv.r_on_ohm;
    si.fstp_vmid_measured = sc.sensors.vmid_fitted ? 1 : 0;
    si.ts_s = sc.ts_s;
    si.speed_div = static_cast<int>(c.speed_loop_divider);
    // Encoder: hal_host counts 0 where theta_m + offset = 0, i.e. the electrical angle at count 0
    // is -p * offset (the firmware is told the true mounting offset).
    // Reversed (sensors.encoder_reversed: hal_host counts -theta_m), the electrical angle at count 0
    // is +p * offset: firmware.encoder_offset_rad is in the same sense as the plant's key.
    const bool reversed = sc.firmware.encoder_reversed.value_or(sc.sensors.encoder_reversed);
    si.enc_lines = static_cast<int>(sc.firmware.encoder_lines.value_or(sc.sensors.encoder_lines));
    si.enc_reversed = reversed ? 1 : 0;
    si.enc_offset_rad = (reversed ? 1.0 : -1.0) * static_cast<double>(pole_pairs) *
                        sc.firmware.encoder_offset_rad.value_or(sc.sensors.encoder_offset_rad);
    // Control: the converter designs the PI from the bandwidth with the same rule as
    // speed_pi_gains() (crossover wc, PI zero at wc/4); the gains are also given explicitly.
    si.flux_band_wb = c.flux_band_wb;
    si.torque_band_nm = c.torque_band_nm;
    si.lpf_cutoff_rad_s = c.lpf_cutoff_rad_s;
    si.handover_auto = c.handover_given ? 0 : 1;
    si.handover_speed_rpm = c.handover_rpm;
    si.handover_hyst_frac = c.handover_hyst_frac;
    si.delay_comp = c.delay_comp ? 1 : 0;
    si.deadtime_comp = c.deadtime_comp ? 1 : 0;
    // The gate driver's setting (inverter.dead_time_s, also when the plant does not model it).
    si.dead_time_s = inv.dead_time_s;
    si.pi_from_bandwidth = 1;
    si.speed_bw_rad_s = 2.0 * kPi * c.speed_bw_hz;
    const SpeedPiGains g = speed_pi_gains(m.j_kgm2, c.speed_bw_hz);
    si.kp_nm_s_rad = g.kp_nm_per_rad_s;
    si.ki_nm_rad = g.ki_nm_per_rad;
    si.torque_limit_nm = c.torque_limit_nm;
    si.speed_limit_rpm = std::fmax(si.speed_limit_rpm, std::fabs(c.speed_ref_rpm));
    si.flux_ref_wb = c.flux_ref_wb;
    si.speed_ref_rpm = c.speed_ref_rpm;
    si.torque_ref_nm = c.torque_ref_nm;
    si.estimator = estimator_of(c.estimator);
    si.compensation = compensation_of(c.compensation, inv.topology);
    si.sstp_table = static_cast<int>(c.table);
    si.mode = c.mode == ControlMode::Torque ? DTC_MODE_TORQUE : DTC_MODE_SPEED;
    // The sensing chain of hal_host (hal_host_sensors.hpp) seen from the firmware: 12-bit codes
    // over 0..3 V; currents -range..+range around mid-scale, voltages 0..range. The firmware
    // calibrates the current offsets itself at start-up with the gates off; 2048 is its start.
    si.adc_i_a_per_count = 2.0 * sc.sensors.current_range_a / PLANT_DEF_ADC_FULL_SCALE_CODES;
    for (int ph = 0; ph < 3; ++ph) {
        si.adc_i_offset[ph] = 2048;
    }
    si.adc_vdc_v_per_count = sc.sensors.voltage_range_v / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si.adc_vdc_offset = 0;
    si.adc_vmid_v_per_count = sc.sensors.voltage_range_v / PLANT_DEF_ADC_FULL_SCALE_CODES;
    si.adc_vmid_offset = 0;
    si.i_trip_a = sc.protection.overcurrent_a;
    si.overspeed_rpm = sc.protection.overspeed_rpm; // 0: derived (dtc_overspeed_default_rpm), < 0: off
    si.stall_time_s = sc.protection.stall_time_s;
    si.vdc_max_v = sc.protection.vdc_max_v;
    si.vdc_min_v = sc.protection.vdc_min_v;
    si.current_limit_auto = c.current_limit_given ? 0 : 1;
    si.current_limit_a = c.current_limit_a;
    si.polarity_mid = c.polarity_mid ? 1 : 0;
    si.vmid_cal = c.vmid_cal ? 1 : 0;
    si.cal_hold = c.cal_hold ? 1 : 0;
    si.fault_detect = c.fault_detect ? 1 : 0;
    si.i_sensors3 = sc.sensors.current_sensors == 3 ? 1 : 0;
    si.reconfig_relay = inv.reconfig_relay ? 1 : 0;
    si.relay_delay_s = inv.relay_delay_s;
    si.lpf_comp = c.lpf_comp ? 1 : 0;
    si.dc_supp = c.dc_supp ? 1 : 0;
    si.c_dc_f = inv.c_dc_f;
    if (m.type != MotorType::Im && c.scheme == Scheme::Itc) {
        si.law = DTC_LAW_PM_ITC; // indirect torque control (firmware/dtc/itc.h); gains from the machine
    }
    if (m.type == MotorType::Im) {
        // Induction-machine law (Casadei 2006): the plant's machine (firmware.* below), no magnet, none of the PM law's start-up hand-over or
        // actuation-delay prediction (im_dtc.h).
        si.rr_ohm = m.rr_ohm;
        si.lls_h = m.lls_h;
        si.llr_h = m.llr_h;
        si.lm_h = m.lm_h;
        si.ls_h = 0.0;
        si.lq_h = 0.0;
        si.psi_m_wb = 0.0;
        si.handover_auto = 0;
        si.handover_speed_rpm = 0.0;
        si.delay_comp = 0;
        // Flux weakening reaches 400 % of base speed (Casadei Fig. 32): the speed reference's
        // limit covers it.
        si.speed_limit_rpm = std::fmax(4.0 * m.rated_speed_rpm, std::fabs(c.speed_ref_rpm));
        // control.scheme with the motor type is the one enum dtc_law
        si.law = c.scheme == Scheme::Dsc    ? DTC_LAW_IM_DSC
                 : c.scheme == Scheme::Sfvc ? DTC_LAW_IM_SFVC
                 : c.scheme == Scheme::Dfoc ? DTC_LAW_IM_DFOC
                 : c.scheme == Scheme::Dsvm ? DTC_LAW_IM_DSVM
                                            : DTC_LAW_IM_DTC;
        si.carrier_hz = c.scheme == Scheme::Sfvc || c.scheme == Scheme::Dfoc ? c.carrier_hz : 0.0;
        si.svm_mode = c.modulation == Modulation::TwoPhase ? 1 : 0;
        si.sfvc_kp_per_s = c.sfvc_kp_per_s;
        si.dfoc_bw_hz = c.dfoc_bw_hz;
        si.dfoc_zeta = c.dfoc_zeta;
        si.dsvm_torque_band2_nm = c.dsvm_torque_band2_nm;
        si.speed_sensor = c.speed_sensor == SpeedSensor::None ? DTC_SPEED_NONE : DTC_SPEED_ENCODER;
        si.flux_weakening = c.flux_weakening ? 1 : 0;
        si.psir_ref_wb = c.rotor_flux_ref_wb;
        si.tau_lo_s = c.observer_tau_s;
        si.tau_hi_s = c.observer_tau_high_s > 0.0 ? c.observer_tau_high_s : c.observer_tau_s;
        si.tau_w_lo_rpm = c.observer_tau_lo_rpm;
        si.tau_w_hi_rpm = c.observer_tau_hi_rpm;
        si.magn_frac = c.magnetise_frac;
        si.rr_track = c.rr_tracking ? 1 : 0;
        si.cm_ref = c.current_model_ref ? 1 : 0;
        si.table_speed_rpm = c.table_speed_rpm;
    }
    // The firmware.* keys given (the belief rows of dtc_si_params.h): the firmware's own values.
    for (const auto& [name, value] : sc.firmware.value) {
        if (const dtc_si_param_t* p = dtc_si_param_find(name.c_str()); p != nullptr && p->type == DTC_SIP_DOUBLE) {
            std::memcpy(reinterpret_cast<char*>(&si) + p->offset, &value, sizeof value);
        }
    }
    return si;
}

std::string keys_of_refusal(const dtc_si_error_t& err)
{
    const dtc_si_param_t* p = err.field != nullptr ? dtc_si_param_find(err.field) : nullptr;
    return p != nullptr ? p->keys : "";
}

} // namespace sil
