// controller_firmware.cpp - the unchanged firmware (firmware/app + firmware/dtc) as the SIL controller.
//
// The firmware reaches the plant only through hal.h, i.e. the active hal_host::Harness: this
// adapter converts the scenario's SI values with the firmware's own converter (so SIL and a
// target build share one conversion), then calls the application's entry points
// (firmware/app/app.h) once per period, exactly as the DSP's ADC interrupt and background loop
// would, and reads the application status for the trace.
#include <cstdio>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

extern "C" {
#include "app.h"
#include "app_proto.h"
#include "dtc_config_si.h"
#include "pil_format.h"
}

#include "controller_adapter.hpp"
#include "sil_constants.hpp"
#include "hal_host.hpp"

static_assert(sil::kAdcOffsetTolCounts == DTC_ADC_OFFSET_TOL_COUNTS, "sil_constants.hpp follows dtc_config.h");

namespace sil {

namespace {

constexpr double kIqOne = 16777216.0; // 2^FIX_IQ_Q, fixmath.h (iq_t = Q24)

int topology_of(Topology t)
{
    return t == Topology::Fstp ? DTC_TOPO_FSTP : DTC_TOPO_SSTP;
}

int compensation_of(Compensation c, Topology t)
{
    switch (c) {
    case Compensation::None: return DTC_COMP_NONE;
    case Compensation::Simple: return t == Topology::Fstp ? DTC_COMP_FSTP_SIMPLE : DTC_COMP_SSTP;
    case Compensation::Proposed: return DTC_COMP_FSTP_PROPOSED;
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

int table_of(SwitchingTable t)
{
    switch (t) {
    case SwitchingTable::Basic: return DTC_ST_BASIC;
    case SwitchingTable::StA: return DTC_ST_A;
    case SwitchingTable::StB: return DTC_ST_B;
    case SwitchingTable::StC: return DTC_ST_C;
    case SwitchingTable::StD: return DTC_ST_D;
    case SwitchingTable::SpeedDependent: return DTC_ST_SPEED;
    }
    return DTC_ST_BASIC;
}

/// A latched fault's one-line description from the firmware's table (app_fault.h APP_FAULT_LIST,
/// APP_ENC_DETAIL_LIST): the meaning with the detail decoded as its kind says (the phase letter
/// for "%c", the encoder check's own text); "" where the table has none.
std::string app_fault_meaning(std::uint16_t fault, int detail)
{
    struct Row {
        unsigned id;
        int kind;
        const char* meaning;
    };
#define SIL_FAULT_ROW_(id, num, name, kind, meaning) {num, kind, meaning},
    static const Row kFaults[] = {APP_FAULT_LIST(SIL_FAULT_ROW_)};
#undef SIL_FAULT_ROW_
    struct EncRow {
        int detail;
        const char* meaning;
    };
#define SIL_ENC_ROW_(num, meaning) {num, meaning},
    static const EncRow kEncoder[] = {APP_ENC_DETAIL_LIST(SIL_ENC_ROW_)};
    static const EncRow kSensor[] = {APP_SENSOR_DETAIL_LIST(SIL_ENC_ROW_)};
#undef SIL_ENC_ROW_
    const auto phase_letter = [](std::string w, int ph) {
        const std::string::size_type at = w.find("%c");
        if (at != std::string::npos) {
            w.replace(at, 2, ph >= 0 && ph <= 2 ? std::string(1, static_cast<char>('A' + ph)) : "?");
        }
        return w;
    };
    for (const Row& r : kFaults) {
        if (r.id != fault) {
            continue;
        }
        std::string w = r.meaning;
        if (r.kind == APP_DETAIL_ENCODER) {
            for (const EncRow& e : kEncoder) {
                if (e.detail == detail) {
                    w = e.meaning;
                }
            }
        } else if (r.kind == APP_DETAIL_SENSOR) {
            for (const EncRow& e : kSensor) {
                if (detail >= 0 && e.detail == detail / 3) {
                    w = phase_letter(e.meaning, detail % 3);
                }
            }
        } else if (r.kind == APP_DETAIL_PHASE) {
            w = phase_letter(w, detail);
        } else if (r.kind == APP_DETAIL_SIGN && r.id == APP_FAULT_OVERSPEED && detail < 0) {
            w += " (reverse)";
        }
        return w;
    }
    return "";
}

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
    si.w_base_rad_s = m.rated_speed_rpm * kPi / 30.0 * static_cast<double>(m.pole_pairs);
    // Machine as the firmware believes it (firmware.*), the plant's values where not given.
    si.rs_ohm = sc.firmware.rs_ohm.value_or(m.rs_ohm);
    si.ls_h = sc.firmware.ls_h.value_or(m.ls_h);
    si.psi_m_wb = sc.firmware.psi_m_wb.value_or(m.psi_m_wb);
    si.pole_pairs = static_cast<int>(m.pole_pairs);
    si.rated_speed_rpm = m.rated_speed_rpm;
    si.rated_torque_nm = m.rated_torque_nm;
    si.rated_current_a = m.rated_current_a;
    si.inertia_kgm2 = m.j_kgm2;
    // Inverter, timing.
    si.topology = topology_of(inv.topology);
    si.vdc_v = inv.vdc_v;
    si.v_ce_v = sc.firmware.v_ce_v.value_or(inv.v_ce_v);
    si.v_d_v = sc.firmware.v_d_v.value_or(inv.v_d_v);
    si.v_f_v = c.v_f_v;
    si.r_on_ohm = sc.firmware.r_on_ohm.value_or(inv.r_on_ohm);
    si.fstp_vmid_measured = sc.sensors.vmid_fitted ? 1 : 0;
    si.ts_s = sc.ts_s;
    si.speed_div = static_cast<int>(c.speed_loop_divider);
    // Encoder: hal_host counts 0 where theta_m + offset = 0, i.e. the electrical angle at count 0
    // is -p * offset (the firmware is told the true mounting offset).
    si.enc_lines = static_cast<int>(sc.sensors.encoder_lines);
    si.enc_offset_rad = -static_cast<double>(m.pole_pairs) * sc.sensors.encoder_offset_rad;
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
    si.dead_time_s = sc.firmware.dead_time_s.value_or(inv.dead_time_s);
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
    si.sstp_table = table_of(c.table);
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
        // Induction-machine law (Casadei 2006): the machine as the firmware believes it
        // (firmware.*, else the plant's), no magnet, none of the PM law's start-up hand-over or
        // actuation-delay prediction (im_dtc.h).
        si.rr_ohm = sc.firmware.rr_ohm.value_or(m.rr_ohm);
        si.lls_h = sc.firmware.lls_h.value_or(m.lls_h);
        si.llr_h = sc.firmware.llr_h.value_or(m.llr_h);
        si.lm_h = sc.firmware.lm_h.value_or(m.lm_h);
        si.ls_h = 0.0;
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
        si.table_speed_rpm = c.table_speed_rpm;
    }
    return si;
}

namespace {

/// The scenario keys a converter field (dtc_config_si_t) is computed from, so that a refusal
/// names what the user set. Per-unit bases come from the link voltage, rated current and speed.
std::string keys_of_field(const std::string& msg)
{
    static const struct {
        const char* field;
        const char* keys;
    } map[] = {
        {"v_base_v", "inverter.vdc_v"},
        {"i_base_a", "motor.rated_current_a"},
        {"w_base_rad_s", "motor.rated_speed_rpm, motor.pole_pairs"},
        {"rs_ohm", "motor.rs_ohm or firmware.rs_ohm (per unit of inverter.vdc_v / motor.rated_current_a)"},
        {"ls_h", "motor.ls_h or firmware.ls_h (per unit of inverter.vdc_v, motor.rated_current_a, "
                 "motor.rated_speed_rpm)"},
        {"psi_m_wb", "motor.psi_m_wb or firmware.psi_m_wb (per unit of inverter.vdc_v / rated electrical speed)"},
        {"pole_pairs", "motor.pole_pairs"},
        {"rated_", "motor.rated_speed_rpm, motor.rated_torque_nm, motor.rated_current_a"},
        {"vdc_v", "inverter.vdc_v"},
        {"v_ce_v", "inverter.v_ce_v or firmware.v_ce_v"},
        {"v_d_v", "inverter.v_d_v or firmware.v_d_v"},
        {"v_f_v", "control.v_f_v"},
        {"r_on_ohm", "inverter.r_on_ohm or firmware.r_on_ohm"},
        {"ts_s", "ts_s"},
        {"speed_div", "control.speed_loop_divider"},
        {"enc_lines", "sensors.encoder_lines"},
        {"enc_offset_rad", "sensors.encoder_offset_rad"},
        {"flux_band_wb", "control.flux_band_wb"},
        {"torque_band_nm", "control.torque_band_nm"},
        {"dsvm_torque_band2_nm", "control.dsvm_torque_band2_nm"},
        {"lpf_cutoff_rad_s", "control.lpf_cutoff_rad_s"},
        {"torque_limit_nm", "control.torque_limit_nm"},
        {"speed_limit_rpm", "control.speed_ref_rpm"},
        {"i_trip_a", "protection.overcurrent_a"},
        {"stall_time_s", "protection.stall_time_s (with ts_s, control.speed_loop_divider)"},
        {"vdc_min_v", "protection.vdc_min_v, protection.vdc_max_v"},
        {"flux_ref_wb", "control.flux_ref_wb"},
        {"speed_ref_rpm", "control.speed_ref_rpm"},
        {"torque_ref_nm", "control.torque_ref_nm"},
        {"adc_i_a_per_count", "sensors.current_range_a (per unit of motor.rated_current_a)"},
        {"adc_vdc_v_per_count", "sensors.voltage_range_v (per unit of inverter.vdc_v)"},
        {"adc_vmid_v_per_count", "sensors.voltage_range_v (per unit of inverter.vdc_v)"},
        {"speed_bw_rad_s", "control.speed_bw_hz"},
        {"inertia_kgm2", "motor.j_kgm2"},
        {"compensation", "control.compensation"},
        {"dead_time_s", "inverter.dead_time_s (or firmware.dead_time_s) against ts_s"},
        {"handover", "control.handover_rpm, control.handover_hyst_frac"},
        {"current_limit_a", "control.current_limit_a (derived from protection.overcurrent_a, inverter.vdc_v, "
                            "motor.*, ts_s, control.delay_comp)"},
        {"polarity_mid", "control.polarity_mid"},
        {"vmid_cal", "control.vmid_cal"},
        {"cal_hold", "control.cal_hold (the hold current is derived from control.torque_limit_nm, motor.psi_m_wb "
                     "and the current limit)"},
        {"lpf_comp", "control.lpf_comp"},
        {"dc_supp", "control.dc_supp"},
        {"c_dc_f", "inverter.c_dc_f"},
        {"rr_ohm", "motor.rr_ohm or firmware.rr_ohm"},
        {"lls_h", "motor.lls_h or firmware.lls_h"},
        {"llr_h", "motor.llr_h or firmware.llr_h"},
        {"lm_h", "motor.lm_h or firmware.lm_h"},
        {"psir_ref_wb", "control.rotor_flux_ref_wb"},
        {"tau_lo_s", "control.observer_tau_s"},
        {"tau_hi_s", "control.observer_tau_high_s"},
        {"tau_w_", "control.observer_tau_lo_rpm, control.observer_tau_hi_rpm"},
        {"table_speed_rpm", "control.table_speed_rpm"},
        {"magn_frac", "control.magnetise_frac (with motor.rr_ohm, motor.llr_h, motor.lm_h, ts_s)"},
        {"speed_filter_s", "ts_s, control.speed_loop_divider"},
        {"fw_", "control.flux_weakening"},
        {"scheme", "control.scheme"},
        {"carrier_hz", "control.carrier_hz, ts_s"},
        {"svm_mode", "control.modulation"},
        {"sfvc_kp_per_s", "control.sfvc_kp_per_s (with ts_s)"},
        {"dfoc_bw_hz", "control.dfoc_bw_hz (with ts_s)"},
        {"dfoc_zeta", "control.dfoc_zeta (with control.dfoc_bw_hz, motor.rs_ohm)"},
        {"speed_sensor", "control.speed_sensor"},
        {"topology", "inverter.topology"},
    };
    for (const auto& m : map) {
        if (msg.rfind(m.field, 0) == 0) {
            return m.keys;
        }
    }
    return "";
}

class FirmwareController final : public Controller {
public:
    explicit FirmwareController(const Scenario& sc) : si_(firmware_si_config(sc)) {}

    std::string init(hal_host::Harness& h) override
    {
        (void)h;
        const dtc_config_si_t& si = si_;
        char msg[256] = {0};
        const int rc = dtc_config_from_si(&si, &cfg_, msg, sizeof msg);
        if (rc != DTC_SI_OK) {
            const std::string keys = keys_of_field(msg);
            return (keys.empty() ? std::string() : keys + ": ") + "firmware configuration refused (" +
                   std::to_string(rc) + "): " + msg;
        }
        dtc_bases_from_si(&si, &bases_);
        te_scale_ = bases_.t_base_nm / kIqOne;
        psi_scale_ = bases_.psi_base_wb / kIqOne;
        hal_init(); // board bring-up, as main() does on the DSP before the ISR is enabled
        const int16_t init_rc = app_init(&cfg_);
        if (init_rc != 0) {
            return "app_init() refused the configuration (dtc_err " + std::to_string(init_rc) + ")";
        }
        if (si.reconfig_relay != 0) {
            // the same drive as an FSTP with the failed phase on the mid-point (dtc_config_post_fault_si)
            dtc_config_si_t post_si;
            if (dtc_config_post_fault_si(&si, &post_si) != DTC_SI_OK) {
                return "inverter.reconfig_relay: the post-fault configuration needs the PM law on the SSTP";
            }
            const int prc = dtc_config_from_si(&post_si, &post_cfg_, msg, sizeof msg);
            if (prc != DTC_SI_OK) {
                return "inverter.reconfig_relay: post-fault (FSTP) configuration refused (" + std::to_string(prc) +
                       "): " + msg;
            }
            const int16_t rrc = app_set_reconfig(&post_cfg_);
            if (rrc != 0) {
                return "inverter.reconfig_relay: app_set_reconfig() refused the post-fault configuration (dtc_err " +
                       std::to_string(rrc) + ")";
            }
        }
        return "";
    }

    void step(hal_host::Harness& h) override
    {
        if (rec_.is_open()) {
            step_recorded(h);
            return;
        }
        app_isr();        // hal_read() -> per-unit, trips -> dtc_step() -> hal_write()
        app_background(); // one pass of the background loop per period (watchdog)
        if (serving_) {
            app_proto_background(); // and of the serial protocol (dtc-sil serve)
        }
        status_fresh_ = false; // the status is copied out only when someone asks (see refresh())
    }

    bool can_record_isr() const override { return true; }

    std::string start_isr_record(const std::string& path) override
    {
        rec_.open(path, std::ios::binary | std::ios::trunc);
        if (!rec_) {
            return "--record-isr " + path + ": cannot open for writing";
        }
        rec_path_ = path;
        rec_count_ = 0;
        hdr_ = pil_header_t{};
        hdr_.version = PIL_VERSION;
        hdr_.config_fields = pil_config_fields();
        hdr_.in_bytes = PIL_IN_BYTES;
        hdr_.out_bytes = PIL_OUT_BYTES;
        hdr_.t1pr = hal_pwm_period();
        std::vector<std::uint8_t> b(PIL_HEADER_BYTES + 4u * hdr_.config_fields);
        pil_header_encode(&hdr_, b.data());
        pil_config_encode(&cfg_, b.data() + PIL_HEADER_BYTES);
        rec_.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
        return rec_ ? "" : "--record-isr " + rec_path_ + ": write failed";
    }

    std::string end_isr_record() override
    {
        if (!rec_.is_open()) {
            return "";
        }
        hdr_.isr_count = rec_count_;
        std::uint8_t b[PIL_HEADER_BYTES];
        pil_header_encode(&hdr_, b);
        rec_.seekp(0);
        rec_.write(reinterpret_cast<const char*>(b), sizeof b);
        rec_.close();
        return rec_ ? "" : "--record-isr " + rec_path_ + ": write failed";
    }

    ControllerEstimates estimates() const override
    {
        refresh();
        ControllerEstimates e;
        e.valid = st_.state == APP_STATE_RUN;
        if (e.valid) {
            e.te_nm = static_cast<double>(st_.out.te_iq) * te_scale_;
            e.psi_alpha_wb = static_cast<double>(st_.out.psi_alpha_iq) * psi_scale_;
            e.psi_beta_wb = static_cast<double>(st_.out.psi_beta_iq) * psi_scale_;
        }
        return e;
    }
    std::string fault() const override
    {
        refresh();
        return app_fault_name(st_.fault);
    }
    std::string fault_detail() const override
    {
        refresh();
        if (st_.fault == APP_FAULT_NONE) {
            return "";
        }
        const std::string w = app_fault_meaning(st_.fault, st_.fault_detail);
        if (w.empty()) {
            return "";
        }
        char t[64];
        std::snprintf(t, sizeof t, " (latched at ISR %lu)", static_cast<unsigned long>(st_.fault_tick));
        return w + t;
    }
    int reconfigured() const override
    {
        refresh();
        return static_cast<int>(st_.reconfigured);
    }
    bool has_estimates() const override { return true; }

    std::string serve(double ts_s) override
    {
        app_set_arming(APP_ARM_COMMAND);
        app_proto_start(static_cast<std::uint32_t>(std::llround(ts_s * 1e9)));
        serving_ = true;
        return "";
    }

private:
    /// step() with the ISR recorded: what hal_read() returns this period (the harness's sample),
    /// the ISR and background pass, then what the firmware did to the HAL and its status.
    void step_recorded(hal_host::Harness& h)
    {
        const hal_meas_t in = h.meas();
        const std::uint64_t w0 = h.hal_writes(), g0 = h.gates_off_calls(), t0 = h.trip_clear_calls();
        app_isr();
        app_background();
        pil_hal_obs_t obs{};
        auto count16 = [](std::uint64_t n) { return static_cast<std::uint16_t>(n > 0xFFFFu ? 0xFFFFu : n); };
        obs.writes = count16(h.hal_writes() - w0);
        obs.gates_off = count16(h.gates_off_calls() - g0);
        obs.trip_clear = count16(h.trip_clear_calls() - t0);
        if (obs.writes != 0u) {
            obs.written = h.last_written_cmd();
        }
        app_get_status(&st_);
        status_fresh_ = true;
        pil_out_t o;
        pil_out_fill(&o, &obs, &st_);
        std::uint8_t b[PIL_IN_BYTES + PIL_OUT_BYTES];
        pil_in_encode(&in, b);
        pil_out_encode(&o, b + PIL_IN_BYTES);
        rec_.write(reinterpret_cast<const char*>(b), sizeof b);
        ++rec_count_;
    }

    std::ofstream rec_;
    std::string rec_path_;
    pil_header_t hdr_{};
    std::uint32_t rec_count_ = 0;
    dtc_config_si_t si_;
    dtc_config_t cfg_{};
    dtc_config_t post_cfg_{}; // the post-fault FSTP configuration (inverter.reconfig_relay)
    dtc_bases_t bases_{};
    // app_get_status() copies the whole status under a critical section (hal.h); the run loop
    // needs it only in the metrics window, for trace rows and for the final fault, so it is read
    // on demand, at most once per period, with the harness still active (Controller contract).
    void refresh() const
    {
        if (!status_fresh_) {
            app_get_status(&st_);
            status_fresh_ = true;
        }
    }
    mutable app_status_t st_{};
    mutable bool status_fresh_ = false;
    bool serving_ = false; // dtc-sil serve: the background loop runs the serial protocol
    double te_scale_ = 0.0;  // N*m per IQ count: t_base / 2^24 (a power-of-two scale: exact)
    double psi_scale_ = 0.0; // Wb per IQ count
};

} // namespace

std::unique_ptr<Controller> make_firmware_controller(const Scenario& sc, std::string* err)
{
    (void)err;
    return std::make_unique<FirmwareController>(sc);
}

} // namespace sil
