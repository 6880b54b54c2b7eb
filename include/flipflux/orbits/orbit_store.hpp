// Saddle orbits solved once: a process-wide memo and an on-disk cache.
//
// Memo: `find_or_solve_saddle_orbit` returns a remembered orbit of the same pendulum (its
// Lagrangian coefficients, compared exactly), arm, energy (exactly), shooting method and
// integrator, or solves it (solve_saddle_orbit) and remembers it. The registry's saddle quantities
// (src/quantities/orbit_quantities.cpp) and the Monte Carlo saddle criterion
// (src/study/criteria.cpp) both go through it, so a scene that continues a family once never solves
// its orbits again. Thread-safe (one mutex per Real); threads asking for an orbit another thread is
// solving wait for that solve instead of repeating it.
//
// Disk: `orbit_to_json` / `orbit_from_json` serialise every field of a saddle_orbit, the reals as
// decimal strings with all digits of Real, so that an orbit read back is bit-identical to the one
// written. `orbit_cache_key` names the cache directory: a hash of the coefficients (decimal text),
// the precision, the method, the integrator, the stage count and tolerance, and the format
// version, so a change of any of them misses the cache.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flipflux/core/scoped_flag.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

/// The remembered orbit (of that method and integrator), or nullopt.
template <class Real>
std::optional<saddle_orbit<Real>> recall_saddle_orbit(
    const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy, orbit_method method,
    orbit_integrator integrator = default_orbit_integrator<Real>());

/// Remembers an orbit (of its arm and energy) for `model`.
template <class Real>
void remember_saddle_orbit(const double_pendulum<Real>& model, const saddle_orbit<Real>& orbit);

/// Every remembered orbit of `model` that converged or stalled, as orbit_to_json records in the
/// memo's order: what another process needs to recall exactly these orbits (an MPI run's rank 0
/// sends them to the others). An orbit stored under two keys (a periodic request answered by the
/// symmetric solution) is sent under its own key only.
template <class Real>
std::vector<std::string> remembered_orbit_records(const double_pendulum<Real>& model);

/// Remembers the orbits of `records` (remembered_orbit_records of another process) for `model`;
/// input_error naming `where` for a malformed record.
template <class Real>
void remember_orbit_records(const double_pendulum<Real>& model,
                            const std::vector<std::string>& records, const std::string& where);

/// Forgets every remembered orbit of every precision (tests).
void forget_saddle_orbits();

/// While an object of this type lives, find_or_solve_saddle_orbit in this thread solves every
/// orbit afresh (and remembers it): for timing a solve (the accuracy report) without forgetting
/// the orbits that other evaluations share.
class saddle_orbit_memo_bypass : public scoped_flag {
  public:
    saddle_orbit_memo_bypass();
};

/// Recall, else solve (solve_saddle_orbit with `options`) and remember a converged or stalled
/// orbit.
template <class Real>
saddle_orbit<Real> find_or_solve_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                              const level_arg<Real>& energy,
                                              const orbit_options<Real>& options = {});

/// Every field, reals as decimal strings (JSON text).
template <class Real>
std::string orbit_to_json(const saddle_orbit<Real>& orbit);

/// Inverse of orbit_to_json; throws input_error naming `where` on malformed text or a checksum
/// that does not match (orbit_to_json writes one over the rest of the record).
template <class Real>
saddle_orbit<Real> orbit_from_json(const std::string& text, const std::string& where);

/// FNV-1a (64 bit) of `text` as 16 hex digits, stable across builds: a record's "checksum" is
/// this of the record's JSON text without it (and the cache key's hash).
std::string orbit_record_checksum(const std::string& text);

/// A record's JSON text with its checksum (re)computed: orbit_to_json's last step; tests use it to
/// build records that pass the checksum but are wrong otherwise.
std::string seal_orbit_record(const std::string& json_text);

/// Why an orbit read from the cache cannot be used for (model, a, energy), or "" when it can: a
/// physical check independent of the solver (arm and energy as asked, T > 0, F > 0, the model's
/// saddle point and saddle energy, the start on the energy surface, the quarter orbit spanning
/// T/4 from the saddle to a turning point on the energy surface, i.e. the orbit closes).
template <class Real>
std::string cached_orbit_problem(const double_pendulum<Real>& model, arm a,
                                 const level_arg<Real>& energy, const saddle_orbit<Real>& orbit);

/// Cache directory name for (model, arm-independent) orbits at Real with `options`.
template <class Real>
std::string orbit_cache_key(const double_pendulum<Real>& model, const orbit_options<Real>& options);

#define FLIPFLUX_ORBIT_STORE_EXTERN(R)                                                          \
    extern template std::optional<saddle_orbit<R>> recall_saddle_orbit<R>(                      \
        const double_pendulum<R>&, arm, const level_arg<R>&, orbit_method, orbit_integrator);   \
    extern template void remember_saddle_orbit<R>(const double_pendulum<R>&,                    \
                                                  const saddle_orbit<R>&);                      \
    extern template std::vector<std::string> remembered_orbit_records<R>(                       \
        const double_pendulum<R>&);                                                             \
    extern template void remember_orbit_records<R>(                                             \
        const double_pendulum<R>&, const std::vector<std::string>&, const std::string&);        \
    extern template saddle_orbit<R> find_or_solve_saddle_orbit<R>(                              \
        const double_pendulum<R>&, arm, const level_arg<R>&, const orbit_options<R>&);          \
    extern template std::string orbit_to_json<R>(const saddle_orbit<R>&);                       \
    extern template saddle_orbit<R> orbit_from_json<R>(const std::string&, const std::string&); \
    extern template std::string orbit_cache_key<R>(const double_pendulum<R>&,                   \
                                                   const orbit_options<R>&);                    \
    extern template std::string cached_orbit_problem<R>(                                        \
        const double_pendulum<R>&, arm, const level_arg<R>&, const saddle_orbit<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_ORBIT_STORE_EXTERN)
#undef FLIPFLUX_ORBIT_STORE_EXTERN

}  // namespace flipflux
