// A study's statistics from its ensembles (src/study/study_statistics.hpp).
#include "study_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "flipflux/ensemble/replicate_check.hpp"
#include "flipflux/ensemble/statistics.hpp"

namespace flipflux::detail {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

}  // namespace

/// One energy's result from its finished ensemble: drift and step counts, and per criterion the
/// statistics against the prediction.
energy_result summarise_energy(
    const ensemble_result& r, const std::string& label, const simulation_request& request,
    const process_group& group,
    const std::vector<std::optional<quantity_value<double>>>& predictions) {
    energy_result e;
    e.label = label;
    e.energy = r.energy;
    e.seconds = r.seconds;
    e.cpu_seconds = r.cpu_seconds;
    e.threads = r.threads;
    e.processes = group.size();
    long steps = 0;
    for (const trajectory_result& t : r.trajectories) {
        e.max_energy_drift = std::max(e.max_energy_drift, t.max_energy_drift);
        steps += t.steps;
        e.failed_trajectories += t.status != rk_status::ok;
        e.energy_check_rejections += t.energy_check_rejections;
    }
    e.steps_per_trajectory =
        static_cast<double>(steps) / static_cast<double>(r.trajectories.size());
    for (std::size_t c = 0; c < request.criteria.size(); ++c) {
        const auto& p = predictions[c];
        e.criteria.push_back(
            {p, analyze(r, c, p ? p->value : nan, request.bins, request.bins, request.replicates)});
    }
    std::vector<double> d;
    for (std::size_t i = 0; i < request.criteria.size(); ++i)
        for (std::size_t j = i + 1; j < request.criteria.size(); ++j) {
            d.clear();
            for (const trajectory_result& t : r.trajectories)  // failed ones are no data
                if (t.status == rk_status::ok)
                    d.push_back(static_cast<double>(t.flips(i)) / r.time -
                                static_cast<double>(t.flips(j)) / r.time);
            e.paired.push_back({i, j, summarize(d)});
        }
    return e;
}

namespace {

/// The replicate errors of criterion c's quality indices: the indices of each replicate alone and
/// of the ensemble without each replicate (statistics.hpp, replicate_quality), over the energies
/// the pooled indices use.
void add_replicate_quality(study_result& out, std::size_t c) {
    const std::size_t R = out.replicates;
    for (const bool chaotic : {false, true}) {
        std::vector<std::vector<quality_sample>> own(R), without(R);
        for (const energy_result& e : out.energies) {
            const criterion_result& x = e.criteria[c];
            if (!x.prediction) continue;
            const criterion_statistics& st = x.statistics;
            if (chaotic && st.chaotic == 0) continue;
            const auto& parts = chaotic ? st.replicate_chaotic_rates : st.replicate_rates;
            const auto sample = [&](const summary_statistics& r) {
                return quality_sample{
                    e.energy,         r.mean, x.prediction->value, r.standard_deviation,
                    r.standard_error, r.count};
            };
            std::vector<summary_statistics> rest;
            for (std::size_t k = 0; k < R; ++k) {
                own[k].push_back(sample(parts[k]));
                rest.clear();
                for (std::size_t j = 0; j < R; ++j)
                    if (j != k) rest.push_back(parts[j]);
                without[k].push_back(sample(merge(rest)));
            }
        }
        auto& pooled =
            chaotic ? out.quality[c].chaotic_trajectories : out.quality[c].all_trajectories;
        replicate_quality(pooled, own, without, out.regimes);
    }
}

}  // namespace

/// The quality indices (paper Sec. 5.6) of each criterion over the energies, per regime: IQI
/// over all trajectories, PQI also over the chaotic sub-ensemble. An energy enters where its
/// criterion has a prediction (and, for the chaotic table, chaotic trajectories).
void add_quality(study_result& out, const double_pendulum<double>& model) {
    out.regimes = paper_regimes(model, out.flip_arm);
    for (std::size_t c = 0; c < out.criteria.size(); ++c) {
        std::vector<quality_sample> all, chaotic;
        for (const energy_result& e : out.energies) {
            const criterion_result& x = e.criteria[c];
            if (!x.prediction) continue;
            const criterion_statistics& st = x.statistics;
            const auto sample = [&](const summary_statistics& r) {
                return quality_sample{
                    e.energy,         r.mean,  x.prediction->value, r.standard_deviation,
                    r.standard_error, r.count, r.skewness,          r.kurtosis};
            };
            all.push_back(sample(st.rates));
            if (st.chaotic > 0) chaotic.push_back(sample(st.chaotic_rates));
        }
        const double scale = out.reference_time > 0 ? out.options.time / out.reference_time : 0;
        out.quality.push_back(
            {quality(all, out.regimes, scale), quality(chaotic, out.regimes, scale)});
        if (out.replicates > 1) add_replicate_quality(out, c);
    }
}

namespace {

/// z-scores over the energies (paper Sec. 5.5): their chi^2, the worst, the largest relative
/// deviation, for one criterion over all or over the chaotic trajectories.
criterion_agreement agreement(const std::vector<energy_result>& energies, std::size_t c,
                              bool chaotic) {
    criterion_agreement a;
    a.worst_z = a.max_relative_deviation = nan;
    for (const energy_result& e : energies) {
        const criterion_statistics& st = e.criteria[c].statistics;
        const summary_statistics& s = chaotic ? st.chaotic_rates : st.rates;
        const double p = st.predicted_rate;
        if (!(p > 0) || !std::isfinite(s.mean) || !(s.standard_error > 0)) continue;
        const double z = (s.mean - p) / s.standard_error, rel = std::abs(s.mean / p - 1);
        a.chi2 += z * z;
        if (!(std::abs(z) <= std::abs(a.worst_z))) a.worst_z = z;
        if (!(rel <= a.max_relative_deviation)) a.max_relative_deviation = rel;
        ++a.energies;
    }
    return a;
}

/// The agreement of criterion c's pooled means with its predictions by the replicate errors,
/// and each replicate's own chi^2 (criterion_agreement::replicate_verdict).
criterion_agreement::replicate_verdict replicate_agreement(
    const std::vector<energy_result>& energies, std::size_t c, bool chaotic, std::size_t R) {
    criterion_agreement::replicate_verdict v;
    v.worst_z = v.max_error_ratio = v.min_error_ratio = nan;
    v.chi2_of_replicates.assign(R, 0);
    for (const energy_result& e : energies) {
        const criterion_statistics& st = e.criteria[c].statistics;
        const summary_statistics& s = chaotic ? st.chaotic_rates : st.rates;
        const auto& parts = chaotic ? st.replicate_chaotic_rates : st.replicate_rates;
        const double p = st.predicted_rate;
        if (!(p > 0) || !std::isfinite(s.mean) || parts.size() != R) continue;
        for (std::size_t k = 0; k < R; ++k) {
            const double z = (parts[k].mean - p) / parts[k].standard_error;
            if (std::isfinite(z)) v.chi2_of_replicates[k] += z * z;
        }
        const double se = replicate_standard_error(parts);
        if (!(se > 0)) continue;
        const double z = (s.mean - p) / se;
        v.chi2 += z * z;
        if (!(std::abs(z) <= std::abs(v.worst_z))) v.worst_z = z;
        const double ratio = se / s.standard_error;
        if (std::isfinite(ratio)) {
            if (!(ratio <= v.max_error_ratio)) v.max_error_ratio = ratio;
            if (!(ratio >= v.min_error_ratio)) v.min_error_ratio = ratio;
            v.error_mismatches += replicate_error_ratio_flagged(ratio, R);
        }
        ++v.energies;
    }
    const double r = static_cast<double>(R);
    v.expected_chi2 = R > 3 ? static_cast<double>(v.energies) * (r - 1) / (r - 3) : nan;
    return v;
}

}  // namespace

/// The agreement of every criterion and the differences between the criteria's predictions.
void add_comparisons(study_result& out) {
    const std::size_t n = out.criteria.size();
    for (std::size_t c = 0; c < n; ++c) {
        out.agreement.push_back(
            {agreement(out.energies, c, false), agreement(out.energies, c, true)});
        if (out.replicates > 1) {
            out.agreement.back().all_trajectories.replicates =
                replicate_agreement(out.energies, c, false, out.replicates);
            out.agreement.back().chaotic_trajectories.replicates =
                replicate_agreement(out.energies, c, true, out.replicates);
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            prediction_difference d{i, j, 0, 0};
            double sum = 0;
            for (const energy_result& e : out.energies) {
                const auto &p = e.criteria[i].prediction, &q = e.criteria[j].prediction;
                if (!p || !q || !(q->value > 0)) continue;
                const double rel = p->value / q->value - 1;
                sum += rel * rel;
                ++d.energies;
            }
            d.rms_relative = d.energies ? std::sqrt(sum / static_cast<double>(d.energies)) : nan;
            out.prediction_differences.push_back(d);
        }
}

}  // namespace flipflux::detail
