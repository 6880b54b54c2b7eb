// Limits on what input may make flipflux allocate or start (docs/limits.md lists every one and
// the refusal it gives). Sizes that drive an allocation are checked up front, before anything is
// computed: the bytes a request will hold are estimated and compared with the machine's memory,
// and thread counts are bounded, so that bad input ends with one line and exit status 2 rather
// than std::bad_alloc, the kernel's OOM killer or a crash inside the OpenMP runtime.
#pragma once

#include <cstdint>
#include <string>

namespace flipflux {

/// The most OpenMP threads (or golden jobs) a command starts; more is refused.
inline constexpr std::uint64_t max_threads = 4096;

/// The most histogram bins per histogram.
inline constexpr std::uint64_t max_bins = 1000000;

/// The most energies one request may list (a command line's --energy, a scene's grid).
inline constexpr std::size_t max_energy_count = 100000;
/// Independent replicates of one ensemble (study/simulation.hpp): each is summarised on its own
/// and the quality indices are recomputed without each, so the cost grows as R^2 energies.
inline constexpr std::uint64_t max_replicates = 1000;
/// Trajectories per energy (and replicate) of one request, on every surface: 1e9 records already
/// need ~440 GB (docs/limits.md), and the count stays far from integer overflow in any product.
inline constexpr std::uint64_t max_trajectories = 1000000000;

/// The most turns the arms of one trajectory may make (an upper bound from the energy and the
/// integration time, ensemble.hpp's check_trajectory_work): at tens of steps per turn, more than
/// this is days per trajectory, and E = 1e300 or T = 1e300 would never end.
inline constexpr double max_turns_per_trajectory = 1e9;

/// The most bytes one request may plan to hold: the machine's physical memory
/// (sysconf(_SC_PHYS_PAGES) * page size), or $FLIPFLUX_MEMORY_LIMIT bytes when that is set to a
/// positive integer (smaller, e.g. for a batch slot).
double memory_budget_bytes();

/// Throws input_error about `field` when `bytes` (an estimate of what the request would hold,
/// `what` says of what) exceeds memory_budget_bytes(); `value` is the offending input's text.
void check_memory(const std::string& field, const std::string& value, double bytes,
                  const std::string& what);

/// A thread count checked against max_threads (0: the runtime's default); throws input_error
/// about `field` above it.
int checked_threads(std::uint64_t requested, const std::string& field);

}  // namespace flipflux
