// metrics.cpp - see metrics.hpp.
#include "metrics.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>

namespace sil {

Window whole_period_window(const std::vector<double>& theta_fund_rad, std::size_t window_n)
{
    Window w;
    const std::size_t total = theta_fund_rad.size();
    if (total < 2 || window_n < 2) {
        return w;
    }
    window_n = std::min(window_n, total);
    const std::size_t last = total - 1;
    const std::size_t first = total - window_n;
    const double span = std::fabs(theta_fund_rad[last] - theta_fund_rad[first]);
    const int periods = static_cast<int>(std::floor(span / (2.0 * kPi) + 1e-9));
    if (periods < 1) {
        return w;
    }
    const double target = static_cast<double>(periods) * (2.0 * kPi);
    std::size_t best = first;
    double best_err = INFINITY;
    for (std::size_t i = first; i < last; ++i) {
        const double err = std::fabs(std::fabs(theta_fund_rad[last] - theta_fund_rad[i]) - target);
        if (err < best_err) {
            best_err = err;
            best = i;
        }
    }
    w.begin = best;
    w.n = last - best;
    w.periods = periods;
    return w;
}

namespace {
/// One FFTW plan for every phase of a window: the planner, not the transform, is the larger cost
/// at window lengths with large prime factors (the default scenario's 7201 = 19 x 379 samples:
/// ~13.6 M host instructions to plan, ~1.7 M per transform). The input is copied into one buffer and
/// the plan executed on it, so every phase is transformed on arrays of the same alignment as
/// the planned ones: the same plan and the same numbers as planning for each phase.
class SpectrumPlan {
public:
    explicit SpectrumPlan(std::size_t n) : n_(n), nc_(n / 2 + 1)
    {
        if (n < 4) {
            throw std::invalid_argument("spectrum: need at least 2 samples per period");
        }
        in_ = fftw_alloc_real(n);
        spec_ = fftw_alloc_complex(nc_);
        plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(n), in_, spec_, FFTW_ESTIMATE);
    }
    SpectrumPlan(const SpectrumPlan&) = delete;
    SpectrumPlan& operator=(const SpectrumPlan&) = delete;
    ~SpectrumPlan()
    {
        fftw_destroy_plan(plan_);
        fftw_free(spec_);
        fftw_free(in_);
    }
    std::size_t size() const { return n_; }
    /// The spectrum of x[0..n) holding `periods` whole periods.
    Spectrum operator()(const double* x, int periods);

private:
    std::size_t n_;
    std::size_t nc_;
    double* in_ = nullptr;
    fftw_complex* spec_ = nullptr;
    fftw_plan plan_ = nullptr;
};

Spectrum SpectrumPlan::operator()(const double* x, int periods)
{
    if (n_ < 4 || periods < 1 || static_cast<std::size_t>(periods) * 2 > n_) {
        throw std::invalid_argument("spectrum: need at least 2 samples per period");
    }
    Spectrum out;
    const std::size_t n = n_, nc = nc_;
    const fftw_complex* spec = spec_;
    std::copy(x, x + n, in_);
    fftw_execute(plan_);
    // RMS^2 of the line at bin k: 2|X_k|^2/N^2 inside, |X_k|^2/N^2 at DC and Nyquist.
    auto rms2 = [&](std::size_t k) {
        const double re = spec[k][0], im = spec[k][1];
        const double m2 = (re * re + im * im) / (static_cast<double>(n) * static_cast<double>(n));
        const bool edge = k == 0 || (n % 2 == 0 && k == n / 2);
        return edge ? m2 : 2.0 * m2;
    };
    const auto f1 = static_cast<std::size_t>(periods);
    const double fund2 = rms2(f1);
    double all2 = 0.0, harm2 = 0.0;
    for (std::size_t k = 1; k < nc; ++k) {
        if (k == f1) {
            continue;
        }
        const double r2 = rms2(k);
        all2 += r2;
        if (k % f1 == 0) {
            harm2 += r2;
        }
    }
    // Harmonic subgroups 2..40 (IEC 61000-4-7 sec. 3.3): the line at h*f1 plus, when the window
    // holds 2 or more periods, its two neighbours at the window's resolution f1/periods.
    double sub2 = 0.0;
    for (std::size_t h = 2; h <= 40; ++h) {
        const std::size_t c = h * f1;
        const std::size_t lo = f1 >= 2 ? c - 1 : c, hi = f1 >= 2 ? c + 1 : c;
        for (std::size_t k = lo; k <= hi && k < nc; ++k) {
            sub2 += rms2(k);
        }
    }
    out.thd40_pct = fund2 > 0.0 ? 100.0 * std::sqrt(sub2 / fund2) : INFINITY;
    out.fundamental_peak = std::sqrt(2.0 * fund2);
    out.thd_pct = fund2 > 0.0 ? 100.0 * std::sqrt(all2 / fund2) : INFINITY;
    out.thd_harmonic_pct = fund2 > 0.0 ? 100.0 * std::sqrt(harm2 / fund2) : INFINITY;
    return out;
}

/// The plan of the last length transformed, kept for the next call of the same length: a sweep's
/// worker process runs one run after another at the same window length, and executing a kept plan
/// gives the same numbers as planning again (the same plan, FFTW_ESTIMATE) without the ~2 M host
/// instructions of a warm planning. Used from one thread (the run's).
SpectrumPlan& plan_for(std::size_t n)
{
    static std::unique_ptr<SpectrumPlan> kept;
    if (!kept || kept->size() != n) {
        kept.reset(); // one plan's buffers at a time
        kept = std::make_unique<SpectrumPlan>(n);
    }
    return *kept;
}

} // namespace

Spectrum spectrum(const double* x, std::size_t n, int periods) { return plan_for(n)(x, periods); }

void prepare_spectrum(std::size_t n)
{
    if (n >= 4) {
        const SpectrumPlan plan(n);
    }
}

double imbalance_pct(const std::array<double, 3>& a)
{
    const double mx = std::max({a[0], a[1], a[2]});
    const double mn = std::min({a[0], a[1], a[2]});
    return mn > 0.0 ? 100.0 * (mx / mn - 1.0) : INFINITY;
}

double thd_total_pct(const std::array<double, 3>& t)
{
    return std::sqrt((t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) / 3.0);
}

double trf_pct(const double* t, std::size_t n, double rated_torque_nm)
{
    if (n == 0) {
        return 0.0;
    }
    const auto mm = std::minmax_element(t, t + n);
    return 100.0 * (*mm.second - *mm.first) / rated_torque_nm;
}

std::vector<double> first_order_filtered(const double* x, std::size_t n, double f_c_hz, double ts_s)
{
    std::vector<double> y(x, x + n);
    if (n == 0 || !(f_c_hz > 0.0)) {
        return y;
    }
    // y_k = y_{k-1} + a (x_k - y_{k-1}), a = 1 - exp(-2 pi f_c ts): the first-order lag
    // 1 / (1 + s / (2 pi f_c)) sampled with the input held over each period (exact at the samples).
    const double a = 1.0 - std::exp(-2.0 * kPi * f_c_hz * ts_s);
    // The window holds whole electrical periods: a first pass from y = x_0 ends close to the
    // periodic steady state, which starts the second (reported) pass.
    double st = x[0];
    for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t i = 0; i < n; ++i) {
            st += a * (x[i] - st);
            y[i] = st;
        }
    }
    return y;
}

double mean(const double* x, std::size_t n)
{
    if (n == 0) {
        return 0.0;
    }
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        s += x[i];
    }
    return s / static_cast<double>(n);
}

double switching_frequency_hz(const Series& s, std::size_t begin, std::size_t n, unsigned legs_mask)
{
    const std::vector<std::uint8_t>* legs[3] = {&s.sa, &s.sb, &s.sc};
    const std::vector<std::uint8_t>* togs[3] = {&s.tog_a, &s.tog_b, &s.tog_c};
    int n_legs = 0;
    double events = 0.0;
    const bool have_en = s.en.size() == s.size();
    for (int l = 0; l < 3; ++l) {
        if ((legs_mask & (1u << l)) == 0u) {
            continue;
        }
        const std::vector<std::uint8_t>& v = *legs[l];
        if (v.size() != s.size()) {
            continue;
        }
        ++n_legs;
        // Boundary before row i, for every row of the window (the first one only if it has a
        // predecessor): each state change turns one device on; re-enabling turns one on as well.
        // With the PWM form a row also counts the changes inside its period, and the state the
        // previous period ended in is its start state toggled that many times.
        const std::vector<std::uint8_t>& tg = *togs[l];
        const bool have_tog = tg.size() == s.size();
        for (std::size_t i = std::max<std::size_t>(begin, 1); i < begin + n; ++i) {
            const bool en_prev = have_en ? s.en[i - 1] != 0u : true;
            const bool en_now = have_en ? s.en[i] != 0u : true;
            if (!en_now) {
                continue;
            }
            const unsigned prev_end = have_tog ? (v[i - 1] ^ (tg[i - 1] & 1u)) : v[i - 1];
            if (!en_prev || v[i] != prev_end) {
                events += 1.0;
            }
            if (have_tog) {
                events += static_cast<double>(tg[i]);
            }
        }
    }
    if (n_legs == 0 || n == 0) {
        return 0.0;
    }
    return events / (2.0 * n_legs * static_cast<double>(n) * s.ts_s);
}

double flux_error_rms_pct(const Series& s, std::size_t begin, std::size_t n)
{
    double e2 = 0.0, p2 = 0.0;
    for (std::size_t i = begin; i < begin + n; ++i) {
        const double ea = s.psi_a_est[i] - s.psi_a[i];
        const double eb = s.psi_b_est[i] - s.psi_b[i];
        e2 += ea * ea + eb * eb;
        p2 += s.psi_a[i] * s.psi_a[i] + s.psi_b[i] * s.psi_b[i];
    }
    return p2 > 0.0 ? 100.0 * std::sqrt(e2 / p2) : INFINITY;
}

double current_ripple_rms_a(const Series& s, std::size_t begin, std::size_t n, int periods)
{
    if (n == 0 || periods < 1 || begin + n >= s.i2_int.size() || begin + n >= s.q_a.size() ||
        begin + n >= s.q_b.size()) {
        return NAN;
    }
    const double nd = static_cast<double>(n);
    const double mean_sq = (s.i2_int[begin + n] - s.i2_int[begin]) / (nd * s.ts_s);
    // Single-line DFT of the per-period means at bin `periods` (period k's mean current stands at
    // the middle of the period: only the phase of the line depends on it, not its magnitude).
    std::complex<double> ca{}, cb{};
    for (std::size_t k = 0; k < n; ++k) {
        const double ia = (s.q_a[begin + k + 1] - s.q_a[begin + k]) / s.ts_s;
        const double ib = (s.q_b[begin + k + 1] - s.q_b[begin + k]) / s.ts_s;
        const std::complex<double> e = std::polar(1.0, -2.0 * kPi * static_cast<double>(periods) * static_cast<double>(k) / nd);
        ca += ia * e;
        cb += ib * e;
    }
    const double x = kPi * static_cast<double>(periods) / nd; // w1 ts / 2
    const double g = 2.0 / nd / (std::sin(x) / x);            // DFT line -> peak amplitude, boxcar undone
    const std::complex<double> fa = g * ca, fb = g * cb, fc = -fa - fb;
    const double fund_sq = 0.5 * (std::norm(fa) + std::norm(fb) + std::norm(fc));
    return std::sqrt(std::fmax(0.0, mean_sq - fund_sq) / 3.0);
}

Metrics compute_metrics(const Series& s, const MetricsConfig& cfg)
{
    Metrics m;
    const std::size_t total = s.size();
    if (total == 0) {
        return m;
    }
    // window_s spans round(window_s / ts) sample intervals, i.e. one more sample than that.
    auto window_n = static_cast<std::size_t>(std::llround(cfg.window_s / s.ts_s)) + 1;
    window_n = std::clamp<std::size_t>(window_n, 1, total);
    Window w = whole_period_window(s.theta_fund_rad, window_n);
    std::size_t b = total - window_n, n = window_n;
    if (w.periods >= 1 && w.n >= 2 * static_cast<std::size_t>(w.periods)) {
        b = w.begin;
        n = w.n;
        std::array<double, 3> fund{}, thd{}, thdh{}, thd40{};
        const std::vector<double>* ph[3] = {&s.ia, &s.ib, &s.ic};
        SpectrumPlan& plan = plan_for(n);
        for (int p = 0; p < 3; ++p) {
            const Spectrum sp = plan(ph[p]->data() + b, w.periods);
            fund[static_cast<std::size_t>(p)] = sp.fundamental_peak;
            thd[static_cast<std::size_t>(p)] = sp.thd_pct;
            thdh[static_cast<std::size_t>(p)] = sp.thd_harmonic_pct;
            thd40[static_cast<std::size_t>(p)] = sp.thd40_pct;
        }
        m.thd40_pct = thd40;
        m.thd40_total_pct = thd_total_pct(thd40);
        m.fundamental_a = fund;
        m.thd_pct = thd;
        m.thd_harmonic_pct = thdh;
        m.imbalance_pct = imbalance_pct(fund);
        m.thd_total_pct = thd_total_pct(thd);
        if (s.i2_int.size() == total) {
            m.current_ripple_rms_a = current_ripple_rms_a(s, b, n, w.periods);
        }
    } else {
        w = Window{b, n, 0};
    }
    m.window = w;
    m.window_s = static_cast<double>(n) * s.ts_s;
    m.f_e_hz = static_cast<double>(w.periods) / m.window_s;
    m.torque_mean_nm = mean(s.te.data() + b, n);
    m.trf_pct = trf_pct(s.te.data() + b, n, cfg.rated_torque_nm);
    {
        const std::vector<double> tf = first_order_filtered(s.te.data() + b, n, cfg.torque_sensor_hz, s.ts_s);
        m.trf_filtered_pct = trf_pct(tf.data(), n, cfg.rated_torque_nm);
    }
    m.speed_mean_rpm = mean(s.speed_rpm.data() + b, n);
    if (s.te_est.size() == total) {
        m.torque_est_mean_nm = mean(s.te_est.data() + b, n);
        m.trf_est_pct = trf_pct(s.te_est.data() + b, n, cfg.rated_torque_nm);
    }
    if (s.psi_a_est.size() == total && s.psi_b_est.size() == total && s.psi_a.size() == total &&
        s.psi_b.size() == total) {
        m.flux_est_error_rms_pct = flux_error_rms_pct(s, b, n);
    }
    if (cfg.switched_legs != 0u) {
        m.switching_freq_hz = switching_frequency_hz(s, b, n, cfg.switched_legs);
    }
    return m;
}

} // namespace sil
