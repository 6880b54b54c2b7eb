// A simulator's trajectory against reference events and states (validation/trajectory_check.hpp):
// what is compared is inferred from the files and said; the double horizon tells a bug from chaos.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "flipflux/core/error.hpp"
#include "flipflux/validation/trajectory_check.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

class TrajectoryCheck : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("trajcheck_" + std::to_string(getpid()));
        fs::create_directories(dir_ / "golden");
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& text) {
        std::ofstream(dir_ / name) << text;
        return dir_ / name;
    }
    /// A golden-like folder: two states over T = 10, their states at 5 and 10, double horizons.
    fs::path golden() {
        write("golden/provenance.json", R"({"time": "10", "states": ["a", "b"]})");
        write("golden/states.csv",
              "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1\n"
              "state,t,theta1,theta2,l1,l2,digits\n"
              "a,5,0.1,3.2,-0.5,0.25,50\n"
              "a,10,-0.2,9.5,0.5,-0.25,50\n");
        write("golden/double_horizons.csv",
              "# generated\n"
              "state,time_tolerance,accuracy,horizon,parted_by\n"
              "a,1e-6,rtol-1e-12,10,\n"
              "a,1e-6,limit,10,\n"
              "a,1e-9,rtol-1e-12,6,dop853-1e-12\n"
              "a,1e-9,limit,8,taylor\n");
        return write("golden/events.csv",
                     "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1\n"
                     "state,time,arm,criterion,direction,digits\n"
                     "a,1.00000000000000000000000001,2,upright,1,50\n"
                     "a,1.5,2,approx,1,50\n"
                     "a,4.0,2,upright,-1,50\n"
                     "a,7.0,2,upright,1,50\n"
                     "a,9.0,1,upright,1,50\n"
                     "b,2.0,2,upright,1,50\n");
    }
    fs::path dir_;
};

// An upright-only simulator writes no criterion column, NumPy's 1.0 / -1.0 and 2.0, any case;
// only upright is compared, and it says so.
TEST_F(TrajectoryCheck, AnUprightOnlyCandidateIsComparedOnItsCriterion) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "a";
    const auto c = compare_flip_events(
        write("c.csv", "time,arm,direction\n1.0,2.0,1.0\n4.0,2,-1.0\n7.0,2,+1\n9.0,1,1\n"), ref, o);
    EXPECT_FALSE(c.differs) << format_event_comparison(c, o);
    ASSERT_EQ(c.criteria, std::vector<std::string>{"upright"});
    EXPECT_TRUE(c.criteria_inferred);
    const auto u = compare_flip_events(
        write("u.csv",
              "time,arm,criterion,direction\n1.0,2,UPRIGHT,1\n4.0,2,Upright,-1\n"
              "7.0,2,upright,1\n9.0,1,upright,1\n"),
        ref, o);
    EXPECT_FALSE(u.differs) << format_event_comparison(u, o);
    // insisting on approx finds the missing stream
    o.criteria = {"upright", "approx"};
    const auto a = compare_flip_events(dir_ / "c.csv", ref, o);
    ASSERT_TRUE(a.differs);
    EXPECT_NE(a.first_difference.find("arm 2 approx event 1: candidate none"), std::string::npos)
        << a.first_difference;
    // a direction that is not +-1, or a fractional arm, is an input error naming the line
    o.criteria.clear();
    for (const std::string row : {"1.0,2,0.5", "1.0,2.5,1", "1.0,2,x"})
        EXPECT_THROW(
            compare_flip_events(write("bad.csv", "time,arm,direction\n" + row + "\n"), ref, o),
            input_error)
            << row;
}

// The golden trajectories end at T = 10 (provenance.json): a longer candidate's later events are
// not compared; with a shorter candidate's states the horizon is its end.
TEST_F(TrajectoryCheck, TheCommonHorizonIsInferredAndSaid) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "a";
    const std::string events = "time,arm,direction\n1.0,2,1\n4.0,2,-1\n7.0,2,1\n9.0,1,1\n";
    const auto c = compare_flip_events(write("c.csv", events + "11.5,2,1\n12,1,-1\n"), ref, o);
    EXPECT_FALSE(c.differs) << format_event_comparison(c, o);
    EXPECT_EQ(c.horizon, 10);
    EXPECT_NE(c.horizon_note.find("common horizon"), std::string::npos) << c.horizon_note;
    // a candidate that stopped at t = 5 (its states say so) is not blamed for the later events
    o.candidate_states = write("s.csv", "t,theta1,theta2,l1,l2\n0,0,0,0,0\n5,0.1,3.2,-0.5,0.25\n");
    const auto s =
        compare_flip_events(write("short.csv", "time,arm,direction\n1.0,2,1\n4.0,2,-1\n"), ref, o);
    EXPECT_FALSE(s.differs) << format_event_comparison(s, o);
    EXPECT_EQ(s.horizon, 5);
    ASSERT_EQ(s.states.size(), 1u);
    EXPECT_TRUE(s.states[0].agrees);
    // without any end known, every event is compared
    event_comparison_options bare;
    const auto b = compare_flip_events(write("b.csv", "time,arm,direction\n0.5,2,1\n"),
                                       write("r.csv",
                                             "time,arm,criterion,direction\n"
                                             "0.5,2,upright,1\n3,2,upright,1\n"),
                                       bare);
    EXPECT_TRUE(b.differs);
    EXPECT_TRUE(std::isinf(b.horizon));
}

// No agreeing event: the max |dt| column says "-", never 0.000e+00.
TEST_F(TrajectoryCheck, NoMaxTimeDifferenceOverZeroAgreeingEvents) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "b";
    const auto c = compare_flip_events(write("c.csv", "time,arm,direction\n2.5,2,1\n"), ref, o);
    ASSERT_TRUE(c.differs);
    const std::string text = format_event_comparison(c, o);
    EXPECT_EQ(text.find("0.000e+00"), std::string::npos) << text;
    EXPECT_NE(text.find("upright   1          1          0         -"), std::string::npos) << text;
}

// At time tolerance 1e-9 the double horizon of state a is 6: a double-precision candidate is
// compared before it by default; a difference after it (with --until) is chaos, before it a bug.
// A candidate with more than 17 digits is compared over the whole common horizon.
TEST_F(TrajectoryCheck, TheDoubleHorizonTellsABugFromChaos) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "a";
    o.time_tolerance = 1e-9;
    const auto late = write("late.csv",
                            "time,arm,direction\n1.0,2,1\n4.0,2,-1\n7.001,2,1\n"
                            "9.0,1,1\n");
    const auto c = compare_flip_events(late, ref, o);
    EXPECT_FALSE(c.differs) << format_event_comparison(c, o);
    EXPECT_EQ(c.horizon, 6);
    EXPECT_TRUE(c.candidate_double);
    EXPECT_NE(c.horizon_note.find("double horizon"), std::string::npos) << c.horizon_note;
    o.until = 10;
    const auto chaos = compare_flip_events(late, ref, o);
    ASSERT_TRUE(chaos.differs);
    EXPECT_NE(chaos.verdict.find("after the double horizon t = 6"), std::string::npos)
        << chaos.verdict;
    EXPECT_NE(chaos.verdict.find("8 at the double limit"), std::string::npos) << chaos.verdict;
    o.until = 0;
    const auto bug = compare_flip_events(
        write("bug.csv", "time,arm,direction\n1.0,2,1\n4.001,2,-1\n7.0,2,1\n9.0,1,1\n"), ref, o);
    ASSERT_TRUE(bug.differs);
    EXPECT_NE(bug.verdict.find("a bug, not chaos"), std::string::npos) << bug.verdict;
    // 1e-8 lies between the tabulated 1e-9 and 1e-6: the horizon of 1e-9 (the tolerance below)
    o.time_tolerance = 1e-8;
    EXPECT_EQ(compare_flip_events(late, ref, o).horizon, 6);
    // quad digits: the whole common horizon, and the difference at 7 is found
    o.time_tolerance = 1e-9;
    const auto quad = compare_flip_events(
        write("quad.csv",
              "time,arm,direction\n1.000000000000000000000000010,2,1\n4.0,2,-1\n"
              "7.001,2,1\n9.0,1,1\n"),
        ref, o);
    EXPECT_FALSE(quad.candidate_double);
    EXPECT_TRUE(quad.differs);
    EXPECT_EQ(quad.horizon, 10);
}

// States: compared at the reference's sample times before the horizon; wrapped angles agree; a
// state off by more than the tolerance is the first difference when it is the earliest.
TEST_F(TrajectoryCheck, FinalStatesAreCompared) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "a";
    const auto events = write("c.csv", "time,arm,direction\n1.0,2,1\n4.0,2,-1\n7.0,2,1\n9.0,1,1\n");
    // theta2 wrapped by -2 pi at t = 5 and by -4 pi at t = 10
    o.candidate_states = write("s.csv",
                               "t,theta1,theta2,l1,l2\n"
                               "5,0.1,-3.0831853071795865,-0.5,0.25\n"
                               "10,-0.2,-3.0663706143591725,0.5,-0.25\n");
    const auto c = compare_flip_events(events, ref, o);
    EXPECT_FALSE(c.differs) << format_event_comparison(c, o);
    ASSERT_EQ(c.states.size(), 2u);
    EXPECT_LT(c.states[1].max_difference, 1e-12);
    o.candidate_states = write("bad.csv",
                               "t,theta1,theta2,l1,l2\n"
                               "5,0.1,3.2,-0.5,0.25001\n"
                               "10,-0.2,9.5,0.5,-0.25\n");
    const auto b = compare_flip_events(events, ref, o);
    ASSERT_TRUE(b.differs);
    EXPECT_NE(b.first_difference.find("state at t = 5"), std::string::npos) << b.first_difference;
    EXPECT_NE(b.first_difference.find("l2 differs by 1.000e-05"), std::string::npos)
        << b.first_difference;
    // a states file without the columns is refused naming the file
    o.candidate_states = write("cols.csv", "t,x\n1,2\n");
    EXPECT_THROW(compare_flip_events(events, ref, o), input_error);
}

// Issue 44's review: below every tabulated tolerance no double horizon is known (none is used);
// with states compared at a tighter tolerance the horizon is that tolerance's; a candidate with
// no criterion column and no event is compared on upright; a pair that agrees across the horizon
// is counted on both sides.
TEST_F(TrajectoryCheck, ReviewFindingsStayFixed) {
    const fs::path ref = golden();
    event_comparison_options o;
    o.state = "a";
    o.time_tolerance = 1e-12;  // the table has 1e-9 and 1e-6 only
    const auto events = write("c.csv", "time,arm,direction\n1.0,2,1\n4.0,2,-1\n7.0,2,1\n9.0,1,1\n");
    const auto below = compare_flip_events(events, ref, o);
    EXPECT_TRUE(std::isnan(below.double_horizon));
    EXPECT_EQ(below.horizon, 10);
    EXPECT_NE(below.horizon_note.find("no double horizon"), std::string::npos)
        << below.horizon_note;
    o.time_tolerance = 1e-6;  // horizon 10; states at 1e-9: horizon 6
    o.state_tolerance = 1e-9;
    o.candidate_states = write("s.csv",
                               "t,theta1,theta2,l1,l2\n5,0.1,3.2,-0.5,0.25\n"
                               "10,-0.2,9.5,0.5,-0.25\n");
    EXPECT_EQ(compare_flip_events(events, ref, o).double_horizon, 6);
    o.candidate_states.clear();
    o.state_tolerance = 0;
    const auto empty = compare_flip_events(write("e.csv", "time,arm,direction\n"), ref, o);
    EXPECT_EQ(empty.criteria, std::vector<std::string>{"upright"});
    // the reference's event 4 at t = 7 lies before a horizon of 7.0000005 (--until); the
    // candidate's partner at 7.0000008 after it: compared, agreeing, and counted
    o.until = 7.0000005;
    const auto edge = compare_flip_events(
        write("edge.csv", "time,arm,direction\n1.0,2,1\n4.0,2,-1\n7.0000008,2,1\n"), ref, o);
    EXPECT_FALSE(edge.differs) << format_event_comparison(edge, o);
    for (const auto& st : edge.streams)
        if (st.criterion == "upright" && st.arm == "2") {
            EXPECT_EQ(st.candidate, 3u);
            EXPECT_EQ(st.reference, 3u);
            EXPECT_EQ(st.agreeing, 3u);
        }
}

// On the real golden data: flipflux's own double run of the chaotic state s05 (DOP853, rtol
// 1e-13, a run not among those that measured the horizons) over T = 40 is a correct
// double-precision simulator. At time tolerance 1e-9 it agrees up to the double horizon (the
// default), and differs after it, which the verdict calls chaos.
TEST(TrajectoryCheckGolden, ACorrectDoubleRunOfAChaoticStateIsNotCalledABug) {
    const fs::path dir = fs::path(::testing::TempDir()) / ("s05_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string golden = std::string(FLIPFLUX_SOURCE_DIR) + "/data/golden/trajectories/";
    const auto run = run_flipflux(
        "trajectory --state 1.0,2.0,0.0,1.581582 --time 40 --rtol 1e-13 "
        "--events " +
        (dir / "ev.csv").string() + " --out " + (dir / "st.csv").string() +
        " --sample-interval 10");
    ASSERT_EQ(run.status, 0) << run.err;
    const std::string validate = "validate --trajectories " + (dir / "ev.csv").string() +
                                 " --states " + (dir / "st.csv").string() + " --reference " +
                                 golden + "events.csv --state s05 --time-tol 1e-9";
    const auto ok = run_flipflux(validate);
    EXPECT_EQ(ok.status, 0) << ok.out << ok.err;
    EXPECT_NE(ok.out.find("the double horizon of s05"), std::string::npos) << ok.out;
    const auto strict = run_flipflux(validate + " --until 40.5");
    EXPECT_EQ(strict.status, 1) << strict.out << strict.err;
    EXPECT_NE(strict.out.find("what chaos does"), std::string::npos) << strict.out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace flipflux::test
