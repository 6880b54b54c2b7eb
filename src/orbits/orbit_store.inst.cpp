// Saddle orbits solved once: memo and serialisation (include/flipflux/orbits/orbit_store.hpp).
#include "flipflux/orbits/orbit_store.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/core/key_claims.hpp"
#include "flipflux/core/real.hpp"

namespace flipflux {

unsigned saddle_orbit_memo_generation();  // src/orbits/orbit_names.cpp
void count_saddle_orbit_memo_miss();      // src/orbits/orbit_names.cpp
bool saddle_orbit_memo_bypassed();        // src/orbits/orbit_names.cpp

namespace {

using json = nlohmann::ordered_json;

template <class Real>
std::string model_text_key(const double_pendulum<Real>& model) {
    const auto& k = model.coefficients();
    std::string s;
    for (const Real* v : {&k.A, &k.B, &k.C, &k.alpha, &k.beta, &k.D0})
        s += to_decimal(*v) + ";";
    return s;
}

template <class Real>
struct memo {
    std::mutex mutex;
    unsigned generation = 0;
    std::map<std::string, saddle_orbit<Real>> orbits;
    key_claims solving;  ///< keys being solved by find_or_solve_saddle_orbit

    static memo& instance() {
        static memo m;
        return m;
    }
    /// E and E - E_s: two decimal inputs that round to one E are two orbits (energy_level).
    static std::string key(const double_pendulum<Real>& model, arm a, const Real& energy,
                           const Real& excess, orbit_method method, orbit_integrator integrator) {
        return model_text_key(model) + precision_name<Real>() + ";" + to_string(a) + ";" +
               to_decimal(energy, full_digits(energy)) + ";" +
               to_decimal(excess, full_digits(excess)) + ";" + to_string(method) + ";" +
               to_string(integrator);
    }
    static std::string key(const double_pendulum<Real>& model, arm a,
                           const energy_level<Real>& energy, orbit_method method,
                           orbit_integrator integrator) {
        return key(model, a, energy.value, energy.above(model.saddle_level(a)), method, integrator);
    }
    void refresh() {  // under the lock
        const unsigned g = saddle_orbit_memo_generation();
        if (g != generation) {
            orbits.clear();
            generation = g;
        }
    }
};

/// Every digit x holds (for mp its guard digits too): a cached orbit reads back bit-identical.
template <class Real>
std::string exact_decimal(const Real& x) {
    return to_decimal(x, full_digits(x));
}

template <class Real>
json real_array(const Real* v, std::size_t n) {
    json a = json::array();
    for (std::size_t i = 0; i < n; ++i)
        a.push_back(exact_decimal(v[i]));
    return a;
}

template <class Real>
Real real_of(const json& j, const std::string& where) {
    if (!j.is_string()) throw input_error(where + ": expected a decimal string");
    return parse_real<Real>(j.get<std::string>(), where);
}

template <class Real>
void read_array(const json& j, Real* out, std::size_t n, const std::string& where) {
    if (!j.is_array() || j.size() != n)
        throw input_error(where + ": expected an array of " + std::to_string(n) + " reals");
    for (std::size_t i = 0; i < n; ++i)
        out[i] = real_of<Real>(j[i], where);
}

// 2: monodromy at the final (beta, T); 3: a checksum of the record; 4: the integrator and its order
constexpr int format_version = 4;

}  // namespace

template <class Real>
std::optional<saddle_orbit<Real>> recall_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                                      const level_arg<Real>& energy,
                                                      orbit_method method,
                                                      orbit_integrator integrator) {
    auto& m = memo<Real>::instance();
    const std::lock_guard<std::mutex> lock(m.mutex);
    m.refresh();
    const auto it = m.orbits.find(memo<Real>::key(model, a, energy, method, integrator));
    if (it == m.orbits.end()) return std::nullopt;
    return it->second;
}

template <class Real>
void remember_saddle_orbit(const double_pendulum<Real>& model, const saddle_orbit<Real>& orbit) {
    auto& m = memo<Real>::instance();
    const std::lock_guard<std::mutex> lock(m.mutex);
    m.refresh();
    m.orbits.insert_or_assign(memo<Real>::key(model, orbit.flip_arm, orbit.energy, orbit.excess,
                                              orbit.method, orbit.integrator),
                              orbit);
}

template <class Real>
std::vector<std::string> remembered_orbit_records(const double_pendulum<Real>& model) {
    std::vector<saddle_orbit<Real>> orbits;
    {
        auto& m = memo<Real>::instance();
        const std::lock_guard<std::mutex> lock(m.mutex);
        m.refresh();
        const std::string prefix = model_text_key(model) + precision_name<Real>() + ";";
        for (const auto& [key, orbit] : m.orbits)
            // a failed orbit (a family remembers it) has no record: recalling it solves again
            if (key.compare(0, prefix.size(), prefix) == 0 &&
                orbit.status != orbit_status::not_converged)
                orbits.push_back(orbit);
    }
    std::vector<std::string> records;
    for (const saddle_orbit<Real>& orbit : orbits)
        records.push_back(orbit_to_json(orbit));  // outside the lock: mp records take time
    return records;
}

template <class Real>
void remember_orbit_records(const double_pendulum<Real>& model,
                            const std::vector<std::string>& records, const std::string& where) {
    for (std::size_t i = 0; i < records.size(); ++i)
        remember_saddle_orbit(
            model,
            orbit_from_json<Real>(records[i], where + " (record " + std::to_string(i + 1) + ")"));
}

template <class Real>
saddle_orbit<Real> find_or_solve_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                              const level_arg<Real>& energy,
                                              const orbit_options<Real>& options) {
    if (saddle_orbit_memo_bypassed()) {
        count_saddle_orbit_memo_miss();
        saddle_orbit<Real> orbit = solve_saddle_orbit(model, a, energy, options);
        if (orbit.status != orbit_status::not_converged) remember_saddle_orbit(model, orbit);
        return orbit;
    }
    // Recall; else, when another thread is solving the same orbit, wait for its result rather
    // than solve it a second time (mp:100 orbits take minutes); else solve it here.
    auto& m = memo<Real>::instance();
    const std::string key = memo<Real>::key(model, a, energy, options.method, options.integrator);
    {
        std::unique_lock<std::mutex> lock(m.mutex);
        std::optional<saddle_orbit<Real>> found;
        // if the solve this thread waits for fails, this thread tries in turn
        if (m.solving.ready_or_claim(lock, key, [&] {
                m.refresh();
                if (const auto it = m.orbits.find(key); it != m.orbits.end()) found = it->second;
                return found.has_value();
            }))
            return std::move(*found);
    }
    // the claim is given back after the orbit is remembered, also on an exception
    const key_claims::claim done(m.solving, m.mutex, key);
    count_saddle_orbit_memo_miss();
    saddle_orbit<Real> orbit = solve_saddle_orbit(model, a, energy, options);
    if (orbit.status != orbit_status::not_converged) {
        remember_saddle_orbit(model, orbit);
        // a periodic request answered by the symmetric formulation (near E_max, see
        // refine_saddle_orbit) is the answer to the request too
        if (orbit.method != options.method) {
            const std::lock_guard<std::mutex> lock(m.mutex);
            m.orbits.insert_or_assign(key, orbit);
        }
    }
    return orbit;
}

template <class Real>
std::string orbit_to_json(const saddle_orbit<Real>& o) {
    json j;
    j["format"] = format_version;
    j["precision"] = precision_name<Real>();
    j["arm"] = to_string(o.flip_arm);
    j["energy"] = exact_decimal(o.energy);
    j["excess"] = exact_decimal(o.excess);
    j["beta"] = exact_decimal(o.beta);
    j["period"] = exact_decimal(o.period);
    j["action"] = exact_decimal(o.action);
    j["period_derivative"] = exact_decimal(o.period_derivative);
    j["saddle"] = real_array(o.saddle.data(), 2);
    j["start"] = real_array(o.start.data(), 4);
    j["turning_points"] = json::array(
        {real_array(o.turning_points[0].data(), 2), real_array(o.turning_points[1].data(), 2)});
    json eig = json::array();
    for (const auto& z : o.floquet.eigenvalues)
        eig.push_back({exact_decimal(z.real()), exact_decimal(z.imag())});
    j["floquet"] = {{"eigenvalues", eig},
                    {"trace", exact_decimal(o.floquet.trace)},
                    {"stability_index", exact_decimal(o.floquet.stability_index)},
                    {"hyperbolic", o.floquet.hyperbolic},
                    {"multiplier", exact_decimal(o.floquet.multiplier)},
                    {"angle", exact_decimal(o.floquet.angle)},
                    {"unit_deviation", exact_decimal(o.floquet.unit_deviation)},
                    {"determinant_deviation", exact_decimal(o.floquet.determinant_deviation)}};
    json mono = json::array();
    for (const auto& row : o.monodromy)
        mono.push_back(real_array(row.data(), 4));
    j["monodromy"] = mono;
    j["status"] = to_string(o.status);
    j["method"] = to_string(o.method);
    j["integrator"] = to_string(o.integrator);
    j["stages"] = o.stages;
    j["order"] = o.order;
    j["steps"] = o.steps;
    j["tolerance"] = exact_decimal(o.tolerance);
    j["newton_iterations"] = o.newton_iterations;
    j["residual"] = exact_decimal(o.residual);
    j["last_update"] = exact_decimal(o.last_update);
    j["energy_error"] = exact_decimal(o.energy_error);
    j["error_estimate_period"] = exact_decimal(o.error_estimate_period);
    j["error_estimate_action"] = exact_decimal(o.error_estimate_action);
    j["double_stage"] = o.double_stage;
    j["quarter_step"] = exact_decimal(o.quarter_step);
    json q = json::array();
    for (const auto& x : o.quarter)
        q.push_back(real_array(x.data(), 4));
    j["quarter"] = q;
    j["checksum"] = orbit_record_checksum(j.dump());  // of the rest (orbit_from_json checks)
    return j.dump() + "\n";
}

template <class Real>
saddle_orbit<Real> orbit_from_json(const std::string& text, const std::string& where) {
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw input_error(where + ": not JSON (" + e.what() + ")");
    }
    try {
        if (!j.is_object() || !j.contains("checksum") || !j.at("checksum").is_string())
            throw input_error(where + ": no checksum (not an orbit record of format " +
                              std::to_string(format_version) + ")");
        const std::string checksum = j.at("checksum").get<std::string>();
        j.erase("checksum");
        if (orbit_record_checksum(j.dump()) != checksum)
            throw input_error(where + ": checksum mismatch (the record was edited or corrupted)");
        if (j.at("format").get<int>() != format_version)
            throw input_error(where + ": cache format " + j.at("format").dump() + ", expected " +
                              std::to_string(format_version));
        if (j.at("precision").get<std::string>() != precision_name<Real>())
            throw input_error(where + ": precision " + j.at("precision").dump() + ", expected " +
                              precision_name<Real>());
        saddle_orbit<Real> o;
        auto r = [&](const char* key) { return real_of<Real>(j.at(key), where + ": " + key); };
        const std::string a = j.at("arm").get<std::string>();
        if (!arm_named(a)) throw input_error(where + ": arm '" + a + "' is not 1 or 2");
        o.flip_arm = *arm_named(a);
        o.energy = r("energy");
        o.excess = r("excess");
        o.beta = r("beta");
        o.period = r("period");
        o.action = r("action");
        o.period_derivative = r("period_derivative");
        read_array(j.at("saddle"), o.saddle.data(), 2, where + ": saddle");
        read_array(j.at("start"), o.start.data(), 4, where + ": start");
        for (std::size_t i = 0; i < 2; ++i)
            read_array(j.at("turning_points").at(i), o.turning_points[i].data(), 2,
                       where + ": turning_points");
        const json& f = j.at("floquet");
        for (std::size_t i = 0; i < 4; ++i) {
            const json& z = f.at("eigenvalues").at(i);
            o.floquet.eigenvalues[i] =
                std::complex<Real>(real_of<Real>(z.at(0), where + ": eigenvalues"),
                                   real_of<Real>(z.at(1), where + ": eigenvalues"));
        }
        auto fr = [&](const char* key) { return real_of<Real>(f.at(key), where + ": " + key); };
        o.floquet.trace = fr("trace");
        o.floquet.stability_index = fr("stability_index");
        o.floquet.hyperbolic = f.at("hyperbolic").get<bool>();
        o.floquet.multiplier = fr("multiplier");
        o.floquet.angle = fr("angle");
        o.floquet.unit_deviation = fr("unit_deviation");
        o.floquet.determinant_deviation = fr("determinant_deviation");
        for (std::size_t i = 0; i < 4; ++i)
            read_array(j.at("monodromy").at(i), o.monodromy[i].data(), 4, where + ": monodromy");
        const std::string status = j.at("status").get<std::string>();
        bool known = false;
        for (orbit_status s :
             {orbit_status::converged, orbit_status::stalled, orbit_status::not_converged}) {
            if (to_string(s) == status) {
                o.status = s;
                known = true;
            }
        }
        if (!known) throw input_error(where + ": status '" + status + "' is unknown");
        o.method = parse_name<orbit_method>(j.at("method").get<std::string>(), where + ": method");
        o.integrator = parse_name<orbit_integrator>(j.at("integrator").get<std::string>(),
                                                    where + ": integrator");
        o.stages = j.at("stages").get<int>();
        o.order = j.at("order").get<int>();
        o.steps = j.at("steps").get<long>();
        o.tolerance = r("tolerance");
        o.newton_iterations = j.at("newton_iterations").get<int>();
        o.residual = r("residual");
        o.last_update = r("last_update");
        o.energy_error = r("energy_error");
        o.error_estimate_period = r("error_estimate_period");
        o.error_estimate_action = r("error_estimate_action");
        o.double_stage = j.at("double_stage").get<std::string>();
        o.quarter_step = r("quarter_step");
        for (const json& x : j.at("quarter")) {
            std::array<Real, 4> v;
            read_array(x, v.data(), 4, where + ": quarter");
            o.quarter.push_back(v);
        }
        if (o.quarter.empty()) throw input_error(where + ": quarter: empty");
        return o;
    } catch (const json::exception& e) {
        throw input_error(where + ": malformed orbit record (" + e.what() + ")");
    }
}

template <class Real>
std::string orbit_cache_key(const double_pendulum<Real>& model,
                            const orbit_options<Real>& options) {
    // NOTE: the integrator is part of the key: the two give the same orbit to within their error
    // estimates, not to the last digit
    const bool taylor = options.integrator == orbit_integrator::taylor;
    const int stages = taylor ? 0 : options.stages > 0 ? options.stages : default_stages<Real>();
    const std::string text = model_text_key(model) + precision_name<Real>() + ";" +
                             to_string(options.method) + ";" + to_string(options.integrator) + ";" +
                             std::to_string(stages) + ";" + to_decimal(options.tolerance) + ";" +
                             std::to_string(format_version);
    std::string name = precision_name<Real>();  // "mp:120" -> "mp120"
    std::erase(name, ':');
    return name + "-" + orbit_record_checksum(text);
}

template <class Real>
std::string cached_orbit_problem(const double_pendulum<Real>& model, arm a,
                                 const level_arg<Real>& level, const saddle_orbit<Real>& o) {
    using std::abs;
    using std::cbrt;
    using std::isfinite;
    if (o.flip_arm != a) return "arm " + to_string(o.flip_arm) + ", expected " + to_string(a);
    const Real& energy = level.value;
    if (o.energy != energy)
        return "energy " + to_decimal(o.energy) + ", expected " + to_decimal(energy);
    if (o.status == orbit_status::not_converged) return "a record of a failed solve";
    if (!isfinite(o.period) || !(o.period > 0))
        return "period T = " + to_decimal(o.period) + " is not > 0";
    if (!isfinite(o.action) || !(o.action > 0))
        return "action F = " + to_decimal(o.action) + " is not > 0";
    // NOTE: loose on purpose (cbrt eps, or 100 times the orbit's own residual near E_max): these
    // checks catch a record of another pendulum or an orbit that does not close, not its last
    // digits (the checksum guards those against corruption).
    const Real eps = std::numeric_limits<Real>::epsilon();
    Real tol = cbrt(eps);
    if (isfinite(o.residual) && 100 * o.residual > tol) tol = 100 * o.residual;
    const Real es = model.saddle_energy(a), scale = abs(energy) + abs(es);
    const Real excess = level.above(model.saddle_level(a));
    if (!(abs(o.excess - excess) <= tol * scale))
        return "excess E - E_s = " + to_decimal(o.excess) + ", the model's is " +
               to_decimal(excess) + " (another pendulum?)";
    if (!(abs(model.potential(o.saddle[0], o.saddle[1]) - es) <= tol * scale))
        return "its saddle point is not the model's (another pendulum?)";
    if (!(abs(o.start[0] - o.saddle[0]) + abs(o.start[1] - o.saddle[1]) <= tol * scale) ||
        !(abs(model.hamiltonian(o.start) - energy) <= tol * scale))
        return "its start is not on the energy surface at the saddle";
    if (o.quarter.size() < 2 || !isfinite(o.quarter_step) || !(o.quarter_step > 0))
        return "no quarter orbit";
    const Real quarter_time = static_cast<Real>(o.quarter.size() - 1) * o.quarter_step;
    if (!(abs(4 * quarter_time - o.period) <= tol * o.period))
        return "its quarter orbit spans " + to_decimal(Real(4 * quarter_time)) +
               " / 4, not the period T = " + to_decimal(o.period) +
               " / 4 (the orbit does not close)";
    const auto& first = o.quarter.front();
    const auto& last = o.quarter.back();
    const Real l0 = abs(o.start[2]) + abs(o.start[3]);
    if (!(abs(first[0]) + abs(first[1]) <= tol * scale) ||
        !(abs(last[2]) + abs(last[3]) <= tol * l0) ||
        !(abs(last[0] + o.saddle[0] - o.turning_points[0][0]) +
              abs(last[1] + o.saddle[1] - o.turning_points[0][1]) <=
          tol * scale))
        return "its quarter orbit does not run from the saddle to a turning point (the orbit "
               "does not close)";
    for (const auto& x : o.quarter) {
        const phase_point<Real> p{x[0] + o.saddle[0], x[1] + o.saddle[1], x[2], x[3]};
        if (!(abs(model.hamiltonian(p) - energy) <= tol * scale))
            return "its quarter orbit leaves the energy surface";
    }
    return orbit_replica_problem(model, o);
}

using R = inst_real;
template std::optional<saddle_orbit<R>> recall_saddle_orbit<R>(const double_pendulum<R>&, arm,
                                                               const level_arg<R>&, orbit_method,
                                                               orbit_integrator);
template void remember_saddle_orbit<R>(const double_pendulum<R>&, const saddle_orbit<R>&);
template std::vector<std::string> remembered_orbit_records<R>(const double_pendulum<R>&);
template void remember_orbit_records<R>(const double_pendulum<R>&, const std::vector<std::string>&,
                                        const std::string&);
template saddle_orbit<R> find_or_solve_saddle_orbit<R>(const double_pendulum<R>&, arm,
                                                       const level_arg<R>&,
                                                       const orbit_options<R>&);
template std::string orbit_to_json<R>(const saddle_orbit<R>&);
template saddle_orbit<R> orbit_from_json<R>(const std::string&, const std::string&);
template std::string orbit_cache_key<R>(const double_pendulum<R>&, const orbit_options<R>&);
template std::string cached_orbit_problem<R>(const double_pendulum<R>&, arm, const level_arg<R>&,
                                             const saddle_orbit<R>&);

}  // namespace flipflux
