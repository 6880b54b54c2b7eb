// Ensemble statistics and quality indices; definitions in include/flipflux/ensemble/statistics.hpp.
#include "flipflux/ensemble/statistics.hpp"

#include <boost/math/distributions/chi_squared.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "flipflux/ensemble/replicate_check.hpp"

namespace flipflux {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// The jackknife standard error from leave-one-out values theta_(k), k = 1..R:
/// sqrt((R - 1) / R sum_k (theta_(k) - mean theta_(.))^2) (NaN when any value is).
double jackknife_error(const std::vector<double>& loo) {
    const double r = static_cast<double>(loo.size());
    double mean = 0, ss = 0;
    for (double x : loo)
        mean += x / r;
    for (double x : loo)
        ss += (x - mean) * (x - mean);
    return std::sqrt((r - 1) / r * ss);
}
}  // namespace

summary_statistics summarize(std::span<const double> v) {
    summary_statistics s;
    s.count = v.size();
    if (v.empty()) {
        s.mean = s.standard_deviation = s.standard_error = s.minimum = s.maximum = nan;
        s.skewness = s.kurtosis = nan;
        return s;
    }
    double sum = 0;
    s.minimum = s.maximum = v[0];
    for (double x : v) {
        sum += x;
        s.minimum = std::min(s.minimum, x);
        s.maximum = std::max(s.maximum, x);
    }
    const double n = static_cast<double>(v.size());
    // identical values: their mean is the value itself (sum / n can be an ulp off, which left a
    // spread of ~1e-17 where there is none, e.g. a bootstrap IQI sd of 2e-15 for zero-spread
    // energies); otherwise the rounded quotient, kept within [min, max]
    s.mean = s.minimum == s.maximum ? s.minimum : std::clamp(sum / n, s.minimum, s.maximum);
    double ss = 0, s3 = 0, s4 = 0;
    for (double x : v) {
        const double d = x - s.mean, d2 = d * d;
        ss += d2;
        s3 += d2 * d;
        s4 += d2 * d2;
    }
    // one value has no sample spread (n - 1 = 0): undefined, not 0 (and no z-score follows)
    s.standard_deviation = v.size() > 1 ? std::sqrt(ss / (n - 1)) : nan;
    s.standard_error = s.standard_deviation / std::sqrt(n);
    const double m2 = ss / n;
    s.skewness = v.size() > 1 && m2 > 0 ? s3 / n / (m2 * std::sqrt(m2)) : nan;
    s.kurtosis = v.size() > 1 && m2 > 0 ? s4 / n / (m2 * m2) : nan;
    return s;
}

summary_statistics merge(std::span<const summary_statistics> parts) {
    summary_statistics s;
    double n = 0, mean = 0, m2 = 0;
    s.minimum = s.maximum = nan;
    for (const summary_statistics& p : parts) {
        if (p.count == 0) continue;
        const double k = static_cast<double>(p.count);
        const double pm2 = p.count > 1 ? p.standard_deviation * p.standard_deviation * (k - 1) : 0;
        const double delta = p.mean - mean, total = n + k;
        mean += delta * k / total;
        m2 += pm2 + delta * delta * n * k / total;
        n = total;
        s.minimum = s.count ? std::min(s.minimum, p.minimum) : p.minimum;
        s.maximum = s.count ? std::max(s.maximum, p.maximum) : p.maximum;
        s.count += p.count;
    }
    s.mean = s.count ? mean : nan;
    s.standard_deviation = s.count > 1 ? std::sqrt(m2 / (n - 1)) : nan;
    s.standard_error = s.standard_deviation / std::sqrt(n);
    s.skewness = s.kurtosis = nan;
    return s;
}

double replicate_standard_error(std::span<const summary_statistics> replicates) {
    std::vector<double> loo;
    std::vector<summary_statistics> rest;
    for (std::size_t k = 0; k < replicates.size(); ++k) {
        if (replicates[k].count == 0) continue;
        rest.clear();
        for (std::size_t j = 0; j < replicates.size(); ++j)
            if (j != k) rest.push_back(replicates[j]);
        const double m = merge(rest).mean;
        if (!std::isfinite(m)) return nan;  // every other replicate empty
        loo.push_back(m);
    }
    if (loo.size() < 2) return nan;
    return jackknife_error(loo);
}

std::array<double, 2> replicate_error_ratio_range(std::size_t replicates) {
    if (replicates < 2)
        throw std::invalid_argument("replicate_error_ratio_range: " + std::to_string(replicates) +
                                    " replicates (at least 2)");
    const double dof = static_cast<double>(replicates - 1);
    const boost::math::chi_squared_distribution<double> chi2(dof);
    const double tail = replicate_check_false_alarm / 2;
    return {std::sqrt(boost::math::quantile(chi2, tail) / dof),
            std::sqrt(boost::math::quantile(boost::math::complement(chi2, tail)) / dof)};
}

bool replicate_error_ratio_flagged(double ratio, std::size_t replicates) {
    if (!std::isfinite(ratio) || replicates < 2) return false;
    const std::array<double, 2> range = replicate_error_ratio_range(replicates);
    return ratio < range[0] || ratio > range[1];
}

std::uint64_t histogram::total() const {
    std::uint64_t t = underflow + overflow;
    for (std::uint64_t c : counts)
        t += c;
    return t;
}

histogram make_histogram(std::span<const double> v, std::size_t bins, double lower, double upper) {
    if (bins == 0 || !(upper > lower))
        throw std::invalid_argument("make_histogram: needs bins > 0 and upper > lower");
    histogram h;
    h.lower = lower;
    h.upper = upper;
    h.counts.assign(bins, 0);
    const double w = (upper - lower) / static_cast<double>(bins);
    for (double x : v) {
        if (x < lower) {
            ++h.underflow;
        } else if (!(x < upper)) {
            ++h.overflow;
        } else {
            const auto i = std::min(bins - 1, static_cast<std::size_t>((x - lower) / w));
            ++h.counts[i];
        }
    }
    return h;
}

histogram auto_histogram(std::span<const double> v, std::size_t bins) {
    if (bins == 0)
        bins = std::clamp<std::size_t>(
            static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(v.size())))), 10, 200);
    double hi = 0;
    for (double x : v)
        hi = std::max(hi, x);
    if (!(hi > 0)) hi = 1;
    return make_histogram(v, bins, 0.0, std::nextafter(hi, 2 * hi));
}

double quantile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return sorted_quantile(v, q);
}

double sorted_quantile(std::span<const double> v, double q) {
    if (v.empty()) return nan;
    const double pos = q * static_cast<double>(v.size() - 1);
    const auto i = static_cast<std::size_t>(std::floor(pos));
    if (i + 1 >= v.size()) return v.back();
    const double f = pos - static_cast<double>(i);
    return v[i] + f * (v[i + 1] - v[i]);
}

criterion_statistics analyze(const ensemble_result& r, std::size_t c, double predicted,
                             std::size_t rate_bins, std::size_t residence_bins,
                             std::size_t replicates) {
    if (c >= r.criteria.size()) throw std::out_of_range("analyze: no such criterion");
    if (replicates == 0 || r.trajectories.size() % replicates != 0)
        throw std::invalid_argument("analyze: " + std::to_string(replicates) +
                                    " replicates do not divide " +
                                    std::to_string(r.trajectories.size()) + " trajectories");
    criterion_statistics s;
    s.criterion = r.criteria[c];
    s.predicted_rate = predicted;
    std::vector<double> rates, chaotic_rates, residence;
    rates.reserve(r.trajectories.size());
    {
        std::size_t gaps = 0;
        for (const trajectory_result& t : r.trajectories)
            if (t.status == rk_status::ok && !t.crossing_times[c].empty())
                gaps += t.crossing_times[c].size() - 1;
        residence.reserve(gaps);
    }
    for (const trajectory_result& t : r.trajectories) {
        // NOTE: a trajectory whose integration failed did not reach T; its flips over T are
        // unknown, so it is no data (docs/limits.md): counted in failed_trajectories only.
        if (t.status != rk_status::ok) continue;
        const auto& times = t.crossing_times[c];
        s.flips += times.size();
        const double rate = static_cast<double>(times.size()) / r.time;
        rates.push_back(rate);
        if (r.chaotic(t)) chaotic_rates.push_back(rate);
        for (std::size_t i = 1; i < times.size(); ++i)
            residence.push_back(times[i] - times[i - 1]);
    }
    s.rates = summarize(rates);
    s.z_score = (s.rates.mean - predicted) / s.rates.standard_error;
    s.chaotic = chaotic_rates.size();
    s.chaotic_fraction =
        r.chaos ? static_cast<double>(s.chaotic) / static_cast<double>(rates.size()) : nan;
    s.chaotic_rates = summarize(chaotic_rates);
    s.chaotic_z_score = (s.chaotic_rates.mean - predicted) / s.chaotic_rates.standard_error;
    s.residence.summary = summarize(residence);
    s.residence.distribution = auto_histogram(residence, residence_bins);
    std::sort(residence.begin(), residence.end());  // once for the three quantiles
    s.residence.q001 = sorted_quantile(residence, 0.001);
    s.residence.q01 = sorted_quantile(residence, 0.01);
    s.residence.median = sorted_quantile(residence, 0.5);
    s.rate_distribution = auto_histogram(rates, rate_bins);
    if (replicates > 1) {
        const std::size_t size = r.trajectories.size() / replicates;
        for (std::size_t k = 0; k < replicates; ++k) {
            rates.clear();
            chaotic_rates.clear();
            for (std::size_t i = k * size; i < (k + 1) * size; ++i) {
                const trajectory_result& t = r.trajectories[i];
                if (t.status != rk_status::ok) continue;
                const double rate = static_cast<double>(t.crossing_times[c].size()) / r.time;
                rates.push_back(rate);
                if (r.chaotic(t)) chaotic_rates.push_back(rate);
            }
            s.replicate_rates.push_back(summarize(rates));
            s.replicate_chaotic_rates.push_back(summarize(chaotic_rates));
        }
    }
    s.counts = flip_counts(r, c);
    return s;
}

flip_count_statistics flip_counts(const ensemble_result& r, std::size_t c) {
    flip_count_statistics out;
    // window counts: sums of n and n^2 over windows, in long double (up to ~1e9 windows)
    for (double window = r.time; window >= 1 && out.fano.size() < 5; window /= 10) {
        window_fano f;
        f.window = window;
        const auto per = static_cast<std::uint64_t>(std::floor(r.time / window * (1 + 1e-12)));
        long double sum[2] = {0, 0}, sum2[2] = {0, 0};
        std::uint64_t windows[2] = {0, 0};
        std::vector<std::uint64_t> count(per);
        for (const trajectory_result& t : r.trajectories) {
            if (t.status != rk_status::ok || per == 0) continue;
            std::fill(count.begin(), count.end(), 0);
            for (double x : t.crossing_times[c]) {
                const auto w = static_cast<std::uint64_t>(x / window);
                if (w < per) ++count[w];
            }
            for (int chaotic = 0; chaotic < 2; ++chaotic) {
                if (chaotic && !r.chaotic(t)) continue;
                for (std::uint64_t n : count) {
                    sum[chaotic] += n;
                    sum2[chaotic] += static_cast<long double>(n) * n;
                }
                windows[chaotic] += per;
            }
        }
        double mean[2], fano[2];
        for (int k = 0; k < 2; ++k) {
            const auto w = static_cast<long double>(windows[k]);
            mean[k] = windows[k] ? static_cast<double>(sum[k] / w) : nan;
            const long double var =
                windows[k] > 1 ? (sum2[k] - sum[k] * sum[k] / w) / (w - 1) : nan;
            fano[k] = mean[k] > 0 ? static_cast<double>(var / (sum[k] / w)) : nan;
        }
        f.windows = windows[0];
        f.windows_chaotic = windows[1];
        f.mean_count = mean[0];
        f.fano = fano[0];
        f.mean_count_chaotic = mean[1];
        f.fano_chaotic = fano[1];
        out.fano.push_back(f);
    }
    // inter-flip times: all trajectories and the chaotic ones, sorted
    std::vector<double> tau[2];
    for (const trajectory_result& t : r.trajectories) {
        if (t.status != rk_status::ok) continue;
        const auto& times = t.crossing_times[c];
        for (int chaotic = 0; chaotic < 2; ++chaotic) {
            if (chaotic && !r.chaotic(t)) continue;
            for (std::size_t i = 1; i < times.size(); ++i)
                tau[chaotic].push_back(times[i] - times[i - 1]);
        }
    }
    double cv2[2];
    for (int k = 0; k < 2; ++k) {
        const summary_statistics s = summarize(tau[k]);
        cv2[k] =
            s.count > 1 ? (s.standard_deviation / s.mean) * (s.standard_deviation / s.mean) : nan;
        std::sort(tau[k].begin(), tau[k].end());
    }
    out.cv2 = cv2[0];
    out.cv2_chaotic = cv2[1];
    const std::vector<double>& all = tau[0];
    if (all.size() > 1 && all.front() > 0 && all.back() > all.front()) {
        constexpr int points = 24;
        const double ratio = all.back() / all.front();
        const auto survival = [](const std::vector<double>& v, double t) {
            if (v.empty()) return nan;
            const auto above = v.end() - std::upper_bound(v.begin(), v.end(), t);
            return static_cast<double>(above) / static_cast<double>(v.size());
        };
        for (int j = 0; j < points; ++j) {
            const double t = all.front() * std::pow(ratio, j / double(points - 1));
            out.survival.push_back({t, survival(all, t), survival(tau[1], t)});
        }
    }
    return out;
}

std::vector<energy_regime> paper_regimes(const double_pendulum<double>& model, arm a) {
    const double es = model.saddle_energy(a), em = model.maximum_energy();
    const double d = em - es;
    std::vector<energy_regime> r{{"full", es, em}};
    if (a == arm::two) {
        r.push_back({"low", es, es + 0.2 * d});
        r.push_back({"central", es + 0.2 * d, es + 0.75 * d});
        r.push_back({"high", es + 0.75 * d, em});
    } else {
        r.push_back({"low", es, es + 0.3 * d});
        r.push_back({"high", es + 0.3 * d, em});
    }
    r.push_back(
        {"all", -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()});
    return r;
}

namespace {

/// Root mean squares of R and S over the samples, S^2 scaled by `scale`.
double rms_index(const std::vector<double>& R, const std::vector<double>& S, double scale) {
    double sum = 0;
    for (std::size_t i = 0; i < R.size(); ++i)
        sum += R[i] * R[i] + scale * S[i] * S[i];
    return std::sqrt(sum / static_cast<double>(R.size()));
}

double sample_sd(const std::vector<double>& v) {
    return summarize(v).standard_deviation;
}

/// The sampling law of an energy's (mean, s^2) as a bivariate normal, drawn as
///     mean* = mean + a z1,   s2* = s^2 + b z1 + c z2   (z1, z2 independent standard normals),
/// a^2 = Var(mean), b a = Cov(mean, s^2), b^2 + c^2 = Var(s^2) (quality_indices).
struct sampling_law {
    double a = 0, b = 0, c = 0;
    explicit sampling_law(const quality_sample& x) {
        const double n = static_cast<double>(std::max<std::size_t>(x.trajectories, 2));
        const double skewness = std::isfinite(x.skewness) ? x.skewness : 0;
        const double kurtosis = std::isfinite(x.kurtosis) ? x.kurtosis : 3;
        const double s2 = x.spread * x.spread, m2 = s2 * (n - 1) / n;  // population variance
        const double m3 = skewness * m2 * std::sqrt(m2), m4 = kurtosis * m2 * m2;
        const double var_s2 = std::max(0.0, (m4 - s2 * s2 * (n - 3) / (n - 1)) / n);
        a = x.standard_error;
        b = a > 0 ? m3 / n / a : 0;
        c = std::sqrt(std::max(0.0, var_s2 - b * b));
    }
};

}  // namespace

std::vector<quality_indices> quality(const std::vector<quality_sample>& samples,
                                     const std::vector<energy_regime>& regimes, double spread_scale,
                                     bool bootstrap) {
    constexpr int resamples = 2000;
    std::vector<quality_indices> out;
    for (const energy_regime& g : regimes) {
        const std::uint64_t seed = 0x51a7157ULL + out.size();  // fixed per regime
        quality_indices q;
        q.regime = g.name;
        std::vector<const quality_sample*> in;
        double r2 = 0, s2 = 0, floor2 = 0;
        for (const quality_sample& x : samples) {
            if (!(x.energy >= g.lower && x.energy < g.upper)) continue;
            // an energy with one trajectory has no spread (NaN): no PQI term, no noise estimate
            if (!(x.predicted > 0) || !std::isfinite(x.predicted) || !std::isfinite(x.simulated) ||
                !std::isfinite(x.spread) || !std::isfinite(x.standard_error))
                continue;
            const double R = std::abs(x.simulated / x.predicted - 1);
            const double S = x.spread / x.predicted;
            r2 += R * R;
            s2 += S * S;
            floor2 += (x.standard_error / x.predicted) * (x.standard_error / x.predicted);
            in.push_back(&x);
            ++q.energies;
        }
        const double n = static_cast<double>(q.energies);
        q.iqi = q.energies ? std::sqrt(r2 / n) : nan;
        q.pqi = q.energies ? std::sqrt((r2 + s2) / n) : nan;
        q.noise_floor = q.energies ? std::sqrt(floor2 / n) : nan;
        q.rms_spread = q.energies ? std::sqrt(s2 / n) : nan;
        q.pqi_reference =
            q.energies && spread_scale > 0 ? std::sqrt((r2 + spread_scale * s2) / n) : nan;
        q.iqi_sd = q.pqi_sd = q.pqi_reference_sd = nan;
        if (q.energies && bootstrap) {
            // the parametric bootstrap, seeded per regime: the same numbers every run
            std::mt19937_64 engine(seed);
            std::normal_distribution<double> normal;
            std::vector<double> iqi(resamples), pqi(resamples), ref(resamples), R(in.size()),
                S(in.size());
            std::vector<sampling_law> law;
            for (const quality_sample* x : in)
                law.emplace_back(*x);
            for (int b = 0; b < resamples; ++b) {
                for (std::size_t i = 0; i < in.size(); ++i) {
                    const quality_sample& x = *in[i];
                    const double z1 = normal(engine), z2 = normal(engine);
                    const double s2 = x.spread * x.spread + law[i].b * z1 + law[i].c * z2;
                    R[i] = (x.simulated + law[i].a * z1) / x.predicted - 1;
                    S[i] = std::sqrt(std::max(0.0, s2)) / x.predicted;
                }
                iqi[static_cast<std::size_t>(b)] = rms_index(R, S, 0);
                pqi[static_cast<std::size_t>(b)] = rms_index(R, S, 1);
                ref[static_cast<std::size_t>(b)] = rms_index(R, S, spread_scale);
            }
            q.iqi_sd = sample_sd(iqi);
            q.pqi_sd = sample_sd(pqi);
            if (spread_scale > 0) q.pqi_reference_sd = sample_sd(ref);
        }
        out.push_back(q);
    }
    return out;
}

void replicate_quality(std::vector<quality_indices>& pooled,
                       const std::vector<std::vector<quality_sample>>& replicates,
                       const std::vector<std::vector<quality_sample>>& without,
                       const std::vector<energy_regime>& regimes) {
    if (replicates.size() < 2 || without.size() != replicates.size()) return;
    std::vector<std::vector<quality_indices>> own, loo;
    for (std::size_t k = 0; k < replicates.size(); ++k) {
        own.push_back(quality(replicates[k], regimes, 0, false));
        loo.push_back(quality(without[k], regimes, 0, false));
    }
    for (std::size_t g = 0; g < pooled.size(); ++g) {
        quality_indices& q = pooled[g];
        std::vector<double> iqi, pqi;
        for (std::size_t k = 0; k < replicates.size(); ++k) {
            q.iqi_replicates.push_back(own[k][g].iqi);
            q.pqi_replicates.push_back(own[k][g].pqi);
            iqi.push_back(loo[k][g].iqi);
            pqi.push_back(loo[k][g].pqi);
        }
        q.iqi_replicate_se = q.energies ? jackknife_error(iqi) : nan;
        q.pqi_replicate_se = q.energies ? jackknife_error(pqi) : nan;
    }
}

}  // namespace flipflux
