// sil_output.cpp - see sil_output.hpp.
#include "sil_output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <unistd.h>
#ifdef __linux__
#include <sys/resource.h>
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
    header += '\n';
    write_failed_ = std::fwrite(header.data(), 1, header.size(), f_) != header.size();
    const unsigned n_workers = std::clamp(std::thread::hardware_concurrency(), 1U, kMaxWorkers);
    batches_.clear();
    queued_.clear();
    free_.clear();
    for (unsigned k = 0; k < n_workers + 2; ++k) { // one per worker, one filling, one queued
        auto b = std::make_unique<Batch>();
        b->rows.reserve(kBatchRows);
        b->text.reset(new char[kBatchRows * kMaxRowBytes]);
        free_.push_back(b.get());
        batches_.push_back(std::move(b));
    }
    fill_ = free_.front();
    free_.pop_front();
    next_seq_ = 0;
    next_write_ = 0;
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
    cv_.notify_all();
    cv_.wait(lk, [this] { return !free_.empty(); }); // waits only while every batch is busy
    fill_ = free_.front();
    free_.pop_front();
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
        Batch* const b = queued_.front();
        queued_.pop_front();
        lk.unlock();
        char* p = b->text.get();
        for (const TraceRow& r : b->rows) {
            p = format(r, p);
        }
        const auto n = static_cast<std::size_t>(p - b->text.get());
        lk.lock();
        cv_.wait(lk, [this, b] { return next_write_ == b->seq; }); // earlier batches first
        lk.unlock();
        const bool ok = std::fwrite(b->text.get(), 1, n, f_) == n; // only this thread writes now
        lk.lock();
        write_failed_ = write_failed_ || !ok;
        ++next_write_;
        b->rows.clear();
        free_.push_back(b);
        cv_.notify_all();
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

namespace {
// Shortest round-trip form (at most 24 characters), or nan / inf / -inf.
inline char* put(char* p, double x)
{
    if (std::isfinite(x)) {
        return std::to_chars(p, p + 32, x).ptr;
    }
    const char* s = std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf");
    const std::size_t n = std::strlen(s);
    std::memcpy(p, s, n);
    return p + n;
}
inline char* put(char* p, int x)
{
    if (x == 0 || x == 1) {
        *p = static_cast<char>('0' + x);
        return p + 1;
    }
    return std::to_chars(p, p + 16, x).ptr;
}
} // namespace

char* TraceWriter::format(const TraceRow& r, char* p) const
{
    const double d1[] = {r.t_s, r.i_a_a, r.i_b_a, r.i_c_a, r.i_alpha_a, r.i_beta_a, r.torque_nm, r.torque_est_nm,
                         r.psi_alpha_wb, r.psi_beta_wb, r.psi_alpha_est_wb, r.psi_beta_est_wb, r.speed_rpm};
    for (double x : d1) {
        p = put(p, x);
        *p++ = ',';
    }
    p = put(p, r.sa);
    *p++ = ',';
    p = put(p, r.sb);
    *p++ = ',';
    p = put(p, r.sc);
    *p++ = ',';
    p = put(p, r.vdc_v);
    *p++ = ',';
    p = put(p, r.en);
    const double d2[] = {r.theta_e_rad, r.vc_lo_v, r.v_alpha_v, r.v_beta_v, r.tload_nm};
    for (double x : d2) {
        *p++ = ',';
        p = put(p, x);
    }
    if (rotor_flux_) {
        *p++ = ',';
        p = put(p, r.psi_r_alpha_wb);
        *p++ = ',';
        p = put(p, r.psi_r_beta_wb);
    }
    *p++ = '\n';
    return p;
}

bool TraceWriter::close(std::string* err)
{
    if (f_ == nullptr) {
        return true;
    }
    if (!fill_->rows.empty()) {
        std::lock_guard<std::mutex> lk(m_);
        fill_->seq = next_seq_++;
        queued_.push_back(fill_); // no free batch needed: nothing is filled after this
        fill_ = nullptr;
    }
    stop(); // the workers drain the queue, in order, then exit
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
        fs::rename(stage_dir_, out_dir_, ec);
        if (ec) {
            *err = out_dir_ + ": cannot move the results in place (" + ec.message() + ")";
            return false;
        }
        active_ = false;
        return true;
    }
    for (const std::string& name : managed) {
        if (!fs::exists(fs::path(stage_dir_) / name, ec)) {
            fs::remove(fs::path(out_dir_) / name, ec);
        }
    }
    for (const auto& e : fs::directory_iterator(stage_dir_)) {
        fs::rename(e.path(), fs::path(out_dir_) / e.path().filename(), ec);
        if (ec) {
            *err = out_dir_ + ": cannot move " + e.path().filename().string() + " in place (" + ec.message() + ")";
            return false;
        }
    }
    fs::remove_all(stage_dir_, ec);
    active_ = false;
    return true;
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

} // namespace sil
