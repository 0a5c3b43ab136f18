// controller_firmware.cpp - the unchanged firmware (firmware/app + firmware/dtc) as the SIL controller.
//
// Built only when firmware/dtc/dtc.h and the SI -> Q-format converter target (dtc_config_si) exist
// (tools/sil/CMakeLists.txt; switch off with -DDTC_SIL_FIRMWARE_ADAPTER=OFF). The firmware talks to
// the plant only through hal.h, i.e. through the active hal_host::Harness; this adapter calls its
// three entry points (firmware/app/app.h) and reads its estimates for the trace.
//
// INTEGRATION POINTS (written before the firmware existed; the lead engineer completes them):
//   (1) build_config(): FirmwareSiConfig -> dtc_config_t through the converter of tools/config.
//   (2) read_estimates(): the firmware's estimated torque and stator flux, converted from per-unit
//       to SI with the bases of firmware/dtc (the torque/flux the firmware logs from dtc_step).
//   (3) fault_code(): the app state machine's latched fault reason, as text.
#include <string>

extern "C" {
#include "app.h"
#include "dtc.h"
}

#include "controller_adapter.hpp"
#include "hal_host.hpp"

namespace sil {

namespace {

class FirmwareController final : public Controller {
public:
    explicit FirmwareController(const Scenario& sc) : si_(firmware_si_config(sc)) {}

    std::string init(hal_host::Harness& h) override
    {
        (void)h;
        std::string err;
        if (!build_config(&err)) {
            return "firmware configuration: " + err;
        }
        const int16_t rc = app_init(&cfg_);
        if (rc != 0) {
            return "app_init() refused the configuration (code " + std::to_string(rc) + ")";
        }
        return "";
    }

    void step(hal_host::Harness& h) override
    {
        (void)h;
        app_isr();        // hal_read() -> dtc_step() -> hal_write(), inside the firmware
        app_background(); // one pass of the background loop per period (watchdog, shadow set)
        read_estimates();
    }

    ControllerEstimates estimates() const override { return est_; }
    std::string fault() const override { return fault_code(); }
    bool has_estimates() const override { return true; }

private:
    // (1) INTEGRATION: convert si_ with tools/config's dtc_config_si into cfg_; return false with
    // its error text when it refuses a value.
    bool build_config(std::string* err)
    {
        (void)err;
        return false;
    }
    // (2) INTEGRATION: fill est_ from the firmware's logged estimates (per-unit -> SI).
    void read_estimates() { est_.valid = false; }
    // (3) INTEGRATION: the latched fault reason of firmware/app, "none" while running.
    std::string fault_code() const { return "none"; }

    FirmwareSiConfig si_;
    dtc_config_t cfg_{};
    ControllerEstimates est_{};
};

} // namespace

std::unique_ptr<Controller> make_firmware_controller(const Scenario& sc, std::string* err)
{
    (void)err;
    return std::make_unique<FirmwareController>(sc);
}

} // namespace sil
