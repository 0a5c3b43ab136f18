// firmware_si.hpp - the scenario's firmware configuration in SI units (tools/config
// dtc_config_si_t) and the scenario keys a converter refusal names.
#ifndef DTC_SIL_FIRMWARE_SI_HPP
#define DTC_SIL_FIRMWARE_SI_HPP

#include <string>

#include "dtc_config_si.h"
#include "scenario.hpp"

namespace sil {

/// The firmware's SI configuration (tools/config dtc_config_si_t) for a scenario: the scenario's
/// values and variants (the firmware.* keys where given), the speed-PI gains derived
/// (speed_pi_gains) and the ADC scaling of hal_host's sensing chain. dtc_config_from_si() turns it
/// into the firmware's Q-format configuration.
dtc_config_si_t firmware_si_config(const Scenario& sc);

/// The scenario key(s) that set the member a converter refusal names (err.field, its row of
/// tools/config/dtc_si_params.h), as that row's text; "" when none (a null argument, the
/// firmware's own check, a member the runner leaves at the converter's default).
std::string keys_of_refusal(const dtc_si_error_t& err);

} // namespace sil

#endif // DTC_SIL_FIRMWARE_SI_HPP
