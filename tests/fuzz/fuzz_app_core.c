/*
 * fuzz_app_core.c - libFuzzer harness of the application ISR (firmware/app/app_core.c).
 *
 * One input = one drive life: a configuration, then a sequence of raw measurements (hal_meas_t)
 * with background actions between them, fed to app_core_step exactly as app.c does on the DSP.
 * Every invariant below aborts (a libFuzzer crash); the build adds ASan and UBSan without
 * recovery, so undefined behaviour and memory errors are crashes too. docs/fuzzing.md has the
 * input layout, the invariants and how to run it.
 *
 * Input layout (bytes past the end read as 0, so every input is valid):
 *   config   fuzz_config(): 6 bytes choose a base configuration from the host converter
 *            (tools/config dtc_config_from_si: law, topology, estimator, compensation, table,
 *            scheme, flags, references), then a patch count and that many raw field writes into
 *            the resulting dtc_config_t (field from the parameter rows, firmware/dtc/dtc_param.h).
 *   session  1 byte: bit 0 ADC codes may take any 16-bit value (else the HAL's 12-bit contract),
 *            bit 1 encoder counts may take any 16-bit value (else 0..counts-1), bit 2 the timer
 *            period T1PR from 2 bytes (else 3750, the F2812 at 150 MHz and 50 us), bit 3 the
 *            first tick from 4 bytes (wrap-around).
 *   records  until the input or FUZZ_MAX_PERIODS periods run out: see run_record().
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_core.h"
#include "dtc_config_si.h"
#include "fuzz_reader.h"
#include "hal.h"
#include "law.h"
#include "swtab.h"

/* Longest drive life per input, control periods: the FSTP mid-point calibration (1024 periods)
 * plus the hold's settling and some RUN periods. */
#define FUZZ_MAX_PERIODS 4096U


#define FUZZ_CHECK(cond, ...)                                                                      \
    do {                                                                                          \
        if (!(cond)) {                                                                            \
            fprintf(stderr, "fuzz_app_core: invariant failed: %s: ", #cond);                      \
            fprintf(stderr, __VA_ARGS__);                                                         \
            fputc('\n', stderr);                                                                  \
            abort();                                                                              \
        }                                                                                         \
    } while (0)

/* ---- configuration -------------------------------------------------------------------------- */

/* Every field of dtc_config_t, from the same X-macro list the emitter and the replay blob use. */
typedef struct {
    size_t off, size;
} fuzz_field_t;

/* Every configuration field, of every law's part (the parameter rows, dtc_param.h), filled in
 * from the rows at the first run. */
static fuzz_field_t fuzz_fields[256];
static size_t fuzz_nfields;

static void fuzz_fields_init(void)
{
    const dtc_param_list_t *lists[4] = {&dtc_params_common, &dtc_params_pm_dtc, &dtc_params_im, &dtc_params_pm_itc};
    size_t l, k;
    if (fuzz_nfields != 0U) {
        return;
    }
    for (l = 0U; l < 4U; l++) {
        for (k = 0U; k < lists[l]->n && fuzz_nfields < sizeof fuzz_fields / sizeof fuzz_fields[0]; k++) {
            const dtc_param_t *p = &lists[l]->rows[k];
            fuzz_fields[fuzz_nfields].off = p->offset;
            fuzz_fields[fuzz_nfields].size =
                p->fmt == DTC_PF_U16 || p->fmt == DTC_PF_Q15 || p->fmt == DTC_PF_ANGLE ? 2U : 4U;
            fuzz_nfields++;
        }
    }
}
#define FUZZ_NFIELDS fuzz_nfields

/* Reads a field as a signed 64-bit value (its stored type's width and signedness do not matter
 * for the patch modes below, which write back the low bytes). */
static int64_t field_get(const dtc_config_t *cfg, const fuzz_field_t *f)
{
    const uint8_t *b = (const uint8_t *)cfg + f->off;
    if (f->size == 2U) {
        int16_t v;
        memcpy(&v, b, 2U);
        return v;
    }
    {
        int32_t v;
        memcpy(&v, b, 4U);
        return v;
    }
}

static void field_set(dtc_config_t *cfg, const fuzz_field_t *f, int64_t v)
{
    uint8_t *b = (uint8_t *)cfg + f->off;
    if (f->size == 2U) {
        const uint16_t u = (uint16_t)(uint64_t)v;
        memcpy(b, &u, 2U);
    } else {
        const uint32_t u = (uint32_t)(uint64_t)v;
        memcpy(b, &u, 4U);
    }
}

/* One raw patch: a field and a value derived from its present value or from the input. */
static void patch_field(dtc_config_t *cfg, rd_t *r)
{
    const fuzz_field_t *f = &fuzz_fields[rd_u8(r) % FUZZ_NFIELDS];
    const uint8_t mode = rd_u8(r);
    const int64_t v = field_get(cfg, f);
    switch (mode & 7U) {
    case 0: field_set(cfg, f, (int64_t)rd_u32(r)); break;                     /* anything */
    case 1: field_set(cfg, f, 0); break;
    case 2: field_set(cfg, f, (int8_t)rd_u8(r)); break;                       /* small */
    case 3: field_set(cfg, f, v + (int8_t)rd_u8(r)); break;                   /* near it */
    case 4: field_set(cfg, f, v * (int64_t)(1U << (rd_u8(r) & 15U))); break; /* larger */
    case 5: field_set(cfg, f, v >> (rd_u8(r) & 31U)); break;                  /* smaller */
    case 6: field_set(cfg, f, f->size == 2U ? 0xFFFF : INT32_MAX); break;
    default: field_set(cfg, f, -v); break;
    }
}

/* The base configuration: the host converter's defaults for the law, the variants chosen by the
 * input. A combination the converter refuses falls back to the law's defaults (that is the
 * converter's business; the firmware sees only accepted structs here and patched ones below). */
static void base_config(rd_t *r, dtc_config_t *cfg, dtc_config_t *post, uint16_t *has_post)
{
    static const double rpm_frac[4] = {0.0, 0.5, -1.0, 1.1};
    dtc_config_si_t si;
    const uint8_t b0 = rd_u8(r), b1 = rd_u8(r), b2 = rd_u8(r), b3 = rd_u8(r), b4 = rd_u8(r);
    const uint8_t b5 = rd_u8(r); /* fault detection and tolerance */
    const int im = (b0 & 1U) != 0U;

    if (im) {
        dtc_config_si_im_defaults(&si);
        si.law = DTC_LAW_IM_DTC + (b0 >> 1) % 5;   /* DTC, DSC, SFVC, DFOC, DSVM */
        si.estimator = (b0 & 0x10U) != 0U ? DTC_EST_VOLTAGE : DTC_EST_IMPROVED;
        si.sstp_table = (b0 >> 5) % 6;             /* BASIC .. ST_SPEED */
        si.speed_sensor = (b1 & 1U) != 0U ? DTC_SPEED_NONE : DTC_SPEED_ENCODER;
        si.flux_weakening = (b1 >> 1) & 1;
        si.svm_mode = (b1 >> 2) & 1;
        if (si.law == DTC_LAW_IM_SFVC || si.law == DTC_LAW_IM_DFOC || (b1 & 8U) != 0U) {
            si.psir_ref_wb = 0.53;
        }
        if (si.law == DTC_LAW_IM_SFVC || si.law == DTC_LAW_IM_DFOC) {
            si.ts_s = 160e-6;
            si.flux_weakening = 0;
        }
        si.compensation = (b1 & 0x10U) != 0U ? DTC_COMP_NONE : DTC_COMP_SSTP;
        si.tau_w_hi_rpm = (b1 & 0x20U) != 0U ? 300.0 : 0.0;
    } else {
        dtc_config_si_defaults(&si);
        si.topology = (b0 >> 1) & 1;
        si.estimator = (b0 & 4U) != 0U ? DTC_EST_CURRENT : DTC_EST_VOLTAGE;
        if (si.topology == DTC_TOPO_SSTP) {
            static const int comp[3] = {DTC_COMP_NONE, DTC_COMP_SSTP, DTC_COMP_SSTP};
            si.compensation = comp[(b0 >> 3) % 3];
            si.sstp_table = (b0 >> 5) % 5;         /* BASIC .. ST_D */
        } else {
            static const int comp[3] = {DTC_COMP_NONE, DTC_COMP_FSTP_SIMPLE, DTC_COMP_FSTP_PROPOSED};
            si.compensation = comp[(b0 >> 3) % 3];
            si.fstp_vmid_measured = (b0 >> 5) & 1;
            si.vmid_cal = si.fstp_vmid_measured != 0 ? (b0 >> 6) & 1 : 0;
            si.cal_hold = si.vmid_cal != 0 ? (b0 >> 7) & 1 : 0;
        }
        si.delay_comp = b1 & 1;
        if ((b1 & 2U) != 0U && !((b5 & 4U) != 0U && si.topology == DTC_TOPO_SSTP)) {
            si.law = DTC_LAW_PM_ITC; /* the indirect torque control (itc.h); no reconfiguration */
        }
        si.handover_auto = (b1 >> 3) & 1;
        si.handover_speed_rpm = si.handover_auto != 0 ? 0.0 : ((b1 >> 4) & 1) * 300.0;
    }
    si.deadtime_comp = (b1 >> 6) & 1;
    si.polarity_mid = (b1 >> 7) & 1;
    si.lpf_comp = b2 & 1;
    si.dc_supp = (b2 >> 1) & 1;
    si.current_limit_auto = (b2 >> 2) & 1;
    si.mode = (b2 >> 3) & 1;
    si.speed_ref_rpm = rpm_frac[(b2 >> 4) & 3U] * si.speed_limit_rpm;
    si.torque_ref_nm = ((b2 >> 6) & 1) * 0.5 * si.torque_limit_nm;
    si.flux_band_wb = (b3 & 1U) != 0U ? 0.01 * si.flux_ref_wb : 0.0;
    si.torque_band_nm = (b3 & 2U) != 0U ? 0.05 * si.torque_limit_nm : 0.0;
    si.enc_lines = (b3 & 4U) != 0U ? 256 : si.enc_lines;
    si.speed_div = 1 + (b3 >> 3) % 16;
    si.enc_offset_rad = (double)b4 * 0.0245;
    si.i_sensors3 = b5 & 1;
    si.fault_detect = (b5 & 2U) != 0U ? 0 : 1;
    *has_post = 0U;
    if ((b5 & 4U) != 0U && !im && si.topology == DTC_TOPO_SSTP) {
        /* a six-switch board with reconfiguration relays: the post-fault FSTP configuration */
        dtc_config_si_t post_si;
        si.i_sensors3 = 1;
        si.fault_detect = 1;
        si.reconfig_relay = 1;
        si.relay_delay_s = (double)(1U + (b5 >> 3)) * 1e-4; /* 0.1 .. 3.2 ms */
        if (dtc_config_post_fault_si(&si, &post_si) == DTC_SI_OK &&
            dtc_config_from_si(&post_si, post, NULL, 0U) == DTC_SI_OK) {
            *has_post = 1U;
        }
    }
    if (dtc_config_from_si(&si, cfg, NULL, 0U) != DTC_SI_OK) {
        *has_post = 0U;
        if (im) {
            dtc_config_si_im_defaults(&si);
        } else {
            dtc_config_si_defaults(&si);
        }
        FUZZ_CHECK(dtc_config_from_si(&si, cfg, NULL, 0U) == DTC_SI_OK, "defaults refused");
    }
}

/* The configuration and the application's init, as app_init() does it (app.c): the core, then
 * the HAL's timer period. Kept in one function so that a change of the init's signature is one
 * place here. Returns the init's code (0 or enum dtc_err). */
static int16_t fuzz_config_and_init(rd_t *r, app_core_t *a, dtc_config_t *cfg, dtc_config_t *post, uint16_t t1pr)
{
    uint8_t k, n;
    int16_t rc;
    uint16_t has_post;
    base_config(r, cfg, post, &has_post);
    n = rd_u8(r);
    n = (n & 0x80U) != 0U ? (uint8_t)(n & 7U) : 0U; /* raw patches in half the inputs at most */
    for (k = 0U; k < n; k++) {
        patch_field(cfg, r);
    }
    rc = app_core_init(a, cfg);
    if (rc != 0) {
        return rc;
    }
    if (has_post != 0U) {
        rc = app_core_set_reconfig(a, post);
        if (rc != 0) {
            return rc;
        }
    }
    return app_core_set_pwm_period(a, t1pr);
}

/* ---- measurements --------------------------------------------------------------------------- */

typedef struct {
    app_core_t app;
    dtc_config_t cfg;
    dtc_config_t post;     /* the post-fault FSTP configuration, when the base has relays */
    int16_t init_rc;
    uint16_t adc16, enc16; /* session modes */
    uint16_t t1pr;
    uint16_t nominal[HAL_ADC_COUNT];
    hal_meas_t m;
    uint32_t enc_pos;      /* encoder position, counts (mod counts when in range) */
    int32_t enc_vel;       /* counts per period */
    uint32_t periods;
    uint16_t fault_latched; /* a fault was seen at the end of the last step */
    uint16_t fault_code;
    uint16_t clear_pending; /* a clear request was made since the last step */
} fuzz_t;

static uint16_t clamp_adc(int64_t v)
{
    return (uint16_t)(v < 0 ? 0 : v > 4095 ? 4095 : v);
}

/* ADC codes of the nominal operating point: zero currents at the configured offsets, the DC link
 * at 1 pu (the voltage base is the nominal link), the mid-point at half of it. */
static void nominal_codes(fuzz_t *z)
{
    const dtc_board_cfg_t *b = &z->cfg.board;
    const int64_t one = (int64_t)1 << 24;
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        z->nominal[k] = clamp_adc(b->adc_i_offset[k]);
    }
    z->nominal[HAL_ADC_VDC] = clamp_adc(b->adc_vdc_gain_iq > 0 ? b->adc_vdc_offset + one / b->adc_vdc_gain_iq : 2048);
    z->nominal[HAL_ADC_VMID] = clamp_adc(b->adc_vmid_gain_iq > 0 ? b->adc_vmid_offset + one / 2 / b->adc_vmid_gain_iq : 1024);
}

static uint16_t enc_counts(const fuzz_t *z)
{
    return z->cfg.board.enc_counts;
}

static uint16_t enc_fold(const fuzz_t *z, uint32_t v)
{
    const uint16_t counts = enc_counts(z);
    if (z->enc16 != 0U || counts == 0U) {
        return (uint16_t)v;
    }
    return (uint16_t)(v % counts);
}

/* Background actions (app.c: app_request_fault_clear, app_set_refs; the HAL's period). */
static void background(fuzz_t *z, rd_t *r, uint8_t op)
{
    app_core_t *a = &z->app;
    if ((op & 1U) != 0U) {
        a->clear_request = 1U;
        z->clear_pending = 1U;
    }
    if ((op & 2U) != 0U && a->cfg != NULL) { /* app_set_refs: refused without a configuration */
        dtc_refs_t refs;
        const uint8_t sel = rd_u8(r);
        int16_t rc;
        law_refs_get(&a->law, &refs);
        if ((sel & 1U) != 0U) {
            refs.speed_ref_iq = (sel & 2U) != 0U ? (iq_t)rd_u32(r)
                                                 : (iq_t)(((int64_t)a->cfg->speed.speed_limit_iq * (int8_t)rd_u8(r)) / 64);
        }
        if ((sel & 4U) != 0U) {
            refs.torque_ref_iq = (sel & 2U) != 0U ? (iq_t)rd_u32(r)
                                                  : (iq_t)(((int64_t)a->cfg->speed.torque_limit_iq * (int8_t)rd_u8(r)) / 64);
        }
        if ((sel & 8U) != 0U) {
            refs.flux_ref_iq = (sel & 2U) != 0U ? (iq_t)rd_u32(r)
                                                : (iq_t)(((int64_t)a->cfg->speed.flux_ref_iq * (int8_t)rd_u8(r)) / 64);
        }
        if ((sel & 16U) != 0U) {
            refs.kp_iq = (iq_t)rd_u32(r);
            refs.ki_ts_iq = (iq_t)rd_u32(r);
        }
        if ((sel & 32U) != 0U) {
            refs.mode = (sel & 64U) != 0U ? rd_u16(r) : (uint16_t)(refs.mode ^ 1U);
        }
        rc = law_shadow_write(&a->law, &refs);
        FUZZ_CHECK(rc <= 0 && rc >= DTC_ERR_PART, "shadow write returned %d", rc);
    }
    if ((op & 4U) != 0U) {
        const uint16_t t1pr = rd_u16(r);
        const int16_t rc = app_core_set_pwm_period(a, t1pr);
        FUZZ_CHECK(rc == 0 || rc == DTC_ERR_SVM, "set_pwm_period returned %d", rc);
        if (rc != 0) {
            FUZZ_CHECK(a->st.state == APP_STATE_FAULT, "refused period without a fault");
        }
        z->t1pr = t1pr;
    }
}

/* ---- invariants ----------------------------------------------------------------------------- */

static int law_is_pwm(const dtc_config_t *c)
{
    return c->law == DTC_LAW_IM_SFVC || c->law == DTC_LAW_IM_DFOC || c->law == DTC_LAW_IM_DSVM ||
           c->law == DTC_LAW_PM_ITC;
}

static void check_status(const fuzz_t *z)
{
    const app_status_t *s = &z->app.st;
    FUZZ_CHECK(s->state == APP_STATE_CALIBRATE || s->state == APP_STATE_RUN || s->state == APP_STATE_FAULT,
               "state %u", s->state);
    FUZZ_CHECK((s->state == APP_STATE_FAULT) == (s->fault != APP_FAULT_NONE), "state %u fault %u", s->state, s->fault);
    FUZZ_CHECK(s->fault < APP_FAULT_COUNT_, "fault %u", s->fault);
    FUZZ_CHECK(strcmp(app_fault_name(s->fault), "unknown") != 0, "fault %u has no name", s->fault);
    FUZZ_CHECK(s->reconfigured <= HAL_RELAY_C, "reconfigured %u", s->reconfigured);
    switch (s->fault) {
    case APP_FAULT_NONE:
    case APP_FAULT_HW_TRIP:
    case APP_FAULT_DC_OVERVOLTAGE:
    case APP_FAULT_DC_UNDERVOLTAGE:
        FUZZ_CHECK(s->fault_detail == 0, "fault %u detail %d", s->fault, s->fault_detail);
        break;
    case APP_FAULT_CONFIG:
        FUZZ_CHECK(s->fault_detail < 0 && s->fault_detail >= DTC_ERR_PART, "config detail %d", s->fault_detail);
        break;
    case APP_FAULT_ENCODER:
        FUZZ_CHECK(s->fault_detail >= 1 && s->fault_detail <= 3, "encoder detail %d", s->fault_detail);
        break;
    case APP_FAULT_ADC_OFFSET:
        FUZZ_CHECK(s->fault_detail >= 0 && s->fault_detail < HAL_ADC_COUNT, "adc detail %d", s->fault_detail);
        break;
    case APP_FAULT_STALL:
        FUZZ_CHECK(s->fault_detail == 1 || s->fault_detail == -1, "stall detail %d", s->fault_detail);
        break;
    case APP_FAULT_CURRENT_SENSOR: /* 3 * check + phase (app_fault.h APP_SENSOR_DETAIL_LIST) */
        FUZZ_CHECK(s->fault_detail >= 0 && s->fault_detail <= 9, "current_sensor detail %d", s->fault_detail);
        break;
    case APP_FAULT_OVERSPEED:
        FUZZ_CHECK(s->fault_detail == 1 || s->fault_detail == -1, "overspeed detail %d", s->fault_detail);
        break;
    case APP_FAULT_ENCODER_SPEED:
        FUZZ_CHECK(s->fault_detail == 1 || s->fault_detail == -1, "encoder_speed detail %d", s->fault_detail);
        break;
    default: /* per phase / leg / channel */
        FUZZ_CHECK(s->fault_detail >= 0 && s->fault_detail <= 2, "fault %u detail %d", s->fault, s->fault_detail);
        break;
    }
}

static void check_legs_of_vector(const dtc_config_t *c, const hal_cmd_t *cmd, uint16_t vec)
{
    const swtab_legs_t l = c->board.topology == DTC_TOPO_FSTP ? swtab_fstp_legs(vec) : swtab_sstp_legs(vec);
    FUZZ_CHECK(cmd->sa == l.sa && cmd->sb == l.sb && cmd->sc == l.sc,
               "legs %u%u%u are not vector %u's %u%u%u", cmd->sa, cmd->sb, cmd->sc, vec, l.sa, l.sb, l.sc);
}

/* Counts -> pu against a double reference: (count - offset) * gain, saturated to the 32-bit IQ
 * range (app_core.h: the product saturates at +-128 pu). Exact in double: |count - offset| <
 * 2^16 and |gain| < 2^31, so the product is below 2^47. */
static iq_t ref_pu(uint16_t count, uint16_t offset, iq_t gain)
{
    const double v = ((double)count - (double)offset) * (double)gain;
    return v >= 2147483647.0 ? INT32_MAX : v <= -2147483648.0 ? INT32_MIN : (iq_t)v;
}

/* The per-unit measurement of a step that converted this sample (RUN, or the rotor hold). */
static void check_conversion(const fuzz_t *z)
{
    const app_core_t *a = &z->app;
    const dtc_board_cfg_t *b = &a->cfg->board;
    const dtc_meas_t *pu = &a->st.meas;
    const iq_t i[3] = {pu->ia_iq, pu->ib_iq, pu->ic_iq};
    uint16_t k;
    for (k = 0U; k < 3U; k++) {
        /* the law's phase k is the physical channel (perm + k) mod 3 (reconfiguration) */
        const uint16_t ch = (uint16_t)((a->perm + k) % 3U);
        if (b->i_sensors3 == 0U && ch != a->meas_ch[0] && ch != a->meas_ch[1]) {
            continue; /* derived by Kirchhoff */
        }
        FUZZ_CHECK(i[k] == ref_pu(z->m.adc[ch], a->offset[ch], b->adc_i_gain_iq), "current %u: %d for code %u",
                   ch, i[k], z->m.adc[ch]);
    }
    FUZZ_CHECK(pu->vdc_iq == ref_pu(z->m.adc[HAL_ADC_VDC], b->adc_vdc_offset, b->adc_vdc_gain_iq),
               "V_dc %d for code %u", pu->vdc_iq, z->m.adc[HAL_ADC_VDC]);
    /* board.enc_reversed: the drive reads enc_counts - 1 - count for a count in range (app_enc.h) */
    const uint16_t last = (uint16_t)(b->enc_counts - 1U);
    const uint16_t count = b->enc_reversed != 0U && z->m.qep_count <= last ? (uint16_t)(last - z->m.qep_count)
                                                                           : z->m.qep_count;
    FUZZ_CHECK(pu->enc_count == count, "encoder count %u for the counter's %u (reversed %u)", pu->enc_count,
               z->m.qep_count, b->enc_reversed);
}

/* The PWM form does what the law asked: the upper device's duty of each leg, read from the compare
 * values by hal.h's rule (Timer 1 counts 0 -> T1PR -> 0; the output is active from the up-count
 * match at cmpr_up to the down-count match at cmpr_dn, a value above T1PR never matches; act
 * says whether active means the upper or the lower device), equals the law's duty (dtc_out_t
 * duty_iq, clamped to [0, 1]; DSVM: the mean of its thirds) within one timer count, 1/T1PR. */
static void check_pwm_duty(const fuzz_t *z, const hal_cmd_t *cmd)
{
    const double t1pr = (double)z->app.t1pr;
    uint16_t x;
    FUZZ_CHECK(z->app.t1pr > 0U, "PWM form without a timer period");
    for (x = 0U; x < 3U; x++) {
        const double up = cmd->cmpr_up[x] > z->app.t1pr ? 0.0 : (t1pr - cmd->cmpr_up[x]) / (2.0 * t1pr);
        const double dn = cmd->cmpr_dn[x] > z->app.t1pr ? 0.0 : (t1pr - cmd->cmpr_dn[x]) / (2.0 * t1pr);
        const double active = up + dn;
        const double upper = cmd->act[x] == HAL_PWM_UPPER_ACTIVE_HIGH ? active : 1.0 - active;
        double want = (double)z->app.st.out.duty_iq[x] / 16777216.0;
        want = want < 0.0 ? 0.0 : want > 1.0 ? 1.0 : want;
        FUZZ_CHECK(upper - want <= 1.0 / t1pr + 1e-9 && want - upper <= 1.0 / t1pr + 1e-9,
                   "leg %u: compare %u/%u act %u with T1PR %u is duty %.6f, the law asked %.6f", x,
                   cmd->cmpr_up[x], cmd->cmpr_dn[x], cmd->act[x], z->app.t1pr, upper, want);
    }
}

/* The command of one step against the state it leaves (see docs/fuzzing.md for the rules). */
static void check_command(const fuzz_t *z, uint16_t off, const hal_cmd_t *cmd, uint16_t state_before,
                          uint16_t reconf_before)
{
    const app_core_t *a = &z->app;
    const app_status_t *s = &a->st;
    uint16_t x;

    FUZZ_CHECK(off <= 1U, "return %u", off);
    FUZZ_CHECK(cmd->form == HAL_CMD_LEGS || cmd->form == HAL_CMD_PWM, "form %u", cmd->form);
    FUZZ_CHECK(cmd->sa <= 1U && cmd->sb <= 1U && cmd->sc <= 1U, "legs %u %u %u", cmd->sa, cmd->sb, cmd->sc);
    FUZZ_CHECK(cmd->enable <= 1U, "enable %u", cmd->enable);
    FUZZ_CHECK(cmd->relay <= HAL_RELAY_C, "relay %u", cmd->relay);
    FUZZ_CHECK(cmd->relay == s->reconfigured, "relay %u, reconfigured %u", cmd->relay, s->reconfigured);
    for (x = 0U; x < 3U; x++) {
        FUZZ_CHECK(cmd->act[x] <= HAL_PWM_UPPER_ACTIVE_LOW, "act[%u] %u", x, cmd->act[x]);
        if (cmd->form == HAL_CMD_PWM) {
            FUZZ_CHECK((uint32_t)cmd->cmpr_up[x] <= (uint32_t)a->t1pr + 1U && (uint32_t)cmd->cmpr_dn[x] <= (uint32_t)a->t1pr + 1U,
                       "cmpr[%u] %u/%u, T1PR %u", x, cmd->cmpr_up[x], cmd->cmpr_dn[x], a->t1pr);
        }
    }
    FUZZ_CHECK(s->tick == z->m.tick, "tick %u, measured %u", s->tick, z->m.tick);

    if (off != 0U) {
        FUZZ_CHECK(cmd->enable == 0U, "gates off requested with enable = 1");
        FUZZ_CHECK(s->state != APP_STATE_RUN || state_before == APP_STATE_RUN || state_before == APP_STATE_CALIBRATE,
                   "RUN entered on a gates-off step from %u", state_before);
    } else {
        FUZZ_CHECK(s->state == APP_STATE_RUN || s->state == APP_STATE_CALIBRATE, "gates on in state %u", s->state);
    }
    if (s->state == APP_STATE_FAULT) {
        FUZZ_CHECK(off == 1U && cmd->enable == 0U, "FAULT with gates on");
    }
    if (z->init_rc != 0) {
        FUZZ_CHECK(s->state == APP_STATE_FAULT && s->fault == APP_FAULT_CONFIG && s->fault_detail == z->init_rc,
                   "refused configuration (%d) left state %u fault %u", z->init_rc, s->state, s->fault);
    }
    if (cmd->enable == 0U) {
        return;
    }

    if (state_before == APP_STATE_CALIBRATE && s->state != APP_STATE_RUN) {
        /* the rotor hold (app_hold.c app_hold_step): FSTP with the mid-point calibration, legs B and
         * C in opposite states, leg A (the mid-point) never */
        FUZZ_CHECK(z->cfg.board.topology == DTC_TOPO_FSTP && z->cfg.board.vmid_cal != 0U && z->cfg.prot.i_hold_iq > 0,
                   "gates on while calibrating without the hold");
        FUZZ_CHECK(cmd->form == HAL_CMD_LEGS && cmd->sa == 0U && cmd->sb != cmd->sc, "hold command %u%u%u form %u",
                   cmd->sa, cmd->sb, cmd->sc, cmd->form);
        return;
    }
    if (state_before == APP_STATE_CALIBRATE) {
        /* the hold's last period: the calibration ended in this step, the hold command stands */
        FUZZ_CHECK(cmd->form == HAL_CMD_LEGS && cmd->sa == 0U && cmd->sb != cmd->sc, "hold command %u%u%u form %u",
                   cmd->sa, cmd->sb, cmd->sc, cmd->form);
        return;
    }
    FUZZ_CHECK(state_before == APP_STATE_RUN && s->state == APP_STATE_RUN, "gates on from %u to %u", state_before, s->state);

    if (s->reconfigured != 0U) {
        /* after a leg failure (app_core.c reconfigure): the FSTP of Hoang Table II in the frame
         * whose phase A' is the failed phase x; leg x off, legs x+1, x+2 are the vector's B', C'.
         * In the period of the reconfiguration itself the six-switch law's legs with leg x off. */
        const uint16_t ph = (uint16_t)(s->reconfigured - 1U);
        const uint16_t legs[3] = {cmd->sa, cmd->sb, cmd->sc};
        FUZZ_CHECK(ph <= 2U && a->perm == ph && a->cfg == &z->post, "reconfigured %u perm %u", s->reconfigured, a->perm);
        FUZZ_CHECK(cmd->form == HAL_CMD_LEGS && legs[ph] == 0U, "failed leg %u commanded", ph);
        if (reconf_before != 0U) {
            const swtab_legs_t l = swtab_fstp_legs(s->out.vector);
            FUZZ_CHECK(s->out.vector >= 1U && s->out.vector <= 4U, "post-fault vector %u", s->out.vector);
            FUZZ_CHECK(legs[(ph + 1U) % 3U] == l.sb && legs[(ph + 2U) % 3U] == l.sc,
                       "post-fault legs %u%u%u are not vector %u's", cmd->sa, cmd->sb, cmd->sc, s->out.vector);
        }
        return;
    }
    if (z->cfg.board.topology == DTC_TOPO_FSTP && !law_is_pwm(&z->cfg)) {
        /* Hoang Table II: V_1..V_4 on legs B and C; leg A is the mid-point */
        FUZZ_CHECK(cmd->form == HAL_CMD_LEGS && cmd->sa == 0U, "FSTP command uses leg A or PWM");
        FUZZ_CHECK(s->out.vector >= 1U && s->out.vector <= 4U, "FSTP vector %u", s->out.vector);
        FUZZ_CHECK(s->out.sector >= 1U && s->out.sector <= 4U, "FSTP sector %u", s->out.sector);
        check_legs_of_vector(&z->cfg, cmd, s->out.vector);
    } else if (!law_is_pwm(&z->cfg)) {
        FUZZ_CHECK(cmd->form == HAL_CMD_LEGS, "SSTP table law wrote PWM");
        FUZZ_CHECK(s->out.vector <= 7U, "SSTP vector %u", s->out.vector);
        FUZZ_CHECK(s->out.sector >= 1U && s->out.sector <= 6U, "SSTP sector %u", s->out.sector);
        check_legs_of_vector(&z->cfg, cmd, s->out.vector);
    } else {
        FUZZ_CHECK(cmd->form == HAL_CMD_PWM, "SVM law wrote leg states");
        FUZZ_CHECK(cmd->sa == 0U && cmd->sb == 0U && cmd->sc == 0U, "SVM law with leg states");
        check_pwm_duty(z, cmd); /* FSTP (ITC): leg A's compare value is the mid-point's, ignored (hal.h) */
        if (z->cfg.law == DTC_LAW_IM_DSVM) {
            FUZZ_CHECK(s->out.vector <= 36U, "DSVM code %u", s->out.vector);
            FUZZ_CHECK(s->out.sector >= 1U && s->out.sector <= 6U, "DSVM sector %u", s->out.sector);
        } else {
            for (x = 0U; x < 3U; x++) {
                FUZZ_CHECK(cmd->cmpr_up[x] == cmd->cmpr_dn[x] && cmd->act[x] == HAL_PWM_UPPER_ACTIVE_HIGH,
                           "SVM leg %u not a centred pulse", x);
            }
        }
    }
}

/* ---- reach ---------------------------------------------------------------------------------- */

/* With FUZZ_APP_STATS set in the environment the harness prints at exit how many steps each
 * state and, in RUN, each law variant received (which parts of the ISR the inputs reach). */
static uint64_t stat_state[4], stat_run[2][2][5], stat_itc_run[2], stat_inputs, stat_refused, stat_reconf_run;

static void stats_print(void)
{
    static const char *const scheme[5] = {"dtc", "dsc", "sfvc", "dfoc", "dsvm"};
    unsigned t, k;
    fprintf(stderr, "fuzz_app_core: inputs %llu (configuration refused %llu); steps calibrate %llu run %llu fault %llu\n",
            (unsigned long long)stat_inputs, (unsigned long long)stat_refused, (unsigned long long)stat_state[1],
            (unsigned long long)stat_state[2], (unsigned long long)stat_state[3]);
    for (t = 0U; t < 2U; t++) {
        fprintf(stderr, "fuzz_app_core: RUN steps PM %s %llu\n", t != 0U ? "fstp" : "sstp",
                (unsigned long long)stat_run[0][t][0]);
    }
    for (k = 0U; k < 5U; k++) {
        fprintf(stderr, "fuzz_app_core: RUN steps IM %s %llu\n", scheme[k], (unsigned long long)stat_run[1][0][k]);
    }
    fprintf(stderr, "fuzz_app_core: RUN steps PM ITC sstp %llu, fstp %llu\n", (unsigned long long)stat_itc_run[0],
            (unsigned long long)stat_itc_run[1]);
    fprintf(stderr, "fuzz_app_core: RUN steps PM reconfigured (post-fault FSTP) %llu\n",
            (unsigned long long)stat_reconf_run);
}

static void stats_step(const fuzz_t *z)
{
    static int on = -1;
    if (on < 0) {
        on = getenv("FUZZ_APP_STATS") != NULL;
        if (on) {
            atexit(stats_print);
        }
    }
    if (!on) {
        return;
    }
    stat_state[z->app.st.state & 3U]++;
    stat_reconf_run += z->app.st.state == APP_STATE_RUN && z->app.st.reconfigured != 0U;
    if (z->app.st.state == APP_STATE_RUN && z->cfg.law == (uint16_t)DTC_LAW_PM_ITC) {
        stat_itc_run[z->cfg.board.topology & 1U]++;
    } else if (z->app.st.state == APP_STATE_RUN) {
        stat_run[dtc_law_is_im(z->cfg.law)][z->cfg.board.topology & 1U][dtc_law_is_im(z->cfg.law) != 0U ? (z->cfg.law - DTC_LAW_IM_DTC) % 5U : 0U]++;
    }
}

/* ---- one record ----------------------------------------------------------------------------- */

/* Record: op byte (bits 0-2 background actions before the period: clear request, new references,
 * new T1PR; bits 3-7: the measurement holds for 1 + n periods), then the measurement byte:
 *   bits 0-1  ADC deviation scale s: each channel's code = nominal + int8 << (2 s), clamped to
 *             12 bits, one byte per channel (5)
 *   bit 2     instead: raw codes, 2 bytes per channel (12 bits, or 16 in the session's 16-bit mode)
 *   bit 3     trip; bit 4 desaturation (1 byte, legs in bits 0-2)
 *   bit 5     index pulse (2 bytes: latched count)
 *   bit 6     encoder speed change (int8 counts per period)
 *   bit 7     encoder count set (2 bytes)
 * Returns 0 when the input or the period budget ran out. */
static int run_record(fuzz_t *z, rd_t *r)
{
    app_core_t *a = &z->app;
    uint8_t op, mb;
    uint16_t k, rep;

    if (r->n == 0U || z->periods >= FUZZ_MAX_PERIODS) {
        return 0;
    }
    op = rd_u8(r);
    background(z, r, op);
    mb = rd_u8(r);
    if ((mb & 4U) != 0U) {
        for (k = 0U; k < HAL_ADC_COUNT; k++) {
            const uint16_t v = rd_u16(r);
            z->m.adc[k] = z->adc16 != 0U ? v : (uint16_t)(v & 0x0FFFU);
        }
    } else {
        const unsigned sh = 2U * (mb & 3U);
        for (k = 0U; k < HAL_ADC_COUNT; k++) {
            z->m.adc[k] = clamp_adc((int64_t)z->nominal[k] + (int64_t)(int8_t)rd_u8(r) * (1 << sh));
        }
    }
    z->m.trip = (uint16_t)((mb >> 3) & 1U);
    z->m.desat = (mb & 0x10U) != 0U ? (uint16_t)(rd_u8(r) & 7U) : 0U;
    z->m.qep_index_seen = (uint16_t)((mb >> 5) & 1U);
    if (z->m.qep_index_seen != 0U) {
        z->m.qep_index_count = enc_fold(z, rd_u16(r));
    }
    if ((mb & 0x40U) != 0U) {
        z->enc_vel += (int8_t)rd_u8(r);
    }
    if ((mb & 0x80U) != 0U) {
        z->enc_pos = rd_u16(r);
    }

    rep = (uint16_t)(1U + (op >> 3));
    for (k = 0U; k < rep && z->periods < FUZZ_MAX_PERIODS; k++) {
        hal_cmd_t cmd;
        const uint16_t before = a->st.state;
        const uint16_t fault_before = a->st.fault;
        const uint16_t hold_before = a->hold.on;
        const uint16_t reconf_before = a->st.reconfigured;
        uint16_t off;
        const uint16_t counts = enc_counts(z);
        z->enc_pos = (uint32_t)((int64_t)z->enc_pos + z->enc_vel);
        if (counts != 0U && z->enc16 == 0U) {
            z->enc_pos %= counts;
        }
        z->m.qep_count = enc_fold(z, z->enc_pos);
        memset(&cmd, 0xA5, sizeof cmd); /* app.c's command is an uninitialised local */
        off = app_core_step(a, &z->m, &cmd);
        check_status(z);
        check_command(z, off, &cmd, before, reconf_before);
        FUZZ_CHECK(reconf_before == 0U || a->st.reconfigured == reconf_before, "reconfigured twice");
        if ((before == APP_STATE_RUN ||
             (before == APP_STATE_CALIBRATE && hold_before != 0U && z->m.trip == 0U && (z->m.desat & 7U) == 0U)) &&
            a->st.reconfigured == reconf_before) { /* the step that reconfigures converted in the old frame */
            check_conversion(z);
        }
        stats_step(z);
        if (before == APP_STATE_FAULT && z->clear_pending == 0U) {
            FUZZ_CHECK(a->st.state == APP_STATE_FAULT && a->st.fault == fault_before,
                       "fault %u left without a clear request", fault_before);
        }
        if (fault_before == APP_FAULT_CONFIG) {
            FUZZ_CHECK(a->st.state == APP_STATE_FAULT && a->st.fault == APP_FAULT_CONFIG, "config fault cleared");
        }
        FUZZ_CHECK(a->clear_request == 0U, "clear request not adopted");
        z->clear_pending = 0U;
        z->m.tick++;
        z->periods++;
    }
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fuzz_t z; /* app.c's instance is a zero-initialised static too */
    rd_t r = {data, size};
    uint8_t sess;

    memset(&z, 0, sizeof z);
    fuzz_fields_init();
    /* the session byte comes after the configuration bytes, but the period is needed at init:
     * take it from the last two bytes of the input when asked (bit 2 of the session byte) */
    z.t1pr = 3750U;
    z.init_rc = fuzz_config_and_init(&r, &z.app, &z.cfg, &z.post, z.t1pr);
    sess = rd_u8(&r);
    z.adc16 = (uint16_t)(sess & 1U);
    z.enc16 = (uint16_t)((sess >> 1) & 1U);
    if ((sess & 4U) != 0U) {
        z.t1pr = rd_u16(&r);
        if (z.init_rc == 0) {
            z.init_rc = app_core_set_pwm_period(&z.app, z.t1pr);
        }
    }
    if ((sess & 8U) != 0U) {
        z.m.tick = rd_u32(&r);
    }
    if (z.init_rc != 0) {
        /* app_init stops at the first refusal: the core is in FAULT with APP_FAULT_CONFIG */
        FUZZ_CHECK(z.app.st.state == APP_STATE_FAULT && z.app.st.fault == APP_FAULT_CONFIG &&
                       z.app.st.fault_detail == z.init_rc,
                   "refused configuration (%d) not latched", z.init_rc);
    }
    stat_inputs++;
    stat_refused += z.init_rc != 0;
    nominal_codes(&z);
    while (run_record(&z, &r)) {
    }
    return 0;
}
