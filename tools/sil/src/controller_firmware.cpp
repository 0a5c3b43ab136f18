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
#include "app_warn.h"
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

namespace {

class FirmwareController final : public Controller {
public:
    explicit FirmwareController(const Scenario& sc) : si_(firmware_si_config(sc)) {}

    std::string init(hal_host::Harness& h) override
    {
        (void)h;
        const dtc_config_si_t& si = si_;
        dtc_si_error_t e;
        if (dtc_config_from_si_err(&si, &cfg_, &e) != DTC_SI_OK) {
            const std::string keys = keys_of_refusal(e);
            return (keys.empty() ? std::string() : keys + ": ") + "firmware configuration refused (" +
                   std::to_string(e.code) + "): " + e.msg;
        }
        char msg[256] = {0};
        dtc_bases_from_si(&si, &bases_);
        te_scale_ = bases_.t_base_nm / kIqOne;
        psi_scale_ = bases_.psi_base_wb / kIqOne;
        ts_s_ = si.ts_s;
        hal_init(); // board bring-up, as main() does on the DSP before the ISR is enabled
        const int16_t init_rc = app_init(&cfg_);
        if (init_rc != 0) {
            return "app_init() refused the configuration (dtc_err " + std::to_string(init_rc) + ")";
        }
        if (si.reconfig_relay != 0) {
            // the same drive as an FSTP with the failed phase on the mid-point (dtc_config_post_fault_si)
            dtc_config_si_t post_si;
            if (dtc_config_post_fault_si(&si, &post_si) != DTC_SI_OK) {
                return "inverter.reconfig_relay: the post-fault configuration needs the PM DTC or the IM switching-table DTC (control.scheme = \"dtc\") on the SSTP";
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
    std::vector<std::string> warnings() const override
    {
        refresh();
        std::vector<std::string> w;
        for (std::uint16_t b = 0; b < APP_WARN_COUNT_; ++b) {
            if ((st_.warnings >> b) & 1u) {
                w.emplace_back(app_warn_name(b));
            }
        }
        return w;
    }
    double warning_time_s() const override
    {
        refresh();
        return st_.warnings != 0u ? static_cast<double>(st_.warn_tick) * ts_s_ : -1.0;
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
    double ts_s_ = 0.0;      // control period, s (the ticks' time)
};

} // namespace

std::unique_ptr<Controller> make_firmware_controller(const Scenario& sc, std::string* err)
{
    (void)err;
    return std::make_unique<FirmwareController>(sc);
}

} // namespace sil
