/*
 * app_proto_param.h - the dispatcher's parameter commands (PARAM_DESC, PARAM_READ, PARAM_WRITE,
 * PARAMS_SAVE, PARAMS_RESTORE) over the configuration's parameter table, and the application's
 * own parameters (comm_timeout_s). Background only.
 */
#ifndef APP_PROTO_PARAM_H
#define APP_PROTO_PARAM_H

#include <stdint.h>

#include "app_proto.h"

/* rs := the ERROR answer to rq (proto.h PROTO_ERROR: the request's id, code, detail). */
void app_proto_error(const frame_t *rq, frame_t *rs, uint16_t code, int16_t detail);

/* Rows of the protocol's parameter table (the configuration's and the application's). */
uint16_t app_param_count(void);

/* CRC-16/CCITT-FALSE (crc16.h) over every row's id, format, quantity, flags, range and name: the
 * host's cached table is valid while it matches (HELLO's param_table_hash). */
uint32_t app_param_table_hash(void);

/* Answers a parameter, save or restore request rq into rs (an unknown command otherwise). */
void app_proto_param(app_proto_t *p, const frame_t *rq, frame_t *rs);

/* Boot: the newest valid stored parameter set (store.h) becomes the configuration in force; with
 * none (or one the checks refuse) the compiled-in configuration stays. Disarmed (before arming). */
void app_params_boot(app_proto_t *p);

/* The command timeout (comm_timeout_s) in ms, 0 = off: the ISR's limit in periods from it. */
void app_proto_set_timeout_ms(app_proto_t *p, uint16_t ms);

#endif /* APP_PROTO_PARAM_H */
