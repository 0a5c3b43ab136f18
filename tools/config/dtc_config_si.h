/*
 * dtc_config_si.h - host-side configuration of the DTC firmware in SI units, and its conversion
 * to the firmware's per-unit Q-format struct (firmware/dtc/dtc_config.h).
 *
 * Host code (C99, double and libm allowed): it is linked by the SIL runner and the tests, and
 * it is where every reciprocal the firmware needs is precomputed, so the firmware never divides.
 *
 *   dtc_config_si_defaults()  the rig of model/include/plant_defaults.h (Hoang Table VIII
 *                             machine, Table IV devices,
 *                             70 V DC link, 50 us, speed loop 10x slower, 2000-line encoder,
 *                             LPF 5 rad/s, zero hysteresis bands, FSTP, voltage model with the
 *                             proposed compensation (Table VI).
 *   dtc_config_from_si()      SI -> dtc_config_t; refuses what cannot be represented with an
 *                             enum dtc_si_err code, the refused member (dtc_config_from_si_err)
 *                             and a message naming it. The members, their units and plain
 *                             ranges are described once in dtc_si_params.h.
 *   dtc_config_emit_c()       writes a dtc_config_t as a C source file for a target build.
 *
 * Per-unit bases: see firmware/dtc/dtc_base.h (V_base, I_base, w_base chosen here).
 */
#ifndef DTC_CONFIG_SI_H
#define DTC_CONFIG_SI_H

#include <stddef.h>
#include <stdio.h>

#include "dtc_config.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int law;                /* enum dtc_law: which machine, control law and scheme */

    /* Per-unit bases. */
    double v_base_v;        /* voltage base (default: nominal DC link) */
    double i_base_a;        /* current base (default: rated peak current) */
    double w_base_rad_s;    /* electrical speed base (default: rated speed * pole pairs) */

    /* Machine (Hoang Table VIII). */
    double rs_ohm;
    double ls_h;            /* of a salient PM its d-axis inductance L_d */
    double lq_h;            /* the q-axis inductance L_q; 0 = ls_h (a surface PM, the default) */
    double psi_m_wb;
    int pole_pairs;
    double rated_speed_rpm;
    double rated_torque_nm;
    double rated_current_a;
    double inertia_kgm2;    /* for the speed-PI design from a bandwidth */
    /* Induction machine (the laws DTC_LAW_IM_*): Casadei's T model, stator-referred, the plant's
     * names (model/include/plant.h); ls_h and psi_m_wb are then unused. */
    double rr_ohm;
    double lls_h, llr_h;    /* stator / rotor leakage inductance */
    double lm_h;            /* magnetising inductance M */

    /* Inverter (Hoang Table IV). */
    int topology;           /* enum dtc_topology */
    double vdc_v;           /* nominal DC link */
    double v_ce_v;          /* device forward drop */
    double v_d_v;           /* diode forward drop */
    double v_f_v;           /* equal drop of the simple schemes (SSTP [29], Hoang Table V) */
    double r_on_ohm;
    int fstp_vmid_measured; /* 1: the mid-point voltage is measured */

    /* Timing. */
    double ts_s;            /* control period (50 us) */
    int speed_div;          /* speed loop every speed_div-th period (10) */

    /* Encoder. */
    int enc_lines;          /* lines per turn (2000); quadrature gives 4x counts */
    double enc_offset_rad;  /* electrical angle at count 0 (the raw count the encoder gives) */
    int enc_reversed;       /* 1: the count runs down for forward rotation of the field */
    int speed_min_counts;   /* speed window: shortest with at least this many counts (100) */

    /* Control. */
    double flux_band_wb;    /* Delta psi_s (full width), >= 0 */
    double torque_band_nm;  /* Delta T_e (full width), >= 0 */
    double lpf_cutoff_rad_s;/* voltage-model low-pass cut-off (5 rad/s) */
    int handover_auto;      /* 1: handover_speed_rpm = dtc_handover_default_rpm(si) */
    double handover_speed_rpm; /* voltage model: current model below it (0 = none), >= 0 */
    double handover_hyst_frac; /* back to the current model below (1 - frac) * handover, [0, 1] */
    int delay_comp;         /* 1: actuation-delay compensation (predict k+1), 0: off */
    int deadtime_comp;      /* 1: dead-time compensation of the reconstructed voltage, 0: off */
    double dead_time_s;     /* the inverter's dead time (the gate driver's setting) */
    int pi_from_bandwidth;  /* 1: kp, ki from speed_bw_rad_s and inertia_kgm2 */
    double speed_bw_rad_s;  /* speed-loop crossover; PI zero at bw/4 */
    double kp_nm_s_rad;     /* N.m per (mechanical rad/s) */
    double ki_nm_rad;       /* N.m per (mechanical rad/s) per s */
    double torque_limit_nm;
    double torque_trim_tau_s; /* torque mode: mean-torque trim time constant (0 = off) */
    double stall_time_s;      /* speed mode: torque at its limit with no shrinking speed error
                               * for this long is a stall fault (app_core); 0 = derived:
                               * max(0.1 s, 20 speed periods) */
    double speed_limit_rpm;
    double flux_ref_wb;
    double speed_ref_rpm;
    double torque_ref_nm;

    /* Induction-machine law (Casadei 2006). */
    double psir_ref_wb;     /* > 0: constant rotor flux, phi_s* by Casadei eq. 19; 0: flux_ref_wb */
    double tau_lo_s;        /* improved estimator (Casadei eq. 20): tau at low speed ... */
    double tau_hi_s;        /* ... and at high speed (section 10.2; equal: fixed tau) */
    double tau_w_lo_rpm;    /* |speed| up to which tau_lo applies */
    double tau_w_hi_rpm;    /* |speed| from which tau_hi applies (>= tau_w_lo_rpm) */
    int speed_sensor;       /* enum dtc_speed_sensor */
    double table_speed_rpm; /* DTC_ST_SPEED: ST-D below, ST-A above; 0 = derived
                             * (dtc_table_speed_default_rpm) */
    double speed_filter_s;  /* sensorless speed: filter time constant of the flux angular speed */
    double magn_frac;       /* start-up: torque allowed once the rotor flux has reached this
                             * fraction of its reference: after tau_r ln(1/(1 - magn_frac)) */
    int rr_track;           /* 1: the rotor resistance tracked on line is used (firmware/dtc/im_sup.h) */
    int cm_ref;             /* 1: Casadei eq. 20's reference from the current model at low speed (im_sup.h) */
    int flux_weakening;     /* 1: Casadei section 12 */
    int fw_window;          /* N control periods per flux-reference decision (>= 20) */
    double fw_step_frac;    /* flux-reference step per decision, fraction of flux_ref_wb */
    double fw_psi_min_frac; /* lowest flux reference, fraction of flux_ref_wb */
    /* Stator-flux vector control (law DTC_LAW_IM_SFVC, Casadei secs. 10.3-10.5) and the
     * rotor-flux-oriented control (DTC_LAW_IM_DFOC, sec. 13: its current-loop gains are derived,
     * dtc_config_from_si). */
    double carrier_hz;      /* SVM carrier: one PWM period per control period, so it must equal
                             * 1 / ts_s; 0 = 1 / ts_s */
    int svm_mode;           /* enum svm_mode (firmware/dtc/svm.h): 0 symmetric, 1 two-phase */
    double sfvc_kp_per_s;   /* flux-regulator gain K_p of Casadei eq. 24, 1/s, in (0, 1/ts_s]; 0 = derived:
                             * 1 / (2 ts_s), half of the flux error removed per period (the
                             * deadbeat gain 1/ts_s halved as a margin for the one-period
                             * prediction's model errors) */
    double dfoc_bw_hz;      /* DFOC current-loop crossover w_c / (2 pi), Hz, below 1 / (6 ts_s) (the
                             * loop's 1.5 ts_s delay takes the whole 90 deg phase margin there);
                             * 0 = derived: w_c = 0.2 / ts_s (17 deg of that margin, no overshoot) */
    double dfoc_zeta;       /* DFOC current-PI placement: 0 = the zero on the stator transient pole
                             * (K_p = sigma L_s w_c, K_i = R_s w_c: first-order loops); > 0 = both
                             * closed-loop poles at w_c with this damping (K_p = 2 zeta w_c sigma L_s
                             * - R_s, K_i = sigma L_s w_c^2: the PI's zero near w_c overshoots) */

    /* DTC with DSVM (law DTC_LAW_IM_DSVM, Casadei sec. 11): the five-level torque comparator's
     * outer band (full width), >= torque_band_nm; 0 = derived: twice the torque a whole active
     * vector changes in one period at standstill (dtc_config_from_si), at least torque_band_nm. */
    double dsvm_torque_band2_nm;

    /* Variants. */
    int estimator;          /* enum dtc_estimator */
    int compensation;       /* enum dtc_compensation */
    int sstp_table;         /* enum dtc_sstp_table */
    int mode;               /* enum dtc_mode */

    /* ADC (12-bit) scaling and nominal offsets; protection levels. */
    double adc_i_a_per_count;
    int adc_i_offset[3];
    double adc_vdc_v_per_count;
    int adc_vdc_offset;
    double adc_vmid_v_per_count;
    int adc_vmid_offset;
    double i_trip_a;
    double vdc_max_v;
    double vdc_min_v;
    /* ---- Current limit and ripple-robust polarity (firmware ilim.h) ---- */
    int current_limit_auto;  /* 1: current_limit_a = dtc_ilim_default_a(si) */
    double current_limit_a;  /* current-limit override on |i|, A; 0 = off, else < i_trip_a */
    int polarity_mid;        /* 1: drops averaged over the period's current, dead-time polarity
                              * at the switching instant (pm_dtc_cfg.h), 0: from the sample */
    int lpf_comp;            /* voltage model: 1 = low-pass gain/phase correction (lpfcorr.h) */
    int dc_supp;             /* voltage model: 1 = DC-current suppression (dtc.c dtc_dcsupp), its
                              * rate w_d = |w| / 20; FSTP with the mid-point measured: also the
                              * mid-point regulation at w_c / 2, with c_dc_f */
    double c_dc_f;           /* each split DC-link capacitor, F (> 0) */
    int vmid_cal;            /* FSTP, mid-point measured: 1 = the app calibrates it against V_dc/2
                              * before the drive starts (firmware app_core.c), 0 = used as measured */
    int cal_hold;            /* with vmid_cal: 1 = the rotor is held by a phase-B/C current while the
                              * mid-point is calibrated (prot.i_hold_iq), 0 = the gates stay off */
    /* ---- Fault detection and tolerance (firmware app_core.c) ---- */
    int i_sensors3;          /* 1: all three phase currents measured (their sum is checked) */
    int fault_detect;        /* 1: open-phase and lost-encoder detection on (levels derived:
                              * dtc_fault_levels), 0: off */
    int reconfig_relay;      /* 1: a relay per phase ties a failed leg's phase to the mid-point
                              * (the post-fault FSTP configuration: dtc_config_post_fault_si) */
    double relay_delay_s;    /* its closing time, s (> 0 with reconfig_relay) */
    double overspeed_rpm;    /* overspeed trip, mechanical rpm, above speed_limit_rpm; 0 = derived:
                              * dtc_overspeed_default_rpm; < 0 = off */
} dtc_config_si_t;

enum dtc_si_err {
    DTC_SI_OK = 0,
    DTC_SI_ERR_NULL = -100,      /* null pointer */
    DTC_SI_ERR_BASE = -101,      /* a base <= 0, or a sample time not below the time base */
    DTC_SI_ERR_MACHINE = -102,   /* rs < 0, ls <= 0, psi_m <= 0, pole pairs < 1, ratings <= 0 */
    DTC_SI_ERR_INVERTER = -103,  /* vdc <= 0, drops or R_on < 0 */
    DTC_SI_ERR_TIMING = -104,    /* ts <= 0, speed_div < 1 */
    DTC_SI_ERR_ENCODER = -105,   /* lines < 1, counts beyond 16 bits, min counts out of range */
    DTC_SI_ERR_BAND = -106,      /* negative hysteresis band */
    DTC_SI_ERR_CUTOFF = -107,    /* LPF cut-off <= 0 or at/above the Nyquist rate pi/ts */
    DTC_SI_ERR_GAIN = -108,      /* negative gain, or a gain/bandwidth design not possible */
    DTC_SI_ERR_LIMIT = -109,     /* torque/speed limit <= 0, protection levels not ordered */
    DTC_SI_ERR_REFERENCE = -110, /* flux reference <= 0, references beyond their limits */
    DTC_SI_ERR_VARIANT = -111,   /* variant out of range or not meant for the topology */
    DTC_SI_ERR_ADC = -112,       /* ADC gain <= 0, offset outside 0..4095 */
    DTC_SI_ERR_RANGE = -113,     /* a value overflows its Q format or a non-zero one rounds to 0 */
    DTC_SI_ERR_FIRMWARE = -114,  /* the firmware validation refused the result (a bug) */
    DTC_SI_ERR_HANDOVER = -115,  /* hand-over speed < 0, hysteresis fraction outside [0, 1] */
    DTC_SI_ERR_DELAY = -116,     /* delay_comp not 0 or 1 */
    DTC_SI_ERR_DEADTIME = -117,  /* deadtime_comp not 0 or 1, dead_time_s outside [0, ts_s/2) */
    DTC_SI_ERR_IM = -118,        /* induction-machine law: a parameter out of range */
    DTC_SI_ERR_ILIM = -119,      /* current_limit_a < 0 or not below i_trip_a, or the derived
                                  * limit is not positive; polarity_mid, vmid_cal, cal_hold not 0
                                  * or 1; no rotor-hold current fits below the trip */
};

void dtc_config_si_defaults(dtc_config_si_t *si);

/* Induction-machine defaults: the plant's default IM (plant_params_im_default: 4 kW, 4 poles,
 * 50 Hz, 220 V; R_s 0.4250, R_r 0.4220 ohm, L_ls = L_lr 1.7663 mH, L_m 52.09 mH, J 0.0131),
 * SSTP on a 311 V link (sqrt(2) 220 V), Casadei's 40 us period, Table 1 with the three-level
 * comparator, the improved estimator with tau = 0.01 s (section 10.2, Fig. 17), speed mode at
 * 0 rpm with the encoder, rated stator flux 0.55 Wb. */
void dtc_config_si_im_defaults(dtc_config_si_t *si);

/* DTC_ST_SPEED hand-over speed (mechanical rpm) from the machine and the link: half the speed at
 * which the back-EMF w phi_s* reaches V_dc/sqrt(3), the largest sinusoidal stator voltage of the
 * SSTP. Below it ST-D (Casadei section 8: the active backward vectors give the torque decrease
 * the null vectors cannot give at low speed), above it ST-A (the null vectors' decrease, which
 * grows with w phi_s, Casadei eq. 15, is then enough and ripples less). */
double dtc_table_speed_default_rpm(const dtc_config_si_t *si);

/* Default hand-over speed (mechanical rpm) of the voltage model, from the configured machine,
 * devices and low-pass: the electrical speed above which
 *   - the back-EMF w*psi_m is at least 3 times the device drop the uncompensated estimator
 *     integrates as if it were stator voltage, max(V_CE, V_d) + R_on * I_rated (the flux-angle
 *     error it causes is then below atan(1/3) = 18 deg even with no compensation, and well
 *     under that with it), and
 *   - the low-pass is at least 10 times above its cut-off (gain error 0.5 %, phase lead 5.7 deg,
 *     flux_est.h),
 *   - the flux error of what the configured compensation leaves uncompensated costs no more
 *     current than the current limit leaves beside rated torque. A leg drop V_r sign(i_x) that
 *     the estimator integrates as stator voltage is a square wave in phase with the current;
 *     its fundamental, (4/pi) k V_r (k = 1 for three switched legs, 2/3 on the FSTP, whose
 *     phase A has no device: amplitude-invariant Clarke of two legs), integrated at w, is a flux
 *     error (4/pi) k V_r / w along the magnet axis when the current is on the torque axis. The
 *     DTC holds the estimated flux at psi_m, so the machine carries i_d = -error / L_s: the
 *     voltage model then needs |i| = sqrt(i_d^2 + I_r^2) <= I_lim, i.e.
 *     w >= (4/pi) k V_r / (L_s sqrt(I_lim^2 - I_r^2)), I_r = T_rated / (3/2 p psi_m)
 *     (the headroom floored at I_lim / 10).
 *     V_r (dtc_handover_residual_v, at I_lim): none max(V_CE, V_d) + R_on I; SSTP [29]
 *     max(|V_CE - V_f|, |V_d - V_f|); FSTP simple (Hoang Table V, no R_on) that + R_on I; proposed 0;
 *     plus V_dc T_d / T_s when the dead time is not compensated. Below that speed the
 *     uncompensated SSTP drive under a constant rated load estimated 0.1 N*m above the true
 *     torque, ran 14 % under-fluxed and stalled (SIL, docs/firmware-core.md).
 * - on the FSTP voltage model with the restoring mid-point reconstruction: where its beta(w)
 *   covers the link sensor's tolerance down to the hand-back speed (1 - handover_hyst_frac) w_h,
 *   w_beta = sqrt(dtc_vmid_gain_tol / dtc_vmid_beta_k) / (1 - handover_hyst_frac); below that a
 *   link read low lets the mid-point run away (firmware/dtc/dtc.c dtc_vmid_dev).
 * whichever is highest: w_h = max(3 (max(V_CE, V_d) + R_on I_rated) / psi_m, 10 w_c, w_cur, w_beta).
 * Hoang Table VIII machine, Table IV devices, 5 rad/s, 6 A trip, 2 x 4.7 mF, hysteresis 0.2: proposed
 * and simple with the mid-point measured max(45.7, 50, <= 43.6, 78.1 / 0.8 = 97.7) rad/s =
 * 933 rpm, without it 477 rpm (p = 1); none 941 rpm on the FSTP, 1441 rpm on the SSTP. */
double dtc_handover_default_rpm(const dtc_config_si_t *si);

/* Restoring mid-point reconstruction of the FSTP voltage model (firmware/dtc/dtc.c dtc_vmid_dev):
 * beta = min(1/16, k w^2), k in s^2 (w the electrical speed in rad/s),
 *     k = 3 C l_s / 8,
 * so that the error beta makes of the mid-point's swing i_a / (2 C w) (C each capacitor), a flux
 * error -beta i_a / (3 C w^2) on phase A, i.e. an inductance error beta / (3 C w^2) on that one
 * phase, stays within l_s / 8 at every speed (l_s the firmware's). 0 where the firmware
 * reconstructs no mid-point (not an FSTP voltage model with the mid-point measured and
 * calibrated). Hoang Table VIII, 2 x 4.7 mF: 5.62e-6 s^2 (beta = 1/16 above 1007 rpm). */
double dtc_vmid_beta_k(const dtc_config_si_t *si);
/* The link-sensor error the restoring term must cover, relative: 2 % gain plus a 1 V offset at
 * the link voltage (a datasheet-grade sensor). The derived hand-over speed stays at or
 * above sqrt(dtc_vmid_gain_tol / k), where beta(w) reaches it (dtc_handover_default_rpm). */
double dtc_vmid_gain_tol(const dtc_config_si_t *si);

/* The leg-drop amplitude, V, that the configured compensation leaves in the voltage model at
 * current i_a (see dtc_handover_default_rpm). */
double dtc_handover_residual_v(const dtc_config_si_t *si, double i_a);

/* Default overspeed trip (mechanical rpm): 10 % above the larger of the rated speed and the speed
 * limit, the fastest the drive is ever asked to turn. Hoang Table VIII (3000 rpm rated and limit): 3300 rpm;
 * the 4 kW IM with its 6000 rpm flux-weakening limit: 6600 rpm. */
double dtc_overspeed_default_rpm(const dtc_config_si_t *si);

/* Default current limit (A, peak) of the firmware's vector override (firmware/dtc/ilim.h), from
 * the trip level and the configured machine and board: I_lim = I_trip - n dI with
 *   dI = T_s (V_max + w_max psi_m + r_s I_trip) / L_s,
 * the largest change of |i| over one control period (Hoang eqs. 6-9: l_s di/dt = v - r_s i - e):
 * V_max the largest voltage vector at the nominal link voltage (SSTP 2 V_dc / 3, FSTP V_dc /
 * sqrt(3), amplitude-invariant Clarke, Hoang eqs. 1-5), the back-EMF term w_max psi_m at
 * speed_limit_rpm, at most V_max (above that speed the inverter cannot control the machine
 * anyway); n = 1 when the limit acts on the current predicted for k+1 (delay_comp on), n = 2 on
 * the sampled current (the vector chosen at k acts only from k+1 on). When the trip level leaves
 * no room for one period's change (slow period, small L_s) the result is 0: no limit, and the
 * trip is the only protection.
 * Hoang Table VIII, Table IV link, 50 us, 3000 rpm, 6 A trip, FSTP: dI = 1.13 A, I_lim = 4.87 A.
 * The induction machine (laws DTC_LAW_IM_*): L_s is its transient inductance sigma L_s and psi_m
 * the rotor flux seen from the stator, (M/L_r) phi_r* (dtc_im_transient_si). The 4 kW IM, 40 us,
 * 6000 rpm, 55 A trip: dI = 5.0 A, I_lim = 45.0 A. Its modulated laws (SFVC, DFOC: the SVM with
 * the back-EMF fed forward; DSVM: the speed ranges of Casadei eq. 15) make the period's mean
 * voltage against the back-EMF: dI = T_s (V_max + r_s I_trip) / (sigma L_s) (40 us: 2.6 A,
 * I_lim = 49.7 A; 160 us: 10.6 A, I_lim = 33.8 A). */
double dtc_ilim_default_a(const dtc_config_si_t *si);
/* Its dI, A: the largest change of |i| over one control period. A salient PM's current changes
 * fastest along its smaller inductance: L_s is min(L_d, L_q) there (dtc_pm_lq_h). */
double dtc_ilim_step_a(const dtc_config_si_t *si);
/* The PM's L_q the firmware takes, H: lq_h, or ls_h when lq_h is 0 (a surface PM). */
double dtc_pm_lq_h(const dtc_config_si_t *si);

/* The induction machine's current dynamics in the form of a PM machine's (Casadei eqs. A6-A9, T
 * model, stator frame): sigma L_s di/dt = v - R_s i - (M/L_r) d phi_r/dt, the rotor-flux term a
 * back-EMF of amplitude w (M/L_r) |phi_r|. *l_h = sigma L_s, *psi_wb = (M/L_r) phi_r*, phi_r* =
 * psir_ref_wb or the no-load rotor flux of flux_ref_wb, (M/L_s) phi_s*. */
void dtc_im_transient_si(const dtc_config_si_t *si, double *l_h, double *psi_wb);

/* The steady-state torque (N*m) of the induction machine at the stator-current amplitude i_a (A,
 * peak), T model in the rotor-flux frame (Casadei eqs. A7-A10 at constant flux: phi_r = M i_d, phi_s
 * = L_s i_d + j sigma L_s i_q, T = 3/2 p (M^2/L_r) i_d i_q):
 *   constant rotor flux (psir_ref_wb > 0, Casadei eq. 19, SFVC, DFOC): i_d = phi_r* / M;
 *   constant stator flux flux_ref_wb: i_d^2 = (phi_s^2 - (sigma L_s i)^2) / (L_s^2 (1 - sigma^2)).
 * 0 when i_a is at or below the magnetising current; HUGE_VAL when the stator flux cannot carry
 * i_a (phi_s < sigma L_s i: the pull-out torque, Casadei eq. 31, limits first).
 * The 4 kW IM, phi_s* = 0.55 Wb, 40 A: 57.9 N*m (218 % of rated). */
double dtc_im_torque_at_current_nm(const dtc_config_si_t *si, double i_a);

/* The IM law's excursion of the phase current above the steady current its torque limit holds,
 * A: the torque the current allows is dtc_im_torque_at_current_nm at I_lim less this.
 *   SFVC: the SVM's ripple about the period's fundamental, at most V_max T_s / (4 sigma L_s). In a
 *     centred pattern (one carrier period per control period) the current departs from its
 *     period's line by the integral of the applied vector's difference from the period's mean,
 *     which is at most V_max (adjacent vectors and the null in one sector) and whose integral over
 *     each half period is zero (the halves mirror each other): at most V_max T_s/2 / 2. Its
 *     deadbeat flux regulator (Casadei eq. 24) takes a step of the reference to the limit without
 *     overshoot (measured: 0.15 dI above the held current on a 300 % step at 1000 rpm, 4 kW,
 *     40 us; 0.01 dI at 160 us on both machines), so I_trip - I_lim = 2 dI stays for the transients.
 *   The switching-table laws and DSVM: dI, a whole period under one vector (dtc_ilim_step_a).
 *   DFOC: dI. Its PI current regulators hold their integrals while the SVM scales the vector onto
 *     its hexagon (im_dfoc.c), so a step to the limit no longer overshoots (a 300 % step at
 *     1000 rpm, 4 kW, 40 us: 47.3 A for 47.0 A held, 51.9 A with the integrals free), but with
 *     the SVM ripple alone (the torque it allows 44 N*m for 31.7 on the 4 kW at 160 us) the
 *     sensorless braking flying start from 100 % loses the flux estimate (docs/sil.md: the DFOC's
 *     angle error under heavy regenerating current), so the room stays.
 * The second machine at 160 us: SFVC 1.31 A (dI 6.46 A). */
double dtc_im_hold_margin_a(const dtc_config_si_t *si);

/* The IM laws' torque room: the torque limit the current allows (dtc_im_torque_at_current_nm at
 * I_lim less dtc_im_hold_margin_a, the converter's, law_im_si.c) against the machine's rated torque. Returns 1 and writes
 * a warning into msg naming the keys when it is below rated_torque_nm: the current the rated torque
 * needs, the margin the period leaves, and the longest control period (ts_s) and the lowest trip
 * level (i_trip_a) that each, alone, would give the rated torque with the same derivation (dI and
 * the law's excursion are proportional to ts_s; with current_limit_auto the margin is the n
 * periods' dI of dtc_ilim_default_a and the excursion). Returns 0 otherwise (not an IM law, no
 * current limit, or room enough).
 * The second machine (im_second_machine.toml) with DFOC at 160 us: 30 A trip, dI 6.46 A, 22.3 N*m
 * for 23.5 rated (11.01 A): ts_s <= 156.8 us (carrier 6378 Hz) or i_trip_a >= 30.45 A; with SFVC
 * (excursion 1.31 A) room enough. */
int dtc_im_torque_room_check(const dtc_config_si_t *si, char *msg, size_t msg_size);

/* The PM indirect torque control's current-loop crossover w_c, rad/s (law_pm_itc_si.c): 60 deg of
 * phase margin against the 1.5 Ts loop delay, pi / (9 Ts). */
double dtc_itc_wc_rad_s(const dtc_config_si_t *si);
/* Its FSTP mid-point regulation's rate w_m, rad/s: the electrical speed at half the rated speed
 * over 20 (law_pm_itc_si.c). */
double dtc_itc_vmid_wm_rad_s(const dtc_config_si_t *si);

/* The post-fault configuration of an SSTP drive with reconfiguration relays, the PM DTC or the IM
 * switching-table DTC: the same drive as an FSTP whose phase A is the failed one (firmware dtc.h
 * dtc_reconfigure, im_dtc.h im_dtc_reconfigure). Changed from si: topology FSTP; the compensation
 * for the same device model (none stays none, the SSTP's equal drop [29] becomes the FSTP's
 * equal-drop Hoang Table V, "simple"); no mid-point calibration and no rotor hold (the drive does
 * not stop for them); the derived hand-over speed and current limit are derived again for the
 * FSTP; the IM's flux references scaled to what the FSTP's voltage holds
 * (dtc_im_fstp_flux_scale). Returns DTC_SI_OK, or DTC_SI_ERR_VARIANT when si is not such a drive
 * with reconfig_relay = 1. */
int dtc_config_post_fault_si(const dtc_config_si_t *si, dtc_config_si_t *post);
/* The IM on the four-switch inverter: the factor (<= 1) on flux_ref_wb and psir_ref_wb that
 * leaves the stator flux within what the FSTP's voltage holds at the drive's speed (the speed
 * reference in speed mode, else the rated speed), law_im_si.c. */
double dtc_im_fstp_flux_scale(const dtc_config_si_t *si);

/* A refusal of the converter: the code, the refused member and the message. */
typedef struct {
    int code;          /* enum dtc_si_err; DTC_SI_OK when converted */
    const char *field; /* the refused dtc_config_si_t member, exactly a row name of dtc_si_params.h
                        * (static storage: look its keys, unit and range up there); "" when no
                        * one member is at fault (a null argument, the firmware's own check) */
    char msg[256];     /* a message naming the field, e.g. "ls_h = -0.001: must be > 0" */
} dtc_si_error_t;

/* Converts si to cfg. Returns DTC_SI_OK or an enum dtc_si_err code, and fills *err (not null). */
int dtc_config_from_si_err(const dtc_config_si_t *si, dtc_config_t *cfg, dtc_si_error_t *err);
/* The same with the message only: msg (if not null) receives it. */
int dtc_config_from_si(const dtc_config_si_t *si, dtc_config_t *cfg, char *msg, size_t msg_len);

/* Writes cfg as a C source file defining `const dtc_config_t <symbol> = {...};` with each
 * field's value and meaning. Returns 0, or -1 on an I/O error. */
int dtc_config_emit_c(const dtc_config_t *cfg, const char *symbol, FILE *f);

/* A configuration field's stored value as a number in its Q format (raw / 2^Q; integers as they
 * are), and the factor that turns such a value of quantity qty (enum dtc_param_qty) into SI from
 * cfg's bases (1 for NONE, RATIO, PU). */
double dtc_param_value(const dtc_config_t *cfg, const dtc_param_t *p);
double dtc_param_si_scale(const dtc_config_t *cfg, uint16_t qty);

/* Per-unit bases derived from si (for tests and tools converting logs back to SI). */
typedef struct {
    double v_base_v, i_base_a, w_base_rad_s, psi_base_wb, z_base_ohm, l_base_h, t_base_nm,
        t_base_s;
} dtc_bases_t;
void dtc_bases_from_si(const dtc_config_si_t *si, dtc_bases_t *b);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CONFIG_SI_H */
