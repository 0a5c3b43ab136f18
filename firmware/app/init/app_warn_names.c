/* app_warn_names.c - the warnings' names (app_warn.h), for the background and the host. */
#include "app_warn.h"

const char *app_warn_name(uint16_t bit)
{
    switch (bit) {
#define APP_WARN_NAME_(id, b, name, meaning)                                                       \
    case APP_WARN_##id: return name;
        APP_WARN_LIST(APP_WARN_NAME_)
#undef APP_WARN_NAME_
    default: return "unknown";
    }
}
