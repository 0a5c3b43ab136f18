/*
 * plant.h - C ABI of the physical plant model (model/, C++17 + Eigen, SI units only).
 *
 * hal/host creates a plant from a parameter struct, applies leg states held for one control
 * period (or per-leg switching instants within it, plant_set_leg_edges), advances it by exactly one period (sub-stepping inside) and reads the true state. The
 * model never includes firmware headers; everything here is SI (suffix gives the unit).
 */
#ifndef DTC_MODEL_PLANT_H
#define DTC_MODEL_PLANT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    PLANT_INVERTER_IDEAL = 0, /* alpha/beta voltages applied directly (plant_set_voltage) */
    PLANT_INVERTER_SSTP = 1,  /* six switches, eight states (Casadei eq. 2, Fig. A2) */
    PLANT_INVERTER_FSTP = 2   /* four switches, phase A on the capacitor mid-point (Hoang Fig. 1b) */
} plant_inverter_t;

typedef enum {
    PLANT_LOAD_SPEED = 0,     /* dynamometer holds load_speed_rpm */
    PLANT_LOAD_TORQUE = 1,    /* constant load torque load_torque_nm (opposes positive speed) */
    PLANT_LOAD_GENERATOR = 2, /* DC-generator load: torque = load_torque_nm * speed / load_speed_rpm */
    PLANT_LOAD_INERTIA = 3,   /* inertia and friction only */
    PLANT_LOAD_FAN = 4        /* quadratic (fan/pump) load: torque = load_torque_nm * (n/load_speed_rpm)^2,
                               * opposing the motion */
} plant_load_t;

typedef enum {
    PLANT_MACHINE_PM = 0,     /* PM BLAC machine (Hoang eqs. 6-10): rs_ohm, ls_h, psi_m_wb, emf_*; salient
                               * (interior PM) when lq_h differs from ls_h */
    PLANT_MACHINE_IM = 1      /* squirrel-cage induction machine (Casadei eqs. A1-A11): rs_ohm, rr_ohm,
                               * lls_h, llr_h, lm_h (T model) */
} plant_machine_t;

typedef struct {
    /* PM BLAC machine (Hoang eqs. 6-10); rs_ohm and pole_pairs serve both machines. */
    double rs_ohm;
    double ls_h;               /* L_d, the inductance along the magnet (a surface PM's L_s) */
    double lq_h;               /* L_q, the inductance across the magnet; 0 or ls_h: a surface PM
                                * (L_d = L_q = ls_h); otherwise a salient PM, rotor frame
                                * psi_d = L_d i_d + psi_m, psi_q = L_q i_q (docs/plant.md) */
    double psi_m_wb;
    int pole_pairs;
    double emf_gain[3];        /* per-phase back-EMF fundamental scale, 1.0 = psi_m_wb */
    double emf_harm[3][3];     /* [phase][3rd, 5th, 7th] amplitude relative to the fundamental */
    /* Which machine; the induction machine's T-model parameters (machine = PLANT_MACHINE_IM). */
    plant_machine_t machine;
    double rr_ohm;             /* rotor resistance, stator-referred */
    double lls_h, llr_h;       /* stator / rotor leakage inductance, stator-referred */
    double lm_h;               /* magnetising inductance */
    /* Mechanics. */
    double j_kgm2;
    double b_nm_s_per_rad;              /* viscous friction, N*m per rad/s */
    double coulomb_nm;         /* Coulomb (dry) friction of the shaft and coupled load, N*m: opposes
                                * the motion; at standstill it holds the rotor while the other
                                * torques sum to at most coulomb_nm (0 = none) */
    /* Inverter. */
    plant_inverter_t inverter;
    double vdc_v;              /* DC source voltage */
    double r_dc_ohm;           /* DC source internal resistance */
    double c_dc_f;             /* each DC-link capacitor (FSTP: two in series; SSTP: one of 2x) */
    double v_ce_v;             /* transistor forward drop (Hoang Table III/IV) */
    double v_d_v;              /* diode forward drop */
    double r_on_ohm;           /* on-state resistance of a conducting device */
    double dead_time_s;
    int drops_enabled;         /* 0: ideal devices (no V_CE, V_d, R_on) */
    int dead_time_enabled;     /* 0: no dead time */
    int finite_dc_link;        /* 0: stiff DC link (capacitor voltages fixed at vdc/2) */
    double r_bal_ohm;          /* balancing resistor across each DC-link capacitor (finite link;
                                * SSTP: across its one capacitor); 0 = not fitted */
    double esr_ohm;            /* equivalent series resistance of each DC-link capacitor (finite
                                * link); 0 = ideal capacitor */
    /* Load. */
    plant_load_t load;
    double load_speed_rpm;
    double load_torque_nm;
    /* Initial state. */
    double speed0_rpm;
    double theta_m0_rad;
    /* Numerics. */
    double max_step_s;         /* largest integration sub-step */
    /* ---- Fault-tolerant reconfiguration hardware. ---- */
    int reconfig_relay;        /* 1: a relay per phase ties that phase to the DC link's capacitor
                                * mid-point (plant_set_relay). The SSTP's link is then the split bank
                                * of the FSTP: two c_dc_f in series with the mid-point brought out */
    double relay_delay_s;      /* the relay's contacts follow its coil command after this delay
                                * (closing and opening alike) */
} plant_params_t;

typedef struct {
    double t_s;
    double i_a, i_b, i_c;             /* phase currents, A */
    double i_alpha_a, i_beta_a;       /* Clarke (amplitude-invariant), A */
    double psi_alpha_wb, psi_beta_wb; /* true stator flux linkage, Wb */
    double theta_e_rad;               /* electrical rotor angle, wrapped to [0, 2*pi) */
    double theta_m_rad;               /* mechanical rotor angle, unwrapped */
    double omega_m_rad_s;
    double speed_rpm;
    double te_nm;                     /* electromagnetic torque */
    double tload_nm;                  /* load torque applied */
    double vdc_v;                     /* DC-link voltage across the capacitor(s) */
    double vc_lo_v, vc_hi_v;          /* FSTP lower / upper capacitor voltages (at the terminals:
                                       * with esr_ohm > 0 they include the ESR drop) */
    double v_alpha_v, v_beta_v;       /* mean applied stator voltage over the last advance */
    /* Energy accounting since creation, J. */
    double e_dc_in_j, e_copper_j, e_device_j, e_friction_j, e_load_j;
    double e_magnetic_j, e_kinetic_j, e_capacitor_j;
    /* ---- Additions (after the original fields, so existing users are unaffected). ---- */
    double e_rdc_j;                   /* loss in the DC source's internal resistance, J */
    double v_a0_v, v_b0_v, v_c0_v;    /* mean terminal-to-negative-rail voltages, last advance */
    int blocked_mask;                 /* bit x set: phase x is held at zero current (all devices
                                       * of that path blocked), at the end of the last advance */
    double e_link_j;                  /* loss in the DC-link capacitors' ESR and balancing
                                       * resistors, J (in e_friction_j: Coulomb friction too) */
    double psi_r_alpha_wb, psi_r_beta_wb; /* induction machine: T-model rotor flux L_r i_r + L_m i_s
                                       * (Casadei's phi_r), Wb; 0 for the PM machine. e_copper_j
                                       * includes the rotor copper loss */
    double i2_int_a2s;                /* integral of i_a^2 + i_b^2 + i_c^2 since creation, A^2 s:
                                       * the continuous currents' mean square over any interval
                                       * (the sampled currents miss the ripple between samples) */
    double q_a_as, q_b_as;            /* integrals of i_a and i_b since creation, A s (charge): the
                                       * mean phase currents over any interval, free of the aliasing
                                       * that sampling once per period suffers */
} plant_state_t;

/* What a drive's sensors can see (addition): the subset of plant_state_t that hal/host samples
 * every control period (phase currents, capacitor voltages, shaft angle and speed). Each field
 * holds exactly the value of the plant_state_t field of the same name. plant_get_sensed() only
 * copies integrator states, while plant_get_state() also evaluates the PM flux, torque, mean
 * voltages and energies; hal/host calls the full read only when its caller asks for it. */
typedef struct {
    double t_s;
    double i_a, i_b, i_c;             /* phase currents, A */
    double theta_m_rad;               /* mechanical rotor angle, unwrapped */
    double omega_m_rad_s;
    double vdc_v;                     /* DC-link voltage across the capacitor(s) */
    double vc_lo_v, vc_hi_v;          /* FSTP lower / upper capacitor voltages */
} plant_sensed_t;

/* Per-leg override (addition), for protection and fault tests. */
typedef enum {
    PLANT_LEG_NORMAL = 0,     /* follow plant_set_legs */
    PLANT_LEG_DIODE_ONLY = 1, /* both gates held off: only the free-wheeling diodes conduct */
    PLANT_LEG_UPPER_ON = 2,   /* upper gate stuck on (lower off), whatever the command */
    PLANT_LEG_LOWER_ON = 3    /* lower gate stuck on (upper off), whatever the command */
} plant_leg_override_t;

/* Integration statistics since creation (addition; benchmark and tests). */
typedef struct {
    unsigned long long steps;        /* accepted integration steps */
    unsigned long long evals;        /* right-hand-side evaluations (4 per RK4 step + events) */
    unsigned long long events;       /* located zero-crossing / release events */
    unsigned long long mode_selects; /* complementarity mode selections with a zero current */
} plant_stats_t;

/* Defaults (values and sources: plant_defaults.h): Hoang Table VIII machine, Table IV devices,
 * 70 V DC link, SSTP. */
void plant_params_default(plant_params_t *p);

/* Sets the machine fields to the default induction machine (machine = PLANT_MACHINE_IM): 4 kW,
 * 4 poles, 50 Hz, 220 V, the Modelica Buildings IM_5HP_400V_50Hz set rescaled to 220 V
 * (plant_defaults.h, docs/plant.md, /work/shared/reference/im-facts.md). Inverter, load and
 * numerics unchanged. */
void plant_params_im_default(plant_params_t *p);

/* Returns NULL and writes a message into err when a parameter is invalid. */
typedef struct plant plant_t;
plant_t *plant_create(const plant_params_t *p, char *err, size_t err_len);
void plant_destroy(plant_t *plant);

/* Leg states for the next advance: 1 = upper device on. enable = 0: all gates off. */
void plant_set_legs(plant_t *plant, int sa, int sb, int sc, int enable);
/* Switching instants of one leg within the next advance: the leg's command (1 = upper device on)
 * is state0 at the start and toggles at each t_s[k], seconds from the start of the advance,
 * non-decreasing. Two instants per leg give one pulse (centred or asymmetric PWM, DSVM's
 * sub-intervals); none holds the leg for the whole advance (0/100 %, two-phase modulation's
 * clamped leg). The integrator lands exactly on each instant. Each instant is a command edge:
 * with dead time the outgoing device turns off at the instant and the incoming one turns on
 * dead_time_s later, the diodes conducting in between (so the terminal voltage's edge moves by
 * the dead time when the current flows into the outgoing device's diode, and not otherwise).
 * An instant at 0 acts at the start; one at or beyond the advance's length acts at its end. */
#define PLANT_LEG_EDGES_MAX 4
typedef struct {
    int state0;
    int n;                            /* 0..PLANT_LEG_EDGES_MAX */
    double t_s[PLANT_LEG_EDGES_MAX];
} plant_leg_edges_t;

/* Commands for the NEXT advance only (after it, each leg holds its last command, as after
 * plant_set_legs). plant_set_legs(sa, sb, sc, en) is this with n = 0 and state0 = sa, sb, sc.
 * Returns 0, or -1 (nothing changed) for n out of range or instants negative, not finite or
 * decreasing. */
int plant_set_leg_edges(plant_t *plant, const plant_leg_edges_t legs[3], int enable);

/* Ideal inverter only: alpha/beta voltages for the next advance. */
void plant_set_voltage(plant_t *plant, double v_alpha_v, double v_beta_v);
/* Change the load while running (load steps). */
void plant_set_load(plant_t *plant, plant_load_t load, double speed_rpm, double torque_nm);

void plant_advance(plant_t *plant, double dt_s);
void plant_get_state(const plant_t *plant, plant_state_t *s);
/* The part of plant_get_state() that the metrics' series read in a recorded period (addition): the
 * fields t_s, i_a, i_b, i_c, i_alpha_a, i_beta_a, psi_alpha_wb, psi_beta_wb, psi_r_alpha_wb,
 * psi_r_beta_wb, te_nm, theta_m_rad, omega_m_rad_s, speed_rpm, i2_int_a2s, q_a_as and q_b_as, each
 * exactly plant_get_state()'s value (the same code); the other fields of *s are left as they were.
 * It skips the link's terminal voltages, the mean voltages, the energies and the load torque. */
void plant_get_state_core(const plant_t *plant, plant_state_t *s);

/* ---- Additions ---- */

/* Hoang Table VII (measured back-EMF at 1500 rpm, peak volts): sets emf_gain[] to each phase's
 * fundamental divided by omega_e * psi_m_wb at 1500 rpm, and emf_harm[][] to the 3rd/5th/7th
 * amplitudes relative to that phase's fundamental. Call after setting psi_m_wb and pole_pairs. */
void plant_params_emf_table_vii(plant_params_t *p);

/* The full-fidelity FSTP rig of Hoang sec. IV: the defaults (Table IV drops, dead time, finite
 * split link) on the four-switch inverter with Table VII's back-EMF, into a DC-generator load of
 * torque_nm reached at 1500 rpm. Starts at standstill (speed0_rpm as the defaults). */
void plant_params_fstp_generator(plant_params_t *p, double torque_nm);

/* Override one leg (0 = A, 1 = B, 2 = C; FSTP leg A has no devices and ignores this). Takes effect
 * at the next advance. Returns 0, or -1 for a bad leg or mode. */
int plant_set_leg_override(plant_t *plant, int leg, plant_leg_override_t mode);

/* Change the largest integration sub-step (s) of a running plant. Returns 0, or -1 if out of the
 * range plant_create accepts (the message says why). */
int plant_set_max_step(plant_t *plant, double max_step_s, char *err, size_t err_len);

void plant_get_stats(const plant_t *plant, plant_stats_t *st);

/* The sensed subset of the state (see plant_sensed_t): a few loads, no model evaluation. */
void plant_get_sensed(const plant_t *plant, plant_sensed_t *s);

/* Set the phase currents (A) directly, e.g. to start a test from a known operating point.
 * Returns -1 unless |i_a + i_b + i_c| <= 1e-12 * (|i_a| + |i_b| + |i_c|) (isolated neutral).
 * The stored magnetic energy changes with it (energy accounting starts from the new state). */
int plant_set_phase_currents(plant_t *plant, double i_a, double i_b, double i_c);

/* ---- Faults. Each acts from the moment it is set (the plant's present time) on. ---- */

typedef enum {
    PLANT_SWITCH_OK = 0,
    PLANT_SWITCH_OPEN = 1,    /* the device never conducts (gate forced off); its anti-parallel diode
                               * still does */
    PLANT_SWITCH_SHORT = 2    /* the device conducts whatever its gate says. When the complementary
                               * device of the leg turns on (shoot-through) the gate driver's
                               * desaturation detection turns every gate of the inverter off: the
                               * plant latches that at the instant the complement's gate turns on
                               * (the ~1 us shoot-through current pulse itself is not integrated) and
                               * reports it (plant_fault_state_t.desat_mask). The shorted device goes
                               * on conducting with every gate off */
} plant_switch_fault_t;

/* Device `upper` (1: upper, 0: lower) of leg `leg` (0..2) fails as `mode`. Returns 0, or -1 for a
 * bad argument, the ideal inverter, or the FSTP's leg A (which has no devices). */
int plant_set_switch_fault(plant_t *plant, int leg, int upper, plant_switch_fault_t mode);

/* Leg `leg` (0..2) disconnected from its phase (open = 1): no device and no diode conducts into
 * that phase; its current is zero unless the relay ties the phase to the mid-point. A non-zero
 * current of that phase is cut to zero at once (the two other phases keep their sum at zero; the
 * phase's magnetic energy leaves the accounts, as in the arc of a real open circuit). Returns 0,
 * or -1 for a bad leg, the ideal inverter or the FSTP's leg A. */
int plant_set_leg_open(plant_t *plant, int leg, int open);

/* Coil command of the reconfiguration relay: 0 = open, 1..3 = tie phase A..C to the capacitor
 * mid-point. The contacts follow relay_delay_s later (the integrator lands on that instant). A
 * phase tied to the mid-point conducts as the FSTP's phase A (no device, no drop); its leg's
 * devices should be off: if a gate of that leg is on while the relay is closed (the capacitor half
 * shorted through the device), the desaturation trip latches as for a shoot-through. Returns 0, or
 * -1 if no relay is fitted (reconfig_relay = 0) or phase is out of 0..3. The contacts move inside
 * an advance, at its start at the earliest (relay_delay_s = 0: at the next advance's start, after
 * that advance's gate commands). */
int plant_set_relay(plant_t *plant, int phase);

/* DC source voltage from now on (a sag: a fraction of vdc_v). The capacitors follow through the
 * link's own dynamics (source resistance, capacitance); a stiff link (finite_dc_link = 0) steps
 * at once. Returns 0, or -1 unless vdc_v is finite and > 0. */
int plant_set_source_voltage(plant_t *plant, double vdc_v);

/* The machine's winding resistances from now on (a winding that warms or cools during a run):
 * rs_ohm (both machines) and rr_ohm (the induction machine's rotor; ignored for the PM machine),
 * the other parameters and the state (currents, rotor flux, speed) kept. Returns 0, or -1 unless
 * both are finite and > 0. */
int plant_set_resistances(plant_t *plant, double rs_ohm, double rr_ohm);

/* Energy accounts (plant_state_t's e_dc_in_j, e_copper_j, e_device_j, e_load_j, e_rdc_j,
 * e_link_j): on = 1 (from creation) integrates them; on = 0 holds them where they are and skips
 * their terms in every right-hand-side evaluation, for a user that never reads them (the SIL run
 * loop: about a fifth of an evaluation's instructions). No other state depends on them: every
 * other field of plant_state_t, and every later state, is the same to the last bit either way.
 * e_friction_j keeps being integrated (it is formed with the shaft's derivative). */
void plant_set_energy_accounts(plant_t *plant, int on);

/* Reset of the gate drivers' desaturation latch (the gates may be commanded again). */
void plant_clear_desat(plant_t *plant);

typedef struct {
    int desat_mask;           /* bit x: leg x's gate driver saw desaturation (latched) */
    double desat_t_s;         /* plant time at which the first desaturation latched (-1: none) */
    int relay_cmd;            /* coil command, 0..3 */
    int relay_closed;         /* phase the contacts tie to the mid-point now, 0 = open */
} plant_fault_state_t;
void plant_get_fault_state(const plant_t *plant, plant_fault_state_t *f);

#ifdef __cplusplus
}
#endif

#endif /* DTC_MODEL_PLANT_H */
