// The command-line tool's progress bar for long commands (simulate, golden): done/total, rate and
// ETA on stderr, redrawn in place on a terminal (at most 5 times a second), a line every 10
// seconds when forced (--progress) into a file or pipe; nothing otherwise.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "flipflux/study/simulation.hpp"

namespace flipflux::cli {

/// "42s", "3m07s", "1h02m03s"; "?" for a negative or non-finite duration.
std::string duration_text(double seconds);

class progress_bar {
  public:
    /// Shown when stderr is a terminal, or when `forced` (--progress); inactive otherwise.
    explicit progress_bar(bool forced);
    bool active() const { return active_; }
    /// done of total `unit` (e.g. "trajectories"); `base`: done before this run (resumed, not
    /// counted in the rate); `detail`: appended (e.g. "energy 2/5").
    void update(std::uint64_t done, std::uint64_t total, const std::string& unit,
                std::uint64_t base = 0, const std::string& detail = "");
    /// Ends a terminal line left open (an interrupted run).
    void finish();

  private:
    bool active_, terminal_;
    bool started_ = false;
    bool open_line_ = false;  ///< a terminal line drawn without its newline
    std::uint64_t base_ = 0;
    std::chrono::steady_clock::time_point start_{}, last_{};
};

/// A study's progress on `bar`: "N/M trajectories, [WHAT, ]energy I/J, ..." (simulate; a scene's
/// ensemble steps, WHAT naming the step's ensembles).
void show_study_progress(progress_bar& bar, const simulation_progress& p,
                         const std::string& what = "");

}  // namespace flipflux::cli
