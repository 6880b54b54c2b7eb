// Names of the saddle-orbit module's enumerations.
#include <atomic>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "flipflux/core/error.hpp"
#include "flipflux/io/checksum.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

namespace {
std::atomic<unsigned> memo_generation{0};
std::atomic<std::size_t> memo_misses{0};
thread_local bool memo_bypassed = false;
}  // namespace

saddle_orbit_memo_bypass::saddle_orbit_memo_bypass() : scoped_flag(memo_bypassed) {}
// Whether a saddle_orbit_memo_bypass lives in this thread.
bool saddle_orbit_memo_bypassed() {
    return memo_bypassed;
}

// Orbits solved by find_or_solve_saddle_orbit because the memo did not have them.
std::size_t saddle_orbit_memo_misses() {
    return memo_misses.load();
}
void count_saddle_orbit_memo_miss() {
    ++memo_misses;
}

// The saddle-orbit memo of every precision (orbit_store.inst.cpp) is cleared lazily when this
// generation changes.
unsigned saddle_orbit_memo_generation() {
    return memo_generation.load();
}

void forget_saddle_orbits() {
    ++memo_generation;
}

}  // namespace flipflux

namespace flipflux {

std::string orbit_record_checksum(const std::string& text) {
    return checksum_hex(text);
}

std::string seal_orbit_record(const std::string& json_text) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(json_text);
    j.erase("checksum");
    j["checksum"] = orbit_record_checksum(j.dump());
    return j.dump() + "\n";
}

}  // namespace flipflux
