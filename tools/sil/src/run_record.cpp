// run_record.cpp - what a run keeps of each period: the metrics window's series and trace.csv's
// rows (see run_parts.hpp).
#include "run_parts.hpp"

#include <algorithm>
#include <cmath>

#include "sil_constants.hpp"

namespace sil {

Recorder::Recorder(const Scenario& sc, std::uint64_t periods, std::uint64_t window_n, bool est, bool trace,
                   unsigned decimate, Series* s)
    : s_(*s),
      // One sample more before the window: the switching count needs the leg state before its start.
      record_from_(periods - std::min<std::uint64_t>(periods, window_n + 1)),
      est_(est),
      legs_(sc.inverter.topology != Topology::Ideal),
      im_(sc.motor.type == MotorType::Im),
      trace_on_(trace),
      decimate_(decimate == 0 ? 1u : decimate),
      pole_pairs_(static_cast<double>(sc.motor.pole_pairs))
{
    s_ = Series{};
    s_.ts_s = sc.ts_s;
    // Sized once for the recorded periods and written by index: no allocation and no capacity
    // check inside the loop.
    const auto n_rec = static_cast<std::size_t>(periods - record_from_);
    for (auto* v : {&s_.ia, &s_.ib, &s_.ic, &s_.te, &s_.psi_a, &s_.psi_b, &s_.speed_rpm, &s_.theta_fund_rad,
                    &s_.i2_int, &s_.q_a, &s_.q_b}) {
        v->resize(n_rec);
    }
    if (est_) {
        for (auto* v : {&s_.te_est, &s_.psi_a_est, &s_.psi_b_est}) {
            v->resize(n_rec);
        }
    }
    if (legs_) {
        for (auto* v : {&s_.sa, &s_.sb, &s_.sc, &s_.en, &s_.tog_a, &s_.tog_b, &s_.tog_c}) {
            v->resize(n_rec);
        }
    }
    trace_.set_rotor_flux_columns(im_);
    trace_.set_fault_columns(sc.faults.any() || sc.inverter.reconfig_relay);
}

bool Recorder::open_trace(const std::string& path, std::string* err) { return !trace_on_ || trace_.open(path, err); }

bool Recorder::close_trace(std::string* err) { return !trace_on_ || trace_.close(err); }

void Recorder::record(std::uint64_t k, const hal_host::Harness& h, const Controller& ctrl)
{
    // The series read only plant_get_state_core()'s fields; a trace row needs the whole state.
    const bool row = trace_on_ && k % decimate_ == 0;
    const plant_state_t& st = row ? h.state() : h.state_core();
    const ControllerEstimates e = ctrl.estimates();
    const hal_cmd_t& cmd = h.applied_cmd();
    const bool en = legs_ ? h.gates_enabled() : !h.trip_latched();
    if (k >= record_from_) {
        record_series(static_cast<std::size_t>(k - record_from_), st, e, cmd, en, h);
    }
    if (row) {
        trace_row(st, e, cmd, en, h);
    }
}

void Recorder::record_series(std::size_t i, const plant_state_t& st, const ControllerEstimates& e,
                             const hal_cmd_t& cmd, bool en, const hal_host::Harness& h)
{
    Series& s = s_;
    const double nan = std::nan("");
    s.ia[i] = st.i_a;
    s.ib[i] = st.i_b;
    s.ic[i] = st.i_c;
    s.i2_int[i] = st.i2_int_a2s;
    s.q_a[i] = st.q_a_as;
    s.q_b[i] = st.q_b_as;
    s.te[i] = st.te_nm;
    s.psi_a[i] = st.psi_alpha_wb;
    s.psi_b[i] = st.psi_beta_wb;
    s.speed_rpm[i] = st.speed_rpm;
    if (im_) {
        // The stator-flux angle, unwrapped sample to sample (it moves by omega_s ts, far below pi
        // per period).
        const double a = std::atan2(st.psi_beta_wb, st.psi_alpha_wb);
        s.theta_fund_rad[i] = i == 0 ? a : s.theta_fund_rad[i - 1] + std::remainder(a - flux_angle_prev_, 2.0 * kPi);
        flux_angle_prev_ = a;
    } else {
        s.theta_fund_rad[i] = pole_pairs_ * st.theta_m_rad;
    }
    if (est_) {
        s.te_est[i] = e.valid ? e.te_nm : nan;
        s.psi_a_est[i] = e.valid ? e.psi_alpha_wb : nan;
        s.psi_b_est[i] = e.valid ? e.psi_beta_wb : nan;
    }
    if (legs_) {
        if (cmd.form == HAL_CMD_PWM) {
            // The PWM form: each leg's state at the period's start and its changes inside.
            std::uint8_t* st0[3] = {&s.sa[i], &s.sb[i], &s.sc[i]};
            std::uint8_t* tog[3] = {&s.tog_a[i], &s.tog_b[i], &s.tog_c[i]};
            for (int x = 0; x < 3; ++x) {
                const plant_leg_edges_t edges = h.pwm_leg_edges(cmd, x);
                *st0[x] = static_cast<std::uint8_t>(edges.state0 != 0);
                *tog[x] = static_cast<std::uint8_t>(edges.n);
            }
        } else {
            s.sa[i] = static_cast<std::uint8_t>(cmd.sa != 0u);
            s.sb[i] = static_cast<std::uint8_t>(cmd.sb != 0u);
            s.sc[i] = static_cast<std::uint8_t>(cmd.sc != 0u);
            s.tog_a[i] = s.tog_b[i] = s.tog_c[i] = 0u;
        }
        s.en[i] = static_cast<std::uint8_t>(en);
    }
}

void Recorder::trace_row(const plant_state_t& st, const ControllerEstimates& e, const hal_cmd_t& cmd, bool en,
                         const hal_host::Harness& h)
{
    const double nan = std::nan("");
    TraceRow& r = trace_.next_row(); // filled in place, every field
    r.t_s = st.t_s;
    r.i_a_a = st.i_a;
    r.i_b_a = st.i_b;
    r.i_c_a = st.i_c;
    r.i_alpha_a = st.i_alpha_a;
    r.i_beta_a = st.i_beta_a;
    r.torque_nm = st.te_nm;
    r.torque_est_nm = e.valid ? e.te_nm : nan;
    r.psi_alpha_wb = st.psi_alpha_wb;
    r.psi_beta_wb = st.psi_beta_wb;
    r.psi_alpha_est_wb = e.valid ? e.psi_alpha_wb : nan;
    r.psi_beta_est_wb = e.valid ? e.psi_beta_wb : nan;
    r.speed_rpm = st.speed_rpm;
    r.sa = legs_ ? static_cast<int>(cmd.sa != 0u) : 0;
    r.sb = legs_ ? static_cast<int>(cmd.sb != 0u) : 0;
    r.sc = legs_ ? static_cast<int>(cmd.sc != 0u) : 0;
    r.vdc_v = st.vdc_v;
    r.en = en ? 1 : 0;
    r.theta_e_rad = st.theta_e_rad;
    r.vc_lo_v = st.vc_lo_v;
    r.v_alpha_v = st.v_alpha_v;
    r.v_beta_v = st.v_beta_v;
    r.tload_nm = st.tload_nm;
    r.psi_r_alpha_wb = st.psi_r_alpha_wb;
    r.psi_r_beta_wb = st.psi_r_beta_wb;
    const plant_fault_state_t fs = h.fault_state();
    r.relay = h.relay_cmd();
    r.relay_closed = fs.relay_closed;
    r.desat = h.meas().desat;
    trace_.commit_row();
}

} // namespace sil
