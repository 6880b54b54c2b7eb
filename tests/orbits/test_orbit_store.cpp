// The saddle-orbit store (orbits/orbit_store.hpp): the on-disk record reads back bit-identically
// in every precision, malformed records are refused naming what is wrong, the memo returns what
// was remembered for the same pendulum, arm, energy and method only, and cache keys separate
// everything that changes an orbit.
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "flipflux/core/decimal.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "support.hpp"

namespace flipflux {
std::size_t saddle_orbit_memo_misses();  // src/orbits/orbit_names.cpp
}

namespace flipflux::test {
namespace {

/// A synthetic orbit whose every field holds a distinct value that is not a short decimal.
template <class Real>
saddle_orbit<Real> synthetic(arm a, const Real& energy) {
    saddle_orbit<Real> o;
    int k = 1;
    auto next = [&k] { return Real(1) / Real(7 * k++ + 3); };
    o.flip_arm = a;
    o.energy = energy;
    o.excess = next(), o.beta = next(), o.period = next(), o.action = next();
    o.period_derivative = next();
    o.saddle = {next(), next()};
    o.start = {next(), next(), next(), next()};
    o.turning_points = {std::array<Real, 2>{next(), next()}, std::array<Real, 2>{next(), next()}};
    for (auto& z : o.floquet.eigenvalues)
        z = std::complex<Real>(next(), -next());
    o.floquet.trace = next(), o.floquet.stability_index = next();
    o.floquet.hyperbolic = true;
    o.floquet.multiplier = next(), o.floquet.angle = next();
    o.floquet.unit_deviation = next(), o.floquet.determinant_deviation = next();
    for (auto& row : o.monodromy)
        for (auto& v : row)
            v = next();
    o.status = orbit_status::stalled;
    o.method = orbit_method::symmetric;
    o.stages = 7, o.steps = 123, o.newton_iterations = 5;
    o.tolerance = next(), o.residual = next(), o.last_update = next(), o.energy_error = next();
    o.error_estimate_period = next(), o.error_estimate_action = next();
    o.double_stage = "report, with \"quotes\"";
    o.quarter_step = next();
    for (int i = 0; i < 3; ++i)
        o.quarter.push_back({next(), next(), next(), next()});
    return o;
}

template <class Real>
void expect_identical(const saddle_orbit<Real>& a, const saddle_orbit<Real>& b) {
    // serialising again gives the same text: every real came back bit for bit
    EXPECT_EQ(orbit_to_json(a), orbit_to_json(b));
    EXPECT_EQ(a.period, b.period);
    EXPECT_EQ(a.monodromy[3][2], b.monodromy[3][2]);
    EXPECT_EQ(a.floquet.eigenvalues[1], b.floquet.eigenvalues[1]);
    EXPECT_EQ(a.quarter.back()[3], b.quarter.back()[3]);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.method, b.method);
    EXPECT_EQ(a.flip_arm, b.flip_arm);
    EXPECT_EQ(a.double_stage, b.double_stage);
}

template <class Real>
class OrbitStore : public test::real_test<Real> {};
TYPED_TEST_SUITE(OrbitStore, real_types, real_name);

TYPED_TEST(OrbitStore, RecordsReadBackBitIdentically) {
    using Real = TypeParam;
    const auto o = synthetic<Real>(arm::one, parse_real<Real>("4.7", "E"));
    expect_identical(o, orbit_from_json<Real>(orbit_to_json(o), "x.json"));
}

TEST(OrbitStore, MalformedRecordsAreRefusedNamingTheProblem) {
    const auto o = synthetic<double>(arm::two, 3.0);
    const auto good = nlohmann::json::parse(orbit_to_json(o));
    auto refused = [](const std::string& text, const std::string& what) {
        try {
            (void)orbit_from_json<double>(text, "f.json");
            ADD_FAILURE() << "accepted: " << what;
        } catch (const input_error& e) {
            EXPECT_NE(std::string(e.what()).find("f.json"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    refused("{not json", "not JSON");
    auto with = [&](const char* key, const nlohmann::json& v) {  // sealed: passes the checksum
        auto j = good;
        j[key] = v;
        return seal_orbit_record(j.dump());
    };
    refused(with("format", 99), "cache format");
    refused(with("precision", "quad"), "precision");
    refused(with("arm", "3"), "arm '3'");
    refused(with("status", "weird"), "status 'weird'");
    refused(with("period", 1.5), "period: expected a decimal string");
    refused(with("period", "1.5x"), "period");
    refused(with("saddle", nlohmann::json::array({"1"})), "saddle: expected an array of 2");
    refused(with("quarter", nlohmann::json::array()), "quarter: empty");
    refused(with("method", "newton"), "method");
    auto j = good;
    j.erase("action");
    refused(seal_orbit_record(j.dump()), "malformed orbit record");
}

// Issue 20: an edited cache entry (period 7.5, action -1) was used silently. Every record carries
// a checksum over the rest of it; an edit or a truncation without resealing is refused.
TEST(OrbitStore, EditedRecordsFailTheChecksum) {
    const auto o = synthetic<double>(arm::two, 3.0);
    const std::string text = orbit_to_json(o);
    EXPECT_NO_THROW((void)orbit_from_json<double>(text, "f.json"));
    auto j = nlohmann::ordered_json::parse(text);
    ASSERT_TRUE(j.contains("checksum"));
    j["period"] = "7.5";
    for (const std::string& bad : {j.dump(), text.substr(0, text.size() / 2) + "}"}) {
        try {
            (void)orbit_from_json<double>(bad, "f.json");
            ADD_FAILURE() << "accepted an edited record";
        } catch (const input_error& e) {
            EXPECT_NE(std::string(e.what()).find("f.json"), std::string::npos) << e.what();
        }
    }
    j.erase("checksum");
    try {
        (void)orbit_from_json<double>(j.dump(), "f.json");
        ADD_FAILURE() << "accepted a record without a checksum";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("no checksum"), std::string::npos) << e.what();
    }
}

// Issue 20: a record that passes the checksum (resealed) but is not a physical orbit of this
// pendulum (period 7.5, action -1, another energy or arm, a quarter orbit that does not close) is
// refused by the physical checks, which accept the orbit as solved.
TEST(OrbitStore, CachedOrbitsAreCheckedPhysically) {
    const double_pendulum<double> model;
    const saddle_orbit<double> o = solve_saddle_orbit(model, arm::two, 3.0);
    ASSERT_NE(o.status, orbit_status::not_converged);
    EXPECT_EQ(cached_orbit_problem(model, arm::two, 3.0, o), "");
    const saddle_orbit<double> back = orbit_from_json<double>(orbit_to_json(o), "f.json");
    EXPECT_EQ(cached_orbit_problem(model, arm::two, 3.0, back), "");
    auto problem = [&](auto edit) {
        saddle_orbit<double> x = o;
        edit(x);
        return cached_orbit_problem(model, arm::two, 3.0, x);
    };
    EXPECT_NE(problem([](auto& x) { x.period = 7.5; }).find("does not close"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.action = -1; }).find("action"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.period = -x.period; }).find("period"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.energy = 3.5; }).find("energy"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.flip_arm = arm::one; }).find("arm"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.excess *= 2; }).find("excess"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.start[2] *= 1.01; }).find("energy surface"),
              std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.quarter.back()[2] += 0.1; }).find("does not close"),
              std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.status = orbit_status::not_converged; }).find("failed"),
              std::string::npos);
    // a record of another pendulum (heavier lower link): its saddle energy differs
    physical_parameters<double> p = model.parameters();
    p.m2 = 2;
    EXPECT_NE(cached_orbit_problem(double_pendulum<double>(p), arm::two, 3.0, o), "");
}

// Issue 45: a resealed record whose derived quantities were edited (the action, multiplier,
// stability index, dT/dE, the monodromy, a sample of the quarter orbit) was believed; the
// replay of the solver's last shot and final orbit at the recorded (beta, T) finds each, while
// the record as solved, and as read back from its JSON, passes (at double, quad and mp:40,
// whose record keeps N + 2 of its guard digits).
template <class Real>
void expect_edits_found(const double_pendulum<Real>& model, const Real& energy) {
    const saddle_orbit<Real> o = solve_saddle_orbit(model, arm::two, energy);
    ASSERT_NE(o.status, orbit_status::not_converged);
    EXPECT_EQ(orbit_replica_problem(model, o), "");
    const saddle_orbit<Real> back = orbit_from_json<Real>(orbit_to_json(o), "f.json");
    EXPECT_EQ(orbit_replica_problem(model, back), "") << precision_name<Real>();
    EXPECT_EQ(cached_orbit_problem(model, arm::two, energy, back), "");
    auto problem = [&](auto edit) {
        saddle_orbit<Real> x = back;
        edit(x);
        return cached_orbit_problem(model, arm::two, energy, x);
    };
    // a millionfold the record's decimal rounding: far below the old checks' cbrt(eps)
    using std::pow;
    const Real tiny = Real(1e6) * pow(Real(10), Real(1 - output_digits<Real>()));
    EXPECT_NE(problem([](auto& x) { x.action *= 2; }).find("action"), std::string::npos);
    EXPECT_NE(problem([&](auto& x) { x.action *= 1 + tiny; }).find("action"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.floquet.multiplier *= 2; }).find("multiplier"),
              std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.floquet.stability_index *= 2; }).find("multiplier"),
              std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.period_derivative *= 2; }).find("dT/dE"), std::string::npos);
    EXPECT_NE(problem([](auto& x) { x.monodromy[0][1] *= 2; }).find("monodromy"),
              std::string::npos);
    EXPECT_NE(
        problem([&](auto& x) { x.quarter[x.quarter.size() / 2][0] += tiny; }).find("quarter orbit"),
        std::string::npos);
}

TEST(OrbitStore, ResealedEditsOfDerivedQuantitiesAreFoundByTheReplay) {
    expect_edits_found(double_pendulum<double>(), 3.0);
    expect_edits_found(double_pendulum<quad>(), quad(4));
    const precision_scope scope(precision{real_kind::mp, 40});
    expect_edits_found(double_pendulum<mp>(), mp(3));
}

TEST(OrbitStore, MemoReturnsOnlyTheSameOrbit) {
    forget_saddle_orbits();
    const double_pendulum<double> model;
    physical_parameters<double> p;
    p.m2 = 2;
    const double_pendulum<double> other(p);
    auto o = synthetic<double>(arm::two, 3.0);
    o.excess = 3.0 - model.saddle_energy(arm::two);  // the memo's key: E and E - E_s
    o.method = orbit_method::periodic;
    o.status = orbit_status::converged;
    remember_saddle_orbit(model, o);
    ASSERT_TRUE(recall_saddle_orbit(model, arm::two, 3.0, orbit_method::periodic).has_value());
    // just above the saddle, two decimal inputs that round to the same E are two orbits
    // (model/energy_level.hpp)
    auto near = synthetic<double>(arm::two, 2.0);
    near.excess = 1e-20;
    near.method = orbit_method::periodic;
    near.status = orbit_status::converged;
    remember_saddle_orbit(model, near);
    const auto level = [](const char* text) { return parse_energy_level<double>(text, "E"); };
    EXPECT_TRUE(recall_saddle_orbit(model, arm::two, level("2.00000000000000000001"),
                                    orbit_method::periodic)
                    .has_value());
    EXPECT_FALSE(recall_saddle_orbit(model, arm::two, level("2.00000000000000000002"),
                                     orbit_method::periodic)
                     .has_value());
    EXPECT_FALSE(recall_saddle_orbit(model, arm::one, 3.0, orbit_method::periodic).has_value());
    EXPECT_FALSE(recall_saddle_orbit(model, arm::two, 3.5, orbit_method::periodic).has_value());
    EXPECT_FALSE(recall_saddle_orbit(model, arm::two, 3.0, orbit_method::symmetric).has_value());
    EXPECT_FALSE(recall_saddle_orbit(other, arm::two, 3.0, orbit_method::periodic).has_value());
    // find_or_solve returns the remembered orbit without solving
    const std::size_t misses = saddle_orbit_memo_misses();
    const auto found = find_or_solve_saddle_orbit(model, arm::two, 3.0);
    EXPECT_EQ(saddle_orbit_memo_misses(), misses);
    EXPECT_EQ(found.period, o.period);  // the synthetic one: nothing was solved
    // a bypass solves afresh (the real orbit, not the synthetic one) and leaves it remembered
    {
        const saddle_orbit_memo_bypass bypass;
        const auto solved = find_or_solve_saddle_orbit(model, arm::two, 3.0);
        EXPECT_EQ(saddle_orbit_memo_misses(), misses + 1);
        EXPECT_NE(solved.period, o.period);
        EXPECT_EQ(solved.period, solve_saddle_orbit(model, arm::two, 3.0, {}).period);
    }
    const auto after = find_or_solve_saddle_orbit(model, arm::two, 3.0);
    EXPECT_EQ(saddle_orbit_memo_misses(), misses + 1);  // recalled, not solved
    EXPECT_NE(after.period, o.period);
    forget_saddle_orbits();
    EXPECT_FALSE(recall_saddle_orbit(model, arm::two, 3.0, orbit_method::periodic).has_value());
}

// What one process remembers, another recalls bit for bit (an MPI run's rank 0 sends its orbits
// to the other ranks): only the pendulum's orbits are sent, and a corrupt record is refused.
TEST(OrbitStore, RememberedRecordsCarryTheOrbitsToAnotherMemo) {
    forget_saddle_orbits();
    const double_pendulum<quad> model;
    physical_parameters<quad> p;
    p.m2 = 2;
    const double_pendulum<quad> other(p);
    const saddle_orbit<quad> solved = find_or_solve_saddle_orbit(model, arm::two, quad(3));
    remember_saddle_orbit(other, synthetic<quad>(arm::two, quad(9)));
    saddle_orbit<quad> failed = synthetic<quad>(arm::two, quad(4));
    failed.status = orbit_status::not_converged;  // a family remembers its failures too
    remember_saddle_orbit(model, failed);
    const std::vector<std::string> records = remembered_orbit_records(model);
    ASSERT_EQ(records.size(), 1u);  // neither the other pendulum's nor the failed one
    forget_saddle_orbits();         // "another process": an empty memo
    ASSERT_FALSE(recall_saddle_orbit(model, arm::two, quad(3), solved.method).has_value());
    remember_orbit_records(model, records, "sent");
    const auto recalled = recall_saddle_orbit(model, arm::two, quad(3), solved.method);
    ASSERT_TRUE(recalled.has_value());
    EXPECT_EQ(orbit_to_json(*recalled), orbit_to_json(solved));  // every field, every bit
    EXPECT_TRUE(recalled->period == solved.period && recalled->action == solved.action);
    std::string corrupt = records[0];
    corrupt[corrupt.find("\"period\"") + 12] ^= 1;
    try {
        remember_orbit_records(model, {corrupt}, "sent");
        ADD_FAILURE() << "a corrupt record was accepted";
    } catch (const input_error& e) {
        EXPECT_NE(std::string(e.what()).find("sent (record 1)"), std::string::npos) << e.what();
    }
    forget_saddle_orbits();
}

// Threads asking for the same orbit at once solve it once: the others wait for its result.
TEST(OrbitStore, ConcurrentRequestsForOneOrbitSolveItOnce) {
    forget_saddle_orbits();
    const double_pendulum<double> model;
    const std::size_t misses = saddle_orbit_memo_misses();
    std::vector<saddle_orbit<double>> found(4);
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < found.size(); ++i)
        threads.emplace_back(
            [&, i] { found[i] = find_or_solve_saddle_orbit(model, arm::one, 4.75); });
    for (std::thread& t : threads)
        t.join();
    EXPECT_EQ(saddle_orbit_memo_misses(), misses + 1);
    for (const auto& o : found)
        EXPECT_EQ(o.period, found[0].period);
    EXPECT_EQ(found[0].period, solve_saddle_orbit(model, arm::one, 4.75, {}).period);
    forget_saddle_orbits();
}

TEST(OrbitStore, CacheKeysSeparatePendulumsPrecisionsAndOptions) {
    const double_pendulum<double> model;
    physical_parameters<double> p;
    p.a2 = 2;  // (L2 alone does not enter the dynamics: the key follows the coefficients)
    const double_pendulum<double> other(p);
    const orbit_options<double> periodic;
    orbit_options<double> symmetric, stages;
    symmetric.method = orbit_method::symmetric;
    stages.stages = 8;
    const std::string k = orbit_cache_key(model, periodic);
    EXPECT_EQ(k, orbit_cache_key(model, periodic));  // deterministic
    EXPECT_EQ(k.rfind("double-", 0), 0u);
    EXPECT_NE(k, orbit_cache_key(other, periodic));
    EXPECT_NE(k, orbit_cache_key(model, symmetric));
    EXPECT_NE(k, orbit_cache_key(model, stages));
    const std::string k50 =
        in_mp(50, [] { return orbit_cache_key(double_pendulum<mp>(), orbit_options<mp>{}); });
    EXPECT_EQ(k50.rfind("mp50-", 0), 0u);  // no ':' in a directory name
    // another precision is another orbit
    const std::string k51 =
        in_mp(51, [] { return orbit_cache_key(double_pendulum<mp>(), orbit_options<mp>{}); });
    EXPECT_EQ(k51.rfind("mp51-", 0), 0u);
}

}  // namespace
}  // namespace flipflux::test
