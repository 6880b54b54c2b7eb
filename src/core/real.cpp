// The names of the real types, parsing precisions ("mp:300"), and the working precision of mp
// (core/real.hpp): one mp precision active in the process at a time, scopes of one precision
// running concurrently, scopes of another waiting.
#include "flipflux/core/real.hpp"

#include <mpfr.h>
#include <algorithm>
#include <charconv>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

#include "flipflux/core/error.hpp"

namespace flipflux {
namespace {

/// The process-wide state behind precision_scope.
struct mp_arbiter {
    std::mutex mutex;
    std::condition_variable changed;
    int active = 0;   ///< requested digits of the active precision (0: none yet)
    int holders = 0;  ///< threads holding the active precision (one hold per thread)

    /// Waits until `digits` may become (or already is) the active precision and holds it.
    void take(std::unique_lock<std::mutex>& lock, int digits) {
        changed.wait(lock, [&] { return holders == 0 || active == digits; });
        if (active != digits) {
            active = digits;
            // NOTE: the only write of Boost's process-wide default precision: no scope of another
            // precision is running (holders == 0).
            mp::default_precision(static_cast<unsigned>(mp_working_digits(digits)));
        }
        ++holders;
    }
    void give(std::unique_lock<std::mutex>&) {
        --holders;
        changed.notify_all();
    }
};

mp_arbiter& arbiter() {
    static mp_arbiter a;
    return a;
}

/// The requested digits of this thread's nested mp scopes, innermost last.
thread_local std::vector<int> thread_scopes;

}  // namespace

precision_scope::precision_scope(const precision& p) {
    if (p.kind != real_kind::mp) return;
    if (p.digits < 1 || p.digits > max_mp_digits)
        throw std::invalid_argument("precision_scope: mp digits " + std::to_string(p.digits) +
                                    " out of range");
    active_ = true;
    mp_arbiter& a = arbiter();
    std::unique_lock<std::mutex> lock(a.mutex);
    if (!thread_scopes.empty() && thread_scopes.back() == p.digits) {
        thread_scopes.push_back(p.digits);  // already held by this thread
        return;
    }
    if (!thread_scopes.empty()) a.give(lock);  // the outer precision, taken back at the end
    a.take(lock, p.digits);
    thread_scopes.push_back(p.digits);
}

precision_scope::~precision_scope() {
    if (!active_) return;
    mp_arbiter& a = arbiter();
    std::unique_lock<std::mutex> lock(a.mutex);
    const int digits = thread_scopes.back();
    thread_scopes.pop_back();
    if (!thread_scopes.empty() && thread_scopes.back() == digits) return;
    a.give(lock);
    if (!thread_scopes.empty()) {
        a.take(lock, thread_scopes.back());
    } else {
        // NOTE: MPFR keeps per-thread caches (pi, log 2, ...) that a thread must free before it
        // ends; the outermost scope of a thread frees them (they are rebuilt on next use)
        mpfr_free_cache2(MPFR_FREE_LOCAL_CACHE);
    }
}

int active_mp_digits() {
    if (!thread_scopes.empty()) return thread_scopes.back();
    mp_arbiter& a = arbiter();
    const std::lock_guard<std::mutex> lock(a.mutex);
    return a.active;
}

std::string precision_name(const precision& p) {
    switch (p.kind) {
#define FLIPFLUX_DETAIL_NAME(id, T, name, ...)                                                  \
    case real_kind::id:                                                                         \
        return has_variable_precision_v<T> ? std::string(name) + ":" + std::to_string(p.digits) \
                                           : std::string(name);
        FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_NAME)
#undef FLIPFLUX_DETAIL_NAME
    }
    throw std::logic_error("precision_name: unknown real kind");
}

precision parse_precision(std::string_view text, std::string_view option) {
    const std::string bad = "'" + std::string(text) + "' ";
    const std::size_t colon = text.find(':');
    const std::string_view kind = text.substr(0, colon);
#define FLIPFLUX_DETAIL_PARSE(id, T, name, ...)                                            \
    if (kind == name) {                                                                    \
        if constexpr (!has_variable_precision_v<T>) {                                      \
            if (colon == std::string_view::npos) return {real_kind::id, 0};                \
        } else if (colon != std::string_view::npos) {                                      \
            const std::string_view digits = text.substr(colon + 1);                        \
            int n = 0;                                                                     \
            const auto [end, ec] =                                                         \
                std::from_chars(digits.data(), digits.data() + digits.size(), n);          \
            if (digits.empty() || ec == std::errc::invalid_argument ||                     \
                end != digits.data() + digits.size())                                      \
                throw input_error::about(                                                  \
                    std::string(option),                                                   \
                    bad + "is not a precision (" name ":DIGITS needs an integer DIGITS)"); \
            if (ec != std::errc() || n < 1 || n > max_mp_digits)                           \
                throw input_error::about(                                                  \
                    std::string(option),                                                   \
                    bad + "is out of range (" name ":DIGITS takes 1 <= DIGITS <= " +       \
                        std::to_string(max_mp_digits) + ")");                              \
            return {real_kind::id, n};                                                     \
        }                                                                                  \
    }
    FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_PARSE)
#undef FLIPFLUX_DETAIL_PARSE
    throw input_error::about(std::string(option),
                             bad + "is not a precision (expected double, quad or mp:DIGITS)");
}

std::vector<precision> parse_precision_list(std::string_view text, std::string_view option) {
    std::vector<precision> list;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view item = text.substr(start, comma - start);
        if (!item.empty()) {
            const precision p = parse_precision(item, option);
            if (std::find(list.begin(), list.end(), p) == list.end()) list.push_back(p);
        }
        start = comma + 1;
    }
    if (list.empty())
        throw input_error::about(std::string(option),
                                 "'" + std::string(text) + "' names no precision");
    std::stable_sort(list.begin(), list.end(), [](const precision& a, const precision& b) {
        return decimal_digits(a) < decimal_digits(b);
    });
    return list;
}

int decimal_digits(const precision& p) {
    if (p.kind == real_kind::mp) return p.digits;
    return dispatch(p, []<class Real>() { return std::numeric_limits<Real>::digits10; });
}

}  // namespace flipflux
