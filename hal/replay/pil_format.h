/*
 * pil_format.h - the ISR recording of processor-in-the-loop (docs/pil.md): what the firmware saw
 * through hal.h in each control period and what it commanded, in a compact little-endian binary
 * format that every replay program (host, simavr, qemu) reads and writes with this code alone.
 *
 * File layout (every integer little-endian, fixed width, no padding):
 *   header   PIL_HEADER_BYTES:
 *              0  magic "DPIL" (4 bytes)
 *              4  u16 version (PIL_VERSION)
 *              6  u16 number of configuration fields n (PIL_CONFIG_FIELDS)
 *              8  u16 input record bytes (PIL_IN_BYTES)
 *             10  u16 output record bytes (PIL_OUT_BYTES)
 *             12  u16 T1PR, what hal_pwm_period() returned when recording
 *             14  u16 reserved, 0
 *             16  u32 number of ISRs recorded
 *   config   n x u32: the fields of dtc_config_t in the order of their parameter rows
 *            (firmware/dtc/dtc_param.h: the common part from version and law on, then the part
 *            of the law, zero-padded to n), the field's bits zero-extended to 32 bits
 *            (a 16-bit signed field is stored as its 16-bit pattern). Enough to rebuild the
 *            firmware configuration exactly, with no knowledge of the target's struct layout.
 *   records  per ISR: an input record (PIL_IN_FIELDS, what hal_read() returned) followed by an
 *            output record (PIL_OUT_FIELDS: the last command passed to hal_write(), the number of
 *            hal_write / hal_gates_off / hal_trip_clear calls in the ISR, and the application
 *            status after it).
 * A replay program writes only output records, one per ISR, in the same format.
 *
 * Host, AVR and Cortex-M code: C99, no library calls, correct at 16-bit int. The field lists are
 * X-macros; tools/pil/pil_compare.py reads the names and widths from this file.
 */
#ifndef PIL_FORMAT_H
#define PIL_FORMAT_H

#include <stdint.h>

#include "app_core.h"
#include "dtc_config.h"
#include "hal.h"

#define PIL_VERSION 3U /* 3: the configuration as the common part plus the law's part */
#define PIL_HEADER_BYTES 20U

/* Input record: hal_meas_t, field by field. PIL_IN_U16(name, member) / PIL_IN_U32(...). */
#define PIL_IN_FIELDS(U16, U32)                                                                   \
    U16(adc_ia, adc[HAL_ADC_IA]) U16(adc_ib, adc[HAL_ADC_IB]) U16(adc_ic, adc[HAL_ADC_IC])        \
    U16(adc_vdc, adc[HAL_ADC_VDC]) U16(adc_vmid, adc[HAL_ADC_VMID]) U16(qep_count, qep_count)     \
    U16(qep_index_seen, qep_index_seen) U16(qep_index_count, qep_index_count) U16(trip, trip)     \
    U16(desat, desat) U32(tick, tick)
#define PIL_IN_BYTES 24U

/* Output record, in file order. U16(name) / U32(name): the members of pil_out_t. */
#define PIL_OUT_FIELDS(U16, U32)                                                                  \
    U16(sa) U16(sb) U16(sc) U16(enable) U16(form)                                                 \
    U16(cmpr_up0) U16(cmpr_up1) U16(cmpr_up2) U16(cmpr_dn0) U16(cmpr_dn1) U16(cmpr_dn2)           \
    U16(act0) U16(act1) U16(act2) U16(relay)                                                      \
    U16(writes) U16(gates_off) U16(trip_clear)                                                    \
    U16(state) U16(fault) U16(fault_detail) U32(st_tick) U32(fault_tick)                          \
    U32(ia_iq) U32(ib_iq) U32(ic_iq) U32(vdc_iq) U32(vmid_iq) U16(enc_count)                      \
    U16(vector) U16(sector) U16(flux_up) U16(torque_dem) U16(speed_tick) U16(on_cm)              \
    U16(i_limited) U16(theta_e)                                                                   \
    U32(psi_alpha_iq) U32(psi_beta_iq) U32(te_iq) U32(te_ref_iq) U32(speed_iq) U32(psi_ref_iq)   \
    U32(psir_mag_iq) U16(reconfigured)
#define PIL_OUT_BYTES 118U

/* One output record as numbers (signed quantities as their two's-complement bit pattern). */
typedef struct {
#define PIL_M16(n) uint16_t n;
#define PIL_M32(n) uint32_t n;
    PIL_OUT_FIELDS(PIL_M16, PIL_M32)
#undef PIL_M16
#undef PIL_M32
} pil_out_t;

/* What a replay or the recorder observed of the HAL during one ISR. */
typedef struct {
    hal_cmd_t written; /* the last command passed to hal_write() (zero if none) */
    uint16_t writes;   /* hal_write() calls */
    uint16_t gates_off;
    uint16_t trip_clear;
} pil_hal_obs_t;

typedef struct {
    uint16_t version;
    uint16_t config_fields;
    uint16_t in_bytes;
    uint16_t out_bytes;
    uint16_t t1pr;
    uint32_t isr_count;
} pil_header_t;

enum pil_err {
    PIL_OK = 0,
    PIL_ERR_MAGIC = -1,   /* not a recording */
    PIL_ERR_VERSION = -2, /* another format version */
    PIL_ERR_LAYOUT = -3   /* field count or record sizes differ from this build's */
};

/* Number of u32 configuration fields (version, law, the common part and the longest law part). */
uint16_t pil_config_fields(void);

void pil_header_encode(const pil_header_t *h, uint8_t b[PIL_HEADER_BYTES]);
/* PIL_OK, or an enum pil_err when the header is not one this build can replay. */
int16_t pil_header_decode(const uint8_t b[PIL_HEADER_BYTES], pil_header_t *h);

/* blob: pil_config_fields() * 4 bytes. */
void pil_config_encode(const dtc_config_t *cfg, uint8_t *blob);
void pil_config_decode(const uint8_t *blob, dtc_config_t *cfg);

void pil_in_encode(const hal_meas_t *m, uint8_t b[PIL_IN_BYTES]);
void pil_in_decode(const uint8_t b[PIL_IN_BYTES], hal_meas_t *m);

/* The output record of one ISR from what the HAL saw and the application status after it. */
void pil_out_fill(pil_out_t *o, const pil_hal_obs_t *obs, const app_status_t *st);
void pil_out_encode(const pil_out_t *o, uint8_t b[PIL_OUT_BYTES]);

#endif /* PIL_FORMAT_H */
