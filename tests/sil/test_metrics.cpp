// Metrics against synthetic signals with known answers (Hoang eqs. 39, 40 and the window rules).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <sys/wait.h>
#include <unistd.h>

#include "metrics.hpp"

using namespace sil;

namespace {
constexpr double kTs = 50e-6;

// Three-phase set with per-phase amplitude, and a common 5th/7th harmonic content.
Series three_phase(double f_hz, double duration_s, std::array<double, 3> amp, double h5 = 0.0, double h7 = 0.0,
                   double phase0 = 0.3)
{
    Series s;
    s.ts_s = kTs;
    const auto n = static_cast<std::size_t>(std::llround(duration_s / kTs));
    for (std::size_t k = 0; k < n; ++k) {
        const double th = 2.0 * kPi * f_hz * static_cast<double>(k) * kTs + phase0;
        const double sh[3] = {0.0, -2.0 * kPi / 3.0, 2.0 * kPi / 3.0};
        double* dst[3] = {nullptr, nullptr, nullptr};
        double v[3];
        for (int p = 0; p < 3; ++p) {
            const double a = th + sh[p];
            v[p] = amp[static_cast<std::size_t>(p)] * (std::cos(a) + h5 * std::cos(5.0 * a) + h7 * std::cos(7.0 * a));
        }
        (void)dst;
        s.ia.push_back(v[0]);
        s.ib.push_back(v[1]);
        s.ic.push_back(v[2]);
        s.theta_fund_rad.push_back(th);
        s.te.push_back(0.3);
        s.speed_rpm.push_back(60.0 * f_hz);
        s.psi_a.push_back(0.0928 * std::cos(th));
        s.psi_b.push_back(0.0928 * std::sin(th));
    }
    return s;
}
} // namespace

TEST(Metrics, SineWithKnownHarmonicsGivesExactThd)
{
    // 25 Hz (1500 rpm, p = 1): 800 samples per period; 5th = 4 %, 7th = 3 % -> THD = 5 % exactly.
    Series s = three_phase(25.0, 0.2, {2.2, 2.2, 2.2}, 0.04, 0.03);
    const Spectrum sp = spectrum(s.ia.data(), 4000, 5);
    EXPECT_NEAR(sp.fundamental_peak, 2.2, 1e-9);
    EXPECT_NEAR(sp.thd_pct, 5.0, 1e-8);
    EXPECT_NEAR(sp.thd_harmonic_pct, 5.0, 1e-8);
}

TEST(Metrics, NonHarmonicRippleCountsInThdButNotInHarmonicOnlyThd)
{
    // 2 A fundamental at 25 Hz + 0.1 A at 1015 Hz (not a multiple of 25 Hz, on a bin of the
    // 0.2 s window): THD = 5 % in the all-lines definition, 0 % counting harmonics only.
    Series s = three_phase(25.0, 0.2, {2.0, 2.0, 2.0});
    for (std::size_t k = 0; k < s.ia.size(); ++k) {
        s.ia[k] += 0.1 * std::sin(2.0 * kPi * 1015.0 * static_cast<double>(k) * kTs);
    }
    const Spectrum sp = spectrum(s.ia.data(), 4000, 5);
    EXPECT_NEAR(sp.thd_pct, 5.0, 1e-8);
    EXPECT_NEAR(sp.thd_harmonic_pct, 0.0, 1e-8);
}

TEST(Metrics, DcOffsetIsNotDistortion)
{
    Series s = three_phase(25.0, 0.2, {2.0, 2.0, 2.0});
    for (double& x : s.ia) {
        x += 0.5;
    }
    const Spectrum sp = spectrum(s.ia.data(), 4000, 5);
    EXPECT_NEAR(sp.fundamental_peak, 2.0, 1e-9);
    EXPECT_NEAR(sp.thd_pct, 0.0, 1e-8);
}

TEST(Metrics, UnbalancedThreePhaseSetGivesKnownImbalanceAndTotalThd)
{
    // Hoang Table IX, FSTP voltage model without compensation: 2.97 / 2.37 / 3.00 A.
    Series s = three_phase(25.0, 0.3, {2.97, 2.37, 3.00}, 0.05);
    MetricsConfig mc;
    mc.window_s = 0.2;
    mc.switched_legs = 0;
    const Metrics m = compute_metrics(s, mc);
    ASSERT_TRUE(m.fundamental_a.has_value());
    EXPECT_NEAR((*m.fundamental_a)[0], 2.97, 1e-6);
    EXPECT_NEAR((*m.fundamental_a)[1], 2.37, 1e-6);
    EXPECT_NEAR((*m.fundamental_a)[2], 3.00, 1e-6);
    EXPECT_NEAR(*m.imbalance_pct, 100.0 * (3.00 / 2.37 - 1.0), 1e-4); // 26.58 %
    // Hoang eq. 39 total: every phase has 5 % -> total 5 %.
    EXPECT_NEAR(*m.thd_total_pct, 5.0, 1e-6);
    EXPECT_NEAR(thd_total_pct({3.0, 4.0, 12.0}), std::sqrt((9.0 + 16.0 + 144.0) / 3.0), 1e-12);
}

TEST(Metrics, WindowIsTrimmedToWholeElectricalPeriods)
{
    // 27 Hz, 0.23 s window: 6.21 periods -> 6 periods; with a non-integer number of samples per
    // period (740.7) the trimmed window holds 4444 samples (6 * 740.74 rounded), and the amplitude
    // comes out within the half-sample leakage bound, while the untrimmed window leaks far more.
    Series s = three_phase(27.0, 0.5, {1.0, 1.0, 1.0});
    MetricsConfig mc;
    mc.window_s = 0.23;
    mc.switched_legs = 0;
    const Metrics m = compute_metrics(s, mc);
    EXPECT_EQ(m.window.periods, 6);
    EXPECT_NEAR(static_cast<double>(m.window.n), 6.0 / 27.0 / kTs, 1.0);
    EXPECT_EQ(m.window.begin + m.window.n, s.size() - 1);
    EXPECT_NEAR(m.window_s, 6.0 / 27.0, kTs);
    EXPECT_NEAR((*m.fundamental_a)[0], 1.0, 2e-4);
    EXPECT_LT((*m.thd_pct)[0], 0.2);
    // The same data over the untrimmed 0.23 s (6.21 periods) treated as 6 periods: visibly wrong.
    const std::size_t n_raw = static_cast<std::size_t>(0.23 / kTs);
    const Spectrum raw = spectrum(s.ia.data() + s.size() - n_raw, n_raw, 6);
    EXPECT_GT(raw.thd_pct, 10.0 * (*m.thd_pct)[0]);
}

TEST(Metrics, WindowFollowsTheAngleNotAnAssumedFrequency)
{
    // Speed steps from 25 Hz to 30 Hz inside the window: the trimming uses the unwrapped angle,
    // so the window still spans an exact multiple of 2 pi.
    std::vector<double> th;
    double a = 0.0;
    for (int k = 0; k < 8000; ++k) {
        th.push_back(a);
        a += 2.0 * kPi * (k < 5000 ? 25.0 : 30.0) * kTs;
    }
    const Window w = whole_period_window(th, 6000);
    ASSERT_GE(w.periods, 1);
    const double span = th[w.begin + w.n] - th[w.begin];
    EXPECT_NEAR(span, 2.0 * kPi * w.periods, 2.0 * kPi * 30.0 * kTs);
    EXPECT_EQ(w.periods, static_cast<int>(std::floor((th.back() - th[2000]) / (2.0 * kPi))));
}

TEST(Metrics, StandstillHasNoSpectralMetrics)
{
    Series s = three_phase(0.0, 0.1, {1.0, 1.0, 1.0});
    MetricsConfig mc;
    mc.window_s = 0.05;
    const Metrics m = compute_metrics(s, mc);
    EXPECT_FALSE(m.fundamental_a.has_value());
    EXPECT_FALSE(m.thd_total_pct.has_value());
    EXPECT_EQ(m.window.n, 1001u); // 0.05 s = 1000 intervals = 1001 samples
    EXPECT_NEAR(m.torque_mean_nm, 0.3, 1e-12);
}

TEST(Metrics, SquareWaveTorqueRippleGivesTrfByEq40)
{
    // 0.3 N*m mean with a +-0.1 N*m square ripple at 1 kHz: peak-to-peak 0.2 N*m -> TRF = 66.67 %
    // of the 0.3 N*m rated torque; mean exactly 0.3 over whole ripple periods.
    Series s = three_phase(25.0, 0.3, {1.0, 1.0, 1.0});
    for (std::size_t k = 0; k < s.te.size(); ++k) {
        s.te[k] = 0.3 + ((k / 10) % 2 == 0 ? 0.1 : -0.1);
    }
    EXPECT_NEAR(trf_pct(s.te.data(), s.te.size(), 0.3), 100.0 * 0.2 / 0.3, 1e-9);
    MetricsConfig mc;
    mc.window_s = 0.2;
    mc.rated_torque_nm = 0.3;
    const Metrics m = compute_metrics(s, mc);
    EXPECT_NEAR(m.trf_pct, 66.6666667, 1e-6);
    EXPECT_EQ(m.window.n, 4000u);             // 5 electrical periods = 200 whole ripple periods
    EXPECT_NEAR(m.torque_mean_nm, 0.3, 1e-12);
}

TEST(Metrics, KnownSwitchingPatternGivesSwitchingFrequency)
{
    // Leg B toggles every period: 1 turn-on per period per leg, shared by its 2 devices ->
    // 1 / (2 ts) = 10 kHz. Leg C toggles every 4th period -> 2.5 kHz. FSTP (legs B, C): mean 6.25 kHz.
    Series s = three_phase(25.0, 0.2, {1.0, 1.0, 1.0});
    const std::size_t n = s.size();
    for (std::size_t k = 0; k < n; ++k) {
        s.sa.push_back(0);
        s.sb.push_back(static_cast<std::uint8_t>(k % 2));
        s.sc.push_back(static_cast<std::uint8_t>((k / 4) % 2));
        s.en.push_back(1);
    }
    EXPECT_NEAR(switching_frequency_hz(s, 1000, 2000, 0x2), 10000.0, 1e-9);
    EXPECT_NEAR(switching_frequency_hz(s, 1000, 2000, 0x4), 2500.0, 1e-9);
    EXPECT_NEAR(switching_frequency_hz(s, 1000, 2000, 0x6), 6250.0, 1e-9);
    // Gates off for the second half: no turn-ons there; re-enabling counts one per leg.
    for (std::size_t k = 2000; k < 3000; ++k) {
        s.en[k] = 0;
    }
    EXPECT_NEAR(switching_frequency_hz(s, 1000, 1000, 0x2), 10000.0, 1e-9);
    EXPECT_NEAR(switching_frequency_hz(s, 2000, 1000, 0x2), 0.0, 1e-9);
    // Window [2500, 3500): 500 enabled rows, one re-enable edge at 3000 plus 499 toggles.
    EXPECT_NEAR(switching_frequency_hz(s, 2500, 1000, 0x2), 500.0 / (2.0 * 1000 * kTs), 1e-9);
}

// The PWM form: a centred pulse on every leg in every period (start low, two changes inside) is one
// turn-on per device per period, 1 / ts = 20 kHz at 50 us (2 changes per period and leg, 2 devices).
TEST(Metrics, PwmFormPulsesInsideThePeriodCount)
{
    Series s = three_phase(25.0, 0.2, {1.0, 1.0, 1.0});
    const std::size_t n = s.size();
    for (std::size_t k = 0; k < n; ++k) {
        for (auto* v : {&s.sa, &s.sb, &s.sc}) v->push_back(0);
        for (auto* v : {&s.tog_a, &s.tog_b, &s.tog_c}) v->push_back(2);
        s.en.push_back(1);
    }
    EXPECT_NEAR(switching_frequency_hz(s, 1000, 2000, 0x7), 1.0 / kTs, 1e-9);
    // Leg A clamped high (state 1, no change inside) every third period: per 3 periods, two
    // pulses (4 changes) plus the boundary changes into and out of the clamp (2): 6 changes.
    for (std::size_t k = 0; k < n; ++k) {
        if (k % 3 == 0) {
            s.sa[k] = 1;
            s.tog_a[k] = 0;
        }
    }
    EXPECT_NEAR(switching_frequency_hz(s, 999, 3000, 0x1), 6.0 / 3.0 / (2.0 * kTs), 1e-9);
}

TEST(Metrics, FluxErrorRmsIsRelativeToTheTrueFluxRms)
{
    Series s = three_phase(25.0, 0.2, {1.0, 1.0, 1.0});
    for (std::size_t k = 0; k < s.size(); ++k) {
        s.psi_a_est.push_back(1.02 * s.psi_a[k]); // 2 % magnitude error
        s.psi_b_est.push_back(1.02 * s.psi_b[k]);
    }
    EXPECT_NEAR(flux_error_rms_pct(s, 0, s.size()), 2.0, 1e-9);
}

TEST(Metrics, EstimateMetricsOnlyWithEstimates)
{
    Series s = three_phase(25.0, 0.2, {1.0, 1.0, 1.0});
    MetricsConfig mc;
    mc.window_s = 0.1;
    mc.switched_legs = 0;
    Metrics m = compute_metrics(s, mc);
    EXPECT_FALSE(m.torque_est_mean_nm.has_value());
    EXPECT_FALSE(m.flux_est_error_rms_pct.has_value());
    EXPECT_FALSE(m.switching_freq_hz.has_value());
    s.te_est.assign(s.size(), 0.33);
    m = compute_metrics(s, mc);
    ASSERT_TRUE(m.torque_est_mean_nm.has_value());
    EXPECT_NEAR(*m.torque_est_mean_nm, 0.33, 1e-12);
    EXPECT_NEAR(*m.trf_est_pct, 0.0, 1e-12);
}

TEST(Metrics, Thd40CountsHarmonicSubgroupsTwoToFortyOnly)
{
    // 5 periods of 25 Hz in 0.2 s (bin = 5 Hz): fundamental 1, 5th 0.1, an interharmonic at
    // 130 Hz (5th's subgroup neighbour, 0.05), the 41st 0.2 and a 3 kHz line 0.3 (switching
    // ripple). IEC 61000-4-7 subgroups 2..40: sqrt(0.1^2 + 0.05^2) = 11.180 %; the full band adds
    // 0.2 and 0.3: sqrt(0.01 + 0.0025 + 0.04 + 0.09) = 37.75 %.
    const std::size_t n = 4000;
    std::vector<double> x(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) * kTs;
        x[k] = std::cos(2 * kPi * 25 * t) + 0.1 * std::cos(2 * kPi * 125 * t + 0.4) +
               0.05 * std::cos(2 * kPi * 130 * t) + 0.2 * std::cos(2 * kPi * 1025 * t) +
               0.3 * std::sin(2 * kPi * 3000 * t);
    }
    const Spectrum sp = spectrum(x.data(), n, 5);
    EXPECT_NEAR(sp.thd40_pct, 100.0 * std::sqrt(0.0125), 1e-8);
    EXPECT_NEAR(sp.thd_pct, 100.0 * std::sqrt(0.0125 + 0.04 + 0.09), 1e-8);
    // Through compute_metrics: per phase and total, beside the full-band THD.
    Series s = three_phase(25.0, 0.2, {2.0, 2.0, 2.0}, 0.04, 0.03);
    MetricsConfig c;
    c.window_s = 0.2;
    const Metrics m = compute_metrics(s, c);
    ASSERT_TRUE(m.thd40_pct && m.thd40_total_pct);
    EXPECT_NEAR((*m.thd40_pct)[1], 5.0, 1e-6);
    EXPECT_NEAR(*m.thd40_total_pct, 5.0, 1e-6);
}

TEST(Metrics, FilteredTrfIsTheRippleThroughAFirstOrderSensor)
{
    // 0.3 N*m + 0.1 N*m ripple at 1 kHz through a 1 kHz first-order sensor: gain 1/sqrt(2)
    // (the held-input discretisation at 20 kHz changes it by < 0.5 %). TRF = 2 * 0.1 * gain / 0.3.
    const std::size_t n = 4000;
    std::vector<double> te(n);
    for (std::size_t k = 0; k < n; ++k) {
        te[k] = 0.3 + 0.1 * std::sin(2 * kPi * 1000.0 * static_cast<double>(k) * kTs);
    }
    const std::vector<double> y = first_order_filtered(te.data(), n, 1000.0, kTs);
    EXPECT_NEAR(trf_pct(y.data(), n, 0.3), 100.0 * 0.2 / std::sqrt(2.0) / 0.3, 0.005 * 100.0 * 0.2 / 0.3);
    EXPECT_NEAR(mean(y.data(), n), 0.3, 1e-4); // unit DC gain, started in steady state
    const std::vector<double> same = first_order_filtered(te.data(), n, 0.0, kTs);
    EXPECT_EQ(same, te); // 0 = unfiltered
    Series s = three_phase(25.0, 0.2, {2.0, 2.0, 2.0});
    s.te = te;
    MetricsConfig c;
    c.window_s = 0.2;
    c.torque_sensor_hz = 1000.0;
    const Metrics m = compute_metrics(s, c);
    EXPECT_NEAR(m.trf_pct, 100.0 * 0.2 / 0.3, 1e-6);
    EXPECT_LT(m.trf_filtered_pct, 0.72 * m.trf_pct);
    EXPECT_GT(m.trf_filtered_pct, 0.69 * m.trf_pct);
}

// Casadei Table 5's ripple: a ripple the once-per-period samples never see as ripple. Each phase
// carries B sin(2 pi f_s t - shift_x) at the sampling frequency f_s = 1/ts (800 f1, a balanced set:
// constant at the samples) plus a 5th harmonic. The plant's integrals of the squared currents and
// of i_a, i_b (written here by Simpson's rule on a fine grid) carry both, so the metric is
// sqrt(B^2/2 + (h5 A)^2/2) per phase.
TEST(Metrics, CurrentRippleUsesTheContinuousCurrentsNotTheSamples)
{
    const double f1 = 25.0, a = 2.0, h5 = 0.04, bhf = 0.3;
    Series s = three_phase(f1, 0.2, {a, a, a}, h5, 0.0, 0.0);
    const double w1 = 2.0 * kPi * f1, ws = 2.0 * kPi / kTs;
    const double sh[3] = {0.0, -2.0 * kPi / 3.0, 2.0 * kPi / 3.0};
    auto phase = [&](int x, double t) {
        const double th = w1 * t + sh[x];
        return a * (std::cos(th) + h5 * std::cos(5.0 * th)) + bhf * std::sin(ws * t + sh[x]);
    };
    double i2 = 0.0, qa = 0.0, qb = 0.0;
    constexpr int kSub = 64; // Simpson sub-intervals per sample interval
    for (std::size_t k = 0; k < s.size(); ++k) {
        s.i2_int.push_back(i2);
        s.q_a.push_back(qa);
        s.q_b.push_back(qb);
        const double t0 = static_cast<double>(k) * kTs, h = kTs / kSub;
        for (int j = 0; j <= kSub; ++j) {
            const double w = (j == 0 || j == kSub) ? 1.0 : (j % 2 ? 4.0 : 2.0);
            const double t = t0 + j * h;
            const double ia = phase(0, t), ib = phase(1, t), ic = phase(2, t);
            i2 += w * h / 3.0 * (ia * ia + ib * ib + ic * ic);
            qa += w * h / 3.0 * ia;
            qb += w * h / 3.0 * ib;
        }
    }
    const Metrics m = compute_metrics(s, MetricsConfig{});
    ASSERT_TRUE(m.current_ripple_rms_a);
    const double expect = std::sqrt(bhf * bhf / 2.0 + (h5 * a) * (h5 * a) / 2.0);
    EXPECT_NEAR(*m.current_ripple_rms_a, expect, 1e-6 * expect);
    // Without the integrals there is no ripple metric (not a sample-based stand-in).
    s.i2_int.clear();
    EXPECT_FALSE(compute_metrics(s, MetricsConfig{}).current_ripple_rms_a);
}

namespace {
// spectrum() of x in a forked child, its four figures' bytes read back through a pipe; with
// `before`, the child first transforms that signal (of the same length: the plan it keeps).
std::array<double, 4> spectrum_in_child(const std::vector<double>& x, int periods,
                                        const std::vector<double>* before = nullptr)
{
    int fds[2];
    EXPECT_EQ(pipe(fds), 0);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        if (before != nullptr) {
            (void)spectrum(before->data(), before->size(), periods + 2);
        }
        const Spectrum sp = spectrum(x.data(), x.size(), periods);
        const double v[4] = {sp.fundamental_peak, sp.thd_pct, sp.thd_harmonic_pct, sp.thd40_pct};
        const ssize_t w = write(fds[1], v, sizeof v);
        _exit(w == static_cast<ssize_t>(sizeof v) ? 0 : 1);
    }
    close(fds[1]);
    std::array<double, 4> v{};
    EXPECT_EQ(read(fds[0], v.data(), sizeof v), static_cast<ssize_t>(sizeof v));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    return v;
}
} // namespace

TEST(Metrics, SpectrumOfAPreparedOrKeptLengthIsTheSameToTheLastBit)
{
    // A sweep's parent plans each spectrum length its runs report (prepare_spectrum), and the runs
    // forked after it plan with FFTW's planner memory warm: their figures must be the ones a cold
    // process computes. 7202 = 2 x 13 x 277 samples (the default scenario's window), 9 periods of
    // a distorted current with an off-grid ripple line, so that every bin carries rounding.
    const std::size_t n = 7202;
    std::vector<double> x(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double t = static_cast<double>(k) * kTs;
        x[k] = 2.2 * std::cos(2 * kPi * 24.99 * t + 0.3) + 0.15 * std::cos(2 * kPi * 5 * 24.99 * t) +
               0.05 * std::sin(2 * kPi * 4731.7 * t) + 1e-3 * std::cos(0.37 * static_cast<double>(k * k % 1009));
    }
    const std::array<double, 4> cold = spectrum_in_child(x, 9);
    prepare_spectrum(n);
    const std::array<double, 4> warm = spectrum_in_child(x, 9);
    EXPECT_EQ(std::memcmp(cold.data(), warm.data(), sizeof cold), 0)
        << cold[1] << " vs " << warm[1] << " (thd_pct)";
    EXPECT_GT(cold[1], 5.0); // the 5th at 0.15 / 2.2 alone is 6.8 %
    // A sweep's worker runs one run after another: the plan it kept from the previous window of
    // that length gives the same figures too.
    std::vector<double> other(n);
    for (std::size_t k = 0; k < n; ++k) {
        other[k] = 1.1 * std::sin(2 * kPi * 30.5 * static_cast<double>(k) * kTs) + 0.01 * static_cast<double>(k % 7);
    }
    const std::array<double, 4> kept = spectrum_in_child(x, 9, &other);
    EXPECT_EQ(std::memcmp(cold.data(), kept.data(), sizeof cold), 0)
        << cold[1] << " vs " << kept[1] << " (thd_pct)";
}
