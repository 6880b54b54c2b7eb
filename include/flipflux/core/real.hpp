// The real types flipflux computes in, their names, the working precision of the MPFR type, and
// run-time dispatch among them.
//
// The supported types are listed ONCE, in FLIPFLUX_REAL_TYPES below; everything else is generated
// from that list: the real_kind enum, the type list, dispatch, the extern template declarations of
// every module (FLIPFLUX_FOR_EACH_REAL), the instantiation units (CMake reads the list and compiles
// every src/**/*.inst.cpp once per entry), the quantity registry's per-type functions and the
// typed tests. Adding a type is one line here.
//
//   double                                    53-bit binary                     "double"
//   quad = boost::multiprecision::float128    113-bit binary                    "quad"
//   mp   = MPFR, precision chosen at run time  N requested decimal digits        "mp:N"
//
// mp:N computes with mp_working_digits(N) = max(N + 10, 30) decimal digits (10 guard digits, and
// at least 30 so that arithmetic with built-in operands never changes Boost's process-wide
// default precision, see precision_scope) and prints N + 2 significant digits.
//
// NOTE: expression templates are off (et_off): `auto x = a * b;` is a value, not an unevaluated
// expression.
#pragma once

#include <boost/multiprecision/float128.hpp>
#include <boost/multiprecision/mpfr.hpp>
#include <climits>
#include <cmath>
#include <compare>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace flipflux {

using quad = boost::multiprecision::float128;
using mp = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<0>,
                                         boost::multiprecision::et_off>;

// clang-format off
/// THE list of real types: X(identifier, C++ type, name, ...) (the trailing arguments are passed
/// through to X). CMake reads the identifiers from these lines: one entry per line, in this form.
#define FLIPFLUX_REAL_TYPES(X, ...)                    \
    X(double_, double, "double", __VA_ARGS__)          \
    X(quad, ::flipflux::quad, "quad", __VA_ARGS__)     \
    X(mp, ::flipflux::mp, "mp", __VA_ARGS__)
// clang-format on

/// Expands M(T) for every supported real type T, e.g. the extern template declarations of a
/// module's header: `#define FLIPFLUX_X_EXTERN(R) extern template ...;` then
/// `FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_X_EXTERN)`.
#define FLIPFLUX_DETAIL_CALL_M(id, T, name, M) M(T)
#define FLIPFLUX_FOR_EACH_REAL(M) FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_CALL_M, M)

/// The kinds of real, one per entry of the list: real_kind::double_, real_kind::quad, ...
enum class real_kind {
#define FLIPFLUX_DETAIL_ENUM(id, T, name, ...) id,
    FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_ENUM)
#undef FLIPFLUX_DETAIL_ENUM
};

/// The supported types as a std::tuple type (for type-level iteration).
#define FLIPFLUX_DETAIL_TUPLE(id, T, name, ...) std::declval<std::tuple<T>>(),
using real_types = decltype(std::tuple_cat(FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_TUPLE)
                                               std::declval<std::tuple<>>()));
#undef FLIPFLUX_DETAIL_TUPLE

inline constexpr std::size_t real_type_count = std::tuple_size_v<real_types>;

namespace detail {
template <template <class> class F, class Tuple>
struct map_real_types;
template <template <class> class F, class... Ts>
struct map_real_types<F, std::tuple<Ts...>> {
    using type = std::tuple<F<Ts>...>;
};
}  // namespace detail

/// std::tuple<F<double>, F<quad>, ...>: one F per supported type (std::get<F<Real>> picks one).
template <template <class> class F>
using per_real_type = typename detail::map_real_types<F, real_types>::type;

namespace detail {
template <class Real, class Tuple>
struct index_in;
template <class Real, class... Ts>
struct index_in<Real, std::tuple<Ts...>> {
    static constexpr std::size_t value = [] {
        constexpr bool same[] = {std::is_same_v<Real, Ts>...};
        for (std::size_t i = 0; i < sizeof...(Ts); ++i)
            if (same[i]) return i;
        return sizeof...(Ts);
    }();
};
}  // namespace detail

template <class Real>
inline constexpr bool is_supported_real_v =
    detail::index_in<Real, real_types>::value < real_type_count;

/// The kind of a supported real type.
template <class Real>
constexpr real_kind kind_of() {
    static_assert(is_supported_real_v<Real>, "unsupported real type");
    return static_cast<real_kind>(detail::index_in<Real, real_types>::value);
}

/// True for types whose precision is chosen at run time (mp).
template <class Real>
inline constexpr bool has_variable_precision_v = std::numeric_limits<Real>::digits == INT_MAX;

/// A working precision: a kind of real and, for a variable-precision kind, the requested decimal
/// digits N of "mp:N" (0 for the fixed kinds).
struct precision {
    real_kind kind = real_kind::double_;
    int digits = 0;
    auto operator<=>(const precision&) const = default;
};

/// Guard digits and the least working precision of mp:N (see the file comment).
inline constexpr int mp_guard_digits = 10;
inline constexpr int mp_min_working_digits = 30;
/// Largest N accepted by "mp:N".
inline constexpr int max_mp_digits = 1000000;

/// Decimal digits mp:N computes with: max(N + mp_guard_digits, mp_min_working_digits).
constexpr int mp_working_digits(int requested) {
    return requested + mp_guard_digits > mp_min_working_digits ? requested + mp_guard_digits
                                                               : mp_min_working_digits;
}

/// mp:N.
inline precision mp_precision(int digits) {
    return {real_kind::mp, digits};
}

/// Makes a precision the working precision of mp for its lifetime (RAII); a no-op for the fixed
/// kinds. Every mp value of a computation must be created inside the scope of its precision.
///
/// NOTE: Boost 1.74 keeps the default precision of mpfr_float in one process-wide variable (not
/// thread-local), and its arithmetic temporarily rewrites that variable whenever an operand's
/// precision differs from it. So one mp precision is active in the process at a time: scopes of
/// the same precision (any number of threads) run concurrently; a scope of another precision
/// waits until every scope of the active one has ended. A thread may nest scopes: an inner scope
/// of another precision gives up the thread's hold on the outer one while it lasts (and waits to
/// take it back when it ends); mp values of the outer precision must not be used inside it except
/// through an explicit conversion (core/convert.hpp). Threads started inside a scope (OpenMP)
/// compute at its precision without a scope of their own; they must finish before it ends.
class precision_scope {
  public:
    explicit precision_scope(const precision& p);
    ~precision_scope();
    precision_scope(const precision_scope&) = delete;
    precision_scope& operator=(const precision_scope&) = delete;

  private:
    bool active_ = false;
};

/// The requested digits N of the mp precision active now (of the innermost scope of this thread,
/// else the process's), or 0 when none has been entered yet.
int active_mp_digits();

/// The precision of Real now: the fixed kinds' own, for mp the active "mp:N".
template <class Real>
precision precision_of() {
    if constexpr (has_variable_precision_v<Real>)
        return {kind_of<Real>(), active_mp_digits()};
    else
        return {kind_of<Real>(), 0};
}

/// "double", "quad", "mp:N".
std::string precision_name(const precision& p);
template <class Real>
std::string precision_name() {
    return precision_name(precision_of<Real>());
}

/// Parses "double", "quad" or "mp:N" (1 <= N <= max_mp_digits). Throws input_error naming
/// `option` and the offending text.
precision parse_precision(std::string_view text, std::string_view option = "precision");

/// Parses a comma-separated list of precisions ("double,quad,mp:50"), ordered by increasing
/// decimal digits, without repeats. Throws input_error naming `option` (an empty list too).
std::vector<precision> parse_precision_list(std::string_view text, std::string_view option);

/// Significant decimal digits the precision resolves: digits10 of the fixed kinds, N for mp:N.
int decimal_digits(const precision& p);

/// Calls f.template operator()<Real>() for the real type of p inside a precision_scope(p),
/// returning its result.
template <class F>
decltype(auto) dispatch(const precision& p, F&& f) {
#define FLIPFLUX_DETAIL_DISPATCH(id, T, name, ...) \
    if (p.kind == real_kind::id) {                 \
        const precision_scope scope(p);            \
        return f.template operator()<T>();         \
    }
    FLIPFLUX_REAL_TYPES(FLIPFLUX_DETAIL_DISPATCH)
#undef FLIPFLUX_DETAIL_DISPATCH
    throw std::logic_error("dispatch: unknown real kind");
}

/// Calls f.template operator()<Real>() for every supported type, in list order.
template <class F>
void for_each_real_type(F&& f) {
    [&]<class... Ts>(std::tuple<Ts...>*) {
        (f.template operator()<Ts>(), ...);
    }(static_cast<real_types*>(nullptr));
}

/// Machine epsilon of Real at the working precision, the root of every tolerance in flipflux.
template <class Real>
inline Real epsilon() {
    return std::numeric_limits<Real>::epsilon();
}

/// Binary digits of Real at the working precision (std::numeric_limits<mp>::digits is INT_MAX).
template <class Real>
inline int binary_digits() {
    if constexpr (has_variable_precision_v<Real>)
        return static_cast<int>(
            boost::multiprecision::detail::digits10_2_2(Real::default_precision()));
    else
        return std::numeric_limits<Real>::digits;
}

/// A method parameter (stages, degree, ...) chosen by the working precision: piecewise linear in
/// the binary digits through `table` ({bits, value} pairs, bits increasing), below the first
/// entry its value, beyond the last growing as (bits / last bits)^power.
inline int scaled_with_precision(int bits, std::initializer_list<std::pair<int, int>> table,
                                 double power) {
    const std::pair<int, int>* prev = table.begin();
    if (bits <= prev->first) return prev->second;
    for (const std::pair<int, int>* p = table.begin() + 1; p != table.end(); prev = p++) {
        if (bits <= p->first)
            return prev->second +
                   static_cast<int>(std::lround(static_cast<double>(p->second - prev->second) *
                                                (bits - prev->first) / (p->first - prev->first)));
    }
    return static_cast<int>(
        std::lround(prev->second * std::pow(static_cast<double>(bits) / prev->first, power)));
}

}  // namespace flipflux
