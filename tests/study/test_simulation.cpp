// The study driver behind `flipflux simulate` and scenes (study/simulation.hpp), called
// directly: energy and criterion lists, refusal of incomplete requests, and a report whose
// statistics are consistent with the per-trajectory results it was built from.
#include <cmath>
#include <filesystem>

#include "flipflux/core/error.hpp"
#include "flipflux/study/settings.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

TEST(Simulation, ParsesEnergyAndCriterionLists) {
    const auto e = parse_energy_list("2.5,3:3.2:0.1,4");
    ASSERT_EQ(e.size(), 5u);
    EXPECT_EQ(e[0].first, "2.5");
    EXPECT_EQ(e[1].first, "3");
    EXPECT_EQ(e[2].first, "3.1");
    EXPECT_EQ(e[3].first, "3.2");
    EXPECT_DOUBLE_EQ(e[3].second, 3.2);
    EXPECT_EQ(e[4].first, "4");
    EXPECT_THROW(parse_energy_list("3:2:0.1"), input_error);
    EXPECT_THROW(parse_energy_list("3:4"), input_error);
    EXPECT_THROW(parse_energy_list("1,,2"), input_error);
    EXPECT_THROW(parse_energy_list("0:1e6:1"), input_error);  // more than 1e5 values
    EXPECT_EQ(parse_criterion_list("saddle,upright"),
              (std::vector<std::string>{"saddle", "upright"}));
    EXPECT_THROW(parse_criterion_list("upright,"), input_error);
    EXPECT_THROW(parse_criterion_list("approx,approx", "criteria"), input_error);
}

TEST(Simulation, RefusesIncompleteRequests) {
    const double_pendulum<double> m;
    simulation_request q;
    q.options.trajectories = 2;
    q.options.time = 1;
    q.criteria = {"upright"};
    EXPECT_THROW(simulate(m, q), input_error);  // no energy
    q.energies = {{"5", 5.0}};
    q.criteria.clear();
    EXPECT_THROW(simulate(m, q), input_error);  // no criterion
    q.criteria = {"upright"};
    q.options.sample_interval = 0.5;
    EXPECT_THROW(simulate(m, q), input_error);  // samples need a directory
}

TEST(Simulation, ReportMatchesTheEnsemble) {
    const double_pendulum<double> m;
    simulation_request q;
    q.criteria = {"upright", "approx"};
    q.energies = {{"4.5", 4.5}};
    q.options.trajectories = 16;
    q.options.time = 20;
    q.options.seed = 4;
    q.options.rtol = 1e-8;
    q.options.threads = 2;
    const study_result result = *simulate(m, q);
    const auto j = study_json(result);
    ensemble_options o = q.options;
    o.energy = 4.5;
    const pendulum_flow flow(m);
    const ensemble_result r =
        run_ensemble(m, o,
                     {{"upright", make_flip_detector(upright_curve<double>{arm::two}, flow)},
                      {"approx", make_flip_detector(approximate_saddle_curve(m, arm::two), flow)}});
    for (std::size_t c = 0; c < 2; ++c) {
        std::uint64_t flips = 0;
        for (const auto& t : r.trajectories)
            flips += t.flips(c);
        const criterion_result& x = result.energies.at(0).criteria.at(c);
        EXPECT_EQ(x.statistics.criterion, q.criteria[c]);
        EXPECT_EQ(x.statistics.flips, flips);
        EXPECT_NEAR(x.statistics.rates.mean, flips / (16.0 * 20), 1e-15);
        ASSERT_TRUE(x.prediction.has_value());
        EXPECT_EQ(x.statistics.predicted_rate, x.prediction->value);
        // the JSON report carries the same numbers as decimal strings
        const auto& s = j["energies"][0]["criteria"][q.criteria[c]];
        EXPECT_EQ(s["flips"].get<std::uint64_t>(), flips);
        EXPECT_EQ(std::stod(s["mean_rate"].get<std::string>()), x.statistics.rates.mean);
        EXPECT_EQ(s["prediction_method"].get<std::string>(), x.prediction->method);
    }
    // the paired difference upright - approx, trajectory by trajectory
    ASSERT_EQ(result.energies[0].paired.size(), 1u);
    std::vector<double> d;
    for (const auto& t : r.trajectories)
        d.push_back((static_cast<double>(t.flips(0)) - static_cast<double>(t.flips(1))) / 20);
    double mean = 0;
    for (double x : d)
        mean += x / static_cast<double>(d.size());
    EXPECT_NEAR(result.energies[0].paired[0].difference.mean, mean, 1e-15);
    EXPECT_EQ(result.energies[0].paired[0].difference.count, 16u);
    // agreement over the one energy: chi2 = z^2
    for (std::size_t c = 0; c < 2; ++c) {
        const criterion_statistics& st = result.energies[0].criteria[c].statistics;
        const criterion_agreement& a = result.agreement.at(c).all_trajectories;
        EXPECT_EQ(a.energies, 1u);
        EXPECT_NEAR(a.chi2, st.z_score * st.z_score, 1e-12 * (1 + a.chi2));
        EXPECT_NEAR(a.worst_z, st.z_score, 1e-12 * (1 + std::abs(st.z_score)));
    }
    ASSERT_EQ(result.prediction_differences.size(), 1u);
    const double pu = result.energies[0].criteria[0].prediction->value,
                 pa = result.energies[0].criteria[1].prediction->value;
    EXPECT_NEAR(result.prediction_differences[0].rms_relative, std::abs(pu / pa - 1), 1e-15);
    ASSERT_EQ(result.quality.size(), 2u);
    EXPECT_EQ(result.quality[0].all_trajectories.at(0).regime, "full");
    EXPECT_EQ(j["quality"]["upright"]["all_trajectories"][0]["regime"], "full");
}

// Replicates (issue 41): replicate k is the study of the k-th index block run on its own (an
// independent route: separate simulate() calls with first_index), the pooled statistics are the
// unreplicated study's of all R N trajectories bit for bit, and a checkpointed run resumed after
// one energy gives the same replicate statistics.
TEST(Simulation, ReplicatesAreIndexBlocksAndPoolToTheWholeEnsemble) {
    const double_pendulum<double> m;
    simulation_request q;
    q.criteria = {"upright", "saddle"};
    q.energies = {{"4.5", 4.5}, {"5", 5.0}};
    q.options.trajectories = 6;
    q.options.time = 30;
    q.options.seed = 9;
    q.options.threads = 2;
    q.timing = false;
    simulation_request whole = q;
    whole.options.trajectories = 18;
    q.replicates = 3;
    const study_result r = *simulate(m, q), w = *simulate(m, whole);
    EXPECT_EQ(r.options.trajectories, 18u);
    for (std::size_t k = 0; k < 2; ++k)
        for (std::size_t c = 0; c < 2; ++c) {
            const criterion_statistics &x = r.energies[k].criteria[c].statistics,
                                       &y = w.energies[k].criteria[c].statistics;
            EXPECT_EQ(x.rates.mean, y.rates.mean);
            EXPECT_EQ(x.rates.standard_deviation, y.rates.standard_deviation);
            EXPECT_EQ(x.z_score, y.z_score);
            EXPECT_TRUE(y.replicate_rates.empty());
            ASSERT_EQ(x.replicate_rates.size(), 3u);
            for (std::size_t b = 0; b < 3; ++b) {
                simulation_request one = q;
                one.replicates = 1;
                one.options.first_index = 6 * b;
                one.energies = {q.energies[k]};
                one.criteria = {q.criteria[c]};
                const criterion_statistics z = simulate(m, one)->energies[0].criteria[0].statistics;
                EXPECT_EQ(x.replicate_rates[b].mean, z.rates.mean) << k << c << b;
                EXPECT_EQ(x.replicate_rates[b].count, z.rates.count);
                EXPECT_EQ(x.replicate_chaotic_rates[b].count, z.chaotic_rates.count);
            }
        }
    // the quality indices pooled are the whole ensemble's; their replicate errors exist
    const quality_indices &qa = r.quality[1].all_trajectories[0],
                          &qb = w.quality[1].all_trajectories[0];
    EXPECT_EQ(qa.iqi, qb.iqi);
    EXPECT_EQ(qa.pqi, qb.pqi);
    EXPECT_EQ(qa.iqi_replicates.size(), 3u);
    EXPECT_TRUE(std::isfinite(qa.iqi_replicate_se) && qa.iqi_replicate_se > 0);
    EXPECT_TRUE(std::isnan(qb.iqi_replicate_se));
    ASSERT_TRUE(r.agreement[1].all_trajectories.replicates.has_value());
    EXPECT_EQ(r.agreement[1].all_trajectories.replicates->chi2_of_replicates.size(), 3u);
    EXPECT_FALSE(w.agreement[1].all_trajectories.replicates.has_value());
    // JSON: pooled fields equal, the replicate block present only with replicates
    const auto jr = study_json(r), jw = study_json(w);
    EXPECT_EQ(jr["energies"][0]["criteria"]["saddle"]["mean_rate"],
              jw["energies"][0]["criteria"]["saddle"]["mean_rate"]);
    EXPECT_EQ(jr["replicates"]["count"], 3);
    EXPECT_FALSE(jw.contains("replicates"));
    // a checkpointed run, interrupted after its first energy (the checkpoint holds it complete),
    // resumes to the same replicate statistics
    const std::filesystem::path file =
        std::filesystem::path(::testing::TempDir()) / "flipflux_replicates.ckpt";
    std::filesystem::remove(file);
    simulation_request first = q;
    first.checkpoint = file;
    first.checkpoint_interval = 0;
    const study_result a = *simulate(m, first);
    const study_result b = *simulate(m, first);  // every energy read back from the checkpoint
    EXPECT_EQ(study_json(a).dump(), study_json(r).dump());
    EXPECT_EQ(study_json(b).dump(), study_json(r).dump());
    std::filesystem::remove(file);
    simulation_request bad = q;
    bad.replicates = 0;
    EXPECT_THROW(simulate(m, bad), input_error);
    bad.replicates = 1001;
    EXPECT_THROW(simulate(m, bad), input_error);
}

}  // namespace
}  // namespace flipflux::test
