// flipflux simulate: Monte Carlo ensembles (paper Sec. 5-6), a thin layer over
// study/simulation.hpp: parses the options and prints the study's JSON report (with the model).
// Also the run-time machinery of long runs:
//   - MPI: when launched by mpirun (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in the
//     environment) MPI is initialised and the ranks share the trajectories (simulation.hpp's
//     process_group); rank 0 prints the report. Otherwise MPI is not touched at all.
//   - SIGINT/SIGTERM: a flag the integrators poll once per step; in-flight trajectories are
//     abandoned, finished ones are in the checkpoint, the exit status is 128 + the signal.
//   - a progress bar on stderr (a terminal, or --progress).
#include <mpi.h>
#include <unistd.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "common.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"

namespace flipflux::cli {
namespace {

std::atomic<int> stop_signal{0};

extern "C" void on_stop_signal(int signal) {
    stop_signal.store(signal);
}

/// Installs the SIGINT/SIGTERM handlers for its lifetime.
class signal_guard {
  public:
    signal_guard() {
        stop_signal.store(0);
        struct sigaction sa {};
        sa.sa_handler = on_stop_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &old_int_);
        sigaction(SIGTERM, &sa, &old_term_);
    }
    ~signal_guard() {
        sigaction(SIGINT, &old_int_, nullptr);
        sigaction(SIGTERM, &old_term_, nullptr);
    }
    signal_guard(const signal_guard&) = delete;
    signal_guard& operator=(const signal_guard&) = delete;

  private:
    struct sigaction old_int_ {};
    struct sigaction old_term_ {};
};

bool launched_by_mpirun() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

/// MPI_COMM_WORLD as a process_group; MPI is initialised and finalised with it.
class mpi_group final : public process_group {
  public:
    mpi_group() {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    ~mpi_group() override { MPI_Finalize(); }
    mpi_group(const mpi_group&) = delete;
    mpi_group& operator=(const mpi_group&) = delete;
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    std::string broadcast(const std::string& text) override {
        unsigned long long n = text.size();
        MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
        std::string out = rank_ == 0 ? text : std::string(n, '\0');
        for (unsigned long long done = 0; done < n;) {  // in pieces below INT_MAX
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Bcast(out.data() + done, piece, MPI_CHAR, 0, MPI_COMM_WORLD);
            done += static_cast<unsigned long long>(piece);
        }
        return out;
    }
    std::vector<std::string> gather(const std::string& text) override {
        std::vector<std::string> out;
        if (rank_ == 0) {
            out.resize(static_cast<std::size_t>(size_));
            out[0] = text;
            for (int r = 1; r < size_; ++r)
                out[static_cast<std::size_t>(r)] = receive(r);
        } else {
            send(text);
        }
        return out;
    }
    bool any(bool flag) override {
        int mine = flag ? 1 : 0, all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        return all != 0;
    }
    [[noreturn]] void abort(int status) {
        MPI_Abort(MPI_COMM_WORLD, status);
        std::_Exit(status);
    }

  private:
    void send(const std::string& text) {
        unsigned long long n = text.size();
        MPI_Send(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, 0, MPI_COMM_WORLD);
        for (unsigned long long done = 0; done < n;) {
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Send(text.data() + done, piece, MPI_CHAR, 0, 1, MPI_COMM_WORLD);
            done += static_cast<unsigned long long>(piece);
        }
    }
    std::string receive(int from) {
        unsigned long long n = 0;
        MPI_Recv(&n, 1, MPI_UNSIGNED_LONG_LONG, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        std::string text(n, '\0');
        for (unsigned long long done = 0; done < n;) {
            const int piece = static_cast<int>(std::min<unsigned long long>(n - done, 1u << 30));
            MPI_Recv(text.data() + done, piece, MPI_CHAR, from, 1, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE);
            done += static_cast<unsigned long long>(piece);
        }
        return text;
    }
    int rank_ = 0, size_ = 1;
};

std::string duration_text(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const auto s = static_cast<long>(seconds + 0.5);
    char buf[64];
    if (s >= 3600)
        std::snprintf(buf, sizeof buf, "%ldh%02ldm%02lds", s / 3600, s / 60 % 60, s % 60);
    else if (s >= 60)
        std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
    else
        std::snprintf(buf, sizeof buf, "%lds", s);
    return buf;
}

/// The progress bar: done/total, rate, ETA; redrawn in place on a terminal (at most 5 times a
/// second), a line every 10 seconds otherwise.
class progress_bar {
  public:
    explicit progress_bar(bool terminal) : terminal_(terminal) {}
    void update(const simulation_progress& p) {
        const auto now = std::chrono::steady_clock::now();
        if (!started_) {
            started_ = true;
            start_ = now;
            base_ = p.resumed;
        }
        const bool final = p.done >= p.total;
        if (!final && now - last_ < std::chrono::milliseconds(terminal_ ? 200 : 10000)) return;
        last_ = now;
        const double elapsed = std::chrono::duration<double>(now - start_).count();
        const double rate = elapsed > 0 ? static_cast<double>(p.done - base_) / elapsed : 0;
        const double eta = rate > 0 ? static_cast<double>(p.total - p.done) / rate : -1;
        constexpr int width = 30;
        const int filled =
            p.total ? static_cast<int>(width * static_cast<double>(p.done) / p.total) : 0;
        std::string bar(static_cast<std::size_t>(filled), '=');
        bar.resize(width, ' ');
        std::fprintf(stderr, "%s[%s] %llu/%llu trajectories, energy %zu/%zu, %.3g/s, ETA %s%s",
                     terminal_ ? "\r" : "", bar.c_str(), static_cast<unsigned long long>(p.done),
                     static_cast<unsigned long long>(p.total), p.energy + 1, p.energies, rate,
                     duration_text(eta).c_str(), terminal_ && !final ? "   " : "\n");
        std::fflush(stderr);
    }
    void finish() {
        if (terminal_ && started_) std::fputc('\n', stderr);
    }

  private:
    bool terminal_;
    bool started_ = false;
    std::uint64_t base_ = 0;
    std::chrono::steady_clock::time_point start_{}, last_{};
};

struct simulate_state {
    std::string energy, arm_text = "2", criteria = "upright,approx,saddle", trajectories, time,
                        seed = "0", rtol = "1e-10", threads = "0", csv_dir, method = "dop853",
                        chaos_threshold = "0.05", first_index = "0", bins = "0",
                        sample_interval = "0", checkpoint, checkpoint_interval = "2",
                        estimator = "long", short_time = "20", reference_time = "0";
    bool no_chaos = false, progress = false, no_timing = false;
    model_options model;
};

std::uint64_t parse_unsigned(const std::string& text, const std::string& option, bool positive) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || (positive && v == 0))
        throw input_error(option + ": '" + text + "' is invalid (expected " +
                          (positive ? "a positive" : "a non-negative") + " integer)");
    return v;
}

double parse_positive(const std::string& text, const std::string& option) {
    const double v = parse_real<double>(text, option);
    if (!(v > 0)) throw input_error(option + ": '" + text + "' is invalid (must be > 0)");
    return v;
}

simulation_request make_request(const simulate_state& s) {
    simulation_request q;
    q.flip_arm = parse_arm(s.arm_text);
    q.energies = parse_energy_list(s.energy);
    q.criteria = parse_criterion_list(s.criteria);
    ensemble_options& o = q.options;
    o.trajectories = parse_unsigned(s.trajectories, "--trajectories", true);
    o.time = parse_positive(s.time, "--time");
    o.seed = parse_unsigned(s.seed, "--seed", false);
    o.first_index = parse_unsigned(s.first_index, "--first-index", false);
    o.rtol = parse_positive(s.rtol, "--rtol");
    o.threads = checked_threads(parse_unsigned(s.threads, "--threads", false), "--threads");
    o.method = parse_name<integration_method>(s.method, "--method");
    o.chaos = !s.no_chaos;
    o.chaos_threshold = parse_positive(s.chaos_threshold, "--chaos-threshold");
    o.sample_interval = parse_real<double>(s.sample_interval, "--sample-interval");
    o.stop = &stop_signal;
    q.bins = parse_unsigned(s.bins, "--bins", false);
    q.csv_dir = s.csv_dir;
    q.checkpoint = s.checkpoint;
    q.checkpoint_interval = parse_real<double>(s.checkpoint_interval, "--checkpoint-interval");
    q.estimator = parse_name<rate_estimator>(s.estimator, "--estimator");
    q.short_time = parse_positive(s.short_time, "--short-time");
    q.reference_time = parse_real<double>(s.reference_time, "--reference-time");
    q.timing = !s.no_timing;
    return q;
}

void run(const simulate_state& s) {
    std::unique_ptr<mpi_group> mpi;
    if (launched_by_mpirun()) mpi = std::make_unique<mpi_group>();
    const bool root = !mpi || mpi->rank() == 0;
    try {
        const double_pendulum<double> model(parse_parameters<double>(s.model));
        simulation_request q = make_request(s);
        q.group = mpi.get();
        progress_bar bar(isatty(2) != 0);
        if (root && (s.progress || isatty(2)))
            q.progress = [&bar](const simulation_progress& p) { bar.update(p); };
        const signal_guard guard;
        std::optional<study_result> result;
        try {
            result = simulate(model, q);
        } catch (const simulation_interrupted& e) {
            bar.finish();
            if (root) std::fprintf(stderr, "flipflux: %s\n", e.what());
            exit_status() = 128 + (e.signal() > 0 ? e.signal() : SIGINT);
            return;
        }
        bar.finish();
        if (result)
            for (const energy_result& e : result->energies)
                if (e.failed_trajectories > 0)  // excluded from the statistics (docs/limits.md)
                    std::fprintf(stderr,
                                 "flipflux: warning: E = %s: %llu of %llu trajectories failed "
                                 "(the integration stopped before T) and are excluded from the "
                                 "statistics (\"failed_trajectories\" in the report)\n",
                                 e.label.c_str(),
                                 static_cast<unsigned long long>(e.failed_trajectories),
                                 static_cast<unsigned long long>(result->options.trajectories));
        if (result) {
            json out = study_json(*result);
            out["model"] = parameters_json(model);
            print(out.dump(2) + "\n");
        }
    } catch (const std::exception& e) {
        if (!mpi || mpi->size() == 1) throw;
        // another rank may wait in a collective: report and end the whole job
        const auto* bad_input = dynamic_cast<const input_error*>(&e);
        if (root || bad_input == nullptr)
            std::fprintf(stderr, "flipflux: %s%s\n", bad_input ? "error: " : "internal error: ",
                         bad_input ? error_text(*bad_input).c_str() : e.what());
        std::fflush(stderr);
        mpi->abort(bad_input ? 2 : 1);
    }
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<simulate_state>();
    CLI::App* sub = app.add_subcommand(
        "simulate",
        "Monte Carlo ensemble at one or more energies: microcanonical initial conditions, "
        "trajectories (DOP853 or DOPRI5 at double), flips of each criterion, statistics as JSON "
        "(and CSV with --csv-dir).");
    sub->add_option("--energy", s->energy,
                    "energy E, a list E1,E2,... or a range FROM:TO:STEP (inclusive; TO - FROM a "
                    "multiple of STEP)")
        ->required();
    sub->add_option("--arm", s->arm_text, "the arm whose flips are counted: 1 or 2")
        ->capture_default_str();
    sub->add_option("--criteria", s->criteria,
                    "comma-separated flip criteria: upright, approx, saddle")
        ->capture_default_str();
    sub->add_option("--trajectories", s->trajectories, "number of trajectories per energy (> 0)")
        ->required();
    sub->add_option("--time", s->time, "integration time T per trajectory (> 0)")->required();
    sub->add_option("--seed", s->seed, "random seed (non-negative integer)")->capture_default_str();
    sub->add_option("--first-index", s->first_index,
                    "index of the first trajectory (split runs across processes)")
        ->capture_default_str();
    sub->add_option("--rtol", s->rtol, "relative (and absolute) tolerance of the integrator")
        ->capture_default_str();
    sub->add_option("--method", s->method, "integrator: dop853 or dopri5")->capture_default_str();
    sub->add_option("--threads", s->threads, "OpenMP threads (0: all available)")
        ->capture_default_str();
    sub->add_option("--chaos-threshold", s->chaos_threshold,
                    "Lyapunov threshold for 'chaotic', in units of sqrt(alpha/A)")
        ->capture_default_str();
    sub->add_flag("--no-chaos", s->no_chaos,
                  "skip the variational equations (no chaotic/regular classification)");
    sub->add_option("--bins", s->bins, "histogram bins (0: square-root rule)")
        ->capture_default_str();
    sub->add_option("--sample-interval", s->sample_interval,
                    "store every trajectory's state at this time interval (needs --csv-dir)")
        ->capture_default_str();
    sub->add_option("--csv-dir", s->csv_dir,
                    "write per-trajectory rates, residence times and histograms as CSV here");
    sub->add_option("--checkpoint", s->checkpoint,
                    "save finished trajectories to FILE and resume from it (same command)");
    sub->add_option("--checkpoint-interval", s->checkpoint_interval,
                    "seconds between checkpoint appends (0: after every trajectory)")
        ->capture_default_str();
    sub->add_option("--estimator", s->estimator,
                    "long: the given trajectories x time; short: the same budget in "
                    "trajectories of length --short-time")
        ->capture_default_str();
    sub->add_option("--short-time", s->short_time, "trajectory length of --estimator short")
        ->capture_default_str();
    sub->add_option("--reference-time", s->reference_time,
                    "also estimate the PQI for trajectories of this length (S scaled by "
                    "sqrt(time / reference); 0: not)")
        ->capture_default_str();
    sub->add_flag("--progress", s->progress,
                  "progress bar on stderr (default: only when stderr is a terminal)");
    sub->add_flag("--no-timing", s->no_timing,
                  "leave out seconds/threads/processes (output identical across runs)");
    add_model_options(*sub, s->model);
    sub->callback([s] { run(*s); });
});

}  // namespace
}  // namespace flipflux::cli
