// sil_output.cpp - see sil_output.hpp.
#include "sil_output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#endif

namespace sil {

namespace fs = std::filesystem;

const char* trace_header()
{
    return "t_s,i_a_a,i_b_a,i_c_a,i_alpha_a,i_beta_a,torque_nm,torque_est_nm,psi_alpha_wb,psi_beta_wb,"
           "psi_alpha_est_wb,psi_beta_est_wb,speed_rpm,sa,sb,sc,vdc_v,en,theta_e_rad,vc_lo_v,v_alpha_v,"
           "v_beta_v,tload_nm";
}

namespace {

// ---- Shortest round-trip text of a double ------------------------------------------------------
// Dragonbox ({fmt}'s fmt::detail::dragonbox::to_decimal, Debian libfmt-dev: a function of {fmt}'s
// detail namespace that its library exports) gives the shortest decimal significand and exponent
// that reads back to the same double, the digits std::to_chars picks; this file then lays them
// out as std::to_chars does, without its general-purpose formatting path (std::to_chars 31 ns per
// trace double on the development host, Dragonbox 14 ns, put_shortest() 25 ns). The test compares
// put_shortest() with std::to_chars byte for byte, so a {fmt} that changed would be caught.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the digit words below are stored as little-endian 64-bit words");

// x = +-sig * 10^exp with sig having no trailing zeros; sig = 0: zero or not finite.
struct Decimal {
    std::uint64_t sig;
    int exp;
};

inline Decimal shortest_decimal(double x)
{
    if (x == 0.0 || !std::isfinite(x)) {
        return {0, 0};
    }
    const auto d = fmt::detail::dragonbox::to_decimal(x); // ignores the sign
    return {d.significand, d.exponent};
}

constexpr std::uint64_t kPow10[20] = {1ULL,
                                      10ULL,
                                      100ULL,
                                      1000ULL,
                                      10000ULL,
                                      100000ULL,
                                      1000000ULL,
                                      10000000ULL,
                                      100000000ULL,
                                      1000000000ULL,
                                      10000000000ULL,
                                      100000000000ULL,
                                      1000000000000ULL,
                                      10000000000000ULL,
                                      100000000000000ULL,
                                      1000000000000000ULL,
                                      10000000000000000ULL,
                                      100000000000000000ULL,
                                      1000000000000000000ULL,
                                      10000000000000000000ULL};

// Decimal digits of n > 0: floor(log10(2) * bit length) is the count or one less.
inline int digit_count(std::uint64_t n)
{
    const int t = ((64 - __builtin_clzll(n)) * 1233) >> 12; // 1233 / 4096 = log10(2) to 4 digits
    return t + (n >= kPow10[t] ? 1 : 0);
}

// The four ASCII digits of every number below 10^4, the first digit in the lowest byte.
struct Digits4 {
    std::uint32_t text[10000];
    constexpr Digits4() : text()
    {
        for (std::uint32_t v = 0; v < 10000U; ++v) {
            text[v] = (0x30U + v / 1000U) | (0x30U + v / 100U % 10U) << 8 | (0x30U + v / 10U % 10U) << 16 |
                      (0x30U + v % 10U) << 24;
        }
    }
};
constexpr Digits4 kDigits4{};

// The 8 decimal digits of v < 10^8 as ASCII, the first digit in the lowest byte (so storing the
// word on a little-endian host writes them in order): two lookups of 4 digits.
inline std::uint64_t ascii8(std::uint32_t v)
{
    return kDigits4.text[v / 10000U] | static_cast<std::uint64_t>(kDigits4.text[v % 10000U]) << 32;
}

inline void store8(char* p, std::uint64_t w) { std::memcpy(p, &w, 8); }

// Bytes [k, k + 16) of the 24-byte little-endian string w0 w1 w2, as two words (0 < k < 8).
inline void from_byte(std::uint64_t w0, std::uint64_t w1, std::uint64_t w2, unsigned k, std::uint64_t* a,
                      std::uint64_t* b)
{
    *a = w0 >> (8U * k) | w1 << (64U - 8U * k);
    *b = w1 >> (8U * k) | w2 << (64U - 8U * k);
}

// std::to_chars(p, p + 32, x) for finite x whose shortest decimal is d (non-finite: nan/inf).
// The digits are built in registers and only stored (whole 8-byte words, later stores
// overwriting the tail of earlier ones), never read back from memory: a load that spans two
// recent stores waits until both reach the cache, which cost more than the digits themselves.
// Inlined into the row loop: a call's register saves cost a tenth of the conversion.
[[gnu::always_inline]] inline char* put_decimal(char* p, double x, Decimal d)
{
    if (d.sig == 0) {
        if (std::isnan(x)) {
            std::memcpy(p, "nan", 3);
            return p + 3;
        }
        if (std::signbit(x)) {
            *p++ = '-';
        }
        if (std::isinf(x)) {
            std::memcpy(p, "inf", 3);
            return p + 3;
        }
        *p = '0';
        return p + 1;
    }
    const int n = digit_count(d.sig); // sig < 10^17: n <= 17
    const int e = d.exp;
    const int point = n + e; // x = 0.DIGITS * 10^point
    const int sci_exp = point - 1;
    // Lengths without the sign: scientific d.ddde+XX (at least two exponent digits), plain
    // DIGITS000 / DIG.ITS / 0.000DIGITS. to_chars writes the shorter, plain on a tie.
    const int sci_len = n + (n > 1 ? 1 : 0) + (sci_exp <= -100 || sci_exp >= 100 ? 5 : 4);
    const int plain_len = e >= 0 ? n + e : (point > 0 ? n + 1 : 2 - e);
    const bool plain = plain_len <= sci_len;
    if (plain && e > 0 && point > 15) {
        // An integer above 10^15 may differ from DIGITS000 (to_chars writes the double's exact
        // value in plain form): leave it to to_chars. Only 16..21-digit integers come here.
        return std::to_chars(p, p + 32, x).ptr;
    }
    *p = '-';
    p += std::signbit(x) ? 1 : 0; // no branch: the sign of a current or a voltage is not predictable
    // The digits left-aligned in 17 places, zeros after them: L = the bytes of w0 w1 w2 (1 byte).
    const std::uint64_t s17 = d.sig * kPow10[17 - n];
    const std::uint64_t rest = s17 % 10000000000000000ULL;
    const std::uint64_t b8 = ascii8(static_cast<std::uint32_t>(rest / 100000000U));
    const std::uint64_t a8 = ascii8(static_cast<std::uint32_t>(rest % 100000000U));
    const std::uint64_t first = 0x30U + s17 / 10000000000000000ULL;
    const std::uint64_t w0 = first | b8 << 8;
    const std::uint64_t w1 = b8 >> 56 | a8 << 8;
    const std::uint64_t w2 = a8 >> 56;
    if (plain) {
        if (e >= 0) { // DIGITS, then e zeros (point = n + e <= 17: the zeros are in L)
            store8(p, w0);
            store8(p + 8, w1);
            p[16] = static_cast<char>(w2);
            return p + point;
        }
        if (point > 0 && point < 8) { // DIG.ITS: L, then the digits from `point` on one place further
            store8(p, w0);
            store8(p + 8, w1);
            p[16] = static_cast<char>(w2);
            std::uint64_t t0;
            std::uint64_t t1;
            from_byte(w0, w1, w2, static_cast<unsigned>(point), &t0, &t1);
            store8(p + point + 1, t0);
            store8(p + point + 9, t1);
            p[point] = '.';
            return p + n + 1;
        }
        if (point > 0) { // DIG.ITS with 8 .. 16 digits before the point (10^7 and above: rare)
            char t[24];
            store8(t, w0);
            store8(t + 8, w1);
            t[16] = static_cast<char>(w2);
            std::memcpy(p, t, static_cast<std::size_t>(point));
            p[point] = '.';
            std::memcpy(p + point + 1, t + point, static_cast<std::size_t>(n - point));
            return p + n + 1;
        }
        // 0.000DIGITS: at most 4 zeros (plain is shorter only up to 4).
        store8(p, 0x3030303030302e30ULL); // "0.000000"
        store8(p + 2 - point, w0);
        store8(p + 10 - point, w1);
        p[18 - point] = static_cast<char>(w2);
        return p + 2 - e;
    }
    p[0] = static_cast<char>(first);
    if (n > 1) { // d.ddd: the digits after the first one place further
        std::uint64_t t0;
        std::uint64_t t1;
        from_byte(w0, w1, w2, 1U, &t0, &t1);
        store8(p + 2, t0);
        store8(p + 10, t1);
        p[1] = '.';
        p += n + 1;
    } else {
        p += 1;
    }
    *p++ = 'e';
    int a = sci_exp;
    if (a < 0) {
        *p++ = '-';
        a = -a;
    } else {
        *p++ = '+';
    }
    if (a >= 100) {
        *p++ = static_cast<char>('0' + a / 100);
        a %= 100;
    }
    p[0] = static_cast<char>('0' + a / 10);
    p[1] = static_cast<char>('0' + a % 10);
    return p + 2;
}

inline char* put_int(char* p, int x)
{
    if (x == 0 || x == 1) {
        *p = static_cast<char>('0' + x);
        return p + 1;
    }
    return std::to_chars(p, p + 16, x).ptr;
}

} // namespace

char* put_shortest(char* p, double x) { return put_decimal(p, x, shortest_decimal(x)); }

TraceWriter::~TraceWriter()
{
    stop();
    if (f_ != nullptr) {
        std::fclose(f_);
    }
}

bool TraceWriter::open(const std::string& path, std::string* err)
{
    f_ = std::fopen(path.c_str(), "wb");
    if (f_ == nullptr) {
        *err = path + ": cannot create";
        return false;
    }
    std::setvbuf(f_, nullptr, _IONBF, 0); // every write is a whole formatted batch
    std::string header = trace_header();
    if (rotor_flux_) {
        header += ",psi_r_alpha_wb,psi_r_beta_wb";
    }
    if (fault_cols_) {
        header += ",relay,relay_closed,desat";
    }
    header += '\n';
    write_failed_ = std::fwrite(header.data(), 1, header.size(), f_) != header.size();
    const unsigned n_workers = std::clamp(std::thread::hardware_concurrency(), 1U, kMaxWorkers);
    batches_.clear();
    queued_.clear();
    free_.clear();
    formatted_.clear();
    formatted_.reserve(kBatches);
    for (std::size_t k = 0; k < kBatches; ++k) {
        auto b = std::make_unique<Batch>();
        b->rows.reset(new TraceRow[kBatchRows]);
        b->text.reset(new char[kBatchRows * kMaxRowBytes]);
        free_.push_back(b.get());
        batches_.push_back(std::move(b));
    }
    fill_ = free_.front();
    free_.pop_front();
    next_seq_ = 0;
    next_write_ = 0;
    writing_ = false;
    stop_ = false;
    workers_.clear();
    for (unsigned k = 0; k < n_workers; ++k) {
        workers_.emplace_back([this] { worker(); });
    }
    return true;
}

void TraceWriter::hand_over()
{
    std::unique_lock<std::mutex> lk(m_);
    fill_->seq = next_seq_++;
    queued_.push_back(fill_);
    cv_.notify_one();
    // Every batch busy (the formatting threads got less core time than the simulation produced
    // rows): this thread formats a queued batch itself rather than wait for them.
    while (free_.empty()) {
        if (!queued_.empty()) {
            format_one(lk);
        } else {
            cv_.wait(lk);
        }
    }
    fill_ = free_.front();
    free_.pop_front();
}

void TraceWriter::format_one(std::unique_lock<std::mutex>& lk)
{
    Batch* const b = queued_.front();
    queued_.pop_front();
    lk.unlock();
    char* p = b->text.get();
    for (std::size_t i = 0; i < b->n; ++i) {
        p = format(b->rows[i], p);
    }
    b->bytes = static_cast<std::size_t>(p - b->text.get());
    lk.lock();
    formatted_.push_back(b);
    if (writing_) {
        return; // the writing thread finds this batch when its turn comes
    }
    writing_ = true;
    for (;;) {
        const auto it = std::find_if(formatted_.begin(), formatted_.end(),
                                     [this](const Batch* x) { return x->seq == next_write_; });
        if (it == formatted_.end()) {
            break;
        }
        Batch* const w = *it;
        formatted_.erase(it);
        lk.unlock();
        const bool ok = std::fwrite(w->text.get(), 1, w->bytes, f_) == w->bytes; // only this thread writes
        lk.lock();
        write_failed_ = write_failed_ || !ok;
        bytes_written_ += w->bytes;
        rows_written_ += w->n;
        ++next_write_;
        w->n = 0;
        free_.push_back(w);
        cv_.notify_all(); // a free batch for write(), maybe the end for close()
    }
    writing_ = false;
}

void TraceWriter::worker()
{
#ifdef __linux__
    // Below the simulation's priority (nice +10, this thread only): the simulation runs whenever
    // it can and the formatting takes the core time it leaves. With equal priorities, three busy
    // threads on two cores give the simulation two thirds of a core and it becomes the bottleneck.
    (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), 10);
#endif
    std::unique_lock<std::mutex> lk(m_);
    for (;;) {
        cv_.wait(lk, [this] { return !queued_.empty() || stop_; });
        if (queued_.empty()) {
            return; // stop_ with nothing left
        }
        format_one(lk);
    }
}

void TraceWriter::stop()
{
    {
        std::lock_guard<std::mutex> lk(m_);
        stop_ = true;
    }
    cv_.notify_all();
    for (std::thread& t : workers_) {
        if (t.joinable()) {
            t.join();
        }
    }
    workers_.clear();
}

char* TraceWriter::format(const TraceRow& r, char* p) const
{
    // Column order, doubles and integers; the doubles' decimals are worked out first, all
    // together, so the processor overlaps the independent conversions.
    const double x[] = {r.t_s,         r.i_a_a,         r.i_b_a,          r.i_c_a,
                        r.i_alpha_a,   r.i_beta_a,      r.torque_nm,      r.torque_est_nm,
                        r.psi_alpha_wb, r.psi_beta_wb,  r.psi_alpha_est_wb, r.psi_beta_est_wb,
                        r.speed_rpm,   r.vdc_v,         r.theta_e_rad,    r.vc_lo_v,
                        r.v_alpha_v,   r.v_beta_v,      r.tload_nm,       r.psi_r_alpha_wb,
                        r.psi_r_beta_wb};
    constexpr int kCommon = 19; // every trace; the last two: induction machine only
    const int nx = rotor_flux_ ? kCommon + 2 : kCommon;
    Decimal d[sizeof x / sizeof x[0]];
    for (int i = 0; i < nx; ++i) {
        d[i] = shortest_decimal(x[i]);
    }
    for (int i = 0; i < 13; ++i) { // t_s .. speed_rpm
        p = put_decimal(p, x[i], d[i]);
        *p++ = ',';
    }
    p = put_int(p, r.sa);
    *p++ = ',';
    p = put_int(p, r.sb);
    *p++ = ',';
    p = put_int(p, r.sc);
    *p++ = ',';
    p = put_decimal(p, x[13], d[13]); // vdc_v
    *p++ = ',';
    p = put_int(p, r.en);
    for (int i = 14; i < nx; ++i) { // theta_e_rad .. tload_nm (, psi_r_alpha_wb, psi_r_beta_wb)
        *p++ = ',';
        p = put_decimal(p, x[i], d[i]);
    }
    if (fault_cols_) {
        for (const int v : {r.relay, r.relay_closed, r.desat}) {
            *p++ = ',';
            p = put_int(p, v);
        }
    }
    *p++ = '\n';
    return p;
}

bool TraceWriter::close(std::string* err)
{
    if (f_ == nullptr) {
        return true;
    }
    {
        std::unique_lock<std::mutex> lk(m_);
        if (fill_->n != 0) {
            fill_->seq = next_seq_++;
            queued_.push_back(fill_); // no free batch needed: nothing is filled after this
        }
        fill_ = nullptr;
        // This thread has nothing else to do: it formats queued batches beside the workers.
        while (!queued_.empty()) {
            format_one(lk);
        }
    }
    stop(); // the workers finish their batches, in order, then exit
    const bool ok_c = std::fclose(f_) == 0;
    f_ = nullptr;
    if (write_failed_ || !ok_c) {
        *err = "trace.csv: write failed (disk full?)";
        return false;
    }
    return true;
}

nlohmann::json metrics_json(const Scenario& sc, const Metrics& m, const RunInfo& info)
{
    using nlohmann::json;
    auto opt = [](const std::optional<double>& x) { return x ? json(*x) : json(nullptr); };
    auto opt3 = [](const std::optional<std::array<double, 3>>& x) {
        return x ? json::array({(*x)[0], (*x)[1], (*x)[2]}) : json(nullptr);
    };
    json j;
    j["scenario"] = sc.name;
    j["sim_time_s"] = info.sim_time_s;
    j["wall_time_s"] = info.wall_time_s;
    j["realtime_factor"] = info.wall_time_s > 0.0 ? info.sim_time_s / info.wall_time_s : 0.0;
    j["isr_count"] = info.isr_count;
    j["fundamental_a"] = opt3(m.fundamental_a);
    j["imbalance_pct"] = opt(m.imbalance_pct);
    j["thd_pct"] = opt3(m.thd_pct);
    j["thd_total_pct"] = opt(m.thd_total_pct);
    j["thd_harmonic_pct"] = opt3(m.thd_harmonic_pct);
    j["thd40_pct"] = opt3(m.thd40_pct);
    j["thd40_total_pct"] = opt(m.thd40_total_pct);
    j["current_ripple_rms_a"] = opt(m.current_ripple_rms_a);
    j["torque_mean_nm"] = m.torque_mean_nm;
    j["torque_est_mean_nm"] = opt(m.torque_est_mean_nm);
    j["trf_pct"] = m.trf_pct;
    j["trf_est_pct"] = opt(m.trf_est_pct);
    j["trf_filtered_pct"] = m.trf_filtered_pct;
    j["torque_sensor_hz"] = sc.metrics.torque_sensor_hz;
    j["speed_mean_rpm"] = m.speed_mean_rpm;
    j["switching_freq_hz"] = opt(m.switching_freq_hz);
    j["flux_est_error_rms_pct"] = opt(m.flux_est_error_rms_pct);
    j["fault"] = info.fault;
    j["fault_detail"] = info.fault_detail;
    j["fault_time_s"] = info.fault_time_s >= 0.0 ? json(info.fault_time_s) : json(nullptr);
    j["hw_trip"] = info.hw_trip;
    j["injected_fault_time_s"] = info.injected_fault_time_s >= 0.0 ? json(info.injected_fault_time_s) : json(nullptr);
    j["reconfigured"] = info.reconfigured.empty() ? json(nullptr) : json(info.reconfigured);
    j["warnings"] = info.warnings;
    j["warning_time_s"] = info.warning_time_s >= 0.0 ? json(info.warning_time_s) : json(nullptr);
    j["speed_dip_rpm"] = info.speed_dip_rpm >= 0.0 ? json(info.speed_dip_rpm) : json(nullptr);
    j["recovery_s"] = info.recovery_s >= 0.0 ? json(info.recovery_s) : json(nullptr);
    j["invalid_commands"] = info.invalid_commands;
    const double t_end = info.sim_time_s;
    j["metrics_window"] = {{"t_start_s", t_end - m.window_s},
                           {"t_end_s", t_end},
                           {"electrical_periods", m.window.periods},
                           {"f_e_hz", m.f_e_hz}};
    j["config"] = {{"mode", to_string(sc.control.mode)},
                   {"implementation", to_string(sc.control.implementation)},
                   {"topology", to_string(sc.inverter.topology)},
                   {"estimator", to_string(sc.control.estimator)},
                   {"compensation", to_string(sc.control.compensation)},
                   {"table", to_string(sc.control.table)},
                   {"load", to_string(sc.load.type)},
                   {"load_torque_nm", sc.load.torque_nm},
                   {"speed_ref_rpm", sc.control.speed_ref_rpm},
                   {"rated_torque_nm", sc.motor.rated_torque_nm},
                   {"ts_s", sc.ts_s}};
    return j;
}

std::string summary_text(const Scenario& sc, const Metrics& m, const RunInfo& info)
{
    char line[256];
    std::ostringstream o;
    std::snprintf(line, sizeof line, "dtc-sil: %s  (%s, %s", sc.name.c_str(),
                  to_string(sc.inverter.topology).c_str(), to_string(sc.control.mode).c_str());
    o << line;
    if (sc.control.mode != ControlMode::OpenLoop) {
        o << ", " << to_string(sc.control.estimator) << " model";
        if (sc.control.estimator == Estimator::Voltage) {
            o << ", compensation " << to_string(sc.control.compensation);
        }
    }
    o << ", " << to_string(sc.load.type) << " load)\n";
    if (sc.load.type == LoadType::Torque || sc.load.type == LoadType::Generator) {
        // The shaft load is the load torque plus the viscous friction B*w of motor.b_nm_s_per_rad: at the
        // speed reference they add up to what the scenario's comment calls the load (Hoang's full
        // load 0.3 N*m = load.torque_nm 0.225 + friction 0.075 N*m at 1500 rpm with the defaults).
        const double w = sc.control.speed_ref_rpm * kPi / 30.0;
        const double tl = sc.load.type == LoadType::Torque || sc.load.speed_rpm == 0.0
                              ? sc.load.torque_nm
                              : sc.load.torque_nm * sc.control.speed_ref_rpm / sc.load.speed_rpm;
        std::snprintf(line, sizeof line,
                      "  load       %.4g N*m load + %.4g N*m friction (motor.b_nm_s_per_rad) = %.4g N*m at %.0f rpm\n", tl,
                      sc.motor.b_nm_s_per_rad * w, tl + sc.motor.b_nm_s_per_rad * w, sc.control.speed_ref_rpm);
        o << line;
    }
    std::snprintf(line, sizeof line, "  simulated %.3f s in %.3f s wall (%.0fx real time, trace %s), %llu ISRs, fault: %s%s\n",
                  info.sim_time_s, info.wall_time_s,
                  info.wall_time_s > 0 ? info.sim_time_s / info.wall_time_s : 0.0, info.traced ? "on" : "off",
                  static_cast<unsigned long long>(info.isr_count), info.fault.c_str(),
                  info.hw_trip && info.fault != "hw_overcurrent" ? " (hardware trip latched too)" : "");
    o << line;
    if (!info.fault_detail.empty()) {
        o << "  fault      " << info.fault << ": " << info.fault_detail << "\n";
    }
    std::snprintf(line, sizeof line, "  window     %.4f s = %d electrical periods (%.2f Hz)\n", m.window_s,
                  m.window.periods, m.f_e_hz);
    o << line;
    std::snprintf(line, sizeof line, "  speed      %.1f rpm\n", m.speed_mean_rpm);
    o << line;
    std::snprintf(line, sizeof line, "  torque     mean %.4f N*m, TRF %.1f %%", m.torque_mean_nm, m.trf_pct);
    o << line;
    if (sc.metrics.torque_sensor_hz > 0.0) {
        std::snprintf(line, sizeof line, " (%.1f %% through a %g Hz sensor)", m.trf_filtered_pct,
                      sc.metrics.torque_sensor_hz);
        o << line;
    }
    if (m.torque_est_mean_nm) {
        std::snprintf(line, sizeof line, "; estimate %.4f N*m, TRF %.1f %%", *m.torque_est_mean_nm,
                      m.trf_est_pct.value_or(NAN));
        o << line;
    }
    o << "\n";
    if (m.fundamental_a) {
        const auto& f = *m.fundamental_a;
        const auto& t = *m.thd_pct;
        std::snprintf(line, sizeof line, "  currents   fundamental A/B/C %.3f / %.3f / %.3f A, imbalance %.2f %%\n", f[0],
                      f[1], f[2], m.imbalance_pct.value_or(NAN));
        o << line;
        std::snprintf(line, sizeof line, "  THD        A/B/C %.2f / %.2f / %.2f %%, total %.2f %%\n", t[0], t[1], t[2],
                      m.thd_total_pct.value_or(NAN));
        o << line;
        if (m.thd40_pct) {
            const auto& t40 = *m.thd40_pct;
            std::snprintf(line, sizeof line, "  THD 2..40  A/B/C %.2f / %.2f / %.2f %%, total %.2f %%\n", t40[0], t40[1],
                          t40[2], m.thd40_total_pct.value_or(NAN));
            o << line;
        }
    } else {
        o << "  currents   no whole electrical period in the window: no spectral metrics\n";
    }
    if (m.switching_freq_hz) {
        std::snprintf(line, sizeof line, "  switching  %.0f Hz per device\n", *m.switching_freq_hz);
        o << line;
    }
    if (m.flux_est_error_rms_pct) {
        std::snprintf(line, sizeof line, "  flux est.  error %.2f %% rms\n", *m.flux_est_error_rms_pct);
        o << line;
    }
    return o.str();
}

bool StagedOutput::begin(const std::string& out_dir, std::string* err)
{
    std::error_code ec;
    fs::path out(out_dir);
    if (out.empty()) {
        *err = "--out: empty directory name";
        return false;
    }
    if (fs::exists(out, ec) && !fs::is_directory(out, ec)) {
        *err = out_dir + ": exists and is not a directory";
        return false;
    }
    fs::path parent = fs::absolute(out, ec).parent_path();
    fs::create_directories(parent, ec);
    if (ec) {
        *err = parent.string() + ": cannot create (" + ec.message() + ")";
        return false;
    }
    out_dir_ = fs::absolute(out).lexically_normal().string();
    if (!out_dir_.empty() && out_dir_.back() == '/') {
        out_dir_.pop_back();
    }
    stage_dir_ = out_dir_ + ".partial-" + std::to_string(static_cast<long>(::getpid()));
    struct stat st_out {}, st_parent {};
    if (::stat(out_dir_.c_str(), &st_out) == 0 && ::stat(parent.c_str(), &st_parent) == 0 &&
        st_out.st_dev != st_parent.st_dev) {
        // out_dir is a mount point: a sibling staging folder is on another file system and no
        // file could be renamed from it; stage inside out_dir, on its own file system.
        stage_dir_ = (fs::path(out_dir_) / (".partial-" + std::to_string(static_cast<long>(::getpid())))).string();
    }
    fs::remove_all(stage_dir_, ec);
    if (!fs::create_directory(stage_dir_, ec)) {
        *err = stage_dir_ + ": cannot create (" + ec.message() + ")";
        return false;
    }
    active_ = true;
    return true;
}

std::string StagedOutput::path(const std::string& file) const { return (fs::path(stage_dir_) / file).string(); }

bool StagedOutput::commit(std::string* err, const std::vector<std::string>& managed)
{
    std::error_code ec;
    if (!fs::exists(out_dir_, ec)) {
        fs::rename(stage_dir_, out_dir_, ec); // one rename: all or nothing
        if (ec) {
            *err = out_dir_ + ": cannot move the results in place (" + ec.message() + ")";
            return false;
        }
        active_ = false;
        return true;
    }
    // out_dir exists: each file it has of the staged or managed names is first moved aside into
    // the staging folder (NAME.previous), then the staged file moved in. On a failure every step
    // done is undone in reverse order.
    struct Step {
        fs::path from, to;
    };
    std::vector<Step> done;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(stage_dir_, ec)) {
        names.push_back(e.path().filename().string());
    }
    for (const std::string& m : managed) {
        if (std::find(names.begin(), names.end(), m) == names.end()) {
            names.push_back(m);
        }
    }
    const fs::path out(out_dir_), stage(stage_dir_);
    std::string failure;
    for (const std::string& name : names) {
        const fs::path old = out / name;
        if (fs::exists(fs::symlink_status(old, ec))) {
            fs::rename(old, stage / (name + ".previous"), ec);
            if (ec) {
                failure = "cannot move the previous " + name + " aside (" + ec.message() + ")";
                break;
            }
            done.push_back({old, stage / (name + ".previous")});
        }
        if (fs::exists(stage / name, ec)) {
            fs::rename(stage / name, old, ec);
            if (ec) {
                failure = "cannot move " + name + " in place (" + ec.message() + ")";
                break;
            }
            done.push_back({stage / name, old});
        }
    }
    if (failure.empty()) {
        fs::remove_all(stage_dir_, ec);
        active_ = false;
        return true;
    }
    std::string left;
    for (auto it = done.rbegin(); it != done.rend(); ++it) {
        fs::rename(it->to, it->from, ec);
        if (ec) {
            left += (left.empty() ? "" : ", ") + it->to.string();
        }
    }
    *err = out_dir_ + ": " + failure;
    if (!left.empty()) {
        touched_ = true;
        *err += "; undoing the files moved so far failed too, left as they are: " + left + " (staging folder " +
                stage_dir_ + " kept)";
        active_ = false; // keep what could not be moved back
    }
    return false;
}

void StagedOutput::abort()
{
    if (active_) {
        std::error_code ec;
        fs::remove_all(stage_dir_, ec);
        active_ = false;
    }
}

StagedOutput::~StagedOutput() { abort(); }

StagedFile::StagedFile(std::string final_path) : final_(std::move(final_path))
{
    if (!final_.empty()) {
        stage_ = final_ + ".partial-" + std::to_string(static_cast<long>(::getpid()));
    }
}

bool StagedFile::commit(std::string* err)
{
    if (stage_.empty() || done_) {
        return true;
    }
    std::error_code ec;
    fs::rename(stage_, final_, ec);
    if (ec) {
        *err = final_ + ": cannot move the recording in place (" + ec.message() + ")";
        return false;
    }
    done_ = true;
    return true;
}

StagedFile::~StagedFile()
{
    if (!stage_.empty() && !done_) {
        std::error_code ec;
        fs::remove(stage_, ec);
    }
}

} // namespace sil
