// The progress bar of long commands (progress.hpp).
#include "progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace flipflux::cli {

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

progress_bar::progress_bar(bool forced)
    : active_(forced || isatty(2) != 0), terminal_(isatty(2) != 0) {}

void progress_bar::update(std::uint64_t done, std::uint64_t total, const std::string& unit,
                          std::uint64_t base, const std::string& detail) {
    if (!active_) return;
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
        started_ = true;
        start_ = now;
        base_ = base;
    }
    const bool final = done >= total;
    if (!final && now - last_ < std::chrono::milliseconds(terminal_ ? 200 : 10000)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(done - base_) / elapsed : 0;
    const double eta = final ? 0 : rate > 0 ? static_cast<double>(total - done) / rate : -1;
    constexpr int width = 30;
    const int filled = total ? static_cast<int>(width * static_cast<double>(done) / total) : 0;
    std::string bar(static_cast<std::size_t>(filled), '=');
    bar.resize(width, ' ');
    std::fprintf(stderr, "%s[%s] %llu/%llu %s%s%s, %.3g/s, ETA %s%s", terminal_ ? "\r" : "",
                 bar.c_str(), static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total), unit.c_str(), detail.empty() ? "" : ", ",
                 detail.c_str(), rate, duration_text(eta).c_str(),
                 terminal_ && !final ? "   " : "\n");
    open_line_ = terminal_ && !final;
    std::fflush(stderr);
}

void progress_bar::finish() {
    if (open_line_) std::fputc('\n', stderr);  // interrupted before the final update
    open_line_ = false;
}

void show_study_progress(progress_bar& bar, const simulation_progress& p, const std::string& what) {
    bar.update(p.done, p.total, "trajectories", p.resumed,
               (what.empty() ? "" : what + ", ") + "energy " + std::to_string(p.energy + 1) + "/" +
                   std::to_string(p.energies));
}

}  // namespace flipflux::cli
