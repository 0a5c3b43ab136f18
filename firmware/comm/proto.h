/*
 * proto.h - command ids and payload layouts of the drive's serial protocol.
 *
 * Transport: frames (frame.h): SOF 0xA5, LEN, CMD, SEQ, payload, CRC-16/CCITT-FALSE. The host
 * sends a request; the drive answers every request it decodes with exactly one frame carrying the
 * same SEQ: either the response, CMD = request | PROTO_RESPONSE, or an error, CMD = PROTO_ERROR.
 * Frames the decoder rejects (bad CRC, LEN) get no answer: the host times out and repeats. The
 * only unsolicited frames are PROTO_TELEMETRY (while the stream is on) with the SEQ of the
 * request that started it.
 *
 * Payload fields are little-endian: u16/i16 two octets, u32/i32 four (frame_put_*, Python
 * struct '<'). "iq" is the firmware's per-unit format, int32 with FIX_IQ_Q = 24 fraction bits
 * (value = raw / 2^24, fixmath.h) against the bases of the configuration (the parameter table
 * carries them as read-only parameters, so the host converts to SI with what the drive reports).
 * "str" is octets of ASCII, not terminated, its length given by the frame's LEN.
 *
 * Layouts below: offset in octets, type, name. A request payload shorter than its layout is
 * answered with PROTO_ERR_LENGTH; longer is accepted (room for additions at the end).
 *
 * Parameters are addressed by the stable numeric id of the parameter table (the law's parameter
 * description: every parameter with id, name, unit, format, range); the protocol carries every
 * value as i32 raw in the parameter's format.
 *
 * The background loop owns the protocol; the 50 us ISR only records captures and faults
 * (capture.h, faultlog.h).
 */
#ifndef PROTO_H
#define PROTO_H

#include <stdint.h>

#define PROTO_VERSION 1u       /* bumped on any incompatible change of a layout below */
#define PROTO_RESPONSE 0x80u   /* CMD bit 7: a response */
#define PROTO_IDLE_MS 20u      /* a silent line for this long ends a truncated frame (frame.h) */
#define PROTO_BAUD 115200L     /* default line speed: 8 data bits, no parity, 1 stop bit */

enum proto_cmd {
    /* HELLO: who is there.
     *   request: empty
     *   response: 0 u16 proto_version (PROTO_VERSION)
     *             2 u16 firmware_version (major << 8 | minor)
     *             4 u32 param_table_hash (CRC-16/CCITT-FALSE of the parameter table's ids,
     *                   formats, quantities, flags, ranges and names, in the low half: the host's
     *                   cached table is valid while it matches)
     *             8 u16 param_count
     *            10 u16 law (enum dtc_law of the configuration in force)
     *            12 u32 isr_period_ns (the control period)
     *            16 u16 iq_q (FIX_IQ_Q)
     *            18 u16 capture_buf_words32 (CAPTURE_BUF_WORDS32) 20 u16 capture_channels_max
     *            22 u16 frame_max_payload (FRAME_MAX_PAYLOAD)  24 u16 faultlog_entries
     *            26 u32 v_base_mv  30 u32 i_base_ma  34 u32 w_base_mrad_s  38 u16 pole_pairs (the
     *                   configuration's per-unit bases, dtc_base.h: the host's SI conversion) */
    PROTO_HELLO = 0x01,

    /* STATUS: the drive's state.
     *   request: empty
     *   response: 0 u16 state (enum app_state)  2 u16 armed (0/1)  4 u16 fault (enum app_fault, app_fault.h)
     *             6 i16 fault_detail  8 u32 tick (ISR count)
     *            12 iq speed  16 iq speed_ref  20 iq te_est  24 iq te_ref
     *            28 iq psi_mag_est  32 iq vdc  36 iq vmid
     *            40 u16 mode (PROTO_MODE_*)  42 u16 faultlog_count (faults recorded since boot)
     *            44 u16 rx_frames 46 u16 rx_crc_errors (frame_dec_stats_t, wrapping counters) */
    PROTO_STATUS = 0x02,

    /* PARAM_DESC: the description of one parameter, by position 0..param_count-1.
     *   request: 0 u16 index
     *   response: 0 u16 index  2 u16 id  4 u16 format (fraction bits of the raw value; 0 = integer)
     *             6 u16 flags (PROTO_PARAM_*)  8 i32 min_raw  12 i32 max_raw  16 i32 default_raw
     *            20 u16 base (enum proto_base: SI value = raw / 2^format * base)
     *            22 u16 name_len  24 str name (name_len octets)  then str unit (the rest)
     *   PROTO_ERR_RANGE for an index >= param_count. */
    PROTO_PARAM_DESC = 0x10,
    /* PARAM_READ: the value in force.
     *   request: 0 u16 id          response: 0 u16 id  2 i32 value_raw */
    PROTO_PARAM_READ = 0x11,
    /* PARAM_WRITE: range-checked, adopted through the shadow set at the ISR's next step.
     *   request: 0 u16 id  2 i32 value_raw
     *   response: 0 u16 id  2 i32 value_raw (as adopted)
     *   errors: PROTO_ERR_PARAM_ID, PROTO_ERR_RANGE, PROTO_ERR_ARMED (flag PROTO_PARAM_DISARMED_ONLY) */
    PROTO_PARAM_WRITE = 0x12,

    /* ARM: gates enabled. Refused (PROTO_ERR_REFUSED, detail enum proto_refusal) unless the
     * calibration is done, the DC link in range, no fault latched and the references are zero.
     *   request: empty             response: empty */
    PROTO_ARM = 0x20,
    /* DISARM: torque to zero, gates off. Always accepted.   request/response: empty */
    PROTO_DISARM = 0x21,
    /* SPEED_REF: speed mode with this reference.  request: 0 iq speed_ref  response: same */
    PROTO_SPEED_REF = 0x22,
    /* TORQUE_REF: torque mode with this reference. request: 0 iq te_ref     response: same */
    PROTO_TORQUE_REF = 0x23,
    /* FAULT_CLEAR: clear a latched fault (the fault log keeps it). request/response: empty;
     * PROTO_ERR_REFUSED when the fault cannot be cleared (configuration). */
    PROTO_FAULT_CLEAR = 0x24,

    /* TELEMETRY_START: unsolicited PROTO_TELEMETRY frames every decim ISR periods (at most what
     * the line carries: the drive raises decim to fit the baud rate and answers with it).
     *   request: 0 u16 decim  2 u16 count (0..4)  4 u16 quantity[count] (enum capture_quantity)
     *   response: 0 u16 decim (in force) */
    PROTO_TELEMETRY_START = 0x30,
    /* TELEMETRY_STOP.  request/response: empty */
    PROTO_TELEMETRY_STOP = 0x31,
    /* TELEMETRY (drive -> host, unsolicited): 0 u32 tick  4 i32 value[count] */
    PROTO_TELEMETRY = 0x32,

    /* CAPTURE_SETUP: capture.h capture_setup(); arms the capture.
     *   request: 0 u16 count (1..CAPTURE_CHANNELS)  2 u16 quantity[4] (unused ones ignored)
     *           10 u16 samples  12 u16 pre  14 u16 decim (1 = every ISR)
     *           16 u16 trigger (enum capture_trigger)  18 u16 trigger_channel (0..count-1)
     *           20 i32 level (in the channel's format)
     *   response: empty; PROTO_ERR_RANGE when capture_setup() refuses (detail: its code) */
    PROTO_CAPTURE_SETUP = 0x40,
    /* CAPTURE_STATUS.
     *   request: empty
     *   response: 0 u16 state (enum capture_state)  2 u16 samples  4 u16 count
     *             6 u32 first_tick (tick of sample 0)  10 u16 decim */
    PROTO_CAPTURE_STATUS = 0x41,
    /* CAPTURE_READ: samples in time order, sample 0 the oldest (pre-trigger first).
     *   request: 0 u16 first_sample  2 u16 n_samples
     *   response: 0 u16 first_sample  2 u16 n_samples (clipped to what fits: n_samples * count
     *             * 4 + 4 <= FRAME_MAX_PAYLOAD)  4 i32 value[n_samples][count] (sample-major)
     *   PROTO_ERR_STATE unless the capture is done. */
    PROTO_CAPTURE_READ = 0x42,
    /* CAPTURE_STOP: back to off. request/response: empty */
    PROTO_CAPTURE_STOP = 0x43,

    /* FAULTLOG_READ: entry k, 0 = the newest (faultlog.h).
     *   request: 0 u16 k
     *   response: 0 u16 k  2 u16 recorded (total since boot)  4 u32 tick  8 u16 reason
     *            10 i16 detail  12 iq ia  16 iq ib  20 iq ic  24 iq vdc  28 iq vmid
     *            32 iq speed  36 iq psi_alpha  40 iq psi_beta  44 iq te_est  48 iq te_ref
     *            52 iq speed_ref  56 u16 sector  58 u16 vector  60 u16 state
     *   PROTO_ERR_RANGE when fewer than k + 1 entries are held. */
    PROTO_FAULTLOG_READ = 0x50,

    /* PARAMS_SAVE: the parameters in force to the storage medium (store.h). Disarmed only.
     *   request: empty    response: 0 u32 sequence of the copy written */
    PROTO_PARAMS_SAVE = 0x60,
    /* PARAMS_RESTORE: source 0 = the newest valid stored copy, 1 = the compiled-in configuration.
     * Disarmed only.  request: 0 u16 source    response: 0 u16 source (loaded) */
    PROTO_PARAMS_RESTORE = 0x61,

    /* IDENTIFY: the self-commissioning's identification (app_ident.h, docs/commissioning.md).
     *   request: 0 u16 sub (PROTO_IDENT_START, PROTO_IDENT_STATUS, PROTO_IDENT_RESULT)
     *   START: from READY under the arm's conditions (PROTO_ERR_REFUSED, detail enum
     *          proto_refusal; PROTO_REFUSE_LAW unless the law is a PM or an IM law; PROTO_ERR_ARMED while
     *          armed): a fresh calibration, then the identification with the gates driven by
     *          it; DISARM stops it.   response: 0 u16 sub
     *   STATUS: response: 0 u16 sub  2 u16 step (enum app_ident_step)  4 u16 fail (enum
     *          app_ident_fail)  6 u16 fail_step  8 i16 fail_detail  10 u16 state (enum app_state)
     *   RESULT: the results so far (complete when step is APP_IDENT_DONE), app_ident_result_t:
     *          response: 0 u16 sub  2 u16 step  4 u16 axis (angle_t)  6 iq r (R_s + R_on, pu of
     *          Z_b = V_b / I_b)  10 iq v0 (pu of V_b)  14 iq l_ts (L / (Z_b Ts))  18 u16 pole_pairs
     *          20 u16 enc_reversed  22 u16 enc_offset (angle_t)  24 i32 counts_per_turn
     *          28 u32 ticks[1..3] (control periods of the steps RS, LS, ENCODER)
     *          40 iq level_i[4]  56 iq level_v[4] (the R fit's points, pu)
     *          72 iq psi (psi_m, pu of V_b / w_b)  76 i32 j_q12  80 iq b  84 iq tc (J, viscous and
     *          Coulomb friction over k_t, app_ident_result_t's units)  88 u32 ticks[6] (SPIN)
     *          92 u16 machine (0 PM, 1 induction machine; then pole_pairs and enc_reversed are
     *          the rotating field's, psi is L_s i_d and k_t = 1.5 p L_M i_d, app_ident.h)
     *          94 iq ls_ts  98 iq lsig_ts (L_s, sigma L_s as L / (Z_b Ts))  102 i32 taur_q4
     *          (tau_r, control periods Q4)  106 iq rr (R_r, pu of Z_b)  110 iq id (the spin's
     *          magnetising current, pu) (app_ident_im.h; 0 on a PM machine)
     *          114 u16 lq_q12 (L_q / L_d, Q12, from step LS's q-axis square wave; 0 until measured
     *          and on an IM)  116 u16 salient (1: |L_q - L_d| > L_d / 16, app_ident.h)
     *   PROTO_ERR_RANGE for another sub. */
    PROTO_IDENTIFY = 0x70,
    /* IDENT_APPLY: the finished identification's results into the parameters in force (app_ident.h
     * app_ident_apply: R_s, the dead time, pole pairs with the encoder gain and direction; on a PM
     * DTC configuration L_s and 1/L_s, psi_m and the encoder's offset, on an IM law's the IM rows
     * derived from R_r, sigma L_s and L_s and those the converter designs from its settings held
     * in u.im.design (the current and torque limits, the magnetisation, the DSVM band, the DFOC
     * current PI, the encoder plausibility); the speed PI's gains and the lost-encoder level from
     * the identified J with speed.speed_bw_iq > 0; app_ident_apply.c), checked by its law's check
     * and applied as a PARAM_WRITE is while disarmed (calibration, then READY); PARAMS_SAVE stores
     * them. Disarmed only.   request: empty    response: 0 u16 rows written (enum
     * app_ident_apply_err APP_IDENT_APPLY_OK: the count of configuration rows whose value changed)
     *   errors: PROTO_ERR_ARMED; PROTO_ERR_STATE (detail APP_IDENT_APPLY_NOT_DONE: no finished
     *   identification); PROTO_ERR_REFUSED (detail PROTO_REFUSE_LAW: the identification's machine
     *   is not the law's: a PM's on other than the PM DTC law, an IM's on other than an IM law);
     *   PROTO_ERR_RANGE (detail: enum app_ident_apply_err APP_IDENT_APPLY_RS ..
     *   APP_IDENT_APPLY_DEADTIME, APP_IDENT_APPLY_IM or APP_IDENT_APPLY_J, a derived value outside
     *   its row, positive;
     *   or the law's check's enum dtc_err code, negative). */
    PROTO_IDENT_APPLY = 0x71,

    /* ERROR (drive -> host): the request was not carried out.
     *   0 u16 request_cmd  2 u16 code (enum proto_err)  4 i16 detail */
    PROTO_ERROR = 0x7F
};

enum proto_err {
    PROTO_ERR_UNKNOWN_CMD = 1, /* no such command id */
    PROTO_ERR_LENGTH = 2,      /* payload shorter than the command's layout */
    PROTO_ERR_PARAM_ID = 3,    /* no parameter with that id */
    PROTO_ERR_RANGE = 4,       /* a value outside its range (detail: field offset or a code) */
    PROTO_ERR_ARMED = 5,       /* refused while armed */
    PROTO_ERR_REFUSED = 6,     /* the drive's state does not allow it (detail: enum proto_refusal) */
    PROTO_ERR_STATE = 7,       /* not now (e.g. capture not done) */
    PROTO_ERR_STORE = 8,       /* the storage medium failed (detail: enum store_status) */
    PROTO_ERR_READ_ONLY = 9    /* PARAM_WRITE of a read-only parameter (PROTO_PARAM_READ_ONLY) */
};

/* Why ARM (or FAULT_CLEAR) was refused: PROTO_ERR_REFUSED's detail. */
enum proto_refusal {
    PROTO_REFUSE_NOT_CALIBRATED = 1,
    PROTO_REFUSE_VDC_RANGE = 2,
    PROTO_REFUSE_FAULT = 3,
    PROTO_REFUSE_REF_NONZERO = 4,
    PROTO_REFUSE_CONFIG = 5,
    PROTO_REFUSE_LAW = 6, /* IDENTIFY: the identification is for the PM and the IM laws (app_ident.h) */
    PROTO_REFUSE_VMID_RANGE = 7 /* FSTP, mid-point measured: the split link's mid-point off V_dc / 2 */
};

/* IDENTIFY sub-commands. */
enum proto_ident_sub {
    PROTO_IDENT_START = 0,
    PROTO_IDENT_STATUS = 1,
    PROTO_IDENT_RESULT = 2
};

/* STATUS mode. */
enum proto_mode {
    PROTO_MODE_SPEED = 0,
    PROTO_MODE_TORQUE = 1
};

/* PARAM_DESC base: what a parameter's value (raw / 2^format) is multiplied by for SI. The
 * per-unit bases are HELLO's (dtc_base.h); RPM: a per-unit electrical speed as mechanical rpm
 * (w_base / pole_pairs * 60 / 2 pi); TURN: an angle_t (a turn = 2 pi rad; format 16). */
enum proto_base {
    PROTO_BASE_ONE = 0,   /* dimensionless, or already SI */
    PROTO_BASE_V = 1,     /* V_base */
    PROTO_BASE_I = 2,     /* I_base */
    PROTO_BASE_W = 3,     /* w_base, electrical rad/s */
    PROTO_BASE_PSI = 4,   /* psi_base */
    PROTO_BASE_T = 5,     /* T_base */
    PROTO_BASE_Z = 6,     /* Z_base */
    PROTO_BASE_L = 7,     /* L_base */
    PROTO_BASE_S = 8,     /* t_base = 1 / w_base */
    PROTO_BASE_RPM = 9,   /* per-unit speed as mechanical rpm */
    PROTO_BASE_TURN = 10, /* 2 pi rad */
    PROTO_BASE_MILLI = 11, /* 1e-3 (milli-units: ms, mV, mA) */
    PROTO_BASE_INV_L = 12, /* 1 / L_base */
    PROTO_BASE_INV_PSI = 13, /* 1 / psi_base */
    PROTO_BASE_T_W = 14   /* T_base / w_base: N.m per electrical rad/s */
};

/* PARAM_DESC flags. */
#define PROTO_PARAM_READ_ONLY 0x0001u     /* a measured or derived value (e.g. the bases) */
#define PROTO_PARAM_DISARMED_ONLY 0x0002u /* writing it while armed is refused (PROTO_ERR_ARMED) */
#define PROTO_PARAM_STORED 0x0004u        /* part of the stored set (PARAMS_SAVE); with READ_ONLY: a
                                           * derived row IDENT_APPLY writes */

#endif /* PROTO_H */
