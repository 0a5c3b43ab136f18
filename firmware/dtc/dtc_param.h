/*
 * dtc_param.h - the one description of every field of the firmware's configuration (dtc_config_t).
 *
 * Each part of the configuration lists its fields once, as an X-macro next to its struct: the
 * common part in dtc_config_common.h (DTC_PARAMS_COMMON), each law's part in its own header
 * (DTC_PARAMS_PM_DTC in pm_dtc_cfg.h, DTC_PARAMS_IM in im_cfg.h, DTC_PARAMS_PM_ITC in
 * pm_itc_cfg.h). A row is
 *
 *   X(id, path, fmt, qty, lo, hi, err, flags, text)
 *
 *   id     stable numeric parameter id (the serial protocol's; never reused): common 1..99, PM DTC
 *          100..199, IM 200..299, PM ITC 300..399
 *   path   the field's member path in dtc_config_t (its name, e.g. speed.kp_iq)
 *   fmt    storage format (enum dtc_param_fmt, without the DTC_PF_ prefix)
 *   qty    what the per-unit value is (enum dtc_param_qty, without DTC_PQ_): which base converts it
 *          to SI and the SI unit (dtc_param_unit)
 *   lo, hi inclusive range of the raw stored value (32-bit integers: U32 fields up to 2^31 - 1)
 *   err    enum dtc_err returned when the value is outside [lo, hi]
 *   flags  DTC_PARAM_RO (derived from other values, or a fact of the board: written only by the
 *          host converter), DTC_PARAM_LIVE (may be changed while the drive runs), or 0 (writable
 *          while the drive is disarmed); DTC_PARAM_RO | DTC_PARAM_STORED: derived, written by the
 *          identification's apply and kept in the stored set
 *   text   one line of meaning (kept in the image only where DTC_PARAM_TEXT is 1)
 *
 * What derives from it: each part's plain range check at init (dtc_param_check_rows, called by
 * dtc_config.c and the laws' checks, which keep only the relations between fields), the parameter
 * access by id of the serial protocol (app/dtc_params.c), the host converter's C emitter and its
 * round trip (tools/config), the ISR recording's configuration blob (hal/replay/pil_format.c), and
 * the parameter table of docs/firmware-core.md (tools/config dtc_config_gen --params-md).
 *
 * Init and background code only: nothing here runs in the 50 us path.
 */
#ifndef DTC_PARAM_H
#define DTC_PARAM_H

#include <stdint.h>

#ifndef DTC_PARAM_TEXT
#define DTC_PARAM_TEXT 0
#endif
/* 0 on a target whose constants take RAM (the AVR): every row's name is "" (the checks then name
 * no field; their codes are unchanged). */
#ifndef DTC_PARAM_NAMES
#define DTC_PARAM_NAMES 1
#endif
#if DTC_PARAM_NAMES
#define DTC_PARAM_NAME_(path_) #path_
#else
#define DTC_PARAM_NAME_(path_) ""
#endif

#ifdef __cplusplus
extern "C" {
#endif

struct dtc_config;

/* Storage format of a field. */
enum dtc_param_fmt {
    DTC_PF_U16 = 0,   /* uint16_t: counts, flags, enums */
    DTC_PF_U32 = 1,   /* uint32_t */
    DTC_PF_Q15 = 2,   /* q15_t (int16_t), value = raw / 2^15 */
    DTC_PF_IQ = 3,    /* iq_t (int32_t), value = raw / 2^FIX_IQ_Q (Q24) */
    DTC_PF_Q31 = 4,   /* q31_t (int32_t), value = raw / 2^31 */
    DTC_PF_ANGLE = 5  /* angle_t (uint16_t), 65536 = one electrical turn */
};

/* What a field's value is: the per-unit base that converts it to SI (dtc_base.h) and its unit.
 * V_b, I_b, w_b are the board's bases (board.v_base_mv, i_base_ma, w_base_mrad_s); psi_b = V_b /
 * w_b, Z_b = V_b / I_b, L_b = Z_b / w_b, T_b = 3/2 p psi_b I_b. */
enum dtc_param_qty {
    DTC_PQ_NONE = 0,    /* a count, flag or enum: the raw value itself */
    DTC_PQ_RATIO = 1,   /* a dimensionless ratio in its Q format */
    DTC_PQ_PU = 2,      /* a per-unit gain with no single SI unit: shown in pu */
    DTC_PQ_V = 3,       /* V_b */
    DTC_PQ_A = 4,       /* I_b */
    DTC_PQ_W = 5,       /* w_b: electrical rad/s */
    DTC_PQ_PSI = 6,     /* psi_b: Wb */
    DTC_PQ_T = 7,       /* T_b: N.m */
    DTC_PQ_Z = 8,       /* Z_b: ohm */
    DTC_PQ_L = 9,       /* L_b: H */
    DTC_PQ_INV_L = 10,  /* 1 / L_b: 1/H */
    DTC_PQ_INV_PSI = 11,/* 1 / psi_b: 1/Wb */
    DTC_PQ_TIME = 12,   /* pu time t w_b: s = value / w_b */
    DTC_PQ_ANGLE = 13,  /* electrical angle, 65536 = 2 pi rad */
    DTC_PQ_A_COUNT = 14,/* I_b per ADC count: A/count */
    DTC_PQ_V_COUNT = 15,/* V_b per ADC count: V/count */
    DTC_PQ_T_W = 16,    /* T_b / w_b: N.m per electrical rad/s */
    DTC_PQ_COUNT = 17
};

#define DTC_PARAM_RO 1U   /* derived or a board fact: not writable by id */
#define DTC_PARAM_LIVE 2U /* may be written while the drive runs */
/* With DTC_PARAM_RO: a derived row the identification writes with the rows it derives from
 * (app_ident_apply.c), kept in the stored parameter set (PARAMS_SAVE) so that a restart keeps it;
 * still not writable by id. */
#define DTC_PARAM_STORED 4U

/* The configuration's parts a row belongs to. */
enum dtc_param_part {
    DTC_PP_COMMON = 0,
    DTC_PP_PM_DTC = 1, /* u.pm_dtc: DTC_LAW_PM_DTC */
    DTC_PP_IM = 2,     /* u.im: DTC_LAW_IM_DTC .. DTC_LAW_IM_DSVM */
    DTC_PP_PM_ITC = 3  /* u.pm_itc: DTC_LAW_PM_ITC */
};

/* A row, packed: the tables are constant data, which the AVR keeps in its 8 KB of RAM (the F2812
 * and the Cortex-M0 in flash): 18 bytes there. */
typedef struct {
    uint16_t id;
    uint16_t offset;      /* offsetof(dtc_config_t, path), in the target's address units */
    unsigned fmt : 3;     /* enum dtc_param_fmt */
    unsigned qty : 5;     /* enum dtc_param_qty */
    unsigned part : 2;    /* enum dtc_param_part */
    unsigned flags : 3;   /* DTC_PARAM_RO, DTC_PARAM_LIVE, DTC_PARAM_STORED */
    int16_t err;          /* enum dtc_err */
    int32_t lo, hi;       /* inclusive raw range; U32 rows within 0 .. 2^31 - 1 */
    const char *name;     /* the path, e.g. "speed.kp_iq" */
#if DTC_PARAM_TEXT
    const char *text;
#endif
} dtc_param_t;

/* A table of rows: the rows of one part, and their number. */
typedef struct {
    const dtc_param_t *rows;
    uint16_t n;
} dtc_param_list_t;

/* The parts' rows, defined by the module that checks the part: the common part by dtc_config.c,
 * the PM DTC's by dtc_check.c, the IM's by im_dtc_check.c, the ITC's by itc_check.c. */
extern const dtc_param_list_t dtc_params_common;
extern const dtc_param_list_t dtc_params_pm_dtc;
extern const dtc_param_list_t dtc_params_im;
extern const dtc_param_list_t dtc_params_pm_itc;

/* The raw value of row p in cfg, widened to 64 bits (U16, U32, ANGLE zero-extended, the others
 * sign-extended). */
int64_t dtc_param_raw(const struct dtc_config *cfg, const dtc_param_t *p);

/* Stores raw into row p's field of cfg, narrowed to the field's format. Range and flags are the
 * caller's to check (dtc_param_in_range, p->flags). Returns 0, or -1 when raw does not fit the
 * field's format (cfg unchanged). */
int16_t dtc_param_store(struct dtc_config *cfg, const dtc_param_t *p, int64_t raw);

/* 1 when raw lies in [p->lo, p->hi]. */
uint16_t dtc_param_in_range(const dtc_param_t *p, int64_t raw);

/* Checks every row of list against cfg, in order. Returns DTC_OK (0), or the first failing row's
 * err with *f (not null) pointed at its name. */
int16_t dtc_param_check_rows(const struct dtc_config *cfg, const dtc_param_list_t *list, const char **f);

/* The SI unit of a quantity ("" for NONE, RATIO, PU). */
const char *dtc_param_unit(uint16_t qty);

/* Row constructors for a part's table (used by the modules that define dtc_params_*). */
#if DTC_PARAM_TEXT
#define DTC_PARAM_ROW(part_, id_, path_, fmt_, qty_, lo_, hi_, err_, flags_, text_)                            \
    {(id_), (uint16_t)offsetof(struct dtc_config, path_), DTC_PF_##fmt_, DTC_PQ_##qty_, (part_), (flags_),    \
     (int16_t)(err_), (int32_t)(lo_), (int32_t)(hi_), DTC_PARAM_NAME_(path_), text_},
#else
#define DTC_PARAM_ROW(part_, id_, path_, fmt_, qty_, lo_, hi_, err_, flags_, text_)                            \
    {(id_), (uint16_t)offsetof(struct dtc_config, path_), DTC_PF_##fmt_, DTC_PQ_##qty_, (part_), (flags_),    \
     (int16_t)(err_), (int32_t)(lo_), (int32_t)(hi_), DTC_PARAM_NAME_(path_)},
#endif

/* Compile-time check that a row's format has its field's size: one member per row, an array of
 * negative length on a mismatch. */
#define DTC_PF_SIZE_U16 2U
#define DTC_PF_SIZE_U32 4U
#define DTC_PF_SIZE_Q15 2U
#define DTC_PF_SIZE_IQ 4U
#define DTC_PF_SIZE_Q31 4U
#define DTC_PF_SIZE_ANGLE 2U
#define DTC_PARAM_SIZE_CHECK(id_, path_, fmt_, qty_, lo_, hi_, err_, flags_, text_)                           \
    char size_ok_##id_[(sizeof(((struct dtc_config *)0)->path_) * (unsigned)CHAR_BIT == DTC_PF_SIZE_##fmt_ * 8U) \
                           ? 1                                                                              \
                           : -1];

#ifdef __cplusplus
}
#endif

/* Defines list_ (a dtc_param_list_t) from a part's X-macro ROWS_, with ROW_ a macro that binds the
 * part (#define ROW_(...) DTC_PARAM_ROW(part, __VA_ARGS__)), and checks each row's format against
 * its field's size at compile time. */
#define DTC_PARAM_TABLE(list_, ROWS_, ROW_)                                                               \
    static const dtc_param_t list_##_rows[] = {ROWS_(ROW_)};                                            \
    const dtc_param_list_t list_ = {list_##_rows, (uint16_t)(sizeof list_##_rows / sizeof list_##_rows[0])}; \
    struct list_##_size_check {                                                                          \
        ROWS_(DTC_PARAM_SIZE_CHECK)                                                                      \
    }

#endif /* DTC_PARAM_H */
