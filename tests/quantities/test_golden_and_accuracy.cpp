// Golden data (data/golden/, include/flipflux/quantities/golden.hpp): the committed rows are
// regenerated on a sample and compared, their certification and grid are checked, and the
// `golden` and `accuracy` commands are run on small selections.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/budget.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/output/accuracy_markdown.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/quantities/accuracy.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/quantities/registry.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

using test::relative_error;

using test::read_text;

const std::vector<std::string> prediction_quantities{"omega", "flux-upright", "flux-approx",
                                                     "rate-upright", "rate-approx"};

bool is_prediction(const std::string& name) {
    return std::find(prediction_quantities.begin(), prediction_quantities.end(), name) !=
           prediction_quantities.end();
}

std::vector<golden_row> committed_rows() {
    return parse_golden_csv(
        read_text(std::string(FLIPFLUX_SOURCE_DIR) + "/data/golden/golden.csv"));
}

TEST(Golden, CommittedRowsAreCertifiedAndCoverTheGrid) {
    const std::vector<golden_row> rows = committed_rows();
    ASSERT_GT(rows.size(), 700u);
    for (const std::string& name : prediction_quantities) {
        for (const std::string a : {"1", "2"}) {
            if (name == "omega" && a == "1") continue;
            const std::string arm_text = name == "omega" ? "" : a;
            const double start = name == "omega" ? 0 : (a == "2" ? 2 : 4);
            for (const std::string& e : golden_energies(start, 6)) {
                const auto it = std::find_if(rows.begin(), rows.end(), [&](const golden_row& r) {
                    return r.quantity == name && r.arm == arm_text && r.energy == e;
                });
                ASSERT_NE(it, rows.end()) << name << " arm " << arm_text << " E " << e;
                EXPECT_GE(it->digits, 40) << name << " arm " << arm_text << " E " << e;
                EXPECT_NE(it->method.find('|'), std::string::npos);  // certified by a 2nd method
            }
        }
    }
    // issue 14: the saddle-orbit rows, both arms, up to E_max - 0.001, each certified to >= 45
    // digits by mp:50 and by the other shooting
    for (const std::string name :
         {"period", "action", "flux-saddle", "rate-saddle", "multiplier", "stability-index"}) {
        for (const std::string a : {"1", "2"}) {
            for (const std::string& e : golden_orbit_energies(a == "2" ? 2 : 4, 6)) {
                const auto it = std::find_if(rows.begin(), rows.end(), [&](const golden_row& r) {
                    return r.quantity == name && r.arm == a && r.energy == e;
                });
                ASSERT_NE(it, rows.end()) << name << " arm " << a << " E " << e;
                EXPECT_GE(it->digits, 45) << name << " arm " << a << " E " << e;
                EXPECT_EQ(it->method, "periodic|symmetric/taylor");
            }
        }
    }
    const nlohmann::json provenance = nlohmann::json::parse(
        read_text(std::string(FLIPFLUX_SOURCE_DIR) + "/data/golden/provenance.json"));
    for (const char* key : {"command", "git_commit", "compiler", "libraries", "precision",
                            "boost_math_policy", "grid", "rows"})
        EXPECT_TRUE(provenance.contains(key)) << key;
    EXPECT_EQ(provenance["rows"].get<std::size_t>(), rows.size());
}

// issue 13: every committed row carries a proven enclosure [value +/- radius] (golden
// --certify-existing), at least as many proven digits as certified ones but one; a sample of the
// prediction rows is proved again here, at 30 digits: each fresh ball must meet the committed
// one (the committed value within the fresh ball widened by the committed radius).
TEST(Golden, CommittedRowsCarryProvenEnclosuresThatAFreshProofMeets) {
    const std::vector<golden_row> rows = committed_rows();
    for (const golden_row& r : rows) {
        ASSERT_FALSE(r.radius.empty()) << r.quantity << " arm " << r.arm << " E " << r.energy;
        EXPECT_GE(r.proven_digits, r.digits - 1)
            << r.quantity << " arm " << r.arm << " E " << r.energy << ": radius " << r.radius;
    }
    std::size_t checked = 0;
    for (std::size_t i = 0; i < rows.size(); i += rows.size() / 17) {
        const golden_row& r = rows[i];
        if (!is_prediction(r.quantity)) continue;
        const arm a = r.arm == "1" ? arm::one : arm::two;
        const certified_enclosure fresh =
            certified_value(r.quantity, model_text{}, a, r.energy, 30);
        EXPECT_GE(fresh.proven_digits, 29) << r.quantity << " E " << r.energy;
        EXPECT_TRUE(enclosure_contains(fresh, r.value, r.radius))
            << r.quantity << " arm " << r.arm << " E " << r.energy << ": committed " << r.value
            << " +/- " << r.radius << ", fresh " << fresh.mid << " +/- " << fresh.radius;
        ++checked;
    }
    EXPECT_GE(checked, 12u);
}

// A sample of the committed rows, recomputed in quad by the default method: equal to the quad
// rounding (the golden value carries >= 40 digits).
TEST(Golden, SampleOfRowsRegeneratesInQuad) {
    const std::vector<golden_row> rows = committed_rows();
    std::size_t checked = 0;
    for (std::size_t i = 0; i < rows.size(); i += rows.size() / 13) {
        const golden_row& r = rows[i];
        if (!is_prediction(r.quantity)) continue;
        const quantity& q = find_quantity(r.quantity);
        const arm a = r.arm == "1" ? arm::one : arm::two;
        const quantity_value<quad> v =
            q.evaluate(double_pendulum<quad>(), a, parse_real<quad>(r.energy, "E"), "");
        EXPECT_LE(relative_error(v.value, r.value), 1e-31)
            << r.quantity << " arm " << r.arm << " E " << r.energy;
        ++checked;
    }
    EXPECT_GE(checked, 10u);
}

// The saddle-orbit rows at E = 5 (both arms) regenerate in double, by the symmetric shooting
// with Gauss-Legendre, to double's accuracy (the orbit's error estimate, at least 64 eps times
// the quantity's condition: the multiplier's is its size relative to 1/mu's, ~1).
TEST(Golden, OrbitRowsRegenerateInDouble) {
    const std::vector<golden_row> rows = committed_rows();
    std::size_t checked = 0;
    for (const golden_row& r : rows) {
        if (is_prediction(r.quantity) || r.energy != "5") continue;
        const quantity& q = find_quantity(r.quantity);
        const quantity_value<double> v =
            q.evaluate(double_pendulum<double>(), r.arm == "1" ? arm::one : arm::two,
                       parse_energy_level<double>(r.energy, "E"), "symmetric/gauss-legendre");
        const double tol = std::max(64 * 2.2e-16, 4 * std::abs(v.error_estimate / v.value));
        EXPECT_LE(relative_error(v.value, r.value), tol) << r.quantity << " arm " << r.arm;
        ++checked;
    }
    EXPECT_EQ(checked, 12u);  // six quantities, two arms
}

// Issues 13 and 14: the golden sets of the other pendulums (data/golden/<name>/), each with its
// parameters in its provenance: a set in mp:100 has every row certified to >= 45 digits (against
// mp:50 and an independent method), a set in quad its prediction rows to >= 12 and its orbit rows
// to >= 4 (near E_max the multiplier amplifies double's errors in the certifying route); a row
// carries a proven enclosure (--certify-existing) wherever its quantity has one, with at least
// as many proven digits as certified ones but one; a sample of each regenerates in double from
// those parameters, to double's accuracy or the row's digits, and its critical energies are the
// model's.
TEST(Golden, EveryPendulumsSetRegeneratesASampleInDouble) {
    namespace fs = std::filesystem;
    std::size_t sets = 0;
    for (const auto& entry :
         fs::directory_iterator(fs::path(FLIPFLUX_SOURCE_DIR) / "data/golden")) {
        if (!entry.is_directory() || !fs::exists(entry.path() / "golden.csv")) continue;
        ++sets;
        const std::string name = entry.path().filename().string();
        const nlohmann::json prov =
            nlohmann::json::parse(read_text((entry.path() / "provenance.json").string()));
        EXPECT_EQ(prov.at("pendulum").get<std::string>(), name);
        const nlohmann::json& p = prov.at("parameters");
        model_text t;
        t.m1 = p.at("m1"), t.m2 = p.at("m2"), t.L1 = p.at("L1"), t.L2 = p.at("L2");
        t.a1 = p.at("a1"), t.a2 = p.at("a2"), t.I1 = p.at("I1"), t.I2 = p.at("I2"), t.g = p.at("g");
        const double_pendulum<double> model = make_model<double>(t);
        const nlohmann::json& c = prov.at("critical_energies");
        EXPECT_LE(relative_error(model.maximum_energy(), c.at("maximum").get<std::string>()),
                  1e-15);
        EXPECT_LE(
            relative_error(model.saddle_energy(arm::two), c.at("saddle_arm2").get<std::string>()),
            1e-15);
        const std::vector<golden_row> rows =
            parse_golden_csv(read_text((entry.path() / "golden.csv").string()));
        ASSERT_GT(rows.size(), 100u) << name;
        EXPECT_EQ(prov.at("rows").get<std::size_t>(), rows.size());
        const bool mp = prov.at("precision").at("values").get<std::string>().rfind("mp:", 0) == 0;
        std::size_t orbit_rows = 0;
        for (const golden_row& r : rows) {
            const int least = mp ? 45 : is_prediction(r.quantity) ? 12 : 4;
            EXPECT_GE(r.digits, least)
                << name << " " << r.quantity << " arm " << r.arm << " E " << r.energy;
            // every set is proved (issue 13): a radius wherever the quantity has an enclosure
            EXPECT_EQ(r.radius.empty(), !has_certified_enclosure(r.quantity))
                << name << " " << r.quantity << " arm " << r.arm << " E " << r.energy;
            if (!r.radius.empty()) {
                EXPECT_GE(r.proven_digits, r.digits - 1)
                    << name << " " << r.quantity << " arm " << r.arm << " E " << r.energy;
            }
            if (!is_prediction(r.quantity)) ++orbit_rows;
        }
        EXPECT_GE(orbit_rows, 6u * 2 * 5) << name;  // six quantities, both arms, >= 5 energies
        std::size_t checked = 0;
        for (std::size_t i = 0; i < rows.size(); i += rows.size() / 7) {
            const golden_row& r = rows[i];
            const quantity& q = find_quantity(r.quantity);
            const arm a = r.arm == "1" ? arm::one : arm::two;
            const quantity_value<double> v =
                q.evaluate(model, a, parse_energy_level<double>(r.energy, "E"), "");
            // double's own accuracy: its error estimate, at least 64 eps times the condition
            // E / |E - E_c| that the rounding of the parameters and of E has near a critical
            // level E_c (the grid comes within U/1000 of them: ~1000), or the row's digits
            const double e = std::stod(r.energy);
            double nearest = std::abs(e - model.maximum_energy());
            for (arm c : {arm::one, arm::two})
                nearest = std::min(nearest, std::abs(e - model.saddle_energy(c)));
            const double condition = std::clamp(e / nearest, 1.0, 2000.0);
            const double tol = std::max({std::pow(10.0, 1 - r.digits), 64 * 2.2e-16 * condition,
                                         4 * std::abs(v.error_estimate / v.value)});
            EXPECT_LE(relative_error(v.value, r.value), tol)
                << name << " " << r.quantity << " arm " << r.arm << " E " << r.energy;
            ++checked;
        }
        EXPECT_GE(checked, 7u);
    }
    EXPECT_GE(sets, 3u);  // with the top-level one (the paper's): four pendulums
}

TEST(Golden, GridCsvAndDigits) {
    const std::vector<std::string> grid = golden_energies(2, 6);
    ASSERT_EQ(grid.front(), "2.05");
    EXPECT_EQ(grid[1], "2.1");
    EXPECT_EQ(grid[79], "6");
    EXPECT_EQ(grid[80], "6.5");
    EXPECT_EQ(grid.back(), "100");
    EXPECT_EQ(golden_energies(0, 6).front(), "0.05");
    EXPECT_EQ(golden_orbit_energies(2, 6),
              (std::vector<std::string>{"2.05", "3", "4", "5", "5.95", "5.99", "5.999"}));
    EXPECT_EQ(golden_orbit_energies(4, 6),
              (std::vector<std::string>{"4.05", "5", "5.95", "5.99", "5.999"}));
    EXPECT_EQ(golden_orbit_energies(1.1, 2.1),
              (std::vector<std::string>{"1.15", "2.05", "2.09", "2.099"}));
    // the check of the values, and the second check of a row the first leaves short of its cap
    EXPECT_EQ(golden_check_precision(mp_precision(100)), mp_precision(50));
    EXPECT_EQ(golden_check_precision(precision{real_kind::quad}), precision{real_kind::double_});
    EXPECT_EQ(golden_recheck_precision(mp_precision(100)), mp_precision(75));
    EXPECT_EQ(golden_recheck_precision(mp_precision(8)), mp_precision(6));
    EXPECT_FALSE(golden_recheck_precision(mp_precision(7)));
    EXPECT_FALSE(golden_recheck_precision(precision{real_kind::quad}));
    EXPECT_EQ(agreement_digits("1.2345", "1.2345"), 50);
    EXPECT_EQ(agreement_digits("1.2346", "1.2345"), 4);
    EXPECT_EQ(agreement_digits("3", "1"), 0);
    EXPECT_EQ(agreement_digits("1", "0"), 0);
    std::vector<golden_row> rows{
        {"omega", "", "1", "3.25", 3, "a|b", "", -1},
        {"flux-upright", "2", "3", "13.0", 3, "elliptic|integral", "", -1}};
    std::vector<golden_row> back = parse_golden_csv(golden_csv(rows));
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].arm, "");
    EXPECT_EQ(back[1].method, "elliptic|integral");
    EXPECT_EQ(back[1].digits, 3);
    EXPECT_EQ(golden_csv(rows).substr(0, golden_csv(rows).find('\n')),
              "quantity,arm,energy,value,digits,method");  // no proof: the 6 columns as before
    // golden --certify: radius and proven_digits, empty in a row without an enclosure
    rows[1].radius = "4.1e-3";
    rows[1].proven_digits = 3;
    const std::string proven = golden_csv(rows);
    EXPECT_EQ(proven.substr(0, proven.find('\n')),
              "quantity,arm,energy,value,digits,method,radius,proven_digits");
    back = parse_golden_csv(proven);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].radius, "");
    EXPECT_EQ(back[0].proven_digits, -1);
    EXPECT_EQ(back[1].radius, "4.1e-3");
    EXPECT_EQ(back[1].proven_digits, 3);
    EXPECT_THROW(parse_golden_csv("header\na,b\n"), input_error);
    EXPECT_THROW(parse_golden_csv("header\na,b,c,d,x,f\n"), input_error);
    EXPECT_THROW(parse_golden_csv("header\na,b,c,d,3,f,1e-3,x\n"), input_error);
    EXPECT_THROW(parse_golden_csv("header\na,b,c,d,3,f,1e-3\n"), input_error);
}

TEST(Golden, CertifyAddsTheProvenRadius) {
    // a prediction row, a row of both arms (omega: no arm) and a saddle-orbit row (the action
    // just above the saddle, in mp:20): each [value +/- radius] is a proven enclosure, its proven
    // digits those of the rounded value
    for (const char* q : {"flux-upright", "omega", "action"}) {
        const std::string dir =
            ::testing::TempDir() + "flipflux_golden_certify_" + std::to_string(getpid()) + "_" + q;
        const test::command_result r =
            test::run_flipflux("golden --out " + dir + " --quantities " + q +
                               " --max-rows 1 --jobs 1 --precision mp:20 --certify");
        ASSERT_EQ(r.status, 0) << r.err;
        const std::vector<golden_row> rows = parse_golden_csv(read_text(dir + "/golden.csv"));
        ASSERT_EQ(rows.size(), 1u) << r.err;
        EXPECT_FALSE(rows[0].radius.empty()) << q;
        EXPECT_GE(rows[0].proven_digits, rows[0].digits - 1) << q << ": " << rows[0].radius;
        EXPECT_EQ(nlohmann::json::parse(r.out)["proven_rows"], 1);
        std::filesystem::remove_all(dir);
    }
}

// The rows of one saddle orbit share one proof (prove_golden_rows asks for the most digits any of
// them has): the committed period, action, multiplier and stability index of arm 2 at E = 5,
// rounded to 13, 14, 15 and 15 digits, cost one orbit proof, not three; arm 1's period at the
// same energy is another orbit, another proof.
TEST(Golden, TheRowsOfOneOrbitShareOneProof) {
    std::vector<golden_row> rows;
    int digits = 13;
    for (const golden_row& r : committed_rows()) {
        const bool orbit = r.quantity == "period" || r.quantity == "action" ||
                           r.quantity == "multiplier" || r.quantity == "stability-index";
        if (!orbit || r.energy != "5") continue;
        if (r.arm == "1" && r.quantity != "period") continue;
        golden_row row = r;
        row.digits = r.arm == "1" ? 14 : std::min(digits++, 15);
        row.value = dispatch(mp_precision(60), [&]<class Real>() {
            return to_decimal(parse_real<Real>(r.value, "value"), row.digits);
        });
        row.radius.clear();
        row.proven_digits = -1;
        rows.push_back(row);
    }
    ASSERT_EQ(rows.size(), 5u);
    const std::size_t before = saddle_orbit_proofs_done();
    prove_golden_rows(rows, model_text{}, 2);
    EXPECT_EQ(saddle_orbit_proofs_done() - before, 2u);
    for (const golden_row& r : rows) {
        EXPECT_FALSE(r.radius.empty()) << r.quantity << " arm " << r.arm;
        EXPECT_GE(r.proven_digits, r.digits - 1) << r.quantity << " arm " << r.arm;
    }
}

// golden --max-seconds: an evaluation or a proof that does not finish in its CPU seconds gives no
// row (skipped, named) or no enclosure (unproven, named), and stops at the bound. A pendulum of
// its own (no memoized orbit) at mp:40: its saddle orbit takes far more than 2 ms to solve.
TEST(Golden, TheTimeBoundSkipsRowsAndProofsItCannotFinish) {
    golden_options options;
    options.quantities = {"period"};
    options.model.m2 = "1.37";
    options.value_precision = mp_precision(40);
    options.max_rows = 1;
    options.max_seconds = 0.002;
    std::vector<std::string> skipped;
    options.skipped = [&](const std::string& what) { skipped.push_back(what); };
    const double start = thread_cpu_seconds();
    EXPECT_TRUE(generate_golden(options).empty());
    EXPECT_LT(thread_cpu_seconds() - start, 1.0);
    ASSERT_EQ(skipped.size(), 1u);
    EXPECT_NE(skipped[0].find("period arm "), std::string::npos) << skipped[0];
    EXPECT_NE(skipped[0].find("did not finish in its 0.002 CPU seconds"), std::string::npos)
        << skipped[0];
    // a committed 50-digit row of omega, whose Arb enclosure at 50 digits takes far more than 1 ms
    std::vector<golden_row> rows;
    for (const golden_row& r : committed_rows())
        if (r.quantity == "omega" && r.energy == "4.3") rows.push_back(r);
    ASSERT_EQ(rows.size(), 1u);
    rows[0].radius.clear();
    rows[0].proven_digits = -1;
    std::vector<std::string> unproven;
    prove_golden_rows(rows, model_text{}, 1, 0.001,
                      [&](const std::string& what) { unproven.push_back(what); });
    EXPECT_TRUE(rows[0].radius.empty());
    ASSERT_EQ(unproven.size(), 1u);
    EXPECT_NE(unproven[0].find("the proof of omega arm - E 4.3: did not finish"), std::string::npos)
        << unproven[0];
}

TEST(Golden, CommandWritesASmallSelection) {
    const std::string dir = ::testing::TempDir() + "flipflux_golden_" + std::to_string(getpid());
    const test::command_result r = test::run_flipflux(
        "golden --out " + dir + " --quantities flux-upright --max-rows 2 --jobs 2");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::vector<golden_row> rows = parse_golden_csv(read_text(dir + "/golden.csv"));
    ASSERT_EQ(rows.size(), 2u) << r.err;
    for (const golden_row& row : rows) {
        EXPECT_EQ(row.quantity, "flux-upright");
        EXPECT_GE(row.digits, 45);
        EXPECT_EQ(row.method, "elliptic|integral");
    }
    const nlohmann::json summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["rows"], 2);
    EXPECT_EQ(summary["skipped"], 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir + "/provenance.json"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/golden.csv.tmp"));

    // --certify-existing proves the committed rows without recomputing them: same values, each
    // with a ball around it that proves its digits; a value wrong in its last digits fails
    const std::string csv = read_text(dir + "/golden.csv");
    EXPECT_EQ(test::run_flipflux("golden --out " + dir + " --certify-existing --merge").status, 2);
    EXPECT_EQ(
        test::run_flipflux("golden --out " + dir + " --certify-existing --precision quad").status,
        2);  // not the set's precision
    const test::command_result proved =
        test::run_flipflux("golden --out " + dir + " --certify-existing --jobs 2");
    ASSERT_EQ(proved.status, 0) << proved.err;
    const std::vector<golden_row> proven = parse_golden_csv(read_text(dir + "/golden.csv"));
    ASSERT_EQ(proven.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        EXPECT_EQ(proven[i].value, rows[i].value);
        EXPECT_FALSE(proven[i].radius.empty());
        EXPECT_GE(proven[i].proven_digits, rows[i].digits - 1) << proven[i].radius;
    }
    EXPECT_NE(read_text(dir + "/provenance.json").find("--certify-existing"), std::string::npos);
    std::string wrong = csv;
    const std::size_t at = wrong.find(rows[0].value) + rows[0].value.size() - 3;
    wrong[at] = wrong[at] == '1' ? '2' : '1';  // the value off by ~1e-(digits - 2) relative
    { std::ofstream(dir + "/golden.csv", std::ios::binary) << wrong; }
    EXPECT_EQ(test::run_flipflux("golden --out " + dir + " --certify-existing").status, 1);
    std::filesystem::remove_all(dir);
    const test::command_result bad =
        test::run_flipflux("golden --quantities nonsense --out " + dir);
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("nonsense"), std::string::npos);
    EXPECT_EQ(test::run_flipflux("golden --jobs 0 --out " + dir).status, 2);
}

/// The digits of `method`'s first cell in a generated table ("| method | 15.4 digits, ..."), or
/// -1 when the row or its figure is missing.
double first_cell_digits(const std::string& md, const std::string& method) {
    const std::size_t row = md.find("| " + method + " | ");
    if (row == std::string::npos) return -1;
    const std::size_t cell = row + method.size() + 5;
    char* end = nullptr;
    const double d = std::strtod(md.c_str() + cell, &end);
    return end == md.c_str() + cell ? -1 : d;
}

// Every method of flux-upright in double, measured on two threads (cells of one precision run
// concurrently), reaches double's target (14 digits against mp:120); the proof row gives the
// digits its ball proves (the contract: a relative radius <= 10^-(15 - 10), in practice about
// 10^-15) and its ball contains the mp:120 reference.
TEST(Accuracy, CommandWritesATable) {
    const std::string out =
        ::testing::TempDir() + "flipflux_accuracy_" + std::to_string(getpid()) + ".md";
    const test::command_result r =
        test::run_flipflux("accuracy --out " + out +
                           " --quantities flux-upright --precisions double --min-seconds 0 "
                           "--threads 2");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string md = read_text(out);
    EXPECT_NE(md.find("## flux-upright"), std::string::npos);
    for (const char* method : {"elliptic", "integral", "curve", "momentum"})
        EXPECT_GE(first_cell_digits(md, method), 14) << method << "\n" << md;
    EXPECT_GE(first_cell_digits(md, "proof (Arb)"), 5) << md;
    EXPECT_NE(md.find("proven digits"), std::string::npos) << md;
    EXPECT_EQ(md.find("**FAILED"), std::string::npos) << md;  // the marker of a failed cell
    EXPECT_NE(md.find("generated by `flipflux accuracy"), std::string::npos);
    std::filesystem::remove(out);
    EXPECT_EQ(test::run_flipflux("accuracy --threads 0 --out " + out).status, 2);
    EXPECT_EQ(test::run_flipflux("accuracy --precisions single --out " + out).status, 2);
    EXPECT_EQ(test::run_flipflux("accuracy --quantities nonsense --out " + out).status, 2);
    EXPECT_EQ(test::run_flipflux("accuracy --min-seconds -1 --out " + out).status, 2);
    EXPECT_EQ(test::run_flipflux("accuracy --max-seconds 0 --out " + out).status, 2);
}

// A cell whose evaluation outlives twice --max-seconds is abandoned (core/budget.hpp), not waited
// for: with a budget of 2 ms of CPU the momentum route's nested quadrature in mp:50 (0.3 s in the
// release build) is cut, while the closed form (no loop that checks the budget) is measured.
TEST(Accuracy, ACellBeyondItsBudgetIsAbandoned) {
    const std::string out =
        ::testing::TempDir() + "flipflux_accuracy_budget_" + std::to_string(getpid()) + ".md";
    const test::command_result r =
        test::run_flipflux("accuracy --out " + out +
                           " --quantities flux-upright --precisions mp:50 --min-seconds 0 "
                           "--max-seconds 0.001");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string md = read_text(out);
    const std::size_t row = md.find("| momentum | ");
    ASSERT_NE(row, std::string::npos) << md;
    EXPECT_NE(md.substr(row, md.find('\n', row) - row).find("abandoned after"), std::string::npos)
        << md;
    EXPECT_GE(first_cell_digits(md, "elliptic"), 46) << md;  // mp:50's target
    std::filesystem::remove(out);
}

// A method whose time in mp:2000, extrapolated from double (t ~ digits^3 with one column: the
// integral's 1-D quadrature at double takes microseconds, so mp:2000 ~ (2010 / 16)^3 = 2e6 times
// that), exceeds --max-seconds is not measured there, and the table gives the estimate. (At
// mp:1000 the estimate, 2.5e5 x 4 us on an Intel Xeon of 2026-12-03, sat on the bound of 1 s: one
// run in eight under load measured the cell instead.)
TEST(Accuracy, AMethodEstimatedTooSlowIsNotMeasured) {
    const std::string out =
        ::testing::TempDir() + "flipflux_accuracy_est_" + std::to_string(getpid()) + ".md";
    const test::command_result r =
        test::run_flipflux("accuracy --out " + out +
                           " --quantities flux-upright --precisions double,mp:2000 --min-seconds 0 "
                           "--max-seconds 1");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string md = read_text(out);
    const std::size_t row = md.find("| integral | ");
    ASSERT_NE(row, std::string::npos) << md;
    const std::string line = md.substr(row, md.find('\n', row) - row);
    EXPECT_NE(line.find("digits"), std::string::npos) << line;  // double: measured
    EXPECT_NE(line.find("not measured (estimated "), std::string::npos) << line;
    std::filesystem::remove(out);
}

// A method or a proof that fails in one cell (no convergence, a Krawczyk test that does not
// contract) is reported in that cell with its error on one line, not dropped.
TEST(Accuracy, AFailedCellIsReportedWithItsError) {
    accuracy_options options;
    options.precisions = {parse_precision("double"), parse_precision("mp:50")};
    accuracy_entry e{"period", "the saddle orbit's period", std::string(proof_method), {}};
    accuracy_cell& ok = e.cells.emplace_back();
    ok.applies = true;
    ok.digits = 22;
    ok.seconds = 0.5;
    ok.energies = 3;
    e.cells.emplace_back().failure = "Krawczyk test failed at E = 5.9 | box\nnot contracted";
    const std::string md = accuracy_markdown({e}, options, "flipflux accuracy", {});
    const std::size_t row = md.find("| proof (Arb) | ");
    ASSERT_NE(row, std::string::npos) << md;
    const std::string line = md.substr(row, md.find('\n', row) - row);
    EXPECT_NE(line.find("22 proven digits"), std::string::npos) << line;
    EXPECT_NE(line.find("| **FAILED: Krawczyk test failed at E = 5.9 / box not contracted** |"),
              std::string::npos)
        << line;
}

// The prose of generated files names the caller's commands only in the caller's words: with none,
// no command text and no empty parentheses; with words, each where it belongs.
TEST(Accuracy, GeneratedProseNamesOnlyTheCallersCommands) {
    accuracy_options options;
    options.precisions = {parse_precision("double")};
    const std::string bare = accuracy_markdown({}, options, "a caller", {});
    EXPECT_NE(bare.find("the exact value ([certified.md](certified.md)), asked"),
              std::string::npos);
    EXPECT_NE(bare.find("measured concurrently, each timed"), std::string::npos);
    EXPECT_FALSE(std::regex_search(bare, std::regex("--[a-z]")));  // no option
    const command_words words{"go", "list", "params", "prove-all", "prove", {"-j", "run -j"}};
    const std::string worded = accuracy_markdown({}, options, "a caller", words);
    EXPECT_NE(worded.find("value (`prove`, [certified.md](certified.md))"), std::string::npos);
    EXPECT_NE(worded.find("concurrently (`-j`, `run -j`), each"), std::string::npos);

    model_text unequal;
    unequal.m2 = "2";
    const auto columns = [&](const command_words& w) {
        return nlohmann::json::parse(
            golden_provenance("a caller", 0, parse_precision("mp:30"), w, unequal));
    };
    const nlohmann::json none = columns({});
    EXPECT_EQ(none["columns"]["quantity"], "registered name");
    EXPECT_EQ(none["columns"]["proven_digits"],
              "a certified run only: floor(-log10(radius / |value|))");
    EXPECT_EQ(none["model"], "double pendulum with the parameters above");
    const nlohmann::json named = columns(words);
    EXPECT_EQ(named["columns"]["quantity"], "registered name (list)");
    EXPECT_EQ(named["columns"]["proven_digits"], "prove-all only: floor(-log10(radius / |value|))");
    EXPECT_EQ(named["model"], "double pendulum with the parameters above (params)");
}

}  // namespace
}  // namespace flipflux
