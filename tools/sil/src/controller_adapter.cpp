// controller_adapter.cpp - controller factory, the SI config view and the open-loop source.
#include "controller_adapter.hpp"

#include "hal_host.hpp"

#include <cmath>

namespace sil {

#if DTC_SIL_HAVE_FIRMWARE
std::unique_ptr<Controller> make_firmware_controller(const Scenario& sc, std::string* err); // controller_firmware.cpp
bool firmware_controller_available() { return true; }
#else
bool firmware_controller_available() { return false; }
#endif

namespace {
ControllerFactory g_reference_factory = nullptr;
}

void register_reference_controller(ControllerFactory factory) { g_reference_factory = factory; }

FirmwareSiConfig firmware_si_config(const Scenario& sc)
{
    FirmwareSiConfig c{};
    // The firmware's own parameter values (firmware.*), the plant's where not given.
    c.rs_ohm = sc.firmware.rs_ohm.value_or(sc.motor.rs_ohm);
    c.ls_h = sc.firmware.ls_h.value_or(sc.motor.ls_h);
    c.psi_m_wb = sc.firmware.psi_m_wb.value_or(sc.motor.psi_m_wb);
    c.pole_pairs = static_cast<int>(sc.motor.pole_pairs);
    c.rated_torque_nm = sc.motor.rated_torque_nm;
    c.rated_current_a = sc.motor.rated_current_a;
    c.rated_speed_rpm = sc.motor.rated_speed_rpm;
    c.topology_fstp = sc.inverter.topology == "fstp" ? 1 : 0;
    c.vdc_nominal_v = sc.inverter.vdc_v;
    c.v_ce_v = sc.firmware.v_ce_v.value_or(sc.inverter.v_ce_v);
    c.v_d_v = sc.firmware.v_d_v.value_or(sc.inverter.v_d_v);
    c.r_on_ohm = sc.firmware.r_on_ohm.value_or(sc.inverter.r_on_ohm);
    c.v_f_v = sc.control.v_f_v;
    c.current_range_a = sc.sensors.current_range_a;
    c.voltage_range_v = sc.sensors.voltage_range_v;
    c.vmid_fitted = sc.sensors.vmid_fitted ? 1 : 0;
    c.encoder_lines = static_cast<int>(sc.sensors.encoder_lines);
    c.encoder_offset_rad = sc.sensors.encoder_offset_rad;
    c.ts_s = sc.ts_s;
    c.speed_loop_divider = static_cast<int>(sc.control.speed_loop_divider);
    c.mode_torque = sc.control.mode == "torque" ? 1 : 0;
    c.estimator_voltage = sc.control.estimator == "voltage" ? 1 : 0;
    c.compensation = sc.control.compensation == "simple" ? 1 : (sc.control.compensation == "proposed" ? 2 : 0);
    static const char* const tables[] = {"basic", "st-a", "st-b", "st-c", "st-d"};
    for (int i = 0; i < 5; ++i) {
        if (sc.control.table == tables[i]) {
            c.table = i;
        }
    }
    c.speed_ref_rpm = sc.control.speed_ref_rpm;
    c.torque_ref_nm = sc.control.torque_ref_nm;
    c.torque_limit_nm = sc.control.torque_limit_nm;
    c.flux_ref_wb = sc.control.flux_ref_wb;
    c.torque_band_nm = sc.control.torque_band_nm;
    c.flux_band_wb = sc.control.flux_band_wb;
    c.lpf_cutoff_rad_s = sc.control.lpf_cutoff_rad_s;
    c.handover_given = sc.control.handover_given ? 1 : 0;
    c.handover_rpm = sc.control.handover_rpm;
    c.handover_hyst_frac = sc.control.handover_hyst_frac;
    c.delay_comp = sc.control.delay_comp ? 1 : 0;
    c.deadtime_comp = sc.control.deadtime_comp ? 1 : 0;
    c.current_limit_given = sc.control.current_limit_given ? 1 : 0;
    c.current_limit_a = sc.control.current_limit_a;
    c.polarity_mid = sc.control.polarity_mid ? 1 : 0;
    c.vmid_cal = sc.control.vmid_cal ? 1 : 0;
    c.lpf_comp = sc.control.lpf_comp ? 1 : 0;
    c.dc_supp = sc.control.dc_supp ? 1 : 0;
    c.c_dc_f = sc.inverter.c_dc_f;
    c.dead_time_s = sc.firmware.dead_time_s.value_or(sc.inverter.dead_time_s);
    const SpeedPiGains g = speed_pi_gains(sc.motor.j_kgm2, sc.control.speed_bw_hz);
    c.speed_kp_nm_per_rad_s = g.kp_nm_per_rad_s;
    c.speed_ki_nm_per_rad = g.ki_nm_per_rad;
    c.overcurrent_a = sc.protection.overcurrent_a;
    c.stall_time_s = sc.protection.stall_time_s;
    c.vdc_min_v = sc.protection.vdc_min_v;
    c.vdc_max_v = sc.protection.vdc_max_v;
    return c;
}

namespace {

class OpenLoopController final : public Controller {
public:
    explicit OpenLoopController(std::vector<VoltageRow> rows) : rows_(std::move(rows)) {}
    std::string init(hal_host::Harness& h) override
    {
        if (rows_.empty()) {
            return "open loop: empty voltage table";
        }
        idx_ = 0;
        (void)h;
        return "";
    }
    void step(hal_host::Harness& h) override
    {
        // Row in force at t_k; a tolerance of 1e-9 periods absorbs k * ts rounding.
        const double t = h.time_s() + 1e-9 * h.ts_s();
        while (idx_ + 1 < rows_.size() && rows_[idx_ + 1].t_s <= t) {
            ++idx_;
        }
        h.set_ideal_voltage(rows_[idx_].v_alpha_v, rows_[idx_].v_beta_v);
    }
    ControllerEstimates estimates() const override { return {}; }
    std::string fault() const override { return "none"; }
    bool has_estimates() const override { return false; }

private:
    std::vector<VoltageRow> rows_;
    std::size_t idx_ = 0;
};

} // namespace

std::vector<VoltageRow> vf_voltage_rows(const Scenario& sc)
{
    // One row per control period, sampled at the period's middle (the held value's fundamental
    // then has no phase lag): f(t) = vf_freq_hz * min(t / vf_ramp_s, 1), angle = 2 pi int f dt
    // (exact for the linear ramp), amplitude = vf_boost_v + vf_v_per_hz * f.
    const ControlCfg& c = sc.control;
    const double kTwoPi = 6.28318530717958647692;
    const auto n = static_cast<std::size_t>(std::ceil(sc.duration_s / sc.ts_s)) + 1u;
    std::vector<VoltageRow> rows(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double t0 = static_cast<double>(k) * sc.ts_s;
        const double t = t0 + 0.5 * sc.ts_s;
        double f, angle;
        if (c.vf_ramp_s > 0.0 && t < c.vf_ramp_s) {
            f = c.vf_freq_hz * t / c.vf_ramp_s;
            angle = kTwoPi * 0.5 * f * t;
        } else {
            f = c.vf_freq_hz;
            const double tr = c.vf_ramp_s;
            angle = kTwoPi * (0.5 * c.vf_freq_hz * tr + c.vf_freq_hz * (t - tr));
        }
        const double v = c.vf_boost_v + c.vf_v_per_hz * f;
        rows[k] = VoltageRow{t0, v * std::cos(angle), v * std::sin(angle)};
    }
    return rows;
}

std::unique_ptr<Controller> make_open_loop_controller(std::vector<VoltageRow> rows)
{
    return std::make_unique<OpenLoopController>(std::move(rows));
}

std::unique_ptr<Controller> make_controller(const Scenario& sc, std::string* err)
{
    if (sc.control.mode == "open_loop") {
        std::vector<VoltageRow> rows;
        if (sc.control.vf_freq_hz > 0.0) {
            rows = vf_voltage_rows(sc);
        } else if (!load_voltage_csv(sc.control.voltage_csv, &rows, err)) {
            return nullptr;
        }
        return make_open_loop_controller(std::move(rows));
    }
    if (sc.control.implementation == "reference") {
        if (g_reference_factory == nullptr) {
            *err = "control.implementation = \"reference\": the reference controller (model/ref_dtc.h) is not "
                   "built into this program";
            return nullptr;
        }
        return g_reference_factory(sc, err);
    }
#if DTC_SIL_HAVE_FIRMWARE
    return make_firmware_controller(sc, err);
#else
    *err = "control.mode = \"" + sc.control.mode +
           "\" needs the firmware (firmware/dtc, tools/config), which this build does not contain; "
           "only control.mode = \"open_loop\" runs without it";
    return nullptr;
#endif
}

} // namespace sil
