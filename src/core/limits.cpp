// Limits on allocations and threads (core/limits.hpp, docs/limits.md).
#include "flipflux/core/limits.hpp"

#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "flipflux/core/error.hpp"

namespace flipflux {

double memory_budget_bytes() {
    if (const char* env = std::getenv("FLIPFLUX_MEMORY_LIMIT"); env != nullptr && *env) {
        std::uint64_t v = 0;
        const char* end = env + std::strlen(env);
        const auto r = std::from_chars(env, end, v);
        if (r.ec == std::errc() && r.ptr == end && v > 0) return static_cast<double>(v);
    }
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return 1e12;  // unknown: a bound still refuses the absurd
    return static_cast<double>(pages) * static_cast<double>(page);
}

namespace {
std::string gigabytes(double bytes) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
    return buf;
}
}  // namespace

void check_memory(const std::string& field, const std::string& value, double bytes,
                  const std::string& what) {
    const double budget = memory_budget_bytes();
    if (!(bytes <= budget))
        throw input_error::about(
            field, "'" + value + "' would need about " +
                       (std::isfinite(bytes) ? gigabytes(bytes) : "unbounded") + " for " + what +
                       ", more than the " + gigabytes(budget) +
                       " of memory available (docs/limits.md)");
}

int checked_threads(std::uint64_t requested, const std::string& field) {
    if (requested > max_threads)
        throw input_error::about(field, "'" + std::to_string(requested) +
                                            "' is too many threads (at most " +
                                            std::to_string(max_threads) + ")");
    return static_cast<int>(requested);
}

}  // namespace flipflux
