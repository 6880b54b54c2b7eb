// Ensemble statistics (ensemble/statistics.hpp) on hand-made data with values worked out by
// hand: summaries, histograms, quantiles, residence times, chaotic sub-ensemble, IQI and PQI,
// and the paper's energy regimes.
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

#include "flipflux/ensemble/replicate_check.hpp"
#include "flipflux/ensemble/statistics.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

TEST(Statistics, Summary) {
    const std::vector<double> v{1, 2, 3, 4};
    const summary_statistics s = summarize(v);
    EXPECT_EQ(s.count, 4u);
    EXPECT_DOUBLE_EQ(s.mean, 2.5);
    EXPECT_DOUBLE_EQ(s.standard_deviation, std::sqrt(5.0 / 3));
    EXPECT_DOUBLE_EQ(s.standard_error, std::sqrt(5.0 / 3) / 2);
    EXPECT_EQ(s.minimum, 1);
    EXPECT_EQ(s.maximum, 4);
    const std::vector<double> one{7};
    // one value: the mean is that value, its spread undefined (regression: reported as 0)
    EXPECT_EQ(summarize(one).mean, 7);
    EXPECT_TRUE(std::isnan(summarize(one).standard_deviation));
    EXPECT_TRUE(std::isnan(summarize(one).standard_error));
    EXPECT_TRUE(std::isnan(summarize(std::vector<double>{}).mean));
    // the shape, by hand: {1, 2, 3, 4, 10} has mean 4, deviations -3 -2 -1 0 6, m2 = 50 / 5,
    // m3 = 180 / 5, m4 = 1394 / 5
    const std::vector<double> tail{1, 2, 3, 4, 10};
    EXPECT_NEAR(summarize(tail).skewness, 36 / std::pow(10.0, 1.5), 1e-14);
    EXPECT_NEAR(summarize(tail).kurtosis, 278.8 / 100, 1e-14);
    EXPECT_NEAR(summarize(v).kurtosis, (2 * 81.0 / 16 + 2 / 16.0) / 4 / (1.25 * 1.25), 1e-14);
    EXPECT_EQ(summarize(v).skewness, 0);
    // no spread, no shape
    EXPECT_TRUE(std::isnan(summarize(one).kurtosis));
    EXPECT_TRUE(std::isnan(summarize(std::vector<double>{2, 2, 2}).skewness));
    // identical values have exactly no spread: ten times 0.1 sum to 0.9999999999999999, whose
    // tenth is an ulp below 0.1 (regression: a spread of 1.5e-17, a zero-spread energy's
    // bootstrap IQI sd 2e-15 instead of 0)
    const summary_statistics same = summarize(std::vector<double>(10, 0.1));
    EXPECT_EQ(same.mean, 0.1);
    EXPECT_EQ(same.standard_deviation, 0);
    EXPECT_EQ(same.standard_error, 0);
    // a mean never leaves [min, max]
    const std::vector<double> close{0.1, 0.1, 0.1, std::nextafter(0.1, 1.0)};
    const summary_statistics c = summarize(close);
    EXPECT_GE(c.mean, c.minimum);
    EXPECT_LE(c.mean, c.maximum);
}

TEST(Statistics, HistogramsAndQuantiles) {
    const std::vector<double> v{-1, 0, 0.5, 0.99, 1, 2.5, 10};
    const histogram h = make_histogram(v, 3, 0, 3);
    EXPECT_EQ(h.counts, (std::vector<std::uint64_t>{3, 1, 1}));
    EXPECT_EQ(h.underflow, 1u);
    EXPECT_EQ(h.overflow, 1u);
    EXPECT_EQ(h.total(), v.size());
    EXPECT_DOUBLE_EQ(h.bin_width(), 1);
    EXPECT_THROW(make_histogram(v, 0, 0, 1), std::invalid_argument);
    EXPECT_THROW(make_histogram(v, 2, 1, 1), std::invalid_argument);
    const std::vector<double> w{0.0, 1.0, 4.0};
    const histogram a = auto_histogram(w);
    EXPECT_EQ(a.counts.size(), 10u);
    EXPECT_EQ(a.overflow, 0u);  // the maximum is inside
    EXPECT_EQ(a.counts.back(), 1u);
    EXPECT_EQ(auto_histogram(std::vector<double>(10000, 1.0)).counts.size(), 100u);
    EXPECT_DOUBLE_EQ(auto_histogram(std::vector<double>{}).upper, 1.0);
    EXPECT_DOUBLE_EQ(quantile({3, 1, 2, 4}, 0.5), 2.5);
    EXPECT_DOUBLE_EQ(quantile({3, 1, 2, 4}, 0), 1);
    EXPECT_DOUBLE_EQ(quantile({3, 1, 2, 4}, 1), 4);
    EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
}

TEST(Statistics, AnalyzeAnEnsemble) {
    ensemble_result r;
    r.time = 10;
    r.chaos = true;
    r.criteria = {"a", "b"};
    auto traj = [](std::vector<double> a, std::vector<double> b, bool chaotic) {
        trajectory_result t;
        t.crossing_times = {std::move(a), std::move(b)};
        t.lyapunov = chaotic ? 1 : -1;  // chaotic: above the threshold rate (0 here)
        return t;
    };
    r.trajectories.push_back(traj({1, 2, 4}, {}, true));    // rate 0.3, residences 1, 2
    r.trajectories.push_back(traj({5}, {3, 3.5}, false));   // rate 0.1
    r.trajectories.push_back(traj({0.5, 1.0}, {1}, true));  // rate 0.2, residence 0.5
    const criterion_statistics s = analyze(r, 0, 0.25);
    EXPECT_EQ(s.criterion, "a");
    EXPECT_EQ(s.flips, 6u);
    EXPECT_DOUBLE_EQ(s.rates.mean, 0.2);
    EXPECT_DOUBLE_EQ(s.rates.standard_deviation, 0.1);
    EXPECT_DOUBLE_EQ(s.z_score, (0.2 - 0.25) / (0.1 / std::sqrt(3.0)));
    EXPECT_EQ(s.chaotic, 2u);
    EXPECT_DOUBLE_EQ(s.chaotic_fraction, 2.0 / 3);
    EXPECT_DOUBLE_EQ(s.chaotic_rates.mean, 0.25);
    EXPECT_EQ(s.residence.summary.count, 3u);
    EXPECT_DOUBLE_EQ(s.residence.summary.minimum, 0.5);
    EXPECT_DOUBLE_EQ(s.residence.summary.maximum, 2);
    EXPECT_DOUBLE_EQ(s.residence.median, 1);
    EXPECT_EQ(s.residence.distribution.total(), 3u);
    EXPECT_EQ(s.rate_distribution.total(), 3u);
    const criterion_statistics b = analyze(r, 1, std::numeric_limits<double>::quiet_NaN(), 4, 5);
    EXPECT_TRUE(std::isnan(b.z_score));
    EXPECT_EQ(b.rate_distribution.counts.size(), 4u);
    EXPECT_EQ(b.residence.summary.count, 1u);
    EXPECT_THROW(analyze(r, 2, 0.1), std::out_of_range);
    r.chaos = false;
    EXPECT_TRUE(std::isnan(analyze(r, 0, 0.25).chaotic_fraction));
}

// Replicates (issue 41): merge() against summarize() of the union, the jackknife against the
// standard deviation of equal replicates' means over sqrt(R) (an identity for equal sizes) and
// against a leave-one-out computed by hand for unequal ones.
TEST(Statistics, ReplicatesMergeAndTheirJackknifeError) {
    std::mt19937_64 engine(7);
    std::exponential_distribution<double> law(3.0);
    std::vector<double> all;
    std::vector<summary_statistics> parts;
    for (int k = 0; k < 6; ++k) {
        std::vector<double> v;
        for (int i = 0; i < 40; ++i)
            v.push_back(law(engine));
        all.insert(all.end(), v.begin(), v.end());
        parts.push_back(summarize(v));
    }
    const summary_statistics whole = summarize(all), merged = merge(parts);
    EXPECT_EQ(merged.count, whole.count);
    EXPECT_NEAR(merged.mean, whole.mean, 1e-15 * whole.mean);
    EXPECT_NEAR(merged.standard_deviation, whole.standard_deviation,
                1e-13 * whole.standard_deviation);
    EXPECT_DOUBLE_EQ(merged.minimum, whole.minimum);
    EXPECT_DOUBLE_EQ(merged.maximum, whole.maximum);
    std::vector<double> means;
    for (const summary_statistics& p : parts)
        means.push_back(p.mean);
    const double expected = summarize(means).standard_deviation / std::sqrt(6.0);
    EXPECT_NEAR(replicate_standard_error(parts), expected, 1e-13 * expected);
    // unequal sizes: replicates {1, 2}, {4}, {6, 7, 8}: leave-one-out means 25/4, 24/5, 7/3
    const std::vector<summary_statistics> uneven{summarize(std::vector<double>{1, 2}),
                                                 summarize(std::vector<double>{4}),
                                                 summarize(std::vector<double>{6, 7, 8})};
    const std::vector<double> loo{25.0 / 4, 24.0 / 5, 7.0 / 3};
    const double m = (loo[0] + loo[1] + loo[2]) / 3;
    double ss = 0;
    for (double x : loo)
        ss += (x - m) * (x - m);
    EXPECT_NEAR(replicate_standard_error(uneven), std::sqrt(2.0 / 3 * ss), 1e-14);
    // an empty replicate is skipped; one replicate with values has no spread
    const std::vector<summary_statistics> one{summarize(std::vector<double>{1, 2}),
                                              summarize(std::vector<double>{})};
    EXPECT_TRUE(std::isnan(replicate_standard_error(one)));
    EXPECT_EQ(merge(one).count, 2u);
}

// analyze() with replicates: each block of trajectories summarised alone, the pooled statistics
// unchanged; a count that R does not divide is refused.
TEST(Statistics, AnalyzeSplitsReplicatesInIndexBlocks) {
    ensemble_result r;
    r.time = 10;
    r.chaos = true;
    r.criteria = {"a"};
    for (int i = 0; i < 6; ++i) {
        trajectory_result t;
        t.index = static_cast<std::uint64_t>(i);
        t.crossing_times = {std::vector<double>(static_cast<std::size_t>(i + 1), 1.0)};
        t.lyapunov = i % 2 == 0 ? 1 : -1;  // chaotic: above the threshold rate (0 here)
        r.trajectories.push_back(t);
    }
    const criterion_statistics one = analyze(r, 0, 0.3), three = analyze(r, 0, 0.3, 0, 0, 3);
    EXPECT_TRUE(one.replicate_rates.empty());
    EXPECT_EQ(three.rates.mean, one.rates.mean);
    EXPECT_EQ(three.z_score, one.z_score);
    ASSERT_EQ(three.replicate_rates.size(), 3u);
    EXPECT_DOUBLE_EQ(three.replicate_rates[0].mean, 0.15);  // rates 0.1, 0.2
    EXPECT_DOUBLE_EQ(three.replicate_rates[2].mean, 0.55);  // rates 0.5, 0.6
    EXPECT_EQ(three.replicate_chaotic_rates[1].count, 1u);  // index 2
    EXPECT_DOUBLE_EQ(three.replicate_chaotic_rates[1].mean, 0.3);
    EXPECT_THROW(analyze(r, 0, 0.3, 0, 0, 4), std::invalid_argument);
}

// Flip counts beyond the mean: exactly periodic flips have Fano factor 0 in windows holding a
// whole number of periods and CV^2 = 0; a Poisson process (exponential inter-flip times) has
// Fano ~ 1 = CV^2 within its sampling error; the tail P(tau > t) is exp(-t / mean) there.
TEST(Statistics, FanoFactorsAndInterFlipTails) {
    ensemble_result periodic;
    periodic.time = 1000;
    periodic.criteria = {"a"};
    trajectory_result t;
    t.crossing_times = {{}};
    for (int i = 0; i < 2000; ++i)
        t.crossing_times[0].push_back(0.25 + 0.5 * i);  // period 0.5
    periodic.trajectories = {t, t};
    const flip_count_statistics p = flip_counts(periodic, 0);
    ASSERT_EQ(p.fano.size(), 4u);  // windows 1000, 100, 10, 1
    for (const window_fano& f : p.fano) {
        EXPECT_NEAR(f.mean_count, f.window / 0.5, 1e-9 * f.window);
        EXPECT_NEAR(f.fano, 0, 1e-12);
        EXPECT_TRUE(std::isnan(f.fano_chaotic));  // no chaotic trajectory
    }
    EXPECT_EQ(p.fano[3].windows, 2000u);
    EXPECT_NEAR(p.cv2, 0, 1e-20);

    ensemble_result poisson;
    poisson.time = 20000;
    poisson.chaos = true;
    poisson.criteria = {"a"};
    std::mt19937_64 engine(11);
    std::exponential_distribution<double> law(2.0);  // rate 2, mean 0.5
    for (int k = 0; k < 4; ++k) {
        trajectory_result x;
        x.lyapunov = 1;  // chaotic: above the threshold rate (0 here)
        x.crossing_times = {{}};
        for (double s = law(engine); s < poisson.time; s += law(engine))
            x.crossing_times[0].push_back(s);
        poisson.trajectories.push_back(x);
    }
    const flip_count_statistics q = flip_counts(poisson, 0);
    // windows 20000 ... 2 (five at most); the Fano factor of 40,000 windows of mean count 2 has
    // a relative standard error ~ sqrt(2 / 40000 + ...) < 2 %
    ASSERT_EQ(q.fano.size(), 5u);
    EXPECT_NEAR(q.fano[4].fano, 1, 0.05);
    EXPECT_NEAR(q.fano[3].fano, 1, 0.1);
    EXPECT_EQ(q.fano[4].fano_chaotic, q.fano[4].fano);
    EXPECT_NEAR(q.cv2, 1, 0.03);
    ASSERT_EQ(q.survival.size(), 24u);
    for (const auto& pt : q.survival) {
        if (pt.survival > 1e-3) {
            EXPECT_NEAR(std::log(pt.survival), -2 * pt.time, 0.15 + 0.1 * 2 * pt.time)
                << "t = " << pt.time;
        }
    }
}

// Issue 20: with --rtol 1e-300 both trajectories failed and the mean rate was 0 (a failed
// trajectory's flips were averaged as zero flips over T). A failed trajectory is no data.
TEST(Statistics, FailedTrajectoriesAreNotCountedAsZeroFlips) {
    ensemble_result r;
    r.time = 10;
    r.chaos = true;
    r.criteria = {"a"};
    auto traj = [](std::vector<double> a, rk_status status) {
        trajectory_result t;
        t.crossing_times = {std::move(a)};
        t.status = status;
        t.lyapunov = 1;  // chaotic: above the threshold rate (0 here)
        return t;
    };
    r.trajectories.push_back(traj({1, 2, 4}, rk_status::ok));            // rate 0.3
    r.trajectories.push_back(traj({}, rk_status::step_size_underflow));  // stopped early
    r.trajectories.push_back(traj({0.5}, rk_status::ok));                // rate 0.1
    const criterion_statistics s = analyze(r, 0, 0.2);
    EXPECT_EQ(s.rates.count, 2u);
    EXPECT_DOUBLE_EQ(s.rates.mean, 0.2);
    EXPECT_EQ(s.flips, 4u);
    EXPECT_EQ(s.chaotic, 2u);
    EXPECT_DOUBLE_EQ(s.chaotic_fraction, 1.0);
    EXPECT_EQ(s.rate_distribution.total(), 2u);
    for (auto& t : r.trajectories)
        t.status = rk_status::step_size_underflow;
    const criterion_statistics none = analyze(r, 0, 0.2);
    EXPECT_EQ(none.rates.count, 0u);
    EXPECT_TRUE(std::isnan(none.rates.mean));  // no data, not a rate of 0
}

TEST(Statistics, QualityIndicesPerRegime) {
    const double_pendulum<double> m;
    const auto g2 = paper_regimes(m, arm::two);
    ASSERT_EQ(g2.size(), 5u);
    EXPECT_EQ(g2[0].name, "full");
    EXPECT_DOUBLE_EQ(g2[0].lower, 2);
    EXPECT_DOUBLE_EQ(g2[0].upper, 6);
    EXPECT_DOUBLE_EQ(g2[1].upper, 2.8);
    EXPECT_DOUBLE_EQ(g2[2].lower, 2.8);
    EXPECT_DOUBLE_EQ(g2[2].upper, 5);
    EXPECT_DOUBLE_EQ(g2[3].lower, 5);
    EXPECT_EQ(g2[4].name, "all");
    const auto g1 = paper_regimes(m, arm::one);
    ASSERT_EQ(g1.size(), 4u);
    EXPECT_DOUBLE_EQ(g1[0].lower, 4);
    EXPECT_DOUBLE_EQ(g1[1].upper, 4.6);
    // R = |sim/pred - 1|, S = spread/pred; IQI = rms R, PQI = rms sqrt(R^2 + S^2)
    const std::vector<quality_sample> samples{
        {2.5, 1.1, 1.0, 0.2},   // R = 0.1, S = 0.2 (low)
        {4.0, 0.97, 1.0, 0.1},  // R = 0.03, S = 0.1 (central)
        {5.5, 2.0, 2.0, 0.0},   // R = 0, S = 0 (high)
        {7.0, 1.0, 2.0, 0.0},   // outside the chaotic range: only in "all"
    };
    const auto q = quality(samples, g2);
    EXPECT_EQ(q[0].energies, 3u);
    // an energy with one trajectory (spread and standard error undefined, NaN) has no term
    std::vector<quality_sample> with_single = samples;
    const double undefined = std::numeric_limits<double>::quiet_NaN();
    with_single.push_back({3.0, 5.0, 1.0, undefined, undefined, 1});
    EXPECT_EQ(quality(with_single, g2)[0].energies, 3u);
    EXPECT_NEAR(quality(with_single, g2)[0].iqi, q[0].iqi, 1e-15);
    EXPECT_NEAR(q[0].iqi, std::sqrt((0.01 + 0.0009) / 3), 1e-15);
    EXPECT_NEAR(q[0].pqi, std::sqrt((0.01 + 0.04 + 0.0009 + 0.01) / 3), 1e-15);
    EXPECT_NEAR(q[1].iqi, 0.1, 1e-15);
    EXPECT_NEAR(q[2].pqi, std::sqrt(0.0009 + 0.01), 1e-15);
    EXPECT_EQ(q[3].iqi, 0);
    EXPECT_EQ(q[4].energies, 4u);
    EXPECT_NEAR(q[4].iqi, std::sqrt((0.01 + 0.0009 + 0.25) / 4), 1e-15);
    const auto none = quality({}, g1);
    EXPECT_TRUE(std::isnan(none[0].iqi));
    EXPECT_TRUE(std::isnan(none[0].iqi_sd));
}

// The statistical errors of the quality indices. One energy, R = 0.1 >> SE / R_pred = 1e-3: the
// IQI is |R|, whose bootstrap sd is SE / R_pred (to the bootstrap's own ~1.6 % for 2000
// resamples: 5 % is 3 sigma); the spread's sd / sqrt(2 (n - 1)) enters the PQI's. Noise floor, RMS
// S and the PQI at a reference length are exact functions of the samples.
TEST(Statistics, QualityIndicesCarryTheirStatisticalErrors) {
    const double_pendulum<double> m;
    const auto regimes = paper_regimes(m, arm::two);
    const double p = 0.2, se = 2e-4, spread = 0.04;  // SE / p = 1e-3, S = 0.2
    const std::size_t n = 201;                       // sd(S) = S / sqrt(400) = 0.01
    const std::vector<quality_sample> one{{3.0, 1.1 * p, p, spread, se, n}};
    const auto q = quality(one, regimes, 0.25);
    const quality_indices& full = q[0];
    ASSERT_EQ(full.energies, 1u);
    EXPECT_NEAR(full.iqi, 0.1, 1e-15);
    EXPECT_NEAR(full.iqi_sd, 1e-3, 0.05e-3);
    EXPECT_NEAR(full.noise_floor, 1e-3, 1e-15);
    EXPECT_NEAR(full.rms_spread, 0.2, 1e-15);
    // PQI = sqrt(R^2 + S^2): sd = sqrt((R sd_R)^2 + (S sd_S)^2) / PQI to first order
    const double pqi = std::sqrt(0.01 + 0.04);
    EXPECT_NEAR(full.pqi, pqi, 1e-15);
    EXPECT_NEAR(full.pqi_sd, std::hypot(0.1 * 1e-3, 0.2 * 0.01) / pqi, 0.05 * full.pqi_sd);
    EXPECT_NEAR(full.pqi_reference, std::sqrt(0.01 + 0.25 * 0.04), 1e-15);
    EXPECT_GT(full.pqi_reference_sd, 0);
    // the same numbers every run (fixed seeds), and no reference without a scale
    const auto again = quality(one, regimes, 0.25);
    EXPECT_EQ(again[0].iqi_sd, full.iqi_sd);
    EXPECT_EQ(again[0].pqi_sd, full.pqi_sd);
    EXPECT_TRUE(std::isnan(quality(one, regimes)[0].pqi_reference));
    // a sample without a positive prediction is left out
    const std::vector<quality_sample> bad{{3.0, 1.0, 0.0, 0.1, 0.01, 10}};
    EXPECT_EQ(quality(bad, regimes)[0].energies, 0u);
}

// The PQI's error where the rates are heavy-tailed (regression: the spread was drawn as if the
// rates were normal, which underestimated PQI_sd several times over all trajectories, where the
// regular trajectories flip at ~3x the mean). Independent route: the nonparametric bootstrap,
// resampling whole trajectories at every energy and recomputing PQI from the resampled rates.
TEST(Statistics, QualityIndexErrorsFollowHeavyTailedRates) {
    const double_pendulum<double> m;
    const auto regimes = paper_regimes(m, arm::two);
    // five energies in "central", 100 trajectories each: 90 chaotic rates spread evenly over
    // [0.8, 1.2] x p and 10 regular ones over [2.9, 3.1] x p (skewed, kurtosis ~ 8)
    const std::vector<double> energies{3.0, 3.5, 4.0, 4.5, 4.9};
    std::vector<std::vector<double>> rates;
    std::vector<quality_sample> samples, as_if_normal;
    for (std::size_t k = 0; k < energies.size(); ++k) {
        const double p = 0.1 * static_cast<double>(k + 1);
        std::vector<double> r;
        for (int i = 0; i < 90; ++i)
            r.push_back(p * (0.8 + 0.4 * i / 89.0));
        for (int i = 0; i < 10; ++i)
            r.push_back(p * (2.9 + 0.2 * i / 9.0));
        const summary_statistics s = summarize(r);
        samples.push_back({energies[k], s.mean, p, s.standard_deviation, s.standard_error, s.count,
                           s.skewness, s.kurtosis});
        as_if_normal.push_back(samples.back());
        as_if_normal.back().skewness = 0;
        as_if_normal.back().kurtosis = 3;
        rates.push_back(std::move(r));
    }
    EXPECT_GT(samples[0].kurtosis, 6);
    const quality_indices q = quality(samples, regimes)[2];
    ASSERT_EQ(q.regime, "central");
    ASSERT_EQ(q.energies, 5u);

    std::mt19937_64 engine(2026);
    std::uniform_int_distribution<std::size_t> pick(0, 99);
    std::vector<double> iqi, pqi, resampled(100);
    for (int b = 0; b < 4000; ++b) {
        double r2 = 0, s2 = 0;
        for (std::size_t k = 0; k < rates.size(); ++k) {
            for (double& x : resampled)
                x = rates[k][pick(engine)];
            const summary_statistics s = summarize(resampled);
            const double p = samples[k].predicted;
            r2 += (s.mean / p - 1) * (s.mean / p - 1);
            s2 += (s.standard_deviation / p) * (s.standard_deviation / p);
        }
        iqi.push_back(std::sqrt(r2 / 5));
        pqi.push_back(std::sqrt((r2 + s2) / 5));
    }
    const double iqi_sd = summarize(iqi).standard_deviation;
    const double pqi_sd = summarize(pqi).standard_deviation;
    // two bootstraps of 2000 and 4000 resamples: each sd to ~1.6 % and ~1.1 %; the normal law of
    // (mean, s^2) is the delta method's, exact to O(1/n) here: 10 % covers both
    EXPECT_NEAR(q.iqi_sd, iqi_sd, 0.1 * iqi_sd);
    EXPECT_NEAR(q.pqi_sd, pqi_sd, 0.1 * pqi_sd);
    // the normal-law spread is far off on these rates: the check can tell the two apart
    EXPECT_LT(quality(as_if_normal, regimes)[2].pqi_sd, 0.6 * pqi_sd);
}

// The heavy-tail check's range (regression: a fixed [1/2, 2] flagged 43 % of well-behaved
// energies at R = 2, found by an independent cross-check): the square roots of the chi^2 quantiles
// 0.0005 and 0.9995 with R - 1 degrees of freedom over R - 1. Reference values: mpmath, the
// regularised incomplete gamma function inverted by root finding at 30 digits.
TEST(Statistics, HeavyTailCheckRangeIsTheRatiosChiSquareRange) {
    const std::vector<std::tuple<std::size_t, double, double>> reference{
        {2, 0.0006266571096723649965, 3.4807564043462127774},
        {3, 0.022363475617226807066, 2.7569734238004693471},
        {5, 0.12641404640299837395, 2.2359201123501487873},
        {10, 0.32858272236951233731, 1.8155442435808528651},
        {100, 0.77282237554342474501, 1.2388248391169785028}};
    for (const auto& [R, lo, hi] : reference) {
        const std::array<double, 2> range = replicate_error_ratio_range(R);
        EXPECT_NEAR(range[0], lo, 1e-12 * lo) << R;
        EXPECT_NEAR(range[1], hi, 1e-12 * hi) << R;
        EXPECT_FALSE(replicate_error_ratio_flagged(1.0, R)) << R;
        EXPECT_TRUE(replicate_error_ratio_flagged(0.99 * lo, R)) << R;
        EXPECT_TRUE(replicate_error_ratio_flagged(1.01 * hi, R)) << R;
        EXPECT_FALSE(replicate_error_ratio_flagged(std::numeric_limits<double>::quiet_NaN(), R));
    }
    // the cross-check's case: two replicates whose means differ by chance far less than their
    // trajectories' spread (ratio 0.02) are within the range of R = 2
    EXPECT_FALSE(replicate_error_ratio_flagged(0.02, 2));
    EXPECT_THROW(replicate_error_ratio_range(1), std::invalid_argument);
}

// The false-alarm rate itself, by simulation: R replicates of N normal rates, the jackknife error
// of the pooled mean over its s / sqrt(n); about replicate_check_false_alarm of the draws flagged
// for every R (the fixed [1/2, 2] gave 0.43 at R = 2 and 0.09 at R = 5).
TEST(Statistics, HeavyTailCheckFalseAlarmRateDoesNotDependOnR) {
    std::mt19937_64 rng(20261130);
    std::normal_distribution<double> normal(0.3, 0.05);
    const std::size_t N = 40, draws = 20000;
    for (std::size_t R : {2, 3, 5, 10}) {
        std::size_t flagged = 0;
        for (std::size_t d = 0; d < draws; ++d) {
            std::vector<summary_statistics> parts;
            std::vector<double> all;
            for (std::size_t k = 0; k < R; ++k) {
                std::vector<double> x(N);
                for (double& v : x)
                    v = normal(rng);
                all.insert(all.end(), x.begin(), x.end());
                parts.push_back(summarize(x));
            }
            const double ratio = replicate_standard_error(parts) / summarize(all).standard_error;
            flagged += replicate_error_ratio_flagged(ratio, R);
        }
        // binomial: expected 20, sd 4.5; the bound 50 is 6.7 sd above
        EXPECT_LE(flagged, 50u) << R;
    }
}

}  // namespace
}  // namespace flipflux::test
