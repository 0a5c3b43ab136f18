/*
 * plant_defaults.h - the one table of default values of the configured rig: machines, inverter,
 * DC link, sensing, protection and the control settings of the papers' experiments. SI units;
 * the suffix of each name gives the unit.
 *
 * Every place that needs a default reads it from here: the plant (plant_params_default,
 * plant_params_im_default), the double-precision reference controller (ref_dtc.h Params), the
 * SIL scenario schema (tools/sil scenario.hpp, hence `dtc-sil keys` and docs/sil.md) and the
 * firmware's SI configuration (tools/config dtc_config_si_defaults, hence the F2812 board
 * configuration target/f2812/dtc_config_board.c). docs/plant.md section 3 explains the values
 * that are not in the papers.
 *
 * Plain C99 macros (constant expressions), so that C and C++ host code share them. Sources:
 * Hoang, Zhu, Foster 2011 (../shared/papers/001_*) and Casadei et al. 2006
 * (../shared/papers/000_*), cited by author.
 */
#ifndef DTC_MODEL_PLANT_DEFAULTS_H
#define DTC_MODEL_PLANT_DEFAULTS_H

#define PLANT_DEF_PI 3.14159265358979323846

/* ---- PM BLAC machine: Hoang Table VIII ---- */
#define PLANT_DEF_PM_RS_OHM 0.466             /* phase resistance */
#define PLANT_DEF_PM_LS_H 3.19e-3             /* synchronous inductance, Ld = Lq (surface PM) */
#define PLANT_DEF_PM_PSI_M_WB 0.0928          /* PM flux linkage, peak */
#define PLANT_DEF_PM_POLE_PAIRS 1
#define PLANT_DEF_PM_RATED_TORQUE_NM 0.3      /* Hoang sec. IV: full load = rated torque */
#define PLANT_DEF_PM_RATED_CURRENT_A 2.2      /* Hoang sec. IV: current demand at rated torque, peak */
#define PLANT_DEF_PM_RATED_SPEED_RPM 3000.0   /* Hoang sec. IV: 1500 rpm is half the rated speed */

/* ---- PM rig mechanics (machine + brushed DC generator + 2000-line encoder, Hoang Fig. 9) ---- */
/* Inertia: not in Hoang; sizing estimate of rotor, generator armature, coupling (docs/plant.md). */
#define PLANT_DEF_PM_J_KGM2 1.0e-4
/* Viscous friction: Hoang sec. IV "inertial load (25 % of full load)" = 0.075 N*m at 1500 rpm:
 * 0.075 / (1500 pi / 30) = 4.77465e-4, given to 5 digits (0.074999 N*m at 1500 rpm). */
#define PLANT_DEF_PM_B_NM_S_PER_RAD 4.7746e-4

/* ---- Induction machine: 4 kW, 4 poles, 50 Hz, 220 V (Casadei sec. 6, the machine of Fig. 5;
 * rated point of Table 5). Casadei prints no parameters: Modelica Buildings IM_5HP_400V_50Hz,
 * every R and L times (220/400)^2 (per-unit values, power and torque unchanged); docs/plant.md
 * section 1. ---- */
#define PLANT_DEF_IM_Z_SCALE 0.3025           /* (220/400)^2 */
#define PLANT_DEF_IM_RS_OHM (1.405 * PLANT_DEF_IM_Z_SCALE)
#define PLANT_DEF_IM_RR_OHM (1.395 * PLANT_DEF_IM_Z_SCALE)     /* stator-referred */
#define PLANT_DEF_IM_LLS_H (5.839e-3 * PLANT_DEF_IM_Z_SCALE)
#define PLANT_DEF_IM_LLR_H (5.839e-3 * PLANT_DEF_IM_Z_SCALE)   /* stator-referred */
#define PLANT_DEF_IM_LM_H (172.2e-3 * PLANT_DEF_IM_Z_SCALE)
#define PLANT_DEF_IM_POLE_PAIRS 2
#define PLANT_DEF_IM_J_KGM2 0.0131            /* Modelica Buildings IM_5HP_400V_50Hz */
#define PLANT_DEF_IM_B_NM_S_PER_RAD 0.0
#define PLANT_DEF_IM_RATED_TORQUE_NM 26.5     /* Casadei Table 5 */
#define PLANT_DEF_IM_RATED_SPEED_RPM 1440.0   /* Casadei Table 5 */
#define PLANT_DEF_IM_RATED_CURRENT_A 19.2     /* peak, this machine at 26.5 N*m (docs/plant.md) */

/* ---- Induction-machine drive rig (Casadei sections 10.2, 10.5, Table 4; the firmware's IM
 * defaults and the SIL scenario's motor.type = "im" defaults) ---- */
#define PLANT_DEF_IM_VDC_V 311.0              /* sqrt(2) * 220 V: six-switch inverter on a rectified 220 V */
#define PLANT_DEF_IM_TS_S 40e-6               /* Casadei Table 4: DTC cycle period 40 us */
#define PLANT_DEF_IM_FLUX_REF_WB 0.55         /* |phi_s| at rated voltage and frequency (im-facts.md) */
#define PLANT_DEF_IM_TORQUE_LIMIT_NM (3.0 * PLANT_DEF_IM_RATED_TORQUE_NM) /* Casadei Fig. 14: 300 % steps */
#define PLANT_DEF_IM_OBSERVER_TAU_S 0.01      /* Casadei sec. 10.2, Fig. 17: improved estimator tau */
#define PLANT_DEF_IM_CARRIER_HZ 6250.0        /* SVM carrier of the stator-flux vector control (control
                                               * period = carrier period): the 160 us DFOC cycle of
                                               * Casadei Table 4, for the constant-switching-
                                               * frequency drive (T1PR 6000) */
#define PLANT_DEF_PWM_CLOCK_HZ 75e6           /* F2812 HSPCLK, Timer 1 clock of the PWM form (hal.h) */
#define PLANT_DEF_CU_TEMPCO_PER_K 0.0039     /* copper's resistance temperature coefficient, 0.39 %/K */
#define PLANT_DEF_IM_MAGN_FRAC 0.9            /* start-up: torque allowed at 90 % of the rotor flux */
/* Sensing and protection sized for the 300 % torque current (about 2.5x rated, 48 A peak):
 * +-100 A Hall sensors, 0..500 V divider, firmware trip at 55 A (below 3x rated = 57.6 A), the
 * hardware comparator just above it, DC-link window 200..400 V. */
#define PLANT_DEF_IM_CURRENT_RANGE_A 100.0
#define PLANT_DEF_IM_VOLTAGE_RANGE_V 500.0
#define PLANT_DEF_IM_OVERCURRENT_A 55.0
#define PLANT_DEF_IM_HW_TRIP_CURRENT_A 57.0
#define PLANT_DEF_IM_VDC_MIN_V 200.0
#define PLANT_DEF_IM_VDC_MAX_V 400.0

/* ---- Inverter: IRAMY20UP60B IPM (Hoang sec. IV), devices Hoang Table IV ---- */
#define PLANT_DEF_VDC_V 70.0                  /* Hoang Table VIII */
#define PLANT_DEF_V_CE_V 0.9                  /* transistor forward drop */
#define PLANT_DEF_V_D_V 1.25                  /* diode forward drop */
#define PLANT_DEF_R_ON_OHM 0.075              /* on-state resistance */
#define PLANT_DEF_V_F_V 0.9                   /* equal drop of the simple schemes, Hoang sec. III-B */
/* Dead time per leg transition: not in Hoang; the gate driver's setting (docs/plant.md). */
#define PLANT_DEF_DEAD_TIME_S 1.0e-6
/* DC link: each capacitor (FSTP: two in series). The FSTP mid-point carries i_a: ripple
 * i_a / (omega_e 2C) = +-1.5 V at 2.2 A, 25 Hz (docs/sil.md). */
#define PLANT_DEF_C_DC_F 4.7e-3
#define PLANT_DEF_R_DC_OHM 0.1                /* bench supply + leads */
/* Reconfiguration relay: contact delay after a coil command. A PCB power relay's
 * operate time, Omron G2RG datasheet: "Operate time 15 ms max., Release time 5 ms max."; the
 * plant uses the operate time (the worst case) for both directions. */
#define PLANT_DEF_RELAY_DELAY_S 15e-3

/* ---- Control settings of Hoang sec. IV ---- */
#define PLANT_DEF_TS_S 50e-6                  /* torque/flux loop period */
#define PLANT_DEF_SPEED_LOOP_DIVIDER 10       /* speed loop 10x slower */
#define PLANT_DEF_LPF_CUTOFF_RAD_S 5.0        /* voltage-model low-pass in place of the integrator */
#define PLANT_DEF_FLUX_REF_WB PLANT_DEF_PM_PSI_M_WB /* |psi_s*| = psi_m */
#define PLANT_DEF_SPEED_REF_RPM 1500.0        /* the test speed */
/* Speed loop (not in Hoang): 10 Hz crossover, PI zero at a quarter of it; output limit 2x rated
 * torque (4.3 A peak, below the 6 A trip). */
#define PLANT_DEF_SPEED_BW_HZ 10.0
#define PLANT_DEF_TORQUE_LIMIT_NM (2.0 * PLANT_DEF_PM_RATED_TORQUE_NM)
#define PLANT_DEF_ENCODER_LINES 2000          /* Hoang Fig. 9(b); 4x quadrature counts */

/* ---- Sensing (12-bit ADC, 0..3 V = codes 0..4095) and protection ---- */
#define PLANT_DEF_ADC_FULL_SCALE_CODES 4095.0
#define PLANT_DEF_CURRENT_RANGE_A 10.0        /* Hall sensor: -range..+range onto 0..3 V */
#define PLANT_DEF_VOLTAGE_RANGE_V 100.0       /* divider: 0..range onto 0..3 V */
#define PLANT_DEF_OVERCURRENT_A 6.0           /* firmware phase over-current trip */
#define PLANT_DEF_HW_TRIP_CURRENT_A 8.0       /* hardware comparator (PDPINTA) */
#define PLANT_DEF_VDC_MIN_V 40.0              /* firmware DC-link under-voltage trip */
#define PLANT_DEF_VDC_MAX_V 90.0              /* firmware DC-link over-voltage trip */

/* ---- Numerics ---- */
#define PLANT_DEF_MAX_STEP_S 50e-6            /* largest plant integration sub-step (docs/plant.md) */

#endif /* DTC_MODEL_PLANT_DEFAULTS_H */
