// The reference trajectories of data/golden/trajectories/ (tools/golden_trajectories.py: mp:50
// against mp:70 over T = 40, certified digits per row): well formed (every state listed, digits
// >= 30, events in time order), and a sample regenerated in quad by the reference route over
// T = 10 -- the grazing state s02 (two crossings 5.5e-4 apart) and the chaotic state s05 --
// has the same events (arm, criterion, direction) with times, and the state at t = 10, within
// quad's epsilon times the growth bound e^(lambda T) of errors (lambda <= 1.4, the largest
// finite-time exponent seen: ReferenceRouteAgreesAcrossPrecisions) times 1e3.
#include <cmath>
#include <map>

#include "flipflux/core/decimal.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/study/trajectory.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

const std::string dir = std::string(FLIPFLUX_SOURCE_DIR) + "/data/golden/trajectories/";

int col(const csv_table& t, const std::string& name) {
    for (std::size_t i = 0; i < t.header.size(); ++i)
        if (t.header[i] == name) return static_cast<int>(i);
    ADD_FAILURE() << "no column " << name;
    return 0;
}

TEST(GoldenTrajectories, AreWellFormedAndCertified) {
    const csv_table states = read_csv(dir + "initial_states.csv");
    const csv_table events = read_csv(dir + "events.csv");
    const csv_table samples = read_csv(dir + "states.csv");
    std::map<std::string, double> last;  // state -> last event time
    std::map<std::string, int> per_state;
    const int s = col(events, "state"), t = col(events, "time"), d = col(events, "digits"),
              a = col(events, "arm"), c = col(events, "criterion");
    int arm1 = 0;
    double grazing_gap = 1;  // s02: the closest pair of arm-2 upright flips
    double previous_upright = -1;
    for (const csv_row& r : events.rows) {
        const double time = parse_real<double>(r.fields[t], "time");
        EXPECT_GE(time, last[r.fields[s]]) << "line " << r.line;
        arm1 += r.fields[a] == "1";
        if (r.fields[s] == "s02" && r.fields[a] == "2" && r.fields[c] == "upright") {
            if (previous_upright >= 0) grazing_gap = std::min(grazing_gap, time - previous_upright);
            previous_upright = time;
        }
        last[r.fields[s]] = time;
        ++per_state[r.fields[s]];
        EXPECT_GE(std::atoi(r.fields[d].c_str()), 30) << "line " << r.line;
    }
    const int sd = col(samples, "digits"), ss = col(samples, "state");
    std::map<std::string, int> sampled;
    for (const csv_row& r : samples.rows) {
        EXPECT_GE(std::atoi(r.fields[sd].c_str()), 30) << "states.csv line " << r.line;
        ++sampled[r.fields[ss]];
    }
    EXPECT_GT(arm1, 10);           // both arms flip
    EXPECT_LT(grazing_gap, 1e-3);  // the grazing flip: two crossings 5.5e-4 apart
    EXPECT_GE(states.rows.size(), 12u);
    for (const csv_row& r : states.rows) {  // every state: t = 10, 20, 40 and some flips
        EXPECT_EQ(sampled[r.fields[0]], 3) << r.fields[0];
        EXPECT_GE(per_state[r.fields[0]], 2) << r.fields[0];
    }
}

void regenerate_in_quad(const std::string& name) {
    const csv_table states = read_csv(dir + "initial_states.csv");
    const csv_table events = read_csv(dir + "events.csv");
    const csv_table samples = read_csv(dir + "states.csv");
    trajectory_request<quad> q;
    bool found = false;
    for (const csv_row& r : states.rows) {
        if (r.fields[0] != name) continue;
        found = true;
        for (std::size_t i = 0; i < 4; ++i)
            q.state[i] = parse_real<quad>(r.fields[i + 1], "state");
    }
    ASSERT_TRUE(found) << name;
    const quad T = 10;
    q.time = T;
    q.criteria = {"upright", "approx"};
    q.arms = {arm::one, arm::two};
    q.sample_interval = T;
    const trajectory_record<quad> r = reference_trajectory(double_pendulum<quad>(), q);
    const double tol = 1e3 * static_cast<double>(std::numeric_limits<quad>::epsilon()) *
                       std::exp(1.4 * static_cast<double>(T)) * 40;  // |x| <= 40
    const int s = col(events, "state"), t = col(events, "time"), a = col(events, "arm"),
              c = col(events, "criterion"), d = col(events, "direction");
    std::size_t k = 0;
    double worst = 0;
    for (const csv_row& row : events.rows) {
        if (row.fields[s] != name || parse_real<double>(row.fields[t], "t") > 10) continue;
        ASSERT_LT(k, r.events.size()) << name << ": quad has fewer events";
        const flip_event<quad>& e = r.events[k++];
        EXPECT_EQ(to_string(e.flip_arm), row.fields[a]) << name << " line " << row.line;
        EXPECT_EQ(e.criterion, row.fields[c]) << name << " line " << row.line;
        EXPECT_EQ(e.direction, std::stoi(row.fields[d])) << name << " line " << row.line;
        const double err = static_cast<double>(abs(e.time - parse_real<quad>(row.fields[t], "t")));
        worst = std::max(worst, err);
        EXPECT_LE(err, tol) << name << " line " << row.line;
    }
    EXPECT_EQ(k, r.events.size()) << name << ": quad has more events before t = 10";
    const int st = col(samples, "state"), tt = col(samples, "t");
    for (const csv_row& row : samples.rows) {
        if (row.fields[st] != name || row.fields[tt] != "10") continue;
        const auto& x = r.states.back();
        for (std::size_t i = 0; i < 4; ++i) {
            const double err =
                static_cast<double>(abs(x[i + 1] - parse_real<quad>(row.fields[i + 2], "x")));
            worst = std::max(worst, err);
            EXPECT_LE(err, tol) << name << " component " << i;
        }
    }
    std::printf(
        "%s: %zu events to t = 10 and the state at t = 10 in quad: worst |error| %.3g "
        "(tolerance %.3g)\n",
        name.c_str(), k, worst, tol);
}

TEST(GoldenTrajectories, GrazingStateRegeneratedInQuad) {
    regenerate_in_quad("s02");
}
TEST(GoldenTrajectories, ChaoticStateRegeneratedInQuad) {
    regenerate_in_quad("s05");
}

}  // namespace
}  // namespace flipflux::test
