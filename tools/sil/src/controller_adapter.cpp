// controller_adapter.cpp - controller factory, the SI config view and the open-loop source.
#include "controller_adapter.hpp"

#include "hal_host.hpp"

#include <cmath>

namespace sil {

std::unique_ptr<Controller> make_firmware_controller(const Scenario& sc, std::string* err); // controller_firmware.cpp

namespace {
ControllerFactory g_reference_factory = nullptr;
}

void register_reference_controller(ControllerFactory factory) { g_reference_factory = factory; }

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
    const auto n = static_cast<std::size_t>(std::ceil(sc.duration_s / sc.ts_s)) + 1u;
    std::vector<VoltageRow> rows(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double t0 = static_cast<double>(k) * sc.ts_s;
        const double t = t0 + 0.5 * sc.ts_s;
        double f, angle;
        if (c.vf_ramp_s > 0.0 && t < c.vf_ramp_s) {
            f = c.vf_freq_hz * t / c.vf_ramp_s;
            angle = (2.0 * kPi) * 0.5 * f * t;
        } else {
            f = c.vf_freq_hz;
            const double tr = c.vf_ramp_s;
            angle = (2.0 * kPi) * (0.5 * c.vf_freq_hz * tr + c.vf_freq_hz * (t - tr));
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
    if (sc.control.mode == ControlMode::OpenLoop) {
        std::vector<VoltageRow> rows;
        if (sc.control.vf_freq_hz > 0.0) {
            rows = vf_voltage_rows(sc);
        } else if (!load_voltage_csv(sc.control.voltage_csv, &rows, err)) {
            return nullptr;
        }
        return make_open_loop_controller(std::move(rows));
    }
    if (sc.control.implementation == Implementation::Reference) {
        if (g_reference_factory == nullptr) {
            *err = "control.implementation = \"reference\": the reference controller (model/ref_dtc.h) is not "
                   "built into this program";
            return nullptr;
        }
        return g_reference_factory(sc, err);
    }
    return make_firmware_controller(sc, err);
}

} // namespace sil
