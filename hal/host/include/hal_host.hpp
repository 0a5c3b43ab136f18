// hal_host.hpp - the SIL binding of hal/include/hal.h on top of the plant (model/include/plant.h).
//
// A Harness owns one plant_t, the simulated clock, the sensor emulation (ADC, encoder, noise with a
// fixed seed) and the hardware protection emulation. The global C functions of hal.h forward to
// the one *active* Harness (Harness::activate()); without an active harness they abort with a
// message, because firmware running on no hardware is a test-setup bug.
//
// Period protocol, one call of run_period() per 50 us control period k, t_k = k * ts:
//   1. sample():  read what the sensors see of the plant at t_k (plant_get_sensed: currents,
//                 capacitor voltages, shaft angle; the full plant_state_t is computed only when
//                 state() asks for it); convert it to ADC codes and encoder counts
//                 (hal_meas_t); run the trip comparator (|i_x| > trip level -> latch, gates off now).
//   2. isr():     the firmware's ISR body (app_isr) runs "instantaneously" at t_k: hal_read() gets
//                 the sample, hal_write() stores the command for period k+1.
//   3. advance(): the plant runs over [t_k, t_k+1) with the command written in period k-1 (the
//                 DSP's shadowed action registers load at the period boundary), then the pending
//                 command becomes the active one.
// Fault tolerance: hal_cmd_t.relay energises the plant's reconfiguration relay at once
// (a GPIO output, not shadowed; its contacts follow after their own delay) and, from that command
// on, holds the named leg's two gates off (the leg must not drive a phase the relay ties to the
// mid-point); relay = 0 gives the leg back. The gate drivers' desaturation outputs (the plant's
// latch) appear in hal_meas_t.desat and latch the trip like PDPINTA; hal_trip_clear() resets them.
// hal_gates_off() acts on the current period at once (the fault path), like forcing the PWM
// outputs to high impedance. A latched trip keeps every gate off until hal_trip_clear() succeeds,
// which it does only once the comparator condition has gone (PDPINTA behaviour, f2812-facts 2.11).
#ifndef HAL_HOST_HPP
#define HAL_HOST_HPP

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "hal.h"
#include "hal_host_sensors.hpp"
#include "plant.h"
#include "plant_defaults.h"

namespace hal_host {

/// Sensor chains, encoder and protection of the emulated board (SI units; defaults from
/// plant_defaults.h).
struct SensorConfig {
    double current_range_a = PLANT_DEF_CURRENT_RANGE_A;    // +-range maps onto the 0..3 V ADC input
    std::array<double, 3> current_offset_a{};  // per phase A, B, C
    std::array<double, 3> current_gain_error{};
    double current_noise_a_rms = 0.0;
    double voltage_range_v = PLANT_DEF_VOLTAGE_RANGE_V;    // 0..range maps onto 0..3 V (dividers)
    double vdc_offset_v = 0.0;
    double vdc_gain_error = 0.0;
    double vmid_offset_v = 0.0;
    double vmid_gain_error = 0.0;
    double voltage_noise_v_rms = 0.0;
    bool vmid_fitted = true;                   // false: HAL_ADC_VMID reads 0
    std::uint32_t encoder_lines = PLANT_DEF_ENCODER_LINES; // Hoang Fig. 9(b): 2000 pulse/rev
    double encoder_offset_rad = 0.0;           // mechanical angle of the index pulse is -offset
    bool encoder_reversed = false;             // counts -theta (A and B exchanged): the index at +offset
    int current_reversed = -1;                 // 0..2: that phase's sensor reads minus its current; -1 none
    double trip_current_a = 0.0;               // PDPINTA comparator level on |i_a|,|i_b|,|i_c|; 0 = off
    std::uint64_t noise_seed = 1;
};

struct HarnessConfig {
    double ts_s = PLANT_DEF_TS_S; // control period = one ISR = one plant advance
    // Timer 1 clock of the PWM form (the F2812's HSPCLK, 75 MHz on the board): T1PR =
    // ts_s * pwm_clock_hz / 2. When that is not a whole number of counts in 1..65534 the PWM form
    // is unavailable: hal_pwm_period() returns 0 and a PWM-form command is an invalid write that
    // turns the gates off (the leg-state form works at any ts_s).
    double pwm_clock_hz = PLANT_DEF_PWM_CLOCK_HZ;
    SensorConfig sensors;
    // Two motor leads exchanged: the inverter's legs B and C drive the machine's phases C and B,
    // and the phase-current sensors (on the legs) read the machine's i_c and i_b.
    bool phases_swapped = false;
};

/// Why the gates are off (for the runner's log).
enum class TripCause { none, overcurrent, desat };

class Harness {
public:
    /// Creates the plant from params. Returns nullptr and sets *err if the plant or the harness
    /// configuration is invalid.
    static std::unique_ptr<Harness> create(const plant_params_t& params, const HarnessConfig& cfg,
                                           std::string* err);
    ~Harness();
    Harness(const Harness&) = delete;
    Harness& operator=(const Harness&) = delete;

    /// Makes this the instance the hal.h functions forward to (one at a time per process).
    void activate();
    void deactivate();
    static Harness* active();

    /// One control period: sample(), isr(), advance().
    template <typename Isr> void run_period(Isr&& isr)
    {
        sample();
        isr();
        advance();
    }
    void sample();
    void advance();

    /// Replay instead of sample(): the next hal_read() returns m (tick and all) instead of the
    /// emulated measurement; the plant is not read. For timing the ISR alone on recorded
    /// measurements (sil_bench); do not mix with advance() in one period.
    void replay_sample(const hal_meas_t& m)
    {
        meas_ = m;
        sampled_ = true;
    }

    /// Ideal inverter only: alpha/beta voltages for the current period (open-loop runs have no
    /// actuation delay: the voltage table already says what is applied when).
    void set_ideal_voltage(double v_alpha_v, double v_beta_v);

    /// Observation inside the period (tests: the current ripple of PWM, its spectrum): with n > 1
    /// every advance() integrates the period in n equal parts and calls f(plant) after each; the
    /// switching instants of the command are split among the parts (the plant's dead time is
    /// kept in absolute time), so the plant sees the same command as in one piece. n = 1 (the
    /// default) advances in one piece. The period-match gates-off path (hal.h: an asymmetric
    /// pulse followed by enable = 0) is not split and calls f once, at the period's end.
    void set_substeps(int n, std::function<void(const plant_t*)> f);

    // --- sensor faults ----------------------------------------------------------------------------
    // They live here, not in the plant: the plant models the power circuit and the machine, and
    // what a sensor reports is this emulation's business (the plant has no sensors).
    /// Encoder signal lost from the next sample(): the QEP count holds its last value and no index
    /// pulse is seen (lost = false: the encoder reads the shaft again).
    void set_encoder_lost(bool lost) { encoder_lost_ = lost; }
    /// Phase `phase` (0..2; -1 = none) current sensor stuck from the next sample(): its ADC channel
    /// reads `code`. The noise is the sensor's (hal_host_sensors.hpp: referred to the measured
    /// current), so a stuck output has none; the draw is still made, so the other channels'
    /// noise is the same sequence as without the fault.
    void set_current_sensor_stuck(int phase, std::uint16_t code)
    {
        stuck_phase_ = phase;
        stuck_code_ = code;
    }
    /// Phase `phase` (0..2) current sensor's offset from the next sample(), A: a drift after the
    /// firmware's start-up calibration, which measures the offset present with the gates off and
    /// removes only that one.
    void set_current_offset(int phase, double offset_a) { adc_[static_cast<std::size_t>(phase)].offset = offset_a; }
    /// Reconfiguration relay (hal_cmd_t.relay): the coil command in force, 0..3.
    std::uint16_t relay_cmd() const { return relay_; }
    /// The plant's fault state (relay contacts, desaturation latch) at time_s().
    plant_fault_state_t fault_state() const
    {
        plant_fault_state_t f;
        plant_get_fault_state(plant_, &f);
        return f;
    }

    // --- what the runner records -------------------------------------------------------------
    /// The plant's full true state at time_s(): between sample() and advance() the state at t_k
    /// that was sampled. Computed by plant_get_state() on the first call after each sample() or
    /// advance() (it costs more than the sensor emulation, and the runner needs it only in the
    /// metrics window or for the trace). A caller that changes the plant through plant() between
    /// calls must call sample() again to see the change.
    const plant_state_t& state() const
    {
        if (state_level_ < 2) {
            plant_get_state(plant_, &state_);
            state_level_ = 2;
        }
        return state_;
    }
    /// The same state with only plant_get_state_core()'s fields valid (plant.h: currents, flux,
    /// torque, shaft, the currents' integrals), which is what the metrics' series read; the
    /// others hold whatever an earlier call left. Cached like state().
    const plant_state_t& state_core() const
    {
        if (state_level_ < 1) {
            plant_get_state_core(plant_, &state_);
            state_level_ = 1;
        }
        return state_;
    }
    const plant_sensed_t& sensed() const { return sensed_; } // sensed subset at t_k (after sample())
    const hal_meas_t& meas() const { return meas_; }        // what hal_read() returns in period k
    const hal_cmd_t& applied_cmd() const { return active_; } // legs applied over period k (after sample)
    bool gates_enabled() const;                              // effective enable over period k
    bool trip_latched() const { return trip_latched_; }
    TripCause trip_cause() const { return trip_cause_; }
    std::uint64_t period_count() const { return k_; }
    double time_s() const { return static_cast<double>(k_) * cfg_.ts_s; }
    double ts_s() const { return cfg_.ts_s; }
    std::uint64_t watchdog_services() const { return watchdog_services_; }
    std::uint64_t hal_writes() const { return writes_; }
    /// The last command passed to hal_write(), as passed (pending_cmd() after a later
    /// hal_gates_off() has enable = 0), and the hal_gates_off() / hal_trip_clear() calls so far:
    /// what an ISR recording (--record-isr, docs/pil.md) takes from the HAL.
    const hal_cmd_t& last_written_cmd() const { return written_; }
    std::uint64_t gates_off_calls() const { return gates_off_calls_; }
    std::uint64_t trip_clear_calls() const { return trip_clear_calls_; }
    /// hal_write() calls with a leg state or enable other than 0/1 (firmware contract violations).
    std::uint64_t invalid_writes() const { return invalid_writes_; }
    bool hal_initialised() const { return initialised_; }
    plant_t* plant() { return plant_; }
    const HarnessConfig& config() const { return cfg_; }
    std::uint16_t pwm_period() const { return t1pr_; } // T1PR of the PWM form (0: unavailable)

    /// Switching instants of leg x over one period for a PWM-form command (hal.h): the EV-A's
    /// up/down counter rule, t = cmpr * ts / (2 T1PR) on the way up and ts - cmpr * ts / (2 T1PR)
    /// on the way down. Exposed for tests.
    plant_leg_edges_t pwm_leg_edges(const hal_cmd_t& cmd, int x) const;

    // --- hal.h back-end (the C functions forward here) ------------------------------------------
    void hal_init();
    void hal_read(hal_meas_t* meas); // clears the index flag: "seen since the previous read"
    void hal_write(const hal_cmd_t* cmd);
    void hal_gates_off();
    void hal_trip_clear();
    void hal_watchdog_service() { ++watchdog_services_; }
    std::uint16_t hal_irq_save();
    void hal_irq_restore(std::uint16_t state);
    std::uint16_t hal_pwm_period() const { return t1pr_; }

private:
    Harness(plant_t* plant, const HarnessConfig& cfg, const plant_params_t& params);
    bool comparator_active() const;
    /// The shaft angle the encoder reads: minus the shaft's with A and B exchanged.
    double encoder_theta() const { return cfg_.sensors.encoder_reversed ? -sensed_.theta_m_rad : sensed_.theta_m_rad; }
    void apply_to_plant();
    void advance_plain(); // one period of the active command, in substeps_ parts
    static bool pwm_asymmetric(const hal_cmd_t& c);

    plant_t* plant_;
    HarnessConfig cfg_;
    plant_inverter_t inverter_;
    int pole_pairs_;
    std::uint16_t t1pr_ = 0;
    std::array<AnalogChannel, HAL_ADC_COUNT> adc_;
    Encoder encoder_;
    GaussianNoise noise_;

    plant_sensed_t sensed_{};
    mutable plant_state_t state_{};
    mutable int state_level_ = 0; // state_ holds: 0 nothing valid, 1 state_core(), 2 state()
    hal_meas_t meas_{};
    hal_cmd_t active_{};  // applied over the current period
    hal_cmd_t pending_{}; // written in the current period, applied from the next boundary
    hal_cmd_t written_{}; // the last hal_write() argument
    double v_alpha_v_ = 0.0, v_beta_v_ = 0.0;
    std::uint64_t k_ = 0;
    std::int64_t last_turn_ = 0;
    bool index_seen_ = false;
    std::uint16_t index_count_ = 0;
    bool sampled_ = false;
    bool trip_latched_ = false;
    TripCause trip_cause_ = TripCause::none;
    bool initialised_ = false;
    std::uint16_t irq_enabled_ = 1;
    std::uint64_t watchdog_services_ = 0;
    std::uint64_t writes_ = 0;
    std::uint64_t gates_off_calls_ = 0;
    std::uint64_t trip_clear_calls_ = 0;
    std::uint64_t invalid_writes_ = 0;
    int substeps_ = 1;
    std::function<void(const plant_t*)> substep_fn_;
    bool encoder_lost_ = false;
    int stuck_phase_ = -1;
    std::uint16_t stuck_code_ = 2048u;
    std::uint16_t relay_ = 0u;
    bool relay_fitted_ = false;
};

} // namespace hal_host

#endif // HAL_HOST_HPP
