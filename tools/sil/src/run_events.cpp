// run_events.cpp - what a scenario schedules during a run (load step, dynamometer speed ramp, the
// injected faults) and the speed's response to a fault (see run_parts.hpp).
#include "run_parts.hpp"

#include <algorithm>
#include <cmath>

#include "sil_constants.hpp"

namespace sil {

// The [faults] table applied to the plant and the sensing emulation, at the start of the first
// control period at or after faults.time_s.
void inject_faults(const Scenario& sc, hal_host::Harness& h)
{
    const FaultsCfg& f = sc.faults;
    plant_t* pl = h.plant();
    if (f.leg_open != FaultPhase::None) {
        plant_set_leg_open(pl, static_cast<int>(f.leg_open) - 1, 1);
    }
    // FaultSwitch: none, a_upper, a_lower, b_upper, ...: leg (v - 1) / 2, upper when (v - 1) even.
    auto sw = [pl](FaultSwitch s, plant_switch_fault_t mode) {
        if (s != FaultSwitch::None) {
            const int v = static_cast<int>(s) - 1;
            plant_set_switch_fault(pl, v / 2, (v % 2) == 0 ? 1 : 0, mode);
        }
    };
    sw(f.switch_open, PLANT_SWITCH_OPEN);
    sw(f.switch_short, PLANT_SWITCH_SHORT);
    if (f.dc_sag != 1.0) {
        plant_set_source_voltage(pl, f.dc_sag * sc.inverter.vdc_v);
    }
    if (f.encoder_lost) {
        h.set_encoder_lost(true);
    }
    if (f.current_sensor_stuck != FaultPhase::None) {
        h.set_current_sensor_stuck(static_cast<int>(f.current_sensor_stuck) - 1,
                                   static_cast<std::uint16_t>(f.current_sensor_code));
    }
}

RunEvents::RunEvents(const Scenario& sc, plant_load_t load)
    : sc_(sc),
      load_(load),
      load_stepped_(sc.load.step_time_s <= 0.0),
      dyno_ramp_(sc.load.type == LoadType::Speed && sc.load.speed_ramp_s > 0.0),
      faults_pending_(sc.faults.any()),
      speed_mode_(sc.control.mode == ControlMode::Speed),
      band_rpm_(0.01 * std::fabs(sc.control.speed_ref_rpm)),
      legs_(sc.inverter.topology != Topology::Ideal)
{
}

void RunEvents::before_sample(hal_host::Harness& h)
{
    const Scenario& sc = sc_;
    if (!load_stepped_ && h.time_s() + 0.5 * sc.ts_s >= sc.load.step_time_s) {
        plant_set_load(h.plant(), load_, dyno_speed_rpm(sc, h.time_s()), sc.load.step_torque_nm);
        load_stepped_ = true;
    }
    if (dyno_ramp_ && h.time_s() >= sc.load.speed_ramp_start_s) {
        // The dynamometer's speed for this period (held over it); the ramp's last value is load.speed_rpm.
        const double t_end = h.time_s() + sc.ts_s;
        plant_set_load(h.plant(), load_, dyno_speed_rpm(sc, t_end),
                       load_stepped_ && sc.load.step_time_s > 0.0 ? sc.load.step_torque_nm : sc.load.torque_nm);
        dyno_ramp_ = t_end < sc.load.speed_ramp_start_s + sc.load.speed_ramp_s;
    }
    if (sc.motor.temp_rise_k != 0.0 && h.time_s() + 0.5 * sc.ts_s >= temp_next_t_) {
        // motor.temp_rise_k: the windings' rise at the middle of the coming millisecond (copper)
        const double dt = 1e-3;
        const double rise = sc.motor.temp_rise_k * std::min(1.0, (h.time_s() + 0.5 * dt) / sc.duration_s);
        const double k = 1.0 + PLANT_DEF_CU_TEMPCO_PER_K * rise;
        (void)plant_set_resistances(h.plant(), sc.motor.rs_ohm * k, sc.motor.rr_ohm * k);
        temp_next_t_ = h.time_s() + dt;
    }
    if (faults_pending_ && h.time_s() + 0.5 * sc.ts_s >= sc.faults.time_s) {
        inject_faults(sc, h);
        faults_pending_ = false;
        fault_t_ = h.time_s();
    }
}

void RunEvents::after_sample(const hal_host::Harness& h)
{
    if (fault_t_ < 0.0 || !speed_mode_) {
        return;
    }
    const double ref = sc_.control.speed_ref_rpm;
    const double n = h.sensed().omega_m_rad_s * (30.0 / kPi);
    if (last_t_ < 0.0) {
        // from the speed the drive had when the fault came, capped at the reference: a fault
        // during the start is measured from where the start had got to
        dip_base_rpm_ = ref >= 0.0 ? std::min(n, ref) : std::max(n, ref);
    }
    dip_rpm_ = std::max(dip_rpm_, ref >= 0.0 ? dip_base_rpm_ - n : n - dip_base_rpm_);
    last_in_ = std::fabs(n - ref) <= band_rpm_;
    last_t_ = h.time_s();
    if (!last_in_) {
        last_out_t_ = last_t_;
    }
}

void RunEvents::after_step(const hal_host::Harness& h, const Controller& ctrl)
{
    if (trip_t_ >= 0.0) {
        return;
    }
    if (hw_trip_t_ < 0.0 && h.trip_latched()) {
        hw_trip_t_ = h.time_s();
    }
    // A trip turns the gates off: the controller is asked only when they go off (and in the
    // gates-off start, where a calibration fault latches), not in every period.
    const bool en = legs_ ? h.gates_enabled() : !h.trip_latched();
    if (!en && (prev_enabled_ || !ever_enabled_) && ctrl.fault() != "none") {
        trip_t_ = h.time_s();
    }
    prev_enabled_ = en;
    ever_enabled_ = ever_enabled_ || en;
}

void RunEvents::report(RunInfo* info) const
{
    if (info->fault != "none" && trip_t_ >= 0.0) {
        info->fault_time_s = trip_t_;
    } else if (info->hw_trip && hw_trip_t_ >= 0.0) {
        info->fault_time_s = hw_trip_t_;
    }
    info->injected_fault_time_s = fault_t_;
    if (fault_t_ >= 0.0 && speed_mode_) {
        info->speed_dip_rpm = dip_rpm_;
        // Back within the band for good: from the first sample after the last one outside it.
        if (last_in_) {
            info->recovery_s = last_out_t_ < 0.0 ? 0.0 : last_out_t_ + sc_.ts_s - fault_t_;
        }
    }
}

} // namespace sil
