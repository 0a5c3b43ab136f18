/*
 * law_io.h - what every control law takes and gives each control period: the per-unit
 * measurements (dtc_meas_t) and the command with the law's estimates for telemetry (dtc_out_t),
 * and the form of the command (enum law_out_form), which a law reports once at init (app/law.h
 * law_out_form). The application converts ADC and QEP counts into dtc_meas_t and the command into
 * the HAL's (hal.h hal_cmd_t: leg states, or compare values of the PWM forms, law.h law_pwm).
 */
#ifndef LAW_IO_H
#define LAW_IO_H

#include <stdint.h>

#include "fixmath.h"

/* The form of a law's command in dtc_out_t. */
enum law_out_form {
    LAW_OUT_LEGS = 0,   /* sa, sb, sc: leg states held over the next period (the DTC laws) */
    LAW_OUT_DUTY = 1,   /* duty_iq: one centred pulse per leg (SVM: IM SFVC, DFOC; svm.h) */
    LAW_OUT_THIRDS = 2  /* thirds: three sub-interval states per leg (IM DSVM, dsvm.h), applied
                         * as one pulse per leg */
};

/* Per-unit measurements of one period (the app converts ADC and QEP counts with the
 * configuration's ADC scaling). Which currents are read (clarke.h): SSTP i_a, i_b; FSTP i_b, i_c;
 * the third field is ignored. */
typedef struct {
    iq_t ia_iq, ib_iq, ic_iq; /* phase currents, pu */
    iq_t vdc_iq;              /* DC-link voltage, pu */
    iq_t vmid_iq;             /* FSTP: lower capacitor (mid-point to negative rail), pu */
    uint16_t enc_count;       /* quadrature counter 0 .. 4*lines - 1 */
} dtc_meas_t;

typedef struct {
    uint16_t sa, sb, sc;   /* leg states for the next period (FSTP: sa = 0, unused) */
    uint16_t vector;       /* SSTP 0..7, FSTP 1..4 (swtab.h); IM DSVM: the code 0..36 (dsvm.h) */
    uint16_t sector;       /* SSTP 1..6, FSTP 1..4 */
    uint16_t flux_up;      /* flux comparator output (1 = increase) */
    int16_t torque_dem;    /* torque comparator output: +1 / 0 / -1 (two-level: +1 / -1) */
    uint16_t speed_tick;   /* 1 when the speed loop ran in this step */
    iq_t psi_alpha_iq, psi_beta_iq; /* estimated stator flux, pu (|psi|: dtc_out_flux_mag) */
    iq_t te_iq;            /* estimated torque (Hoang eq. 10), pu */
    iq_t te_ref_iq;        /* torque reference in force, pu */
    iq_t speed_iq;         /* measured electrical speed, pu */
    angle_t theta_e;       /* encoder electrical angle */
    uint16_t on_cm;        /* 1: the flux came from the current model (estimator = current, or
                            * the voltage model below its hand-over speed) */
    iq_t psi_ref_iq;       /* stator-flux reference in force, pu */
    iq_t psir_mag_iq;      /* IM law: estimated rotor-flux magnitude (Casadei eq. 21), updated on
                            * the speed-loop periods; PM: 0 */
    uint16_t i_limited;    /* 1: the current limit (ilim.h) replaced the table's vector */
    /* The PWM forms (enum law_out_form, the law's at init): DUTY, the command is duty_iq, one
     * centred pulse per leg; THIRDS, it is thirds, the upper device's state in each third of the
     * period, duty_iq then the mean; sa/sb/sc are then 0. The LEGS laws never write these
     * fields. */
    iq_t duty_iq[3];       /* upper-device duty of legs A, B, C over the next period, [0, 1] */
    uint16_t thirds[3];    /* THIRDS: legs A, B, C, bit 2 = first third, 1 = upper on */
} dtc_out_t;

/* The part of every law's report that states what is in force: the torque reference, the speed,
 * the angle the law is oriented on, whether the flux came from the current model, and the flux
 * reference (dtc_out_t's fields of the same names). Inline: five stores. */
static inline void law_out_state(dtc_out_t *o, iq_t te_ref, iq_t speed, angle_t theta, uint16_t on_cm,
                                 iq_t psi_ref)
{
    o->te_ref_iq = te_ref;
    o->speed_iq = speed;
    o->theta_e = theta;
    o->on_cm = on_cm;
    o->psi_ref_iq = psi_ref;
}

/* The duty-form laws (SVM: IM SFVC, DFOC; PM ITC): the table laws' fields of o at 0 (leg states,
 * vector, sector, comparator outputs); the command is duty_iq. */
static inline void law_out_duty_only(dtc_out_t *o)
{
    o->sa = 0U;
    o->sb = 0U;
    o->sc = 0U;
    o->vector = 0U;
    o->sector = 0U;
    o->flux_up = 0U;
    o->torque_dem = 0;
}

#endif /* LAW_IO_H */
