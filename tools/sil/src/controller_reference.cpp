// controller_reference.cpp - model/'s double-precision reference DTC (model/include/ref_dtc.h) as
// a SIL controller, on the same measurements as the firmware.
//
// The reference sees what the firmware sees: the ADC codes and encoder count of hal_host,
// converted back to SI through the ideal sensing chain (no offset calibration: with non-zero
// sensor offsets configured, it sees them uncorrected), and it writes its leg states through
// hal_write(), so the one-period actuation delay and the plant are identical. Differences in the
// metrics are then the fixed-point arithmetic (and the firmware's offset calibration / speed
// measurement), which is what the fixed-point vs double tests bound.
//
// Speed for the speed loop: encoder count difference over speed_loop_divider periods (the same
// information the firmware's speed measurement has). No protection: the reference never trips.
#include <cmath>
#include <deque>

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "ref_dtc.h"

namespace sil {

namespace {


class ReferenceController final : public Controller {
public:
    explicit ReferenceController(const Scenario& sc) : sc_(sc) {}

    std::string init(hal_host::Harness& h) override
    {
        (void)h;
        dtc_ref::Params p;
        const bool fstp = sc_.inverter.topology == Topology::Fstp;
        p.topology = fstp ? dtc_ref::Topology::FSTP : dtc_ref::Topology::SSTP;
        p.estimator = sc_.control.estimator == Estimator::Voltage ? dtc_ref::FluxEstimator::VOLTAGE_MODEL
                                                                  : dtc_ref::FluxEstimator::CURRENT_MODEL;
        switch (sc_.control.compensation) {
        case Compensation::None: p.comp = dtc_ref::DropComp::NONE; break;
        case Compensation::Simple:
            p.comp = fstp ? dtc_ref::DropComp::FSTP_SIMPLE : dtc_ref::DropComp::SSTP_EQUAL;
            break;
        case Compensation::Proposed: p.comp = dtc_ref::DropComp::FSTP_PROPOSED; break;
        }
        switch (sc_.control.table) {
        case SwitchingTable::Basic: p.table = dtc_ref::SwitchingTable::CASADEI_T1; break;
        case SwitchingTable::StA: p.table = dtc_ref::SwitchingTable::ST_A; break;
        case SwitchingTable::StB: p.table = dtc_ref::SwitchingTable::ST_B; break;
        case SwitchingTable::StC: p.table = dtc_ref::SwitchingTable::ST_C; break;
        case SwitchingTable::StD: p.table = dtc_ref::SwitchingTable::ST_D; break;
        case SwitchingTable::SpeedDependent: // IM only: refused for the PM machine at scenario load
            return "control.table = \"speed-dependent\": not a table of the PM reference controller";
        }
        if (fstp) {
            p.table = dtc_ref::SwitchingTable::HOANG_FSTP;
        }
        p.mode = sc_.control.mode == ControlMode::Torque ? dtc_ref::ControlMode::TORQUE : dtc_ref::ControlMode::SPEED;
        p.ts_s = sc_.ts_s;
        p.speed_divider = static_cast<int>(sc_.control.speed_loop_divider);
        p.rs_ohm = sc_.motor.rs_ohm;
        p.ls_h = sc_.motor.ls_h;
        p.psi_m_wb = sc_.motor.psi_m_wb;
        p.pole_pairs = static_cast<int>(sc_.motor.pole_pairs);
        p.v_ce_v = sc_.inverter.v_ce_v;
        p.v_d_v = sc_.inverter.v_d_v;
        p.r_on_ohm = sc_.inverter.r_on_ohm;
        p.v_f_v = sc_.control.v_f_v;
        p.lpf_wc_rad_s = sc_.control.lpf_cutoff_rad_s;
        p.voltage_delay_periods = 2; // hal.h: written in k, applied over period k+1
        p.psi_ref_wb = sc_.control.flux_ref_wb;
        p.band_psi_wb = sc_.control.flux_band_wb;
        p.band_te_nm = sc_.control.torque_band_nm;
        const SpeedPiGains g = speed_pi_gains(sc_.motor.j_kgm2, sc_.control.speed_bw_hz);
        p.kp_nm_s_rad = g.kp_nm_per_rad_s;
        p.ki_nm_rad = g.ki_nm_per_rad;
        p.te_max_nm = sc_.control.torque_limit_nm;
        if (ctrl_.init(p) != 0) {
            return "reference controller: " + ctrl_.message();
        }
        ctrl_.set_speed_ref(sc_.control.speed_ref_rpm * kPi / 30.0);
        ctrl_.set_torque_ref(sc_.control.torque_ref_nm);
        hal_init();
        return "";
    }

    void step(hal_host::Harness& h) override
    {
        hal_meas_t raw;
        hal_read(&raw);
        const hal_host::SensorConfig& s = h.config().sensors;
        const double a_per_v = s.current_range_a / 1.5;
        auto amps = [&](int ch) { return (hal_host::adc_code_to_volts(raw.adc[ch]) - 1.5) * a_per_v; };
        auto volts = [&](int ch) { return hal_host::adc_code_to_volts(raw.adc[ch]) * s.voltage_range_v / 3.0; };
        const double cpt = 4.0 * static_cast<double>(s.encoder_lines);
        const double theta_m = (static_cast<double>(raw.qep_count) + 0.5) / cpt * 2.0 * kPi - s.encoder_offset_rad;

        // Mechanical speed from the count advance over the last speed_loop_divider periods.
        counts_.push_back(raw.qep_count);
        const std::size_t win = static_cast<std::size_t>(sc_.control.speed_loop_divider);
        double omega = 0.0;
        if (counts_.size() > win) {
            int d = static_cast<int>(counts_.back()) - static_cast<int>(counts_.front());
            const int half = static_cast<int>(cpt / 2.0);
            d = d > half ? d - static_cast<int>(cpt) : (d < -half ? d + static_cast<int>(cpt) : d);
            omega = static_cast<double>(d) / cpt * 2.0 * kPi / (static_cast<double>(win) * sc_.ts_s);
            counts_.pop_front();
        }

        dtc_ref::Meas m;
        m.i_a = amps(HAL_ADC_IA);
        m.i_b = amps(HAL_ADC_IB);
        m.i_c = amps(HAL_ADC_IC);
        m.vdc_v = volts(HAL_ADC_VDC);
        m.have_vc = sc_.inverter.topology == Topology::Fstp && s.vmid_fitted;
        m.vc_lo_v = m.have_vc ? volts(HAL_ADC_VMID) : 0.5 * m.vdc_v;
        m.vc_hi_v = m.vdc_v - m.vc_lo_v;
        m.theta_e_rad = std::fmod(static_cast<double>(sc_.motor.pole_pairs) * theta_m, 2.0 * kPi);
        m.omega_m_rad_s = omega;
        if (first_) {
            ctrl_.reset(m.theta_e_rad); // voltage-model flux starts at psi_m e^{j theta_e}
            first_ = false;
        }
        const dtc_ref::Out o = ctrl_.step(m);
        hal_cmd_t cmd{}; // leg-state form (form = HAL_CMD_LEGS = 0)
        cmd.sa = static_cast<std::uint16_t>(o.sa);
        cmd.sb = static_cast<std::uint16_t>(o.sb);
        cmd.sc = static_cast<std::uint16_t>(o.sc);
        cmd.enable = 1u;
        hal_write(&cmd);
        est_ = ControllerEstimates{true, o.te_nm, o.psi_alpha, o.psi_beta};
    }

    ControllerEstimates estimates() const override { return est_; }
    std::string fault() const override { return "none"; }
    bool has_estimates() const override { return true; }

private:
    Scenario sc_;
    dtc_ref::Controller ctrl_;
    std::deque<std::uint16_t> counts_;
    bool first_ = true;
    ControllerEstimates est_{};
};

} // namespace

std::unique_ptr<Controller> make_reference_controller(const Scenario& sc, std::string* err)
{
    (void)err;
    return std::make_unique<ReferenceController>(sc);
}

} // namespace sil
