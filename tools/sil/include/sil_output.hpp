// sil_output.hpp - trace.csv rows, metrics.json, the stdout summary, and all-or-nothing output.
#ifndef DTC_SIL_OUTPUT_HPP
#define DTC_SIL_OUTPUT_HPP

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "metrics.hpp"
#include "scenario.hpp"

namespace sil {

/// One trace row: plant state at t_k, the controller's estimates made from the sample at t_k,
/// and the leg states applied over [t_k, t_k+1).
struct TraceRow {
    double t_s, i_a_a, i_b_a, i_c_a, i_alpha_a, i_beta_a;
    double torque_nm, torque_est_nm;
    double psi_alpha_wb, psi_beta_wb, psi_alpha_est_wb, psi_beta_est_wb;
    double speed_rpm;
    int sa, sb, sc;
    double vdc_v;
    int en;
    double theta_e_rad, vc_lo_v, v_alpha_v, v_beta_v, tload_nm;
    double psi_r_alpha_wb, psi_r_beta_wb;  // induction machine only (rotor-flux columns)
    int relay, relay_closed, desat;        // fault columns only: the relay's coil command
                                           // (hal_cmd_t.relay), its contacts, meas.desat
};

/// Column names, in order.
const char* trace_header();

/// Writes x at p in the shortest form that reads back to the same double: for finite x byte for
/// byte the text of std::to_chars(p, p + 32, x) (plain or scientific, whichever is shorter, plain
/// on a tie); "nan" (whatever its sign), "inf" or "-inf" otherwise. Needs 48 writable bytes at p (it stores
/// whole 8- and 24-byte blocks past the end of the text); returns the end of the text.
char* put_shortest(char* p, double x);

/// Buffered CSV writer: every double in the shortest form that reads back to the same double
/// (put_shortest(): strtod / numpy.loadtxt give the identical value back); the leg states and the
/// enable are integers. write() (or next_row() and commit_row()) only fills a row of a batch of
/// kBatchRows (no allocation).
/// Full batches go to a small pool of formatting threads (one per core, at most kMaxWorkers),
/// which format each batch into the batch's own text buffer; a formatted batch is written with
/// one fwrite by whichever thread finds it next in file order, so rows stay in order and no
/// formatting thread waits for another. The formatting threads run at a lower priority than the
/// simulation (Linux), which then never waits for a core while it has a free batch to fill; when
/// no batch is free (the formatting threads got too little core time), write() formats a queued
/// batch itself, and close() formats the last ones beside the threads. All buffers are allocated
/// at open().
class TraceWriter {
public:
    TraceWriter() = default;
    ~TraceWriter();
    TraceWriter(const TraceWriter&) = delete;
    TraceWriter& operator=(const TraceWriter&) = delete;
    bool open(const std::string& path, std::string* err);
    /// Induction machine: append the psi_r_alpha_wb, psi_r_beta_wb columns (call before open).
    void set_rotor_flux_columns(bool on) { rotor_flux_ = on; }
    /// Faults or the reconfiguration relay configured: append the relay, relay_closed, desat
    /// columns (call before open).
    void set_fault_columns(bool on) { fault_cols_ = on; }
    /// The next row, to be filled in place (no copy) and then committed. Every field must be set.
    TraceRow& next_row() { return fill_->rows[fill_->n]; }
    void commit_row()
    {
        if (++fill_->n == kBatchRows) { // a batch of fixed size: no allocation
            hand_over();
        }
    }
    void write(const TraceRow& r)
    {
        next_row() = r;
        commit_row();
    }
    bool close(std::string* err);
    /// Bytes and rows in the file so far (the header's bytes excluded): measured, for the size guard.
    std::uint64_t bytes_written() const { return bytes_written_.load(std::memory_order_relaxed); }
    std::uint64_t rows_written() const { return rows_written_.load(std::memory_order_relaxed); }
    static constexpr std::size_t kMaxRowBytes = 640; // 21 doubles x <= 24 chars + 4 ints + commas + 48 slack
    static constexpr std::size_t kBatchRows = 256;
    static constexpr std::size_t kBatches = 16;      // filling + queued + being formatted + waiting to be written
    static constexpr unsigned kMaxWorkers = 3;

private:
    struct Batch {
        std::unique_ptr<TraceRow[]> rows; // kBatchRows
        std::size_t n = 0;                // rows filled
        std::unique_ptr<char[]> text;     // kBatchRows * kMaxRowBytes, not zeroed (pages touched when used)
        std::size_t bytes = 0;            // formatted text
        std::uint64_t seq = 0;            // position in the file
    };
    void hand_over();
    void worker();
    /// Takes one queued batch (lk held on entry and exit), formats it with lk released, then
    /// writes every formatted batch that is next in file order unless another thread is doing so.
    void format_one(std::unique_lock<std::mutex>& lk);
    char* format(const TraceRow& r, char* p) const;
    void stop();
    std::FILE* f_ = nullptr;
    bool write_failed_ = false;
    std::vector<std::unique_ptr<Batch>> batches_; // owns every batch
    Batch* fill_ = nullptr;                       // the batch write() fills
    std::deque<Batch*> queued_, free_;
    std::vector<Batch*> formatted_;               // formatted, not yet written
    bool writing_ = false;                        // a thread is writing formatted batches
    std::uint64_t next_seq_ = 0, next_write_ = 0;
    std::vector<std::thread> workers_;
    std::mutex m_;
    std::condition_variable cv_;
    bool stop_ = false;
    bool rotor_flux_ = false;
    bool fault_cols_ = false;
    std::atomic<std::uint64_t> bytes_written_{0}, rows_written_{0};
};

struct RunInfo {
    double sim_time_s = 0.0;
    double wall_time_s = 0.0;
    std::uint64_t isr_count = 0;
    std::string fault = "none";
    std::string fault_detail;  // why, in words (empty when fault is "none")
    double fault_time_s = -1.0; // when the run noticed the fault (plant divergence), -1: not known
    std::uint64_t invalid_commands = 0;
    bool hw_trip = false;
    bool traced = false; // trace.csv written (its cost is in wall_time_s)
    // Injected faults ([faults]): when they occurred (-1: none configured), the phase
    // the firmware moved onto the mid-point ("" = none or the controller has no such status), and
    // the speed's response after the fault (speed mode; NaN = not defined, see docs/sil.md).
    double injected_fault_time_s = -1.0;
    std::string reconfigured;
    std::vector<std::string> warnings; // the firmware's warnings raised in the run (app_warn.h names)
    double warning_time_s = -1.0;      // when the first was raised (-1: none)
    double speed_dip_rpm = -1.0;  // largest drop after the fault below the speed at the fault (capped at
                                  // control.speed_ref_rpm); -1: n/a
    double recovery_s = -1.0;     // fault until the speed is back within 1 % of the reference for
                                  // good; -1: n/a or never
};

nlohmann::json metrics_json(const Scenario& sc, const Metrics& m, const RunInfo& info);
std::string summary_text(const Scenario& sc, const Metrics& m, const RunInfo& info);

/// Output staging: files are written into a fresh sibling directory (inside the destination when
/// the destination is a mount point, so that every move is a rename on one file system) and moved
/// into the destination only when the run completed, so a failed run leaves nothing partial behind.
class StagedOutput {
public:
    /// Checks that out_dir can be used (a directory or not existing, parent creatable) and creates
    /// the staging directory.
    bool begin(const std::string& out_dir, std::string* err);
    std::string path(const std::string& file) const;
    /// Moves every staged file into out_dir (replacing files of the same name) and removes the
    /// files of `managed` this run did not produce (no stale trace.csv next to a new metrics.json,
    /// no plot_run.py figures of a previous run next to new results).
    bool commit(std::string* err, const std::vector<std::string>& managed = {"trace.csv", "metrics.json",
                                                                            "currents.png", "torque.png",
                                                                            "flux_locus.png",
                                                                            "flux_components.png"});
    /// All or nothing: when it fails, every file moved so far is moved back and out_dir is as it
    /// was; touched() is true only when that rollback failed too (err then says what is left).
    bool touched() const { return touched_; }
    /// Removes the staging directory (also done by the destructor if not committed).
    void abort();
    ~StagedOutput();

private:
    std::string out_dir_, stage_dir_;
    bool active_ = false;
    bool touched_ = false;
};

/// One file written under a staging name (PATH.partial-PID) and renamed to PATH by commit();
/// removed by the destructor if not committed. An empty PATH stages nothing.
class StagedFile {
public:
    explicit StagedFile(std::string final_path);
    const std::string& path() const { return stage_; }
    bool commit(std::string* err);
    ~StagedFile();
    StagedFile(const StagedFile&) = delete;
    StagedFile& operator=(const StagedFile&) = delete;

private:
    std::string final_, stage_;
    bool done_ = false;
};

} // namespace sil

#endif // DTC_SIL_OUTPUT_HPP
