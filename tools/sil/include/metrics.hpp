// metrics.hpp - the SIL metrics of Hoang 2011 Tables IX and X, computed from sampled signals.
//
// Window: the last metrics_window_s of the run, trimmed to a whole number of periods of the phase
// currents' fundamental, using the unwrapped angle of that fundamental (exact under speed ripple;
// no assumption of a constant frequency): the PM machine's electrical angle p theta_m; for the
// induction machine, whose currents run at the stator frequency, not at p times the rotor
// speed, the angle of the plant's stator flux (psi_alpha, psi_beta). Spectra use FFTW (real-input DFT of the trimmed window, no window function:
// with whole periods the fundamental and its harmonics fall on bins exactly).
//
// Definitions:
//   fundamental_a[x]  peak amplitude of phase x's fundamental, A.
//   thd_pct[x]        Hoang eq. 39, THD_x = sqrt(sum_{n>=2} X_n^2) / X_1 * 100 %. The sum runs over
//                     every spectral line except DC and the fundamental, so switching ripple that is
//                     not locked to the fundamental counts too and the result does not depend on the
//                     window length; for a periodic signal this equals eq. 39 exactly.
//                     thd_harmonic_pct counts only the integer harmonics n*f1 (eq. 39 read literally).
//   thd_total_pct     Hoang eq. 39: sqrt((THD_A^2 + THD_B^2 + THD_C^2) / 3).
//   thd40_pct[x]      harmonics 2..40 only, IEC 61000-4-7 style: the RMS of the harmonic subgroups
//                     h = 2..40 (the line at h*f1 and, with 2 or more periods in the window, its two
//                     neighbours at the window's resolution) over the fundamental; switching ripple
//                     above 40 f1 does not count. thd40_total_pct combines the phases as Hoang eq. 39.
//   imbalance_pct     100 * (max/min - 1) of the three fundamentals.
//   trf_pct           Hoang eq. 40: (T_max - T_min) / T_rated * 100 % over the window.
//   trf_filtered_pct  Hoang eq. 40 on the plant torque after a first-order low-pass of torque_sensor_hz
//                     (what a torque transducer of that bandwidth shows; 0 = unfiltered = trf_pct).
//   switching_freq_hz turn-on events per second per switching device, averaged over the switched
//                     legs: every leg-state change turns one of the leg's two devices on, and so does
//                     re-enabling the gates; f = events / (2 * legs * T_window).
//   flux_est_error_rms_pct  100 * rms(|psi_est - psi|) / rms(|psi|).
#ifndef DTC_SIL_METRICS_HPP
#define DTC_SIL_METRICS_HPP

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "sil_constants.hpp"

namespace sil {

/// Signals sampled once per control period (row k = instant t_k; legs = applied over period k).
struct Series {
    double ts_s = 50e-6;
    std::vector<double> ia, ib, ic;
    std::vector<double> te, te_est;                 // te_est may be empty (no estimator)
    std::vector<double> psi_a, psi_b, psi_a_est, psi_b_est; // *_est may be empty
    std::vector<double> speed_rpm;
    std::vector<double> theta_fund_rad;             // unwrapped angle of the currents' fundamental, rad
    std::vector<double> i2_int;                     // plant's integral of i_a^2+i_b^2+i_c^2, A^2 s (may be empty)
    std::vector<double> q_a, q_b;                   // plant's integrals of i_a, i_b, A s (empty with i2_int)
    std::vector<std::uint8_t> sa, sb, sc, en;       // leg states at the period's start; may be empty (ideal inverter)
    std::vector<std::uint8_t> tog_a, tog_b, tog_c;  // leg-state changes inside the period (PWM form); empty = none
    std::size_t size() const { return ia.size(); }
};

/// [begin, begin + n) covers `periods` whole periods of the fundamental; periods == 0 if none fits.
struct Window {
    std::size_t begin = 0;
    std::size_t n = 0;
    int periods = 0;
};

/// Largest whole number of periods of the fundamental inside the last `window_n` samples.
/// The window ends at the last sample; its start is the sample whose angle is closest to
/// theta_end - periods * 2 pi (the end sample itself begins the next period, so it is excluded).
Window whole_period_window(const std::vector<double>& theta_fund_rad, std::size_t window_n);

struct Spectrum {
    double fundamental_peak = 0.0; // peak amplitude of the fundamental
    double thd_pct = 0.0;          // all non-DC, non-fundamental lines (see header)
    double thd_harmonic_pct = 0.0; // integer harmonics only
    double thd40_pct = 0.0;        // harmonic subgroups 2..40 (see header)
};
/// DFT of x[0..n) that holds `periods` whole periods (fundamental at bin `periods`). The plan of
/// the last length is kept for the next call of that length (spectrum() and compute_metrics()
/// share it): the same plan, so the same numbers, without planning again. Not thread-safe.
Spectrum spectrum(const double* x, std::size_t n, int periods);
/// Plans (and drops) the transform of n samples that spectrum() and compute_metrics() make. FFTW
/// keeps what its planner found for the rest of the process, and so does every process forked
/// after the call: there the same plan (the same numbers) costs a fraction (the default
/// scenario's 7202 samples: ~14 M host instructions cold, ~2 M warm). n < 4: nothing.
void prepare_spectrum(std::size_t n);

double imbalance_pct(const std::array<double, 3>& amplitudes);
double thd_total_pct(const std::array<double, 3>& thd);
double trf_pct(const double* t, std::size_t n, double rated_torque_nm);
double mean(const double* x, std::size_t n);
/// x[0..n) through 1 / (1 + s / (2 pi f_c)), sampled every ts_s, started in its periodic steady
/// state (see metrics.cpp); f_c <= 0 returns x unchanged.
std::vector<double> first_order_filtered(const double* x, std::size_t n, double f_c_hz, double ts_s);
/// legs_mask: bit 0 = leg A, bit 1 = B, bit 2 = C.
double switching_frequency_hz(const Series& s, std::size_t begin, std::size_t n, unsigned legs_mask);
double flux_error_rms_pct(const Series& s, std::size_t begin, std::size_t n);
/// Three-phase rms current ripple (Casadei sec. 13, Table 5): sqrt of the mean over the window of
/// (1/3) sum_x (i_x - i_x,1)^2, i_x,1 the fundamental, for a window of `periods` whole periods.
/// Everything comes from the plant's integrals at rows begin and begin + n..., never from the
/// once-per-period samples (they miss the ripple between them, and the ripple at the sampling
/// frequency +- f1 aliases onto f1): the continuous mean square from s.i2_int; the fundamentals
/// from the per-period mean currents (differences of s.q_a, s.q_b; i_c = -i_a - i_b), whose DFT
/// line at f1 is the continuous one times sinc(w1 ts / 2) (divided out); the fundamentals' share
/// sum_x |I_x,1|^2 / 2 is orthogonal to the rest over whole periods (Parseval). NaN without the
/// integrals.
double current_ripple_rms_a(const Series& s, std::size_t begin, std::size_t n, int periods);

struct MetricsConfig {
    double window_s = 0.2;
    double rated_torque_nm = 0.3;
    unsigned switched_legs = 0x7; // 0 for the ideal inverter
    double torque_sensor_hz = 0.0; // trf_filtered_pct: first-order cutoff, 0 = unfiltered
};

struct Metrics {
    Window window;
    double window_s = 0.0;       // trimmed window actually used
    double f_e_hz = 0.0;         // periods / window_s
    std::optional<std::array<double, 3>> fundamental_a, thd_pct, thd_harmonic_pct, thd40_pct;
    std::optional<double> imbalance_pct, thd_total_pct, thd40_total_pct;
    std::optional<double> current_ripple_rms_a; // current_ripple_rms_a() over the window
    double torque_mean_nm = 0.0, trf_pct = 0.0, trf_filtered_pct = 0.0;
    std::optional<double> torque_est_mean_nm, trf_est_pct, flux_est_error_rms_pct;
    double speed_mean_rpm = 0.0;
    std::optional<double> switching_freq_hz;
};

/// All metrics over the last cfg.window_s of s. Without a whole electrical period in the window
/// (standstill) the spectral metrics are empty and the others use the untrimmed window.
Metrics compute_metrics(const Series& s, const MetricsConfig& cfg);

} // namespace sil

#endif // DTC_SIL_METRICS_HPP
