// Statistics of a simulated ensemble (paper Sec. 5.3, 5.5 and 6):
//   - per-trajectory rate r_i = N_i / T; ensemble mean, sample standard deviation (n - 1),
//     standard error sd / sqrt(n); z = (mean - R_pred) / standard error;
//   - the same over the chaotic sub-ensemble (lambda_T above the threshold) and its fraction;
//   - residence times: differences of successive crossing times within each trajectory (the
//     paper's "residence times between successive flips", Fig. waiting_times), their minimum
//     (the gap of the saddle criterion) and quantiles;
//   - histograms of the rates and of the residence times;
//   - the quality indices over a set of energies (paper eqs. implementation_quality_index and
//     prediction_quality_index), per energy regime:
//         R(E) = |R_sim(E) / R_pred(E) - 1|,  S(E) = sigma(E) / R_pred(E),
//         IQI = sqrt(mean_E R(E)^2),          PQI = sqrt(mean_E (R(E)^2 + S(E)^2)),
//     sigma the trajectory-to-trajectory standard deviation of the rates.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux {

struct summary_statistics {
    std::size_t count = 0;
    double mean = 0, standard_deviation = 0, standard_error = 0, minimum = 0, maximum = 0;
    /// The sample's shape: skewness m3 / m2^(3/2) and kurtosis m4 / m2^2 (not the excess; 3 for
    /// a normal law), m_k = mean (x - mean)^k. They set the uncertainty of the spread and its
    /// correlation with the mean (the quality indices' errors). NaN for fewer than two values
    /// or no spread (m2 = 0).
    double skewness = 0, kurtosis = 0;
};

/// Two-pass mean, sample standard deviation and shape (standard deviation and standard error NaN
/// for a single value, where n - 1 = 0; everything NaN for none).
summary_statistics summarize(std::span<const double> values);

/// The summary of the union of disjoint samples from their summaries (count, mean, standard
/// deviation, standard error, minimum, maximum; Chan et al.'s pairwise update of the squared
/// deviations). Parts with no values are skipped; the shape (skewness, kurtosis) is NaN.
summary_statistics merge(std::span<const summary_statistics> parts);

/// The jackknife standard error of the pooled mean over R >= 2 independent replicates: with
/// m_(k) the mean of the union of every replicate but k,
///     se = sqrt((R - 1) / R sum_k (m_(k) - mean_k m_(k))^2).
/// For equal replicate sizes this is the standard deviation of the replicate means over sqrt(R);
/// for unequal ones (the chaotic sub-ensemble of each replicate) it is the ratio estimator's. It
/// sees whatever makes replicates differ (rare islands, sticky orbits), not only the
/// trajectory-to-trajectory spread. NaN with fewer than two replicates with values.
double replicate_standard_error(std::span<const summary_statistics> replicates);

/// Equal-width bins on [lower, upper); values outside are counted in underflow/overflow.
struct histogram {
    double lower = 0, upper = 1;
    std::vector<std::uint64_t> counts;
    std::uint64_t underflow = 0, overflow = 0;
    double bin_width() const { return (upper - lower) / static_cast<double>(counts.size()); }
    std::uint64_t total() const;
};
histogram make_histogram(std::span<const double> values, std::size_t bins, double lower,
                         double upper);
/// Bins on [0, max(values)] (upper bound nudged up to include the maximum), `bins` of them or,
/// with bins = 0, the square-root rule clamped to [10, 200].
histogram auto_histogram(std::span<const double> values, std::size_t bins = 0);

/// The q-quantile (0 <= q <= 1) by linear interpolation between order statistics.
double quantile(std::vector<double> values, double q);
/// The q-quantile of values sorted in increasing order (quantile without the sort: several
/// quantiles of one sample from one sort).
double sorted_quantile(std::span<const double> sorted, double q);

struct residence_statistics {
    summary_statistics summary;            ///< count, mean, sd, min (the gap), max
    double q001 = 0, q01 = 0, median = 0;  ///< 0.1 %, 1 % and 50 % quantiles
    histogram distribution;
};

/// The Fano factor of the flip counts in windows of length `window`: every trajectory's
/// [0, T) cut into floor(T / window) windows, var / mean of their counts (over all trajectories
/// and over the chaotic ones; NaN where no window has a flip). For a renewal process of flips it
/// tends to the CV^2 of the inter-flip times as the window grows. The windows of all
/// trajectories are pooled, so trajectories with different rates (regular ones among chaotic)
/// add w x (their rates' spread)^2 / mean rate at every window w, most visibly at w = T; the
/// chaotic subset is the one to compare with the renewal CV^2.
struct window_fano {
    double window = 0;
    std::uint64_t windows = 0, windows_chaotic = 0;
    double mean_count = 0, fano = 0, mean_count_chaotic = 0, fano_chaotic = 0;
};

/// Flip statistics beyond the mean: Fano factors against the window length (T, T/10, ... down
/// to at least one time unit, at most five), the renewal prediction CV^2 = var / mean^2 of the
/// inter-flip (residence) times, and the tail of their distribution: P(tau > t) at 24 times
/// spaced geometrically from the smallest to the largest residence time (a sticky regime shows
/// as a power law there, chaotic mixing as an exponential).
struct flip_count_statistics {
    std::vector<window_fano> fano;
    double cv2 = 0, cv2_chaotic = 0;  ///< NaN with fewer than two residence times
    struct tail_point {
        double time = 0, survival = 0, survival_chaotic = 0;
    };
    std::vector<tail_point> survival;
};

struct criterion_statistics {
    std::string criterion;
    double predicted_rate = 0;  ///< NaN when no prediction is available
    std::uint64_t flips = 0;    ///< total crossings in the ensemble
    summary_statistics rates;   ///< per-trajectory N / T
    double z_score = 0;         ///< (mean - predicted) / standard error (NaN without prediction)
    std::size_t chaotic = 0;    ///< trajectories classified chaotic
    double chaotic_fraction = 0;
    summary_statistics chaotic_rates;
    double chaotic_z_score = 0;  ///< z of the chaotic sub-ensemble's mean
    residence_statistics residence;
    histogram rate_distribution;
    /// With R > 1 replicates (analyze's `replicates`): the summaries of each replicate's rates,
    /// over all its trajectories and over its chaotic ones (replicate k: the k-th block of
    /// trajectories in index order). Empty with one replicate.
    std::vector<summary_statistics> replicate_rates, replicate_chaotic_rates;
    flip_count_statistics counts;
};

/// Statistics of criterion `c` of an ensemble over its trajectories that reached T (status ok):
/// a failed trajectory is excluded, never counted as zero flips. predicted_rate may be NaN.
/// `replicates` R > 1: the trajectories (in index order) are R replicates of equal size, each
/// summarised on its own too (std::invalid_argument when R does not divide their number).
criterion_statistics analyze(const ensemble_result& result, std::size_t c, double predicted_rate,
                             std::size_t rate_bins = 0, std::size_t residence_bins = 0,
                             std::size_t replicates = 1);

/// The flip statistics beyond the mean of criterion `c` (criterion_statistics::counts).
flip_count_statistics flip_counts(const ensemble_result& result, std::size_t c);

// ---- quality indices over energies ---------------------------------------------------------

struct quality_sample {
    double energy, simulated, predicted, spread;  ///< spread: trajectory-to-trajectory sd
    double standard_error = 0;     ///< of `simulated` (the bootstrap's and the noise floor's)
    std::size_t trajectories = 0;  ///< behind `simulated` (the bootstrap of `spread`)
    /// The per-trajectory rates' shape (summary_statistics), which sets the spread's uncertainty;
    /// the defaults are a normal law's (a non-finite value is read as the default).
    double skewness = 0, kurtosis = 3;
};

/// An energy interval [lower, upper).
struct energy_regime {
    std::string name;
    double lower, upper;
};

/// The paper's regimes, scaled to the model: with E_s the saddle energy of `a` and E_m the
/// maximum energy, arm 2: full [E_s, E_m), low [E_s, E_s + 0.2 D), central [E_s + 0.2 D,
/// E_s + 0.75 D), high [E_s + 0.75 D, E_m), D = E_m - E_s (egalitarian: 2, 2.8, 5, 6); arm 1:
/// full, low [E_s, E_s + 0.3 D), high [E_s + 0.3 D, E_m) (egalitarian: 4, 4.6, 6). Plus "all"
/// (every energy given).
std::vector<energy_regime> paper_regimes(const double_pendulum<double>& model, arm a);

struct quality_indices {
    std::string regime;
    std::size_t energies = 0;  ///< samples in the regime (the rest is NaN when 0)
    double iqi = 0, pqi = 0;
    /// Statistical errors: standard deviations over a parametric bootstrap, 2000 resamples with a
    /// fixed seed (the same numbers every run). Per energy the simulated mean and the sample
    /// variance s^2 are drawn from the bivariate normal law of their sampling distribution,
    ///     Var(mean) = standard_error^2,  Var(s^2) = (m4 - s^4 (n - 3) / (n - 1)) / n,
    ///     Cov(mean, s^2) = m3 / n,
    /// with m3, m4 the sample's central moments (its skewness and kurtosis), and the spread is
    /// sqrt(max(s^2, 0)). For a normal law this is spread ~ N(spread, spread / sqrt(2 (n - 1)))
    /// to first order; heavy-tailed rates (regular trajectories among chaotic ones) have a
    /// spread several times more uncertain than that.
    double iqi_sd = 0, pqi_sd = 0;
    /// sqrt(mean_E (standard_error / R_pred)^2): the IQI of an exact prediction, pure noise.
    double noise_floor = 0;
    double rms_spread = 0;  ///< sqrt(mean_E S(E)^2), the spread's share of the PQI
    /// With a reference length T_ref: the PQI expected for trajectories of that length, S^2
    /// scaled by T / T_ref (S of time averages falls as 1/sqrt(T) for mixing trajectories; an
    /// estimate), and its bootstrap sd. NaN without a reference.
    double pqi_reference = 0, pqi_reference_sd = 0;
    /// With replicates (replicate_quality): the jackknife standard errors of iqi and pqi over the
    /// replicates (each recomputed without one replicate), and every replicate's own iqi and pqi
    /// (at its own, smaller size: their spread is the seed-to-seed spread of such a run).
    /// NaN and empty without replicates.
    double iqi_replicate_se = std::numeric_limits<double>::quiet_NaN(),
           pqi_replicate_se = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> iqi_replicates, pqi_replicates;
};

/// The quality indices of `samples` per regime (samples without a positive, finite prediction
/// and a finite simulated rate are left out). `spread_scale` = T / T_ref for pqi_reference
/// (0: none).
std::vector<quality_indices> quality(const std::vector<quality_sample>& samples,
                                     const std::vector<energy_regime>& regimes,
                                     double spread_scale = 0, bool bootstrap = true);

/// The replicate errors of `pooled` (quality() of the whole ensemble): `replicates[k]` are the
/// samples of replicate k alone and `without[k]` those of every replicate but k (the same
/// energies, summaries merged); sets iqi/pqi_replicate_se (jackknife) and iqi/pqi_replicates.
void replicate_quality(std::vector<quality_indices>& pooled,
                       const std::vector<std::vector<quality_sample>>& replicates,
                       const std::vector<std::vector<quality_sample>>& without,
                       const std::vector<energy_regime>& regimes);

}  // namespace flipflux
