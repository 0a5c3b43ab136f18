// run.cpp - the SIL run loop (see run.hpp).
#include "run.hpp"

#include <chrono>
#include <cmath>
#include <fstream>

#include "controller_adapter.hpp"

namespace sil {

namespace {
constexpr double kPi = 3.14159265358979323846;

plant_load_t load_kind(const std::string& t)
{
    if (t == "speed") {
        return PLANT_LOAD_SPEED;
    }
    if (t == "torque") {
        return PLANT_LOAD_TORQUE;
    }
    if (t == "fan") {
        return PLANT_LOAD_FAN;
    }
    if (t == "generator") {
        return PLANT_LOAD_GENERATOR;
    }
    return PLANT_LOAD_INERTIA;
}
} // namespace

plant_params_t plant_params_from(const Scenario& sc)
{
    plant_params_t p;
    plant_params_default(&p); // fields this runner does not know keep the plant's own defaults
    p.rs_ohm = sc.motor.rs_ohm;
    p.ls_h = sc.motor.ls_h;
    p.psi_m_wb = sc.motor.psi_m_wb;
    p.pole_pairs = static_cast<int>(sc.motor.pole_pairs);
    const std::array<double, 3>* harm[3] = {&sc.motor.emf_harm_a, &sc.motor.emf_harm_b, &sc.motor.emf_harm_c};
    for (int ph = 0; ph < 3; ++ph) {
        p.emf_gain[ph] = sc.motor.emf_gain[static_cast<std::size_t>(ph)];
        for (int h = 0; h < 3; ++h) {
            p.emf_harm[ph][h] = (*harm[ph])[static_cast<std::size_t>(h)];
        }
    }
    if (sc.motor.type == "im") {
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
    p.b_nms = sc.motor.b_nms;
    p.inverter = sc.inverter.topology == "fstp"   ? PLANT_INVERTER_FSTP
                 : sc.inverter.topology == "sstp" ? PLANT_INVERTER_SSTP
                                                  : PLANT_INVERTER_IDEAL;
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
    p.load_speed_rpm = sc.load.speed_rpm;
    p.load_torque_nm = sc.load.torque_nm;
    p.speed0_rpm = sc.initial_speed_rpm;
    p.theta_m0_rad = sc.initial_theta_m_rad;
    p.max_step_s = sc.max_step_s;
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
    s.trip_current_a = sc.protection.hw_trip_current_a;
    s.noise_seed = static_cast<std::uint64_t>(sc.sensors.seed);
    return c;
}

unsigned switched_legs(const Scenario& sc)
{
    if (sc.inverter.topology == "sstp") {
        return 0x7u;
    }
    if (sc.inverter.topology == "fstp") {
        return 0x6u; // legs B and C; phase A sits on the capacitor mid-point
    }
    return 0u;
}

bool run_scenario(const Scenario& sc, const RunOptions& opt, RunResult* res, std::string* err)
{
    std::unique_ptr<Controller> ctrl = make_controller(sc, err);
    if (!ctrl) {
        return false;
    }
    return run_scenario_with(sc, std::move(ctrl), opt, res, err);
}

bool run_scenario_with(const Scenario& sc, std::unique_ptr<Controller> ctrl, const RunOptions& opt, RunResult* res,
                       std::string* err)
{
    // Everything that can be refused is refused before the first period and before any file exists.
    if (!ctrl) {
        *err = "no controller";
        return false;
    }
    const plant_params_t pp = plant_params_from(sc);
    std::unique_ptr<hal_host::Harness> h = hal_host::Harness::create(pp, harness_config_from(sc), err);
    if (!h) {
        return false;
    }
    h->activate();
    struct Deactivate {
        hal_host::Harness* h;
        ~Deactivate() { h->deactivate(); }
    } deactivate_guard{h.get()};
    if (std::string e = ctrl->init(*h); !e.empty()) {
        *err = "controller: " + e;
        return false;
    }

    StagedOutput out;
    TraceWriter trace;
    const bool writing = !opt.out_dir.empty();
    if (writing) {
        if (!out.begin(opt.out_dir, err)) {
            return false;
        }
        trace.set_rotor_flux_columns(sc.motor.type == "im");
        if (opt.write_trace && !trace.open(out.path("trace.csv"), err)) {
            return false;
        }
    }

    const auto periods = static_cast<std::uint64_t>(std::llround(sc.duration_s / sc.ts_s));
    // The metrics window spans round(window/ts) periods: that many + 1 samples (metrics.cpp).
    const auto window_n =
        std::min<std::uint64_t>(periods, static_cast<std::uint64_t>(std::llround(sc.metrics_window_s / sc.ts_s)) + 1);
    // One sample more before the window: the switching count needs the leg state before its start.
    const std::uint64_t record_from = periods - std::min<std::uint64_t>(periods, window_n + 1);
    Series& s = res->series;
    s = Series{};
    s.ts_s = sc.ts_s;
    const bool est = ctrl->has_estimates();
    const bool legs = sc.inverter.topology != "ideal";
    // Sized once for the recorded periods and written by index: no allocation and no capacity
    // check inside the loop.
    const auto n_rec = static_cast<std::size_t>(periods - record_from);
    for (auto* v : {&s.ia, &s.ib, &s.ic, &s.te, &s.psi_a, &s.psi_b, &s.speed_rpm, &s.theta_e}) {
        v->resize(n_rec);
    }
    if (est) {
        for (auto* v : {&s.te_est, &s.psi_a_est, &s.psi_b_est}) {
            v->resize(n_rec);
        }
    }
    if (legs) {
        for (auto* v : {&s.sa, &s.sb, &s.sc, &s.en}) {
            v->resize(n_rec);
        }
    }
    const double pole_pairs = static_cast<double>(sc.motor.pole_pairs);
    const unsigned decimate = opt.decimate == 0 ? 1u : opt.decimate;
    bool load_stepped = sc.load.step_time_s <= 0.0;
    const double nan = std::nan("");

    const auto t0 = std::chrono::steady_clock::now();
    for (std::uint64_t k = 0; k < periods; ++k) {
        if (!load_stepped && h->time_s() + 0.5 * sc.ts_s >= sc.load.step_time_s) {
            plant_set_load(h->plant(), pp.load, sc.load.speed_rpm, sc.load.step_torque_nm);
            load_stepped = true;
        }
        h->sample();
        ctrl->step(*h);
        const bool record = k >= record_from;
        const bool trace_row = writing && opt.write_trace && k % decimate == 0;
        if (!record && !trace_row) {
            // Before the metrics window with no trace row: nothing to record, so neither the
            // full plant state (plant_get_state) nor the controller's estimates are read.
            h->advance();
            continue;
        }
        const plant_state_t& st = h->state();
        const ControllerEstimates e = ctrl->estimates();
        const hal_cmd_t& cmd = h->applied_cmd();
        const bool en = legs ? h->gates_enabled() : !h->trip_latched();
        if (record) {
            const auto i = static_cast<std::size_t>(k - record_from);
            s.ia[i] = st.i_a;
            s.ib[i] = st.i_b;
            s.ic[i] = st.i_c;
            s.te[i] = st.te_nm;
            s.psi_a[i] = st.psi_alpha_wb;
            s.psi_b[i] = st.psi_beta_wb;
            s.speed_rpm[i] = st.speed_rpm;
            s.theta_e[i] = pole_pairs * st.theta_m_rad;
            if (est) {
                s.te_est[i] = e.valid ? e.te_nm : nan;
                s.psi_a_est[i] = e.valid ? e.psi_alpha_wb : nan;
                s.psi_b_est[i] = e.valid ? e.psi_beta_wb : nan;
            }
            if (legs) {
                s.sa[i] = static_cast<std::uint8_t>(cmd.sa != 0u);
                s.sb[i] = static_cast<std::uint8_t>(cmd.sb != 0u);
                s.sc[i] = static_cast<std::uint8_t>(cmd.sc != 0u);
                s.en[i] = static_cast<std::uint8_t>(en);
            }
        }
        if (trace_row) {
            TraceRow r{};
            r.t_s = st.t_s;
            r.ia_a = st.i_a;
            r.ib_a = st.i_b;
            r.ic_a = st.i_c;
            r.i_alpha_a = st.i_alpha_a;
            r.i_beta_a = st.i_beta_a;
            r.torque_nm = st.te_nm;
            r.torque_est_nm = e.valid ? e.te_nm : nan;
            r.psi_alpha_wb = st.psi_alpha_wb;
            r.psi_beta_wb = st.psi_beta_wb;
            r.psi_alpha_est_wb = e.valid ? e.psi_alpha_wb : nan;
            r.psi_beta_est_wb = e.valid ? e.psi_beta_wb : nan;
            r.speed_rpm = st.speed_rpm;
            r.sa = legs ? static_cast<int>(cmd.sa != 0u) : 0;
            r.sb = legs ? static_cast<int>(cmd.sb != 0u) : 0;
            r.sc = legs ? static_cast<int>(cmd.sc != 0u) : 0;
            r.vdc_v = st.vdc_v;
            r.en = en ? 1 : 0;
            r.theta_e_rad = st.theta_e_rad;
            r.vc_lo_v = st.vc_lo_v;
            r.v_alpha_v = st.v_alpha_v;
            r.v_beta_v = st.v_beta_v;
            r.tload_nm = st.tload_nm;
            r.psi_r_alpha_wb = st.psi_r_alpha_wb;
            r.psi_r_beta_wb = st.psi_r_beta_wb;
            trace.write(r);
        }
        h->advance();
    }
    const auto t1 = std::chrono::steady_clock::now();

    MetricsConfig mc;
    mc.window_s = sc.metrics_window_s;
    mc.rated_torque_nm = sc.motor.rated_torque_nm;
    mc.switched_legs = switched_legs(sc);
    res->metrics = compute_metrics(s, mc);
    res->info.sim_time_s = static_cast<double>(periods) * sc.ts_s;
    res->info.wall_time_s = std::chrono::duration<double>(t1 - t0).count();
    res->info.isr_count = periods;
    res->info.fault = ctrl->fault();
    res->info.invalid_commands = h->invalid_writes();
    res->info.hw_trip = h->trip_latched();

    if (writing) {
        if (opt.write_trace && !trace.close(err)) {
            return false;
        }
        std::ofstream mj(out.path("metrics.json"));
        mj << metrics_json(sc, res->metrics, res->info).dump(2) << "\n";
        mj.close();
        if (!mj) {
            *err = "metrics.json: write failed";
            return false;
        }
        if (!out.commit(err)) {
            return false;
        }
    }
    (void)kPi;
    return true;
}

} // namespace sil
