// run.cpp - the SIL run loop (see run.hpp).
#include "run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <new>
#include <thread>
#include <ostream>

extern "C" {
#include "app_fault.h"
#include "hal_host_line.hpp"
#include "proto.h"
}

#include "controller_adapter.hpp"
#include "run_parts.hpp"

namespace sil {

volatile std::sig_atomic_t g_stop_signal = 0;

namespace {

plant_load_t load_kind(LoadType t)
{
    switch (t) {
    case LoadType::Speed: return PLANT_LOAD_SPEED;
    case LoadType::Torque: return PLANT_LOAD_TORQUE;
    case LoadType::Generator: return PLANT_LOAD_GENERATOR;
    case LoadType::Inertia: return PLANT_LOAD_INERTIA;
    case LoadType::Fan: return PLANT_LOAD_FAN;
    }
    return PLANT_LOAD_INERTIA;
}

plant_inverter_t inverter_kind(Topology t)
{
    switch (t) {
    case Topology::Ideal: return PLANT_INVERTER_IDEAL;
    case Topology::Sstp: return PLANT_INVERTER_SSTP;
    case Topology::Fstp: return PLANT_INVERTER_FSTP;
    }
    return PLANT_INVERTER_IDEAL;
}
} // namespace

plant_params_t plant_params_from(const Scenario& sc)
{
    plant_params_t p;
    plant_params_default(&p); // fields this runner does not know keep the plant's own defaults
    p.rs_ohm = sc.motor.rs_ohm;
    p.ls_h = sc.motor.ls_h;
    p.lq_h = sc.motor.lq_h;  // = ls_h: a surface PM
    p.psi_m_wb = sc.motor.psi_m_wb;
    p.pole_pairs = static_cast<int>(sc.motor.pole_pairs);
    const std::array<double, 3>* harm[3] = {&sc.motor.emf_harm_a, &sc.motor.emf_harm_b, &sc.motor.emf_harm_c};
    for (int ph = 0; ph < 3; ++ph) {
        p.emf_gain[ph] = sc.motor.emf_gain[static_cast<std::size_t>(ph)];
        for (int h = 0; h < 3; ++h) {
            p.emf_harm[ph][h] = (*harm[ph])[static_cast<std::size_t>(h)];
        }
    }
    if (sc.motor.type == MotorType::Im) {
        p.machine = PLANT_MACHINE_IM;  // every IM field below comes from the scenario
        p.psi_m_wb = 0.0;
        p.rs_ohm = sc.motor.rs_ohm;
        p.rr_ohm = sc.motor.rr_ohm;
        p.lls_h = sc.motor.lls_h;
        p.llr_h = sc.motor.llr_h;
        p.lm_h = sc.motor.lm_h;
        p.pole_pairs = static_cast<int>(sc.motor.pole_pairs);
    }
    p.j_kgm2 = sc.motor.j_kgm2;
    p.b_nm_s_per_rad = sc.motor.b_nm_s_per_rad;
    p.inverter = inverter_kind(sc.inverter.topology);
    p.vdc_v = sc.inverter.vdc_v;
    p.r_dc_ohm = sc.inverter.r_dc_ohm;
    p.c_dc_f = sc.inverter.c_dc_f;
    p.r_bal_ohm = sc.inverter.r_bal_ohm;
    p.esr_ohm = sc.inverter.esr_ohm;
    p.coulomb_nm = sc.load.coulomb_nm;
    p.v_ce_v = sc.inverter.v_ce_v;
    p.v_d_v = sc.inverter.v_d_v;
    p.r_on_ohm = sc.inverter.r_on_ohm;
    p.dead_time_s = sc.inverter.dead_time_s;
    p.drops_enabled = sc.inverter.drops ? 1 : 0;
    p.dead_time_enabled = sc.inverter.dead_time ? 1 : 0;
    p.finite_dc_link = sc.inverter.finite_dc_link ? 1 : 0;
    p.load = load_kind(sc.load.type);
    p.load_speed_rpm = dyno_speed_rpm(sc, 0.0);
    p.load_torque_nm = sc.load.torque_nm;
    p.speed0_rpm = sc.initial_speed_rpm;
    p.theta_m0_rad = sc.initial_theta_m_rad;
    p.max_step_s = sc.max_step_s;
    p.reconfig_relay = sc.inverter.reconfig_relay ? 1 : 0;
    p.relay_delay_s = sc.inverter.relay_delay_s;
    return p;
}

hal_host::HarnessConfig harness_config_from(const Scenario& sc)
{
    hal_host::HarnessConfig c;
    c.ts_s = sc.ts_s;
    hal_host::SensorConfig& s = c.sensors;
    s.current_range_a = sc.sensors.current_range_a;
    s.current_offset_a = sc.sensors.current_offset_a;
    s.current_gain_error = sc.sensors.current_gain_error;
    s.current_noise_a_rms = sc.sensors.current_noise_a_rms;
    s.voltage_range_v = sc.sensors.voltage_range_v;
    s.vdc_offset_v = sc.sensors.vdc_offset_v;
    s.vdc_gain_error = sc.sensors.vdc_gain_error;
    s.vmid_offset_v = sc.sensors.vmid_offset_v;
    s.vmid_gain_error = sc.sensors.vmid_gain_error;
    s.voltage_noise_v_rms = sc.sensors.voltage_noise_v_rms;
    s.vmid_fitted = sc.sensors.vmid_fitted;
    s.encoder_lines = static_cast<std::uint32_t>(sc.sensors.encoder_lines);
    s.encoder_offset_rad = sc.sensors.encoder_offset_rad;
    s.encoder_reversed = sc.sensors.encoder_reversed;
    s.current_reversed = static_cast<int>(sc.sensors.current_reversed) - 1;
    c.phases_swapped = sc.inverter.phases_swapped;
    s.trip_current_a = sc.protection.hw_trip_current_a;
    s.noise_seed = static_cast<std::uint64_t>(sc.sensors.seed);
    return c;
}

hal_host::Harness* ActiveHarness::open(const Scenario& sc, std::string* err)
{
    pp_ = plant_params_from(sc);
    h_ = hal_host::Harness::create(pp_, harness_config_from(sc), err);
    if (h_) {
        // Nothing the SIL reports reads the plant's energy accounts (plant.h): not integrated.
        plant_set_energy_accounts(h_->plant(), 0);
        h_->activate();
    }
    return h_.get();
}

ActiveHarness::~ActiveHarness()
{
    if (h_) {
        h_->deactivate();
    }
}

unsigned switched_legs(const Scenario& sc)
{
    switch (sc.inverter.topology) {
    case Topology::Sstp: return 0x7u;
    case Topology::Fstp: return 0x6u; // legs B and C; phase A sits on the capacitor mid-point
    case Topology::Ideal: return 0u;
    }
    return 0u;
}

PlantBounds plant_bounds(const Scenario& sc)
{
    // Far beyond anything the machine can do, so only a diverged integration crosses them:
    // current 100x the larger of rated and the link's short-circuit current V/Rs; speed 100x the
    // largest speed the scenario names; voltage 100x the link.
    const double rpm = std::max({sc.motor.rated_speed_rpm, std::fabs(sc.initial_speed_rpm),
                                 std::fabs(sc.control.speed_ref_rpm), std::fabs(sc.load.speed_rpm)});
    PlantBounds b;
    b.current_a = 100.0 * std::max({sc.motor.rated_current_a, sc.inverter.vdc_v / sc.motor.rs_ohm,
                                    sc.protection.overcurrent_a, sc.protection.hw_trip_current_a});
    b.omega_rad_s = 100.0 * rpm * kPi / 30.0;
    b.voltage_v = 100.0 * sc.inverter.vdc_v;
    return b;
}

namespace {
/// The first quantity of s beyond its bound, named (plant_out_of_bounds once one is).
[[gnu::noinline]] std::string out_of_bounds_text(const plant_sensed_t& s, const PlantBounds& b)
{
    struct Q {
        const char* name;
        double v, bound;
        const char* unit;
    };
    const Q q[] = {{"i_a", s.i_a, b.current_a, "A"},         {"i_b", s.i_b, b.current_a, "A"},
                   {"i_c", s.i_c, b.current_a, "A"},         {"omega_m", s.omega_m_rad_s, b.omega_rad_s, "rad/s"},
                   {"vdc", s.vdc_v, b.voltage_v, "V"},       {"vc_lo", s.vc_lo_v, b.voltage_v, "V"},
                   {"vc_hi", s.vc_hi_v, b.voltage_v, "V"}};
    for (const Q& x : q) {
        if (!(std::fabs(x.v) <= x.bound)) { // also true for NaN
            char line[160];
            std::snprintf(line, sizeof line, "%s = %g %s %s", x.name, x.v, x.unit,
                          std::isfinite(x.v) ? "beyond the physical bound" : "is not finite");
            std::string r = line;
            if (std::isfinite(x.v)) {
                std::snprintf(line, sizeof line, " %g %s", x.bound, x.unit);
                r += line;
            }
            return r;
        }
    }
    return "";
}
} // namespace

std::string plant_out_of_bounds(const plant_sensed_t& s, const PlantBounds& b)
{
    // Every period: the common case (all within, none NaN) decided by comparisons alone; the
    // table that names the quantity is built only when one is out.
    if (std::fabs(s.i_a) <= b.current_a && std::fabs(s.i_b) <= b.current_a && std::fabs(s.i_c) <= b.current_a &&
        std::fabs(s.omega_m_rad_s) <= b.omega_rad_s && std::fabs(s.vdc_v) <= b.voltage_v &&
        std::fabs(s.vc_lo_v) <= b.voltage_v && std::fabs(s.vc_hi_v) <= b.voltage_v) {
        return std::string();
    }
    return out_of_bounds_text(s, b);
}

namespace {
/// A firmware fault name with what it means in this scenario: the offset calibration runs with
/// the gates off, and a spinning rotor whose line back-EMF peak exceeds the link conducts through
/// the diodes (a rectifier), which the calibration sees as an offset.
void name_fault(const Scenario& sc, RunInfo* info)
{
    // The firmware sees rectifier current first as an ADC offset, or, when it is large, as a
    // latched hardware trip or an over-current: whichever it names, the cause is the same.
    const std::string adc_offset = app_fault_name(APP_FAULT_ADC_OFFSET);
    const bool calibration_fault = info->fault == adc_offset || info->fault == app_fault_name(APP_FAULT_HW_TRIP) ||
                                   info->fault == app_fault_name(APP_FAULT_OVERCURRENT);
    if (calibration_fault) {
        const double w_e = std::fabs(sc.initial_speed_rpm) * kPi / 30.0 * static_cast<double>(sc.motor.pole_pairs);
        const double e_line_pk = std::sqrt(3.0) * sc.motor.psi_m_wb * w_e;
        const double v_link = sc.inverter.topology == Topology::Fstp ? 0.5 * sc.inverter.vdc_v : sc.inverter.vdc_v;
        if (e_line_pk > v_link) {
            char line[200];
            std::snprintf(line, sizeof line,
                          "rectifier conduction during the gates-off offset calibration: line back-EMF peak "
                          "%.1f V at initial_speed_rpm = %g exceeds the %.1f V the diodes block (firmware fault "
                          "%s)",
                          e_line_pk, sc.initial_speed_rpm, v_link, info->fault.c_str());
            info->fault = "rectifier_conduction";
            info->fault_detail = line;
        } else if (info->fault == adc_offset) {
            info->fault_detail = "current-sensor offset calibration out of range (gates off)";
        }
    }
    if (info->hw_trip && info->fault == "none") {
        char line[160];
        std::snprintf(line, sizeof line,
                      "hardware over-current comparator latched (protection.hw_trip_current_a = %g A): gates off",
                      sc.protection.hw_trip_current_a);
        info->fault = "hw_overcurrent";
        info->fault_detail = line;
    }
}

std::string hms(double s)
{
    char b[32];
    if (!(s >= 0.0) || s > 1e7) {
        return "?";
    }
    const auto t = static_cast<long>(s + 0.5);
    if (t >= 3600) {
        std::snprintf(b, sizeof b, "%ldh%02ldm", t / 3600, (t / 60) % 60);
    } else if (t >= 60) {
        std::snprintf(b, sizeof b, "%ldm%02lds", t / 60, t % 60);
    } else {
        std::snprintf(b, sizeof b, "%lds", t);
    }
    return b;
}

/// Metrics that are undefined for this run (a ratio to a zero fundamental after a trip, an
/// estimate that never became valid) become empty (null in metrics.json) instead of NaN.
void drop_undefined(Metrics* m)
{
    auto f3 = [](std::optional<std::array<double, 3>>& a) {
        if (a && !(std::isfinite((*a)[0]) && std::isfinite((*a)[1]) && std::isfinite((*a)[2]))) {
            a.reset();
        }
    };
    auto f1 = [](std::optional<double>& a) {
        if (a && !std::isfinite(*a)) {
            a.reset();
        }
    };
    f3(m->fundamental_a);
    f3(m->thd_pct);
    f3(m->thd_harmonic_pct);
    f3(m->thd40_pct);
    f1(m->thd40_total_pct);
    f1(m->current_ripple_rms_a);
    f1(m->imbalance_pct);
    f1(m->thd_total_pct);
    f1(m->torque_est_mean_nm);
    f1(m->trf_est_pct);
    f1(m->flux_est_error_rms_pct);
    f1(m->switching_freq_hz);
}

bool metrics_finite(const Metrics& m)
{
    return std::isfinite(m.torque_mean_nm) && std::isfinite(m.trf_pct) && std::isfinite(m.trf_filtered_pct) &&
           std::isfinite(m.speed_mean_rpm);
}

/// Where the plant left physics (empty `why`: it did not).
struct Divergence {
    std::string why;
    double t_s = -1.0;
    std::uint64_t period = 0; // the period whose sample left the bounds (the run's length)
};

/// A run without metrics (null in metrics.json).
void no_metrics(RunResult* res)
{
    const double nan = std::nan("");
    res->metrics = Metrics{};
    res->metrics.torque_mean_nm = nan;
    res->metrics.trf_pct = nan;
    res->metrics.trf_filtered_pct = nan;
    res->metrics.speed_mean_rpm = nan;
}

/// The run's metrics from its series and its fault's name: a diverged plant has no metrics, only
/// why; otherwise the metrics, the firmware fault named for this scenario, and a metric that is
/// not finite reported as such.
void fault_metrics(const Scenario& sc, const Divergence& div, RunResult* res)
{
    if (!div.why.empty()) {
        // The recorded window is incomplete and the state meaningless: no metrics, only why.
        no_metrics(res);
        res->info.fault = "plant_diverged";
        res->info.fault_time_s = div.t_s;
        res->info.fault_detail = "plant state at t = " + std::to_string(div.t_s) + " s: " + div.why +
                                 " (an input drove the model outside physics; no metrics)";
        return;
    }
    MetricsConfig mc;
    mc.window_s = sc.metrics_window_s;
    mc.rated_torque_nm = sc.motor.rated_torque_nm;
    mc.switched_legs = switched_legs(sc);
    mc.torque_sensor_hz = sc.metrics.torque_sensor_hz;
    res->metrics = compute_metrics(res->series, mc);
    drop_undefined(&res->metrics);
    name_fault(sc, &res->info);
    if (!metrics_finite(res->metrics)) {
        res->info.fault_detail = (res->info.fault == "none" ? std::string() : res->info.fault + "; ") +
                                 "torque, TRF or speed mean not finite although the plant state stayed "
                                 "within its bounds";
        res->info.fault = "non_finite_metric";
    }
}
} // namespace

bool run_failed_physically(const RunInfo& info) { return info.fault == "plant_diverged" || info.fault == "non_finite_metric"; }

bool run_scenario(const Scenario& sc, const RunOptions& opt, RunResult* res, std::string* err)
{
    std::unique_ptr<Controller> ctrl = make_controller(sc, err);
    if (!ctrl) {
        return false;
    }
    return run_scenario_with(sc, std::move(ctrl), opt, res, err);
}

namespace {
bool run_once(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
              std::string* err);
} // namespace

bool run_scenario_with(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
                       std::string* err)
{
    try {
        return run_once(sc, std::move(ctrl), opt, res, err);
    } catch (const std::bad_alloc&) {
        // The staging folder and recording are removed on the way out (their destructors).
        *err = "out of memory (a scenario size the checks let through: please report it)";
        return false;
    }
}

namespace {
// Words of dtc-sil serve's parameter medium: two slots of 512 words (store.h), a 25LC256's 16 K
// words would only make the file larger.
constexpr std::uint16_t kServeStoreWords = 1024;

bool run_once(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
              std::string* err)
{
    // Everything that can be refused is refused before the first period and before any file exists.
    if (!ctrl) {
        *err = "no controller";
        return false;
    }
    ActiveHarness active;
    hal_host::Harness* const h = active.open(sc, err);
    if (h == nullptr) {
        return false;
    }
    if (std::string e = ctrl->init(*h); !e.empty()) {
        *err = "controller: " + e;
        return false;
    }
    const bool serving = !opt.serial_link.empty();
    // dtc-sil serve: the parameter store's medium, an EEPROM kept in the file LINK.params (a
    // restart of the same link boots into the parameters saved there).
    std::unique_ptr<hal_host::StoreMedium> medium;
    struct MediumOff {
        hal_host::StoreMedium* m = nullptr;
        ~MediumOff()
        {
            if (m != nullptr) {
                m->deactivate();
            }
        }
    } medium_off;
    if (serving) {
        try {
            medium = std::make_unique<hal_host::StoreMedium>(kServeStoreWords, 32, hal_host::StoreMedium::Kind::eeprom,
                                                             opt.serial_link + ".params");
        } catch (const std::exception& ex) {
            *err = std::string("--serial ") + opt.serial_link + ": parameter store: " + ex.what();
            return false;
        }
        medium->activate();
        medium_off.m = medium.get();
        if (std::string e = ctrl->serve(sc.ts_s); !e.empty()) {
            *err = e;
            return false;
        }
    }
    // A served run without --duration-s lasts until a signal: periods is then only a bound.
    const bool until_signal = serving && opt.serve_duration_s <= 0.0;
    const double duration_s = serving && !until_signal ? opt.serve_duration_s : sc.duration_s;
    const auto periods = until_signal ? (std::uint64_t{1} << 62)
                                      : static_cast<std::uint64_t>(std::llround(duration_s / sc.ts_s));
    if (periods == 0) {
        *err = "duration_s = " + std::to_string(duration_s) + " s simulates no full control period";
        return false;
    }
    const unsigned decimate = opt.decimate == 0 ? 1u : opt.decimate;
    const bool writing = !opt.out_dir.empty();
    if (writing && opt.write_trace && !opt.force && !until_signal) {
        const double rows = std::floor(static_cast<double>(periods - 1) / decimate) + 1.0;
        const double bytes = rows * kTraceBytesPerRow;
        if (bytes > opt.max_trace_bytes) {
            char line[400];
            const double fit = std::ceil(rows * decimate * kTraceBytesPerRow / opt.max_trace_bytes);
            std::snprintf(line, sizeof line,
                          "trace.csv would be about %.1f GB (%.0f rows of ~%.0f bytes), above the %.1f GB limit: "
                          "use --decimate %.0f (or more), --no-trace, or --force",
                          bytes / 1e9, rows, kTraceBytesPerRow, opt.max_trace_bytes / 1e9, fit);
            *err = line;
            return false;
        }
    }
    // The metrics window spans round(window/ts) periods: that many + 1 samples (metrics.cpp).
    const auto window_n =
        std::min<std::uint64_t>(periods, static_cast<std::uint64_t>(std::llround(sc.metrics_window_s / sc.ts_s)) + 1);
    if (window_n > kMaxWindowSamples) {
        *err = "metrics_window_s = " + std::to_string(sc.metrics_window_s) + " s holds " + std::to_string(window_n) +
               " samples, above the " + std::to_string(kMaxWindowSamples) + " the metrics window may hold";
        return false;
    }
    if (!opt.record_isr.empty() && !ctrl->can_record_isr()) {
        *err = ctrl->start_isr_record(opt.record_isr);
        return false;
    }
    if (opt.check_only) {
        return true;
    }
    // The recording is written under a staging name and renamed only when the run completed: an
    // interrupted or failed run leaves no truncated recording under the name asked for.
    StagedFile record(opt.record_isr);
    if (!opt.record_isr.empty()) {
        if (std::string e = ctrl->start_isr_record(record.path()); !e.empty()) {
            *err = e;
            return false;
        }
    }

    StagedOutput out;
    Recorder rec(sc, periods, window_n, ctrl->has_estimates(), writing && opt.write_trace, decimate, &res->series);
    if (writing) {
        if (!out.begin(opt.out_dir, err) || !rec.open_trace(out.path("trace.csv"), err)) {
            return false;
        }
    }
    const bool guard_trace = writing && opt.write_trace && !opt.force && !until_signal;
    const double trace_rows = std::floor(static_cast<double>(periods - 1) / decimate) + 1.0;
    RunEvents events(sc, active.params().load);
    const PlantBounds bounds = plant_bounds(sc);
    Divergence div;

    // dtc-sil serve: the firmware's SCI on a pseudo-terminal, modelled at its baud rate in
    // simulated time (hal_host_line.hpp); pumped every kServePump periods.
    std::unique_ptr<hal_host::SerialLine> sci;
    std::unique_ptr<hal_host::PtyLink> pty;
    constexpr std::uint64_t kServePump = 8;
    if (serving) {
        sci = std::make_unique<hal_host::SerialLine>(static_cast<double>(PROTO_BAUD), sc.ts_s);
        try {
            pty = std::make_unique<hal_host::PtyLink>(opt.serial_link);
        } catch (const std::exception& ex) {
            *err = std::string("--serial ") + opt.serial_link + ": " + ex.what();
            return false;
        }
        sci->activate();
    }
    struct LineOff {
        hal_host::SerialLine* l;
        ~LineOff()
        {
            if (l != nullptr) {
                l->deactivate();
            }
        }
    } sci_off{sci.get()};
    bool stopped = false;
    std::uint64_t k = 0;

    const auto t0 = std::chrono::steady_clock::now();
    auto t_progress = t0;
    for (; k < periods; ++k) {
        if (serving && (k % kServePump) == 0u) {
            pty->pump(*sci);
            if (g_stop_signal != 0) {
                stopped = true;
                break;
            }
            if (opt.pace > 0.0) {
                // wall time of period k at `pace` times real time
                const auto due = t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(static_cast<double>(k) * sc.ts_s / opt.pace));
                if (due > std::chrono::steady_clock::now() + std::chrono::microseconds(200)) {
                    std::this_thread::sleep_until(due);
                }
            }
        }
        if ((k & 4095u) == 0u && k != 0u && !serving) {
            if (g_stop_signal != 0) {
                if (opt.progress != nullptr) {
                    *opt.progress << "\n";
                }
                *err = "interrupted by signal " + std::to_string(static_cast<int>(g_stop_signal)) +
                       " at t = " + std::to_string(h->time_s()) + " s";
                return false; // the StagedOutput destructor removes the staging folder
            }
            if (opt.progress != nullptr) {
                const auto now = std::chrono::steady_clock::now();
                if (std::chrono::duration<double>(now - t_progress).count() >= 0.5) {
                    t_progress = now;
                    const double el = std::chrono::duration<double>(now - t0).count();
                    const double frac = static_cast<double>(k) / static_cast<double>(periods);
                    char line[160];
                    std::snprintf(line, sizeof line, "\rdtc-sil: %.3f / %.3f s simulated (%.1f %%), ETA %s   ",
                                  h->time_s(), static_cast<double>(periods) * sc.ts_s, 100.0 * frac,
                                  hms(el * (1.0 - frac) / frac).c_str());
                    *opt.progress << line << std::flush;
                }
            }
            if (guard_trace && rec.trace_rows() > 0) {
                // The trace's size measured on the rows written so far, projected to the run's end.
                const double per_row = static_cast<double>(rec.trace_bytes()) / static_cast<double>(rec.trace_rows());
                const double bytes = static_cast<double>(rec.trace_bytes()) +
                                     per_row * std::max(0.0, trace_rows - static_cast<double>(rec.trace_rows()));
                if (bytes > opt.max_trace_bytes) {
                    char line[400];
                    std::snprintf(line, sizeof line,
                                  "trace.csv would be about %.2f GB (%.0f rows of %.0f bytes, measured on the first "
                                  "%llu), above the %.1f GB limit: use --decimate %.0f (or more), --no-trace, or "
                                  "--force",
                                  bytes / 1e9, trace_rows, per_row,
                                  static_cast<unsigned long long>(rec.trace_rows()), opt.max_trace_bytes / 1e9,
                                  std::ceil(decimate * bytes / opt.max_trace_bytes));
                    *err = line;
                    return false;
                }
            }
        }
        events.before_sample(*h);
        h->sample();
        events.after_sample(*h);
        if (std::string why = plant_out_of_bounds(h->sensed(), bounds); !why.empty()) {
            div = Divergence{why, h->time_s(), k};
            break;
        }
        ctrl->step(*h);
        events.after_step(*h, *ctrl);
        if (rec.wants(k)) {
            rec.record(k, *h, *ctrl);
        }
        h->advance();
        if (serving) {
            sci->advance_period();
        }
    }
    if (serving) {
        pty->pump(*sci);
    }
    // Closing the trace (the writer thread's last batch) is part of the loop's cost.
    if (writing && !rec.close_trace(err)) {
        return false;
    }
    const auto t1 = std::chrono::steady_clock::now();
    if (opt.progress != nullptr && periods > 4096u) {
        *opt.progress << "\r" << std::string(70, ' ') << "\r" << std::flush;
    }

    if (!opt.record_isr.empty()) {
        if (std::string e = ctrl->end_isr_record(); !e.empty()) {
            *err = e;
            return false;
        }
    }

    res->info = RunInfo{};
    const std::uint64_t done = !div.why.empty() ? div.period : stopped ? k : periods;
    res->info.sim_time_s = static_cast<double>(done) * sc.ts_s;
    res->info.wall_time_s = std::chrono::duration<double>(t1 - t0).count();
    res->info.isr_count = done;
    res->info.fault = ctrl->fault();
    res->info.fault_detail = ctrl->fault_detail();
    res->info.warnings = ctrl->warnings();
    res->info.warning_time_s = ctrl->warning_time_s();
    res->info.invalid_commands = h->invalid_writes();
    res->info.hw_trip = h->trip_latched();
    res->info.traced = writing && opt.write_trace;
    if (const int r = ctrl->reconfigured(); r >= 1 && r <= 3) {
        res->info.reconfigured = std::string(1, static_cast<char>('a' + r - 1));
    }
    events.report(&res->info);
    if (stopped && div.why.empty()) {
        // a served run ended by a signal before its metrics window: the run's facts, no metrics
        no_metrics(res);
        name_fault(sc, &res->info);
    } else {
        fault_metrics(sc, div, res);
    }

    if (writing) {
        std::ofstream mj(out.path("metrics.json"));
        mj << metrics_json(sc, res->metrics, res->info).dump(2) << "\n";
        mj.close();
        if (!mj) {
            *err = "metrics.json: write failed";
            return false;
        }
        if (!out.commit(err)) {
            res->output_touched = out.touched();
            return false;
        }
    }
    if (!record.commit(err)) {
        return false;
    }
    return true;
}
} // namespace

} // namespace sil
