/*
 * dtc_params.h - the parameters of the linked laws by id: the rows of dtc_param.h of the common
 * part and of each law linked into the image (DTC_LAW_*_LINKED), for the serial protocol and the
 * host tools. Implemented in app/dtc_params.c, which is compiled with the image's law selection:
 * a PM image lists no IM parameter and the reverse.
 *
 * Background code only (the protocol's dispatcher, init); nothing here runs in the 50 us path.
 */
#ifndef DTC_PARAMS_H
#define DTC_PARAMS_H

#include <stdint.h>

#include "dtc_config.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Number of rows of the linked parts, and the row at index i (0 .. count-1: the common part's rows
 * first, then each linked law's part in enum dtc_param_part order), or NULL past the end. */
uint16_t dtc_param_count(void);
const dtc_param_t *dtc_param_at(uint16_t i);

/* The row with parameter id id, or NULL when no linked part has it. */
const dtc_param_t *dtc_param_find(uint16_t id);

/* The rows of the part that holds law's configuration (its u member), or NULL when law is not an
 * enum dtc_law or its law is not linked. */
const dtc_param_list_t *dtc_param_law_list(uint16_t law);

/* 1 when row p belongs to the configuration of law (the common part, or the law's own part). */
uint16_t dtc_param_of_law(const dtc_param_t *p, uint16_t law);

/* Reads row p's raw value from cfg into *raw (U32 values above 2^31 - 1 as their bit pattern).
 * Returns DTC_OK, DTC_ERR_NULL, or DTC_ERR_PART when p is not a row of cfg's law. */
int16_t dtc_param_get(const dtc_config_t *cfg, const dtc_param_t *p, int32_t *raw);

/* Writes raw into row p's field of cfg after checking it: DTC_ERR_READONLY for a derived or board
 * row (DTC_PARAM_RO), DTC_ERR_PART when p is not a row of cfg's law, the row's err when raw is
 * outside [lo, hi] (U32 rows take raw's bit pattern as unsigned). cfg is unchanged on any error.
 * The row's own range only: the relations with other fields are the law's check's (law_check),
 * which the caller runs on the changed copy before applying it. Whether the drive may be running
 * (DTC_PARAM_LIVE) is the caller's to decide. */
int16_t dtc_param_set(dtc_config_t *cfg, const dtc_param_t *p, int32_t raw);

#ifdef __cplusplus
}
#endif

#endif /* DTC_PARAMS_H */
