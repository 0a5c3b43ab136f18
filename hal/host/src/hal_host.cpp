// hal_host.cpp - Harness (see hal_host.hpp) and the C functions of hal.h forwarding to it.
#include "hal_host.hpp"

#include <utility>
#include "hal_host_pwm.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace hal_host {

namespace {
Harness* g_active = nullptr;

Harness& active_or_die(const char* fn)
{
    if (g_active == nullptr) {
        std::fprintf(stderr, "hal_host: %s() called with no active Harness (call Harness::activate())\n", fn);
        std::abort();
    }
    return *g_active;
}

bool finite_nonneg(double x) { return std::isfinite(x) && x >= 0.0; }

} // namespace

std::unique_ptr<Harness> Harness::create(const plant_params_t& params, const HarnessConfig& cfg,
                                         std::string* err)
{
    auto fail = [err](const std::string& m) {
        if (err != nullptr) {
            *err = m;
        }
        return std::unique_ptr<Harness>();
    };
    const SensorConfig& s = cfg.sensors;
    if (!(std::isfinite(cfg.ts_s) && cfg.ts_s > 0.0)) {
        return fail("control period ts_s must be > 0");
    }
    if (!(std::isfinite(cfg.pwm_clock_hz) && cfg.pwm_clock_hz > 0.0)) {
        return fail("pwm_clock_hz must be > 0");
    }
    if (!(std::isfinite(s.current_range_a) && s.current_range_a > 0.0)) {
        return fail("current sensor range must be > 0 A");
    }
    if (!(std::isfinite(s.voltage_range_v) && s.voltage_range_v > 0.0)) {
        return fail("voltage sensor range must be > 0 V");
    }
    if (!finite_nonneg(s.current_noise_a_rms) || !finite_nonneg(s.voltage_noise_v_rms) ||
        !finite_nonneg(s.trip_current_a)) {
        return fail("sensor noise and trip level must be finite and >= 0");
    }
    if (s.encoder_lines == 0u || s.encoder_lines > 16383u) {
        return fail("encoder lines must be 1..16383 (4 * lines counts must fit 16 bits)");
    }
    char buf[512] = {0};
    plant_t* plant = plant_create(&params, buf, sizeof buf);
    if (plant == nullptr) {
        return fail(std::string("plant: ") + (buf[0] != '\0' ? buf : "invalid parameters"));
    }
    return std::unique_ptr<Harness>(new Harness(plant, cfg, params));
}

Harness::Harness(plant_t* plant, const HarnessConfig& cfg, const plant_params_t& params)
    : plant_(plant), cfg_(cfg), inverter_(params.inverter), pole_pairs_(params.pole_pairs),
      t1pr_(t1pr_counts(cfg.ts_s, cfg.pwm_clock_hz)),
      encoder_(cfg.sensors.encoder_lines, cfg.sensors.encoder_offset_rad), noise_(cfg.sensors.noise_seed)
{
    const SensorConfig& s = cfg.sensors;
    for (int ph = 0; ph < 3; ++ph) {
        adc_[static_cast<std::size_t>(ph)] =
            current_channel(s.current_range_a, s.current_gain_error[static_cast<std::size_t>(ph)],
                            s.current_offset_a[static_cast<std::size_t>(ph)], s.current_noise_a_rms);
    }
    adc_[HAL_ADC_VDC] = voltage_channel(s.voltage_range_v, s.vdc_gain_error, s.vdc_offset_v, s.voltage_noise_v_rms);
    adc_[HAL_ADC_VMID] = voltage_channel(s.voltage_range_v, s.vmid_gain_error, s.vmid_offset_v, s.voltage_noise_v_rms);
    plant_get_sensed(plant_, &sensed_);
    last_turn_ = encoder_.turn(encoder_theta());
    relay_fitted_ = params.reconfig_relay != 0;
    active_ = hal_cmd_t{};
    pending_ = active_;
}

Harness::~Harness()
{
    if (g_active == this) {
        g_active = nullptr;
    }
    plant_destroy(plant_);
}

void Harness::activate() { g_active = this; }
void Harness::deactivate()
{
    if (g_active == this) {
        g_active = nullptr;
    }
}
Harness* Harness::active() { return g_active; }

bool Harness::comparator_active() const
{
    const double lim = cfg_.sensors.trip_current_a;
    if (lim <= 0.0) {
        return false;
    }
    return std::fabs(sensed_.i_a) > lim || std::fabs(sensed_.i_b) > lim || std::fabs(sensed_.i_c) > lim;
}

void Harness::sample()
{
    plant_get_sensed(plant_, &sensed_);
    state_level_ = 0;

    // Protection first: the comparator acts in hardware, before any software sees the sample.
    if (comparator_active() && !trip_latched_) {
        trip_latched_ = true;
        trip_cause_ = TripCause::overcurrent;
    }
    // Gate-driver desaturation (the plant latched it at the shoot-through's instant and turned
    // every gate off there): the drivers pull PDPINTA too.
    plant_fault_state_t fs;
    plant_get_fault_state(plant_, &fs);
    meas_.desat = static_cast<std::uint16_t>(fs.desat_mask);
    if (fs.desat_mask != 0 && !trip_latched_) {
        trip_latched_ = true;
        trip_cause_ = TripCause::desat;
    }

    // Encoder: index pulse whenever the shaft crossed the index position since the last sample;
    // a lost signal leaves the counter and the index flag as they were.
    std::int64_t turn = last_turn_;
    if (!encoder_lost_) {
        meas_.qep_count = encoder_.read(encoder_theta(), &turn);
    }
    if (turn != last_turn_) {
        // The capture unit latches the counter at the pulse edge: the index position is count 0
        // when crossing forward, and the count just below it (4*lines - 1) when crossing backward.
        index_seen_ = true;
        index_count_ = turn > last_turn_ ? 0u
                                         : static_cast<std::uint16_t>(encoder_.counts_per_turn() - 1u);
        last_turn_ = turn;
    }

    // ADC: one noise draw per noisy channel per period, in channel order (reproducible for a
    // seed and a configuration; noiseless channels cost no draw).
    // The sensors sit on the inverter's legs: with the leads B and C exchanged (phases_swapped) leg
    // B carries the machine's i_c; a sensor mounted the wrong way round reads minus its current.
    const bool sw = cfg_.phases_swapped;
    double x[HAL_ADC_COUNT] = {sensed_.i_a, sw ? sensed_.i_c : sensed_.i_b, sw ? sensed_.i_b : sensed_.i_c,
                               sensed_.vdc_v, sensed_.vc_lo_v};
    if (cfg_.sensors.current_reversed >= 0 && cfg_.sensors.current_reversed < 3) {
        x[cfg_.sensors.current_reversed] = -x[cfg_.sensors.current_reversed];
    }
    for (int ch = 0; ch < HAL_ADC_COUNT; ++ch) {
        const AnalogChannel& a = adc_[static_cast<std::size_t>(ch)];
        const double n = a.noise_rms > 0.0 ? noise_.next() : 0.0;
        meas_.adc[ch] = a.code(x[ch], n);
    }
    if (stuck_phase_ >= 0 && stuck_phase_ < 3) {
        meas_.adc[stuck_phase_] = stuck_code_;
    }
    if (!cfg_.sensors.vmid_fitted || (inverter_ != PLANT_INVERTER_FSTP && !relay_fitted_)) {
        meas_.adc[HAL_ADC_VMID] = 0u;
    }
    meas_.qep_index_seen = index_seen_ ? 1u : 0u;
    meas_.qep_index_count = index_count_;
    meas_.trip = trip_latched_ ? 1u : 0u;
    meas_.tick = static_cast<std::uint32_t>(k_ & 0xFFFFFFFFu);
    sampled_ = true;
}

bool Harness::gates_enabled() const { return active_.enable != 0u && !trip_latched_; }

plant_leg_edges_t Harness::pwm_leg_edges(const hal_cmd_t& cmd, int x) const
{
    const double ts = cfg_.ts_s;
    const double tick = ts / (2.0 * t1pr_);
    const std::uint16_t up = cmd.cmpr_up[x], dn = cmd.cmpr_dn[x];
    // Compare output active while T1CNT >= the value in force (hal.h): from the up-count match
    // to the down-count match; a value above T1PR leaves its half inactive.
    const double a = up <= t1pr_ ? up * tick : 0.5 * ts;
    const double b = dn <= t1pr_ ? ts - dn * tick : 0.5 * ts;
    const int inv = cmd.act[x] == HAL_PWM_UPPER_ACTIVE_LOW ? 1 : 0;
    plant_leg_edges_t e{};
    if (!(a < b)) {
        e.state0 = inv; // never active
    } else if (a <= 0.0 && b >= ts) {
        e.state0 = 1 - inv; // active the whole period
    } else if (a <= 0.0) {
        e.state0 = 1 - inv;
        e.n = 1;
        e.t_s[0] = b;
    } else {
        e.state0 = inv;
        e.n = b >= ts ? 1 : 2;
        e.t_s[0] = a;
        e.t_s[1] = b;
    }
    return e;
}

bool Harness::pwm_asymmetric(const hal_cmd_t& c)
{
    if (c.form != HAL_CMD_PWM) {
        return false;
    }
    for (int x = 0; x < 3; ++x) {
        if (c.cmpr_up[x] != c.cmpr_dn[x]) {
            return true;
        }
    }
    return false;
}

void Harness::apply_to_plant()
{
    if (inverter_ == PLANT_INVERTER_IDEAL) {
        if (trip_latched_) {
            plant_set_voltage(plant_, 0.0, 0.0);
        } else {
            plant_set_voltage(plant_, v_alpha_v_, v_beta_v_);
        }
        return;
    }
    const int en = gates_enabled() ? 1 : 0;
    if (active_.form == HAL_CMD_PWM && t1pr_ == 0u) {
        plant_set_legs(plant_, 0, 0, 0, 0); // no timer period for this ts_s: refused, gates off
        return;
    }
    if (active_.form == HAL_CMD_PWM) {
        const plant_leg_edges_t e[3] = {pwm_leg_edges(active_, 0), pwm_leg_edges(active_, 1), pwm_leg_edges(active_, 2)};
        plant_set_leg_edges(plant_, e, en);
        return;
    }
    plant_set_legs(plant_, active_.sa != 0u ? 1 : 0, active_.sb != 0u ? 1 : 0, active_.sc != 0u ? 1 : 0, en);
}

void Harness::advance()
{
    if (!sampled_) {
        sample(); // keep the protocol robust when a caller advances without sampling
    }
    apply_to_plant();
    if (inverter_ != PLANT_INVERTER_IDEAL && pwm_asymmetric(active_) && gates_enabled() && pending_.enable == 0u) {
        // Period-match reload in force (hal.h): the all-off command written in this period loads
        // at the period match, so the gates go off half-way through.
        plant_advance(plant_, 0.5 * cfg_.ts_s);
        plant_set_legs(plant_, 0, 0, 0, 0);
        plant_advance(plant_, 0.5 * cfg_.ts_s);
    } else {
        advance_plain();
    }
    if (substeps_ > 1 && substep_fn_ && inverter_ != PLANT_INVERTER_IDEAL && pwm_asymmetric(active_) &&
        gates_enabled() && pending_.enable == 0u) {
        substep_fn_(plant_);
    }
    state_level_ = 0;
    ++k_;
    active_ = pending_; // shadow registers load at the period boundary
    sampled_ = false;
}

void Harness::set_substeps(int n, std::function<void(const plant_t*)> f)
{
    substeps_ = n > 1 ? n : 1;
    substep_fn_ = std::move(f);
}

void Harness::advance_plain()
{
    if (substeps_ <= 1) {
        plant_advance(plant_, cfg_.ts_s);
        return;
    }
    // The PWM form's instants of the whole period (apply_to_plant set them for one piece), split:
    // part j starts in the state the earlier instants left and takes those in [t0, t1), shifted
    // to its start (the last part also those at or beyond its end, which act there).
    const bool pwm = inverter_ != PLANT_INVERTER_IDEAL && active_.form == HAL_CMD_PWM && t1pr_ != 0u;
    plant_leg_edges_t e[3]{};
    if (pwm) {
        for (int x = 0; x < 3; ++x) {
            e[x] = pwm_leg_edges(active_, x);
        }
    }
    const int en = gates_enabled() ? 1 : 0;
    const double h = cfg_.ts_s / substeps_;
    for (int j = 0; j < substeps_; ++j) {
        if (pwm) {
            const double t0 = j * h, t1 = (j + 1) * h;
            plant_leg_edges_t part[3]{};
            for (int x = 0; x < 3; ++x) {
                part[x].state0 = e[x].state0;
                for (int k = 0; k < e[x].n; ++k) {
                    const double t = e[x].t_s[k];
                    if (t < t0) {
                        part[x].state0 ^= 1;
                    } else if (j == substeps_ - 1 || t < t1) {
                        part[x].t_s[part[x].n++] = t - t0;
                    }
                }
            }
            plant_set_leg_edges(plant_, part, en);
        }
        plant_advance(plant_, h);
        if (substep_fn_) {
            substep_fn_(plant_);
        }
    }
}

void Harness::set_ideal_voltage(double v_alpha_v, double v_beta_v)
{
    v_alpha_v_ = v_alpha_v;
    v_beta_v_ = v_beta_v;
}

void Harness::hal_init()
{
    initialised_ = true;
    active_ = hal_cmd_t{};
    pending_ = active_;
    irq_enabled_ = 1;
}

void Harness::hal_read(hal_meas_t* meas)
{
    if (meas == nullptr) {
        return;
    }
    *meas = meas_;
    index_seen_ = false;
    meas_.qep_index_seen = 0u;
}

void Harness::hal_write(const hal_cmd_t* cmd)
{
    if (cmd == nullptr) {
        return;
    }
    ++writes_;
    bool bad = cmd->sa > 1u || cmd->sb > 1u || cmd->sc > 1u || cmd->enable > 1u || cmd->form > HAL_CMD_PWM;
    if (cmd->form == HAL_CMD_PWM) {
        bad = bad || t1pr_ == 0u;
        for (int x = 0; x < 3; ++x) {
            bad = bad || cmd->act[x] > HAL_PWM_UPPER_ACTIVE_LOW;
        }
    }
    bad = bad || cmd->relay > HAL_RELAY_C;
    if (bad) {
        ++invalid_writes_;
    }
    pending_ = *cmd;
    if (cfg_.phases_swapped) {
        // the machine's phase B on leg C and C on leg B: the plant's phase x takes leg x's command
        std::swap(pending_.cmpr_up[1], pending_.cmpr_up[2]);
        std::swap(pending_.cmpr_dn[1], pending_.cmpr_dn[2]);
        std::swap(pending_.act[1], pending_.act[2]);
        std::swap(pending_.sb, pending_.sc);
    }
    written_ = *cmd;
    if (cmd->relay != relay_ && cmd->relay <= HAL_RELAY_C && relay_fitted_ && inverter_ == PLANT_INVERTER_SSTP) {
        // The coil at once (GPIO); the leg it names off from now (both its gates).
        if (relay_ != HAL_RELAY_OPEN) {
            plant_set_leg_override(plant_, relay_ - 1, PLANT_LEG_NORMAL);
        }
        relay_ = cmd->relay;
        plant_set_relay(plant_, relay_);
        if (relay_ != HAL_RELAY_OPEN) {
            plant_set_leg_override(plant_, relay_ - 1, PLANT_LEG_DIODE_ONLY);
        }
    }
}

void Harness::hal_gates_off()
{
    ++gates_off_calls_;
    active_.enable = 0u;
    pending_.enable = 0u;
}

void Harness::hal_trip_clear()
{
    ++trip_clear_calls_;
    if (trip_latched_ && !comparator_active()) {
        trip_latched_ = false;
        trip_cause_ = TripCause::none;
        plant_clear_desat(plant_);
    }
}

std::uint16_t Harness::hal_irq_save()
{
    const std::uint16_t s = irq_enabled_;
    irq_enabled_ = 0;
    return s;
}

void Harness::hal_irq_restore(std::uint16_t state) { irq_enabled_ = state; }

} // namespace hal_host

// ---- hal.h: thin forwarding to the active harness -------------------------------------------
extern "C" {

void hal_init(void) { hal_host::active_or_die("hal_init").hal_init(); }
void hal_read(hal_meas_t* meas) { hal_host::active_or_die("hal_read").hal_read(meas); }
void hal_write(const hal_cmd_t* cmd) { hal_host::active_or_die("hal_write").hal_write(cmd); }
void hal_gates_off(void) { hal_host::active_or_die("hal_gates_off").hal_gates_off(); }
void hal_trip_clear(void) { hal_host::active_or_die("hal_trip_clear").hal_trip_clear(); }
void hal_watchdog_service(void) { hal_host::active_or_die("hal_watchdog_service").hal_watchdog_service(); }
uint16_t hal_pwm_period(void) { return hal_host::active_or_die("hal_pwm_period").hal_pwm_period(); }
uint16_t hal_irq_save(void) { return hal_host::active_or_die("hal_irq_save").hal_irq_save(); }
void hal_irq_restore(uint16_t state) { hal_host::active_or_die("hal_irq_restore").hal_irq_restore(state); }

} // extern "C"
