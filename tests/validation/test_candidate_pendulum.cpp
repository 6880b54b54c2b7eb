// Issue 15 (validate reads the pendulum from a candidate's header): the `# pendulum:` declaration
// is parsed with every malformation refused by file:line, parameters compare as decimal numbers,
// the golden set with the declared parameters is picked (the bundled sets' provenance.json), and
// the CLI validates against it; no matching set, or a declaration that contradicts the model
// options, is one line and exit status 2. The reference values are the bundled golden rows
// (another pendulum's set, certified by two precisions), not this code's output.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/validation/candidate_pendulum.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

const fs::path golden = fs::path(FLIPFLUX_SOURCE_DIR) / "data/golden";

class CandidatePendulum : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("cand_pendulum_" + std::to_string(getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir_ / name) << text;
        return (dir_ / name).string();
    }
    fs::path dir_;
};

// A golden row of a set, as "energy" and "value" (the test's reference).
std::pair<std::string, std::string> golden_row(const fs::path& file, const std::string& prefix) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) {
            const std::size_t e = prefix.size(), v = line.find(',', e);
            return {line.substr(e, v - e), line.substr(v + 1, line.find(',', v + 1) - v - 1)};
        }
    ADD_FAILURE() << "no row " << prefix << " in " << file;
    return {};
}

TEST_F(CandidatePendulum, DeclarationIsParsedBeforeTheHeaderOnly) {
    const auto d = read_declared_pendulum(
        write("a.csv",
              "\xEF\xBB\xBF# a comment\n# pendulum: m2=3, L2=0.70\n#pendulum: g=9.81 m1=1\n"
              "quantity,arm,energy,value\n# pendulum: m2=5\n"));
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(d->where, (dir_ / "a.csv").string() + ":2");
    EXPECT_EQ(d->parameters.m2, "3");
    EXPECT_EQ(d->parameters.L2, "0.70");
    EXPECT_EQ(d->parameters.g, "9.81");
    EXPECT_TRUE(d->parameters.a2.empty());  // not given: the link's length
    EXPECT_FALSE(read_declared_pendulum(write("b.csv", "quantity,arm,energy,value\n")));
}

TEST_F(CandidatePendulum, MalformedDeclarationsAreRefusedByLine) {
    const auto refused = [&](const std::string& line, const std::string& part) {
        const std::string f = write("bad.csv", "#\n" + line + "\nquantity,arm,energy,value\n");
        try {
            (void)read_declared_pendulum(f);
            ADD_FAILURE() << "accepted: " << line;
        } catch (const input_error& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(f + ":2: pendulum: ", 0), 0u) << what;
            EXPECT_NE(what.find(part), std::string::npos) << what;
        }
    };
    refused("# pendulum: m3=1", "'m3' is not a parameter");
    refused("# pendulum: m2=nan", "m2: 'nan' is not a finite decimal number");
    refused("# pendulum: m2=0x3", "'0x3'");
    refused("# pendulum: m2=3 m2=3", "m2 is given twice");
    refused("# pendulum: m2 3", "'m2' is not KEY=VALUE");
    refused("# pendulum: m2=", "m2: '' is not");
    refused("# pendulum:", "no parameters");
}

TEST_F(CandidatePendulum, ParametersCompareAsNumbersWithTheDefaultsResolved) {
    model_text a, b;
    a.m2 = "3";
    b.m2 = "3.000";
    b.a2 = "1";  // = L2: the point-mass default
    EXPECT_TRUE(same_parameters(a, b));
    b.m2 = "3.0000000000000000000000000000001";  // beyond double and quad: still another pendulum
    EXPECT_FALSE(same_parameters(a, b));
    EXPECT_EQ(parameters_text(a), "m1=1 m2=3 L1=1 L2=1 a1=1 a2=1 I1=0 I2=0 g=1");
}

TEST_F(CandidatePendulum, TheGoldenSetWithTheDeclaredParametersIsPicked) {
    model_text p;
    p.m2 = "3.0";
    p.L2 = "0.7";
    p.g = "9.81";
    const golden_set s = golden_set_for(golden, p, "c.csv:1");
    EXPECT_EQ(s.name, "unequal-point-masses");
    EXPECT_EQ(s.dir, golden / "unequal-point-masses");
    EXPECT_EQ(golden_set_for(golden, model_text{}, "x").name, "egalitarian");
    EXPECT_EQ(golden_set_for(golden, model_text{}, "x").dir, golden);
    p.g = "9.8";
    try {
        (void)golden_set_for(golden, p, "c.csv:1");
        ADD_FAILURE() << "a pendulum without a set was matched";
    } catch (const input_error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("c.csv:1: the pendulum m1=1 m2=3.0 L1=1 L2=0.7 a1=1 a2=0.7 I1=0 I2=0 "
                             "g=9.8 has no golden set under",
                             0),
                  0u)
            << what;
        EXPECT_NE(what.find("unequal-point-masses (m1=1 m2=3 "), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
}

// The CLI: a correct value of the unequal pendulum passes against its set, picked by the header;
// the same file without the header is unmatched (not compared) against the paper's set; a wrong
// value fails; a declaration without a set, or against --pendulum or the model options, is
// refused with one line.
TEST_F(CandidatePendulum, ValidatePicksTheSetOfTheCandidatesPendulum) {
    const auto [energy, value] =
        golden_row(golden / "unequal-point-masses/golden.csv", "rate-upright,2,");
    const std::string row = "rate-upright,2," + energy + "," + value + "\n";
    const std::string head = "# pendulum: m1=1 m2=3 L1=1 L2=0.7 g=9.81\n";
    const std::string g = " --golden " + golden.string() + " --allow-missing";
    const std::string good = write("good.csv", head + "quantity,arm,energy,value\n" + row);
    const auto ok = run_flipflux("validate " + good + g);
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_NE(ok.out.find("1 ok"), std::string::npos) << ok.out;
    EXPECT_NE(ok.err.find("golden set 'unequal-point-masses'"), std::string::npos) << ok.err;
    EXPECT_EQ(run_flipflux("validate " + good + g + " --pendulum unequal-point-masses").status, 0);
    EXPECT_EQ(run_flipflux("validate " + good + g + " --m2 3 --L2 0.7 --g 9.81").status, 0);

    const std::string bare = write("bare.csv", "quantity,arm,energy,value\n" + row);
    const auto paper = run_flipflux("validate " + bare + g + " --require-all");
    EXPECT_EQ(paper.status, 1) << paper.out;  // the paper's set has no row at that energy
    EXPECT_NE(paper.out.find("1 unmatched"), std::string::npos) << paper.out;
    // the model options pick the set as a header does
    EXPECT_EQ(run_flipflux("validate " + bare + g + " --m2 3 --L2 0.7 --g 9.81").status, 0);

    // its 10th significant digit changed: wrong by ~1e-9 relative whatever digits the set holds
    std::string wrong_value = value;
    for (std::size_t i = 0, significant = 0; i < wrong_value.size(); ++i) {
        const char c = wrong_value[i];
        if (c < '0' || c > '9' || (significant == 0 && c == '0')) continue;
        if (++significant == 10) {
            wrong_value[i] = static_cast<char>('0' + (c - '0' + 5) % 10);
            break;
        }
    }
    ASSERT_NE(wrong_value, value);
    const std::string bad =
        write("bad.csv", head + "quantity,arm,energy,value\n" + "rate-upright,2," + energy + "," +
                             wrong_value + "\n");
    EXPECT_EQ(run_flipflux("validate " + bad + g + " --rtol 1e-14").status, 1);

    const auto refused = [&](const std::string& args, const std::string& part) {
        const auto r = run_flipflux(args);
        EXPECT_EQ(r.status, 2) << args << "\n" << r.out;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
    };
    const std::string none =
        write("none.csv", "# pendulum: m2=2\nquantity,arm,energy,value\n" + row);
    refused("validate " + none + g, none + ":1: the pendulum m1=1 m2=2 ");
    refused("validate " + good + g + " --pendulum light-upper-arm",
            "--pendulum: 'light-upper-arm' is not the set of the pendulum of " + good + ":1");
    refused("validate " + good + g + " --m2 2", good + ":1: pendulum: m1=1 m2=3 ");
    refused("validate " + good + g + " --m2 x", "--m2: 'x'");
}

// validate --ensemble: the rates are predicted for the pendulum the candidate declares. A count
// equal to the unequal pendulum's golden rate (to rounding) passes; the same count judged for the
// paper's pendulum (no header) fails. flips_sq is given, so no pilot ensemble runs.
TEST_F(CandidatePendulum, EnsembleRatesArePredictedForTheDeclaredPendulum) {
    const auto [energy, value] =
        golden_row(golden / "unequal-point-masses/golden.csv", "rate-upright,2,");
    const double rate = std::stod(value), M = 1000, tau = 10;
    const double n = std::round(rate * M * tau), v = std::max(n / M, 1.0);  // Var N per trajectory
    const std::string row = "upright,2," + energy + ",1000,10," + std::to_string(long(n)) + "," +
                            std::to_string(long(std::ceil(n * n / M + (M - 1) * v))) + "\n";
    const std::string cols = "criterion,arm,energy,trajectories,time,flips,flips_sq\n";
    const std::string good = write("ens.csv", "# pendulum: m2=3 L2=0.7 g=9.81\n" + cols + row);
    const auto r = run_flipflux("validate --ensemble " + good);
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("1 pass"), std::string::npos) << r.out;
    const auto paper = run_flipflux("validate --ensemble " + write("ens0.csv", cols + row));
    EXPECT_EQ(paper.status, 1) << paper.out;
    const auto bad = run_flipflux("validate --ensemble " +
                                  write("ens1.csv", "# pendulum: m2=-3\n" + cols + row));
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("ens1.csv:1: pendulum: m2: '-3' is invalid"), std::string::npos)
        << bad.err;
}

}  // namespace
}  // namespace flipflux::test
