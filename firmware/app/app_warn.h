/*
 * app_warn.h - the firmware's warnings: conditions the drive reports and runs on (a fault stops
 * it, app_fault.h; a warning does not). The one list of their names: the application's status
 * carries them as bits (app_status_t.warnings, bit APP_WARN_<id>: raised at least once since
 * app_core_init), the host reads them by these names (dtc-sil's metrics.json "warnings").
 *
 *   X(id, bit, name, meaning)
 */
#ifndef APP_WARN_H
#define APP_WARN_H

#include <stdint.h>

#define APP_WARN_LIST(X)                                                                           \
    X(IM_MODEL_MISMATCH, 0, "im_model_mismatch",                                                   \
      "IM laws: the improved estimator's rotor flux and a current model's disagree: the configured " \
      "rotor resistance or magnetising inductance is off the machine's (firmware/dtc/im_sup.h)")

#define APP_WARN_ENUM_(id, bit, name, meaning) APP_WARN_##id = bit,
enum app_warn { APP_WARN_LIST(APP_WARN_ENUM_) APP_WARN_COUNT_ };
#undef APP_WARN_ENUM_

/* The name of warning bit `bit` (APP_WARN_LIST), "unknown" for any other number; never NULL. */
const char *app_warn_name(uint16_t bit);

#endif /* APP_WARN_H */
