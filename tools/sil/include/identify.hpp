// identify.hpp - dtc-sil identify: the firmware's self-commissioning on a scenario's rig
// (firmware/app/app_ident.h, docs/commissioning.md).
#ifndef DTC_SIL_IDENTIFY_HPP
#define DTC_SIL_IDENTIFY_HPP

#include <string>

#include "scenario.hpp"

namespace sil {

struct IdentifyReport {
    double max_time_s = 10.0; // the whole sequence's time limit (the identification then fails: timeout)
    bool ok = false;
    std::string failed_step;  // "rs", "ls", "encoder" (empty when ok)
    std::string reason;       // the firmware's named reason
    double duration_s = 0.0;
    std::string json;         // identification.json's text
    std::string warning;      // what the user must know beside the values (a salient PM), or empty
};

/// Runs the identification on the scenario's plant (faults included) with the firmware given the
/// board data only, and writes DIR/identified.toml and DIR/identification.json (nothing when
/// out_dir is empty: rep->json only, dtc-sil sweep --identify). False with *err when it could not
/// run or write (a failed identification still writes both and returns true with rep->ok = false).
bool identify(const Scenario& sc, const std::string& out_dir, IdentifyReport* rep, std::string* err);

} // namespace sil

#endif // DTC_SIL_IDENTIFY_HPP
