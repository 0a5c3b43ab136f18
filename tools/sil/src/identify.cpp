// identify.cpp - dtc-sil identify: the firmware's self-commissioning (firmware/app/app_ident.h) on a
// scenario's rig, and its results as a [firmware] overlay (identified.toml) and a report against the
// plant's true values (identification.json). docs/commissioning.md.
#include "identify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

extern "C" {
#include "app.h"
#include "dtc_config_si.h"
}

#include "controller_adapter.hpp"
#include "hal_host.hpp"
#include "run.hpp"
#include "run_parts.hpp"

namespace sil {

namespace {

constexpr double kIqOne = 16777216.0; // 2^FIX_IQ_Q (iq_t = Q24)

const char* step_name(unsigned step)
{
    switch (step) {
    case APP_IDENT_RS: return "rs";
    case APP_IDENT_LS: return "ls";
    case APP_IDENT_ENCODER: return "encoder";
    case APP_IDENT_SPIN: return "spin";
    case APP_IDENT_DONE: return "done";
    default: return "start";
    }
}

std::string fail_text(const app_ident_t& d, const app_status_t& st)
{
    switch (d.fail) {
    case APP_IDENT_FAIL_OPEN_PHASE:
        return "open_phase: the current regulator reached its voltage limit with the current below a quarter of "
               "its reference, or (induction machine) a quadrature current above a quarter of the injected one that "
               "it cannot null (a phase, leg or connection carries no current)";
    case APP_IDENT_FAIL_BOUNDS: {
        static const char* const q[] = {"?",          "R (slope of V = R I + V0)", "V0 (intercept)", "L_s (L_d)",
                                        "pole pairs", "psi_m",                     "J (the coast's fit)",
                                        "L_q (or L_q / L_d outside 1/4 .. 8)"};
        const int k = d.fail_detail >= 1 && d.fail_detail <= 7 ? d.fail_detail : 0;
        if (d.fail_detail == APP_IDENT_Q_IM_LSIG) {
            return "out_of_bounds: sigma L_s outside its plausibility bounds (Z_b Ts / 16 .. L_s / 2)";
        }
        if (d.fail_detail == APP_IDENT_Q_IM_TAUR) {
            return "out_of_bounds: tau_r or R_r outside its plausibility bounds";
        }
        return std::string("out_of_bounds: ") + q[k] + " outside its plausibility bounds";
    }
    case APP_IDENT_FAIL_ENC_NOT_COUNTING:
        return "encoder_not_counting: the count moved " + std::to_string(d.fail_detail) +
               " over one electrical turn of the current vector";
    case APP_IDENT_FAIL_ENC_LINES:
        return "encoder_lines: " + std::to_string(d.fail_detail) +
               " counts per electrical turn, no whole fraction of the configured counts per turn (wrong line count?)";
    case APP_IDENT_FAIL_OVERCURRENT: return "overcurrent: a phase above 1.25 x rated current";
    case APP_IDENT_FAIL_TRIP: return std::string("trip: the drive's protection tripped (") + app_fault_name(st.fault) + ")";
    case APP_IDENT_FAIL_COUPLED_LOAD:
        return "coupled_load: the rotor turned freely in the encoder step but stayed below half the spin speed at "
               "the spin's q current (a load coupled to the shaft; uncouple it to identify the machine's mechanics)";
    case APP_IDENT_FAIL_BLOCKED:
        if (d.fail_step == APP_IDENT_ENCODER) {
            return "blocked: the count did not move under a rotating field and the field's q voltage is below half "
                   "of omega_e L_s i_d (the rotor does not follow the field: blocked)";
        }
        return "blocked: the rotor did not reach an eighth of the spin speed in 2 s at half rated q current (a "
               "blocked rotor or a coupled load)";
    case APP_IDENT_FAIL_VDC_LOW:
        if (d.fail_step != APP_IDENT_SPIN) {
            return "dc_link_low: the current regulator at its voltage limit (a quarter of the measured DC link) while "
                   "a level was measured (the DC link too low for rated current in this machine)";
        }
        return "dc_link_low: the current regulator at its voltage limit before an eighth of the spin speed (the DC "
               "link too low to spin the machine)";
    case APP_IDENT_FAIL_NOT_SETTLED:
        return "not_settled: the voltage and current of DC level " + std::to_string(d.fail_detail) +
               " did not settle within 200 windows (a rotor time constant above about a second, or a turning rotor)";
    case APP_IDENT_FAIL_SENSOR_SIGN:
        if (d.fail_detail >= 1 && d.fail_detail <= 3) {
            return std::string("current_sensor_reversed: phase ") + static_cast<char>('A' + d.fail_detail - 1) +
                   " read the wrong sign on its own sign pulse (its current sensor mounted the wrong way round)";
        }
        return "current_sensor_reversed: a phase current of the wrong sign on a sign pulse (sensor polarity or "
               "wiring)";
    case APP_IDENT_FAIL_MOVED:
        return "rotor_moved: the encoder count moved by " + std::to_string(d.fail_detail) +
               " counts (more than about 1/64 turn) during the q-axis pulses of the L_q measurement (a very light "
               "rotor, or a load turning the shaft): L_q would carry the back-EMF";
    case APP_IDENT_FAIL_NOT_AT_REST:
        return "not_at_rest: the rotor did not come to rest on a DC vector within 2 s (a coupled load, a blocked or "
               "a far too heavy rotor)";
    default: return "unknown";
    }
}

// The firmware's configuration for the identification: the scenario's board (sensing, link,
// topology, encoder lines), nameplate (rated current, speed, torque) and protection; for the
// machine the law's configuration needs, placeholders that carry nothing of the plant (the
// identification reads none of them: app_ident.h).
dtc_config_si_t ident_si(const Scenario& sc)
{
    dtc_config_si_t si = firmware_si_config(sc);
    const double z_b = si.v_base_v / si.i_base_a;
    si.rs_ohm = z_b / 64.0;
    si.ls_h = z_b * sc.ts_s * 4.0;
    si.pole_pairs = 1;
    si.w_base_rad_s = sc.motor.rated_speed_rpm * kPi / 30.0;
    si.psi_m_wb = sc.motor.rated_torque_nm / (1.5 * sc.motor.rated_current_a); // nameplate torque constant, p = 1
    if (sc.motor.type != MotorType::Im) {
        si.flux_ref_wb = si.psi_m_wb; // an induction machine keeps the drive's configured stator flux (its spin's)
    }
    si.enc_offset_rad = 0.0;
    si.inertia_kgm2 = 1e-4;
    si.kp_nm_s_rad = 0.0;
    si.ki_nm_rad = 0.0;
    si.cal_hold = 0; // the start-up's rotor hold needs the machine; the identification aligns the rotor itself
    si.enc_reversed = 0; // the direction is identified from the raw count
    if (sc.motor.type == MotorType::Im) {
        // placeholders for the induction machine's law, from the bases only (nothing of the plant):
        // L_m = 512 Z_b Ts, L_ls = L_lr = 16 Z_b Ts, R_r = Z_b / 16 (tau_r = 8192 Ts)
        si.rr_ohm = z_b / 16.0;
        si.lls_h = z_b * sc.ts_s * 16.0;
        si.llr_h = si.lls_h;
        si.lm_h = z_b * sc.ts_s * 512.0;
        si.ls_h = 0.0;
        si.psi_m_wb = 0.0;
    }
    return si;
}

double wrap_pi(double x) { return std::remainder(x, 2.0 * kPi); }

std::string fmt(double x)
{
    char b[40];
    std::snprintf(b, sizeof b, "%.6g", x);
    return b;
}

} // namespace

bool identify(const Scenario& sc, const std::string& out_dir, IdentifyReport* rep, std::string* err)
{
    const bool im = sc.motor.type == MotorType::Im;
    if ((sc.motor.type != MotorType::Pmsm && !(im && sc.inverter.topology == Topology::Sstp)) ||
        sc.inverter.topology == Topology::Ideal) {
        *err = "identify: the PM machine on the SSTP or FSTP, or the induction machine on the SSTP (motor.type = "
               "\"pmsm\" or \"im\", inverter.topology \"sstp\" or \"fstp\")";
        return false;
    }
    const dtc_config_si_t si = ident_si(sc);
    dtc_config_t cfg;
    char msg[256] = {0};
    if (const int rc = dtc_config_from_si(&si, &cfg, msg, sizeof msg); rc != DTC_SI_OK) {
        *err = "identify: firmware configuration refused (" + std::to_string(rc) + "): " + msg;
        return false;
    }
    ActiveHarness active;
    hal_host::Harness* const h = active.open(sc, err);
    if (h == nullptr) {
        return false;
    }
    hal_init();
    if (const int16_t rc = app_init(&cfg); rc != 0) {
        *err = "identify: app_init() refused the configuration (dtc_err " + std::to_string(rc) + ")";
        return false;
    }
    app_request_ident();
    // The rig as the identification finds it: the scenario's load law at its initial torque; the
    // scenario's load step belongs to its test run, not to the machine (its faults stay).
    Scenario rig = sc;
    rig.load.step_time_s = 0.0;
    RunEvents events(rig, active.params().load);
    const auto max_periods = static_cast<std::uint64_t>(std::llround(rep->max_time_s / sc.ts_s));
    app_ident_t d{};
    app_status_t st{};
    std::uint64_t k = 0;
    for (; k < max_periods; ++k) {
        events.before_sample(*h);
        h->sample();
        app_isr();
        app_background();
        h->advance();
        if ((k & 63u) == 0u) {
            app_get_ident(&d);
            app_get_status(&st);
            if (d.step == APP_IDENT_DONE || d.step == APP_IDENT_FAILED || st.state == APP_STATE_FAULT) {
                break;
            }
        }
    }
    app_get_ident(&d);
    app_get_status(&st);
    rep->duration_s = static_cast<double>(k) * sc.ts_s;

    // Results in SI (app_ident.h formats; bases: V_b = inverter.vdc_v, I_b = rated current).
    const double v_b = si.v_base_v, i_b = si.i_base_a, z_b = v_b / i_b;
    const double ts = sc.ts_s;
    const double r_fit = d.res.r_iq / kIqOne * z_b;
    const double v0 = d.res.v0_iq / kIqOne * v_b;
    const double ls = d.res.l_ts_iq / kIqOne * z_b * ts;
    const int p = d.res.pole_pairs;
    const double off_e = d.res.enc_offset / 65536.0 * 2.0 * kPi;
    // The board's device data (the inverter's datasheet): R_on is in series with R_s in every
    // conduction state (Hoang Table III: v = rail - v_f - R_on i), so no injection separates them:
    // the slope is R_s + R_on (docs/commissioning.md).
    // (An inverter without drops, inverter.drops = false, has datasheet values 0.)
    const double r_on = sc.inverter.drops ? sc.inverter.r_on_ohm : 0.0;
    const double v_ce = sc.inverter.drops ? sc.inverter.v_ce_v : 0.0;
    const double v_d = sc.inverter.drops ? sc.inverter.v_d_v : 0.0;
    const double rs = r_fit - r_on;
    // V0 = g (V_CE + V_d + 2 V_dc T_d / T_s) on the injection axis, g = 1/sqrt(3) on the beta axis
    // (FSTP: legs B and C carry +-I), 2/3 on the alpha axis (SSTP: +I in leg A, -I/2 in B and C)
    // (docs/commissioning.md): the dead time follows with the datasheet's thresholds.
    const double g = d.res.axis == 0 ? 2.0 / 3.0 : 1.0 / std::sqrt(3.0);
    const double td = (v0 / g - v_ce - v_d) * ts / (2.0 * sc.inverter.vdc_v);
    const double drop_rated = v0 + r_on * i_b;

    const MotorCfg& m = sc.motor;
    const double td_true = sc.inverter.dead_time ? sc.inverter.dead_time_s : 0.0;
    const double thr_true = sc.inverter.drops ? v_ce + v_d : 0.0;
    const double r_on_true = sc.inverter.drops ? r_on : 0.0;
    const double v0_true = g * (thr_true + 2.0 * sc.inverter.vdc_v * td_true / ts);
    const double drop_true = v0_true + r_on_true * i_b;
    // hal_host: the electrical angle at count 0 is -p * sensors.encoder_offset_rad.
    // The inverter's frame with two leads exchanged (inverter.phases_swapped) is the machine's mirrored
    // (theta_inv = -theta_e): the count then runs down for the inverter's forward field, as with a
    // reversed encoder (hal_host counts -theta_m, the angle at count 0 +p offset); both cancel.
    const bool rev_true = sc.sensors.encoder_reversed != sc.inverter.phases_swapped;
    const double off_e_true = wrap_pi((rev_true ? 1.0 : -1.0) * static_cast<double>(m.pole_pairs) * sc.sensors.encoder_offset_rad);

    double step_s[7] = {};
    for (unsigned k2 = 0; k2 < 7; ++k2) {
        step_s[k2] = d.res.ticks[k2] * ts;
    }
    const bool ok = d.step == APP_IDENT_DONE;
    const unsigned failed_step = d.step == APP_IDENT_FAILED ? d.fail_step : (ok ? 0u : d.step);
    // the steps' order (APP_IDENT_SPIN is numbered after APP_IDENT_FAILED)
    auto rank = [](unsigned step) { return step == APP_IDENT_SPIN ? 4u : step; };
    auto status_of = [&](unsigned step) -> std::string {
        if (ok || (failed_step != 0 && rank(step) < rank(failed_step))) {
            return "ok";
        }
        return step == failed_step ? "failed" : "not_run";
    };
    nlohmann::json q = nlohmann::json::object();
    auto add = [&](const std::string& key, double id, double truth, const std::string& unit, unsigned step,
                   bool relative, const std::string& note) {
        nlohmann::json e;
        e["identified"] = id;
        e["true"] = truth;
        e["unit"] = unit;
        if (relative) {
            e["error_pct"] = truth != 0.0 ? 100.0 * (id - truth) / truth : 0.0;
        } else {
            e["error"] = id - truth;
        }
        e["step"] = step_name(step);
        e["duration_s"] = step_s[step];
        e["status"] = status_of(step);
        if (!note.empty()) {
            e["note"] = note;
        }
        q[key] = e;
    };
    add("rs_ohm", rs, m.rs_ohm, "ohm", APP_IDENT_RS, true, "slope R_s + R_on less the datasheet R_on");
    add("r_slope_ohm", r_fit, m.rs_ohm + r_on_true, "ohm", APP_IDENT_RS, true,
        "slope of V = R I + V0 on the injection axis: R_s + R_on");
    add("v0_v", v0, v0_true, "V", APP_IDENT_RS, true, "g (V_CE + V_d + 2 V_dc T_d / T_s), g = 1/sqrt(3) (FSTP, beta axis) or 2/3 (SSTP, alpha axis)");
    add("drop_at_rated_v", drop_rated, drop_true, "V", APP_IDENT_RS, true,
        "inverter drop on the injection axis at rated current: V0 + R_on I_rated");
    add("dead_time_s", td, td_true, "s", APP_IDENT_RS, true, "from V0 with the datasheet's V_CE + V_d");
    // Spin (app_ident.h formats): psi_m in pu of V_b / w_b; J, B, T_c over k_t I_b (k_t = 1.5 p psi_m)
    // in pu current x Ts^2 per count, x Ts per count, pu current; a count is 2 pi / enc_counts rad.
    const double psi = d.res.psi_iq / kIqOne * v_b / si.w_base_rad_s;
    double kt_ib = 1.5 * p * psi * i_b;
    const double rad_per_count = 2.0 * kPi / (4.0 * static_cast<double>(si.enc_lines)); // the board data's lines
    double j_id = d.res.j_q12 / 4096.0 * kt_ib * ts * ts / rad_per_count;
    double b_id = d.res.b_iq / kIqOne * kt_ib * ts / rad_per_count;
    double tc_id = d.res.tc_iq / kIqOne * kt_ib;
    // the plant's friction: motor.b_nm_s_per_rad, and the DC generator's torque proportional to speed
    const double b_true = m.b_nm_s_per_rad + (sc.load.type == LoadType::Generator && sc.load.speed_rpm > 0.0
                                                  ? sc.load.torque_nm / (sc.load.speed_rpm * kPi / 30.0)
                                                  : 0.0);
    double saliency = 0.0; // L_q / L_d (PM)
    bool salient = false;  // the firmware's verdict: L_q departs from L_d beyond the measurement's accuracy
    double im_ls = 0.0, im_lsig = 0.0, im_l = 0.0, im_lm = 0.0, im_rr = 0.0, im_ls_spin = 0.0;
    if (im) {
        // Induction machine (app_ident_im.h): L_s, sigma L_s as L / (Z_b Ts); tau_r in periods (Q4);
        // R_r (T model with L_lr = L_ls, so L_r = L_s) and R_R (inverse Gamma) in pu of Z_b. The T
        // model's split of the leakage is not observable at the stator's terminals: with
        // L_ls = L_lr = l, sigma L_s = L_s - (L_s - l)^2 / L_s gives l = L_s (1 - sqrt(1 - sigma)),
        // L_m = L_s - l.
        im_ls = d.res.im.ls_ts_iq / kIqOne * z_b * ts;
        im_lsig = d.res.im.lsig_ts_iq / kIqOne * z_b * ts;
        const double sigma = im_ls > 0.0 ? std::clamp(im_lsig / im_ls, 0.0, 1.0) : 0.0;
        im_l = im_ls * (1.0 - std::sqrt(1.0 - sigma));
        im_lm = im_ls - im_l;
        im_rr = d.res.im.rr_iq / kIqOne * z_b;
        const double taur = d.res.im.taur_q4 / 16.0 * ts;
        const double ls_t = m.lls_h + m.lm_h, lr_t = m.llr_h + m.lm_h;
        const double lsig_t = ls_t - m.lm_h * m.lm_h / lr_t;
        add("ls_h", im_ls, ls_t, "H", APP_IDENT_RS, true,
            "L_s = L_ls + L_m: the stator flux over the current after the DC step settled");
        // Spinning (app_ident_im.c): psi_iq = L_s i_d at the configured stator flux; J, B, T_c over
        // k_t = 1.5 p L_M i_d (L_M = L_s - sigma L_s, the inverse-Gamma magnetising inductance).
        const double id_a = d.res.im.id_iq / kIqOne * i_b;
        im_ls_spin = id_a > 0.0 ? psi / id_a : 0.0;
        if (im_ls_spin > im_lsig) {
            const double sig = im_lsig / im_ls_spin;
            im_l = im_ls_spin * (1.0 - std::sqrt(1.0 - sig));
            im_lm = im_ls_spin - im_l;
            kt_ib = 1.5 * p * (im_ls_spin - im_lsig) * id_a * i_b;
            j_id = d.res.j_q12 / 4096.0 * kt_ib * ts * ts / rad_per_count;
            b_id = d.res.b_iq / kIqOne * kt_ib * ts / rad_per_count;
            tc_id = d.res.tc_iq / kIqOne * kt_ib;
        }
        add("ls_spin_h", im_ls_spin, ls_t, "H", APP_IDENT_SPIN, true,
            "L_s at the configured stator flux, turning: the q voltage's slope over the electrical speed over i_d");
        add("id_a", id_a, 0.0, "A", APP_IDENT_SPIN, false, "the spin's magnetising current: flux_ref_wb over the standstill L_s");
        q["id_a"].erase("true");
        q["id_a"].erase("error");
        add("sigma_ls_h", im_lsig, lsig_t, "H", APP_IDENT_LS, true,
            "transient inductance sigma L_s = L_s - L_m^2 / L_r: voltage steps on the half-rated hold");
        add("tau_r_s", taur, lr_t / m.rr_ohm, "s", APP_IDENT_RS, true,
            "rotor time constant L_r / R_r: the area of the rotor flux's rise after the DC step");
        add("rr_ohm", im_rr, m.rr_ohm, "ohm", APP_IDENT_RS, true, "R_r = L_r / tau_r with L_r = L_s (L_lr = L_ls)");
        add("rr_inv_gamma_ohm", (im_ls - im_lsig) / taur, m.rr_ohm * (m.lm_h / lr_t) * (m.lm_h / lr_t), "ohm",
            APP_IDENT_RS, true, "R_R = R_r (L_m / L_r)^2 = L_M / tau_r: independent of the leakage split");
        add("lm_h", im_lm, m.lm_h, "H", APP_IDENT_SPIN, true,
            "L_m = L_s - l with the spinning L_s (the standstill L_s if the spin failed), l = L_ls = L_lr assumed equal");
        add("lls_h", im_l, m.lls_h, "H", APP_IDENT_LS, true, "L_ls = L_s (1 - sqrt(1 - sigma)), L_lr = L_ls assumed");
        add("llr_h", im_l, m.llr_h, "H", APP_IDENT_LS, true, "L_lr = L_ls assumed");
        add("pole_pairs", p, static_cast<double>(m.pole_pairs), "", APP_IDENT_ENCODER, false,
            "the encoder's counts per turn of a field rotating at w_b / 8, the rotor unloaded");
        add("encoder_reversed", d.res.enc_reversed, rev_true ? 1.0 : 0.0, "", APP_IDENT_ENCODER, false,
            "the count runs down for the inverter's forward field");
        add("j_kgm2", j_id, m.j_kgm2, "kg*m^2", APP_IDENT_SPIN, true,
            "acceleration at i_q = (2/p)^2 / 8 of rated under indirect field orientation and a coast");
        add("b_nm_s_per_rad", b_id, b_true, "N*m*s/rad", APP_IDENT_SPIN, false,
            "viscous friction; a fan load (torque ~ speed^2) is absorbed in b and T_c");
        add("coulomb_nm", tc_id, sc.load.coulomb_nm, "N*m", APP_IDENT_SPIN, false, "");
    } else {
        // L_d and L_q (step LS: the d steps, then the q square wave; lq_periods is the latter's share;
        // the firmware keeps L_q / L_d in Q12)
        const double lq = ls * d.res.lq_q12 / 4096.0;
        const double lq_s = d.lq_periods * ts;
        add("ls_h", ls, m.ls_h, "H", APP_IDENT_LS, true,
            "L_d: the rotor aligned on the step axis (the value the PM law runs on; a salient PM's L_d)");
        add("ld_h", ls, m.ls_h, "H", APP_IDENT_LS, true, "L_d: voltage steps on the half-rated DC current along the aligned axis");
        q["ld_h"]["duration_s"] = step_s[APP_IDENT_LS] - lq_s;
        add("lq_h", lq, m.lq_h, "H", APP_IDENT_LS, true,
            "L_q: an alternating voltage square wave along the quadrature axis on the same hold, volt-seconds over the "
            "current swing");
        q["lq_h"]["duration_s"] = lq_s;
        if (d.res.lq_q12 == 0U) {
            q["lq_h"]["status"] = q["ls_h"]["status"] == "ok" ? "failed" : q["ls_h"]["status"];
        }
        saliency = ls > 0.0 && lq > 0.0 ? lq / ls : 0.0;
        salient = d.res.salient != 0U;
        add("pole_pairs", p, static_cast<double>(m.pole_pairs), "", APP_IDENT_ENCODER, false, "");
        add("encoder_reversed", d.res.enc_reversed, rev_true ? 1.0 : 0.0, "", APP_IDENT_ENCODER, false,
            "the count runs down for the inverter's forward field: a reversed encoder or two motor leads exchanged");
        {
            const double e_deg = wrap_pi(off_e - off_e_true) * 180.0 / kPi;
            add("encoder_offset_el_deg", off_e * 180.0 / kPi, off_e_true * 180.0 / kPi, "deg (electrical)",
                APP_IDENT_ENCODER, false, "");
            q["encoder_offset_el_deg"]["error"] = e_deg;
        }
        add("psi_m_wb", psi, m.psi_m_wb, "Wb", APP_IDENT_SPIN, true,
            "slope of the q voltage over the electrical speed at constant q current (Hoang eqs. 6-9)");
        add("j_kgm2", j_id, m.j_kgm2, "kg*m^2", APP_IDENT_SPIN, true, "acceleration at half rated q current and a coast");
        add("b_nm_s_per_rad", b_id, b_true, "N*m*s/rad", APP_IDENT_SPIN, true,
            "viscous friction, the coupled DC generator's included");
        add("coulomb_nm", tc_id, sc.load.coulomb_nm, "N*m", APP_IDENT_SPIN, false, "");
    }
    nlohmann::json j;
    j["scenario"] = sc.path;
    j["status"] = ok ? "ok" : "failed";
    j["failed_step"] = ok ? "" : step_name(failed_step);
    j["reason"] = ok ? "" : (d.step == APP_IDENT_FAILED ? fail_text(d, st)
                                                        : (st.state == APP_STATE_FAULT ? "drive fault before the identification"
                                                                                       : "timeout"));
    j["duration_s"] = rep->duration_s;
    j["injection_axis"] = d.res.axis == 0 ? "alpha" : "beta";
    // an induction machine's encoder step turns the rotor (a rotating field): it is part of its spin
    j["standstill_s"] = step_s[1] + step_s[2] + (im ? 0.0 : step_s[3]);
    j["spin_s"] = step_s[APP_IDENT_SPIN] + (im ? step_s[3] : 0.0);
    j["quantities"] = q;
    if (!im && d.res.lq_q12 != 0U) {
        // The verdict on saliency (the firmware's res.salient: |L_q - L_d| > L_d / 16).
        j["saliency_ratio"] = saliency;
        j["saliency_ratio_true"] = m.lq_h / m.ls_h;
        j["salient"] = salient;
        j["saliency"] = salient ? "salient: L_q / L_d = " + fmt(saliency) +
                                      ", beyond the measurement's accuracy (1/16); the PM law runs on L_d "
                                      "(firmware.ls_h) and L_q (firmware.lq_h): see docs/commissioning.md, salient PM"
                                : "no saliency: L_q / L_d = " + fmt(saliency) + ", within the measurement's accuracy (1/16)";
    }
    for (unsigned l = 0; l < APP_IDENT_R_LEVELS; ++l) {
        j["rs_fit_points"].push_back({{"i_a", d.res.level_i_iq[l] / kIqOne * i_b}, {"v_v", d.res.level_v_iq[l] / kIqOne * v_b}});
    }
    j["not_identified"] = {"v_ce_v", "v_d_v", "r_on_ohm"};


    if (!im && salient) {
        rep->warning = "salient PM: L_q / L_d = " + fmt(saliency) + " (L_d = " + fmt(ls) + " H, L_q = " +
                       fmt(ls * d.res.lq_q12 / 4096.0) +
                       " H); identified.toml gives the PM law both (ls_h = L_d, lq_h = L_q; docs/commissioning.md, "
                       "salient PM)";
    }
    rep->ok = ok;
    rep->failed_step = ok ? "" : step_name(failed_step);
    rep->reason = j["reason"];
    rep->json = j.dump(2);

    if (out_dir.empty()) {
        return true; // the report only (dtc-sil sweep --identify)
    }
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
        *err = "--out " + out_dir + ": " + ec.message();
        return false;
    }
    {
        std::ofstream f(std::filesystem::path(out_dir) / "identification.json");
        f << rep->json << "\n";
        if (!f) {
            *err = "cannot write " + out_dir + "/identification.json";
            return false;
        }
    }
    std::ostringstream t;
    t << "# dtc-sil identify " << sc.path << ": the firmware's self-commissioning (docs/commissioning.md).\n"
      << "# Use: dtc-sil run SCENARIO --overlay identified.toml\n";
    if (!ok) {
        t << "# FAILED in step " << rep->failed_step << ": " << rep->reason << "\n";
    }
    t << "# Not identified: v_ce_v, v_d_v, r_on_ohm are the board's datasheet values (not separable by DC\n"
      << "# injection), rs_ohm is the slope less r_on_ohm.\n"
      << "[firmware]\n";
    if (ok || failed_step > APP_IDENT_RS) {
        t << "rs_ohm = " << fmt(rs) << "\n";
        t << "dead_time_s = " << fmt(std::fmax(td, 0.0)) << "\n";
    }
    if (im && ok) {
        t << "rr_ohm = " << fmt(im_rr) << "\n";
        t << "lls_h = " << fmt(im_l) << "\n";
        t << "llr_h = " << fmt(im_l) << "\n";
        t << "lm_h = " << fmt(im_lm) << "\n";
        t << "pole_pairs = " << p << "\n";
        t << "encoder_reversed = " << (d.res.enc_reversed != 0U ? "true" : "false") << "\n";
        t << "j_kgm2 = " << fmt(j_id) << "\n";
        t << "b_nm_s_per_rad = " << fmt(std::fmax(b_id, 0.0)) << "\n";
        t << "coulomb_nm = " << fmt(std::fmax(tc_id, 0.0)) << "\n";
    }
    if (!im && (ok || failed_step > APP_IDENT_LS)) {
        // ls_h is L_d (the d steps with the rotor aligned), lq_h L_q; within the measurement's accuracy
        // (not salient) lq_h is L_d, a surface PM, as the firmware's IDENT_APPLY writes it
        const double lq = ls * d.res.lq_q12 / 4096.0;
        t << "# ls_h is L_d. L_d = " << fmt(ls) << " H, L_q = " << fmt(lq) << " H, L_q / L_d = " << fmt(saliency)
          << (salient ? ": salient, the PM law runs on L_d and L_q (docs/commissioning.md)"
                      : ": no saliency, lq_h = ls_h (a surface PM)")
          << "\n";
        t << "ls_h = " << fmt(ls) << "\n";
        if (d.res.lq_q12 != 0U) {
            t << "lq_h = " << fmt(salient ? lq : ls) << "\n";
        }
    }
    if (!im && ok) {
        t << "pole_pairs = " << p << "\n";
        // sensors.encoder_offset_rad's sense: the electrical angle at count 0 is -p times it, +p times it
        // reversed (firmware.encoder_reversed).
        t << "encoder_offset_rad = " << fmt(wrap_pi((d.res.enc_reversed != 0U ? off_e : -off_e) / p)) << "\n";
        t << "encoder_reversed = " << (d.res.enc_reversed != 0U ? "true" : "false") << "\n";
        t << "psi_m_wb = " << fmt(psi) << "\n";
        t << "j_kgm2 = " << fmt(j_id) << "\n";
        // friction measured below zero (noise on a frictionless rotor) is written as 0
        t << "b_nm_s_per_rad = " << fmt(std::fmax(b_id, 0.0)) << "\n";
        t << "coulomb_nm = " << fmt(std::fmax(tc_id, 0.0)) << "\n";
    }
    std::ofstream f(std::filesystem::path(out_dir) / "identified.toml");
    f << t.str();
    if (!f) {
        *err = "cannot write " + out_dir + "/identified.toml";
        return false;
    }
    return true;
}

} // namespace sil
