// bench_plant - simulated seconds per wall second of the plant (prints figures; not a test).
//
// Full-fidelity FSTP (Hoang Table IV drops, 2 us dead time, finite split DC link with source
// resistance, Hoang Table VII back-EMF) driven with a fixed switching pattern: one decision per
// 50 us period, the four FSTP vectors rotating at the 1500 rpm electrical frequency with every
// fourth period reversed, so both legs switch and every period has a dead-time segment.
// The cost split is shown by switching each non-ideality off in turn, by a run that does not read
// the state, and by the integrator counts.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include "plant.h"
#include "ref_dtc.h"

namespace {
constexpr double kPi = 3.14159265358979323846;

struct Result {
    double ratio, cpu_ratio, ns_per_period, steps_per_period, evals_per_period, events_per_period;
};

// Pattern source: 0 = rotating vector reversed every 4th period (a leg switches in almost every
// period), 1 = recorded from the reference FSTP DTC (current model, Hoang Table II) closing the loop
// on the same plant at 1000 rpm with a 0.2 N*m generator load (recorded first, not timed).
int g_pattern = 0;
// 0: plant_get_state every period, as hal/host does; 1: not read (shows plant_get_state's share).
int g_skip_state = 0;
// Speed at the end of the last IM PWM run (printed: the drive holds the rated point).
double g_last_speed_rpm = 0.0;
static int pat[2][200000];

void record_dtc_pattern(const plant_params_t &p0, int n) {
    plant_params_t p = p0;
    p.load_speed_rpm = 1000.0;
    p.load_torque_nm = 0.2;
    p.speed0_rpm = 1000.0;
    char err[256];
    plant_t *pl = plant_create(&p, err, sizeof err);
    dtc_ref::Params rp;
    rp.topology = dtc_ref::Topology::FSTP;
    rp.table = dtc_ref::SwitchingTable::HOANG_FSTP;
    rp.voltage_delay_periods = 1;
    dtc_ref::Controller c;
    if (!pl || c.init(rp) != 0) {
        std::fprintf(stderr, "record_dtc_pattern: setup failed\n");
        std::exit(1);
    }
    c.set_speed_ref(1000.0 * 2 * kPi / 60);
    plant_state_t s;
    for (int k = 0; k < n; ++k) {
        plant_get_state(pl, &s);
        dtc_ref::Meas m;
        m.i_a = s.i_a; m.i_b = s.i_b; m.i_c = s.i_c; m.vdc_v = s.vdc_v;
        m.have_vc = true; m.vc_lo_v = s.vc_lo_v; m.vc_hi_v = s.vc_hi_v;
        m.theta_e_rad = s.theta_e_rad; m.omega_m_rad_s = s.omega_m_rad_s;
        const dtc_ref::Out o = c.step(m);
        pat[0][k] = o.sb;
        pat[1][k] = o.sc;
        plant_set_legs(pl, 0, o.sb, o.sc, 1);
        plant_advance(pl, 50e-6);
    }
    plant_destroy(pl);
}

// A plant for the benchmark (exits on a refused parameter set).
plant_t *make_plant(const plant_params_t &p) {
    char err[256];
    plant_t *pl = plant_create(&p, err, sizeof err);
    if (!pl) {
        std::fprintf(stderr, "plant_create: %s\n", err);
        std::exit(1);
    }
    return pl;
}

// Times n periods of period(k) on pl (wall clock and this thread's CPU time), then destroys pl.
template <class Period>
Result timed(plant_t *pl, int n, double sim_s, Period period) {
    timespec c0, c1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < n; ++k) period(k);
    const auto t1 = std::chrono::steady_clock::now();
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
    const double wall = std::chrono::duration<double>(t1 - t0).count();
    const double cpu = double(c1.tv_sec - c0.tv_sec) + 1e-9 * double(c1.tv_nsec - c0.tv_nsec);
    plant_stats_t st;
    plant_get_stats(pl, &st);
    plant_destroy(pl);
    return {sim_s / wall, sim_s / cpu, cpu / n * 1e9, double(st.steps) / n, double(st.evals) / n, double(st.events) / n};
}

Result run(const plant_params_t &p, double sim_s) {
    plant_t *pl = make_plant(p);
    const int n = static_cast<int>(sim_s / 50e-6);
    // Pre-compute the pattern so the timed loop is the plant alone.
    if (g_pattern == 0) {
        for (int k = 0; k < n && k < 200000; ++k) {
            const double ang = 2 * kPi * 25.0 * k * 50e-6 + kPi / 2;
            dtc_ref::fstp_vector_towards((k % 4 == 3) ? ang + kPi : ang, pat[0][k], pat[1][k]);
        }
    }
    plant_state_t s;
    return timed(pl, n, sim_s, [&](int k) {
        plant_set_legs(pl, 0, pat[0][k], pat[1][k], 1);
        plant_advance(pl, 50e-6);
        if (!g_skip_state) plant_get_state(pl, &s);  // hal/host reads the state every period
    });
}

// Induction machine on the SSTP (Casadei's inverter): a 50 Hz six-step vector sequence with a null
// vector every 4th period, so all three legs switch and most periods have dead-time segments, at
// 40 us periods (Casadei's DTC period), near the rated point (1440 rpm, 26.5 N*m constant load).
Result run_im(const plant_params_t &p, double sim_s) {
    plant_t *pl = make_plant(p);
    const double ts = 40e-6;
    const int n = static_cast<int>(sim_s / ts);
    static int leg[200000 * 5 / 4][3];
    for (int k = 0; k < n; ++k) {
        const double a = std::fmod(2 * kPi * 50.0 * k * ts + kPi / 2, 2 * kPi);
        const int sec = static_cast<int>(std::floor((a + kPi / 6) / (kPi / 3))) % 6;
        static const int tab[6][3] = {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}, {1, 0, 1}};
        for (int x = 0; x < 3; ++x) leg[k][x] = (k % 4 == 3) ? 0 : tab[sec][x];
    }
    plant_state_t s;
    return timed(pl, n, sim_s, [&](int k) {
        plant_set_legs(pl, leg[k][0], leg[k][1], leg[k][2], 1);
        plant_advance(pl, ts);
        plant_get_state(pl, &s);
    });
}

// Induction machine on the SSTP driven with PWM edges (plant_set_leg_edges), 40 us periods:
// sinusoidal references at the rated 50 Hz with min-max zero-sequence injection (the centred
// pulses of space-vector PWM), amplitude at the rated 220 V (phase peak 220 sqrt(2/3) = 179.6 V,
// just inside the linear range vdc / sqrt(3) of the 311 V link), centred pulses: each leg high for
// d_x Ts in the middle of the period, d_x = 1/2 + v_x / vdc, so every leg has two edges (two
// dead-time segments) per period. 26.5 N*m constant load from 1440 rpm (the rated point).
Result run_im_pwm(const plant_params_t &p, double sim_s) {
    plant_t *pl = make_plant(p);
    const double ts = 40e-6;
    const int n = static_cast<int>(sim_s / ts);
    static double duty[200000 * 5 / 4][3];
    const double vpk = 220.0 * std::sqrt(2.0 / 3.0);
    for (int k = 0; k < n; ++k) {
        const double a = 2 * kPi * 50.0 * (k + 0.5) * ts;  // reference at the period's centre
        double v[3];
        for (int x = 0; x < 3; ++x) v[x] = vpk * std::cos(a - 2 * kPi / 3 * x);
        const double v0 = -0.5 * (std::fmax(v[0], std::fmax(v[1], v[2])) + std::fmin(v[0], std::fmin(v[1], v[2])));
        for (int x = 0; x < 3; ++x) duty[k][x] = std::fmin(1.0, std::fmax(0.0, 0.5 + (v[x] + v0) / p.vdc_v));
    }
    plant_state_t s;
    plant_leg_edges_t e[3];
    const Result r = timed(pl, n, sim_s, [&](int k) {
        for (int x = 0; x < 3; ++x) {
            e[x].state0 = 0;
            e[x].n = 2;
            e[x].t_s[0] = 0.5 * ts * (1.0 - duty[k][x]);
            e[x].t_s[1] = 0.5 * ts * (1.0 + duty[k][x]);
        }
        plant_set_leg_edges(pl, e, 1);
        plant_advance(pl, ts);
        plant_get_state(pl, &s);
    });
    g_last_speed_rpm = s.speed_rpm;
    return r;
}

void line(const char *name, const plant_params_t &p, double sim_s, int im = 0) {
    if (im) {
        Result (*f)(const plant_params_t &, double) = (im == 2) ? run_im_pwm : run_im;
        Result best = f(p, sim_s);
        for (int r = 0; r < 2; ++r) {
            const Result x = f(p, sim_s);
            if (x.cpu_ratio > best.cpu_ratio) best = x;
        }
        std::printf("%-44s %6.0fx %6.0fx  %7.1f ns/period  steps %.2f  rhs evals %.2f  events %.3f\n", name,
                    best.ratio, best.cpu_ratio, best.ns_per_period, best.steps_per_period, best.evals_per_period,
                    best.events_per_period);
        return;
    }
    Result best = run(p, sim_s);
    for (int r = 0; r < 2; ++r) {  // best of three against the noise of a shared machine
        const Result x = run(p, sim_s);
        if (x.cpu_ratio > best.cpu_ratio) best = x;
    }
    std::printf("%-44s %6.0fx %6.0fx  %7.1f ns/period  steps %.2f  rhs evals %.2f  events %.3f\n", name,
                best.ratio, best.cpu_ratio, best.ns_per_period, best.steps_per_period, best.evals_per_period,
                best.events_per_period);
}
}  // namespace

int main(int argc, char **argv) {
    double sim_s = (argc > 1) ? std::atof(argv[1]) : 2.0;
    if (!(sim_s > 0.0) || sim_s > 9.0) sim_s = 2.0;  // pattern buffer holds 10 s
    plant_params_t p;
    plant_params_fstp_generator(&p, 0.3);
    p.speed0_rpm = 1500.0;
    std::printf("bench_plant: %.1f s simulated per case, 50 us periods, max_step %.1f us, dead time %.1f us\n",
                sim_s, p.max_step_s * 1e6, p.dead_time_s * 1e6);
    std::printf("%-44s %7s %7s  %s\n", "case", "wall", "cpu", "(x real time; cost per period in thread CPU time)");
    line("FSTP full fidelity (default max_step 50 us)", p, sim_s);
    g_skip_state = 1;
    line("  - state not read (plant_advance alone)", p, sim_s);
    g_skip_state = 0;
    plant_params_t q = p;
    q.max_step_s = 25e-6;
    line("FSTP full fidelity, max_step 25 us", q, sim_s);
    q = p;
    q.max_step_s = 12.5e-6;
    line("FSTP full fidelity, max_step 12.5 us", q, sim_s);
    q = p;
    for (int x = 0; x < 3; ++x) q.emf_harm[x][0] = q.emf_harm[x][1] = q.emf_harm[x][2] = 0.0;
    line("  - sinusoidal EMF (no Table VII harmonics)", q, sim_s);
    q = p;
    q.dead_time_enabled = 0;
    line("  - no dead time", q, sim_s);
    q = p;
    q.drops_enabled = 0;
    line("  - ideal devices", q, sim_s);
    q = p;
    q.finite_dc_link = 0;
    line("  - stiff DC link", q, sim_s);
    // A realistic pattern: what the reference DTC actually commands.
    const int n = static_cast<int>(sim_s / 50e-6);
    record_dtc_pattern(p, n);
    int changes = 0;
    for (int k = 1; k < n; ++k) changes += (pat[0][k] != pat[0][k - 1]) + (pat[1][k] != pat[1][k - 1]);
    g_pattern = 1;
    std::printf("reference-DTC pattern (FSTP, 1000 rpm, 0.2 N*m generator): %.3f leg transitions per period\n",
                double(changes) / n);
    q = p;
    q.load_speed_rpm = 1000.0;
    q.load_torque_nm = 0.2;
    q.speed0_rpm = 1000.0;
    line("FSTP full fidelity, reference-DTC pattern", q, sim_s);
    // The induction machine (default IM, 311 V link) on the SSTP with drops and dead time.
    plant_params_t im;
    plant_params_default(&im);
    plant_params_im_default(&im);
    im.inverter = PLANT_INVERTER_SSTP;
    im.vdc_v = 311.0;
    im.load = PLANT_LOAD_TORQUE;
    im.load_torque_nm = 26.5;
    im.speed0_rpm = 1440.0;
    std::printf("induction machine (default IM, 4 kW), SSTP 311 V, drops + %.1f us dead time, 40 us periods, "
                "six-step 50 Hz pattern with a null every 4th period:\n", im.dead_time_s * 1e6);
    line("IM SSTP full fidelity (40 us periods)", im, sim_s, 1);
    std::printf("same machine and inverter, centred PWM edges (plant_set_leg_edges): 50 Hz sinusoidal references "
                "with min-max injection at rated 220 V, two edges per leg per period:\n");
    line("IM SSTP full fidelity, PWM edges (40 us)", im, sim_s, 2);
    std::printf("  (speed at the end of the last run: %.1f rpm)\n", g_last_speed_rpm);
    return 0;
}
