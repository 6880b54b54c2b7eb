// The paired ensemble check (validation/paired_check.hpp, docs/validating.md).
#include "flipflux/validation/paired_check.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/study_files.hpp"

namespace flipflux {
namespace {

struct paired_row {
    int line = 0;
    std::string name;  ///< trajectory column, or ""
    std::string energy_text;
    double energy = 0, time = 0;
    phase_point<double> state{};
    arm flip_arm = arm::two;
    std::string criterion;
    std::uint64_t flips = 0, reference = 0;
    bool stable = true;  ///< flipflux's two integrations give the same count
};

std::vector<paired_row> read_rows(const std::filesystem::path& file,
                                  const double_pendulum<double>& model) {
    const csv_table t = read_csv(file);
    const auto col = [&](const char* name) { return column_index(t, name); };
    const initial_state_columns sc(t);
    const int tc = col("time"), ac = col("arm"), fc = col("flips"), cc = col("criterion"),
              nc = col("trajectory");
    if (!sc.complete() || tc < 0 || ac < 0 || fc < 0)
        throw input_error(file.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name the columns energy, theta1, theta2, l1, l2, "
                          "time, arm, flips (and optionally criterion, trajectory)");
    std::vector<paired_row> rows;
    for (const csv_row& r : t.rows) {
        const std::string at = file.string() + ":" + std::to_string(r.line) + ": ";
        if (r.fields.size() != t.header.size()) throw input_error(at + "wrong number of fields");
        const auto number = [&](int c, const std::string& name) {
            return finite_field(r.fields[static_cast<std::size_t>(c)], name, at);
        };
        paired_row p;
        p.line = r.line;
        p.name = nc >= 0 ? r.fields[nc] : "";
        p.energy_text = r.fields[static_cast<std::size_t>(sc.energy)];
        std::tie(p.energy, p.state) = read_initial_state(r, sc, model, at);
        p.time = number(tc, "time");
        if (!(p.time > 0)) throw input_error(at + "time '" + r.fields[tc] + "' must be > 0");
        const double a = number(ac, "arm");
        if (!arm_numbered(a)) throw input_error(at + "arm '" + r.fields[ac] + "' is not 1 or 2");
        p.flip_arm = *arm_numbered(a);
        const double f = number(fc, "flips");
        if (!(f >= 0) || f != std::floor(f) || f > 1e15)
            throw input_error(at + "flips '" + r.fields[fc] + "' is not a count");
        p.flips = static_cast<std::uint64_t>(f);
        const std::optional<std::string> named =
            cc >= 0 ? criterion_named(r.fields[cc])
                    : std::optional<std::string>(default_criterion());
        if (!named)
            throw input_error(at + "criterion '" + r.fields[cc] + "' is not " +
                              criterion_alternatives());
        p.criterion = *named;
        try {  // a trajectory that could not finish: the file's line, not an option
            check_trajectory_work(model, p.energy, p.time, "time");
        } catch (const input_error& e) {
            throw input_error(at + "time " + r.fields[tc] + ": " + e.detail());
        }
        rows.push_back(p);
    }
    if (rows.empty()) throw input_error(file.string() + ": no trajectories");
    return rows;
}

/// flipflux's counts: each distinct (state, T) integrated once with every criterion its rows ask.
void count_flips(const double_pendulum<double>& model, const std::filesystem::path& file,
                 std::vector<paired_row>& rows, const paired_check_options& options) {
    using key = std::tuple<std::array<double, 4>, double, double>;  // state, T, E
    std::map<key, std::vector<std::size_t>> trajectories;
    for (std::size_t i = 0; i < rows.size(); ++i)
        trajectories[{rows[i].state, rows[i].time, rows[i].energy}].push_back(i);
    std::uint64_t index = 0;
    for (const auto& entry : trajectories) {
        // named, not structured bindings: clang 14 cannot capture those in the lambda below
        const key& k = entry.first;
        const std::vector<std::size_t>& members = entry.second;
        std::vector<std::unique_ptr<flip_detector_base>> owned;
        std::vector<flip_detector_base*> detectors;
        std::vector<std::size_t> counted;  // rows with a detector, in detector order
        for (const std::size_t i : members) {
            const paired_row& p = rows[i];
            if (!(p.energy > criterion_threshold(model, p.flip_arm, p.criterion))) {
                rows[i].reference = 0;  // no flip possible: flipflux counts none
                continue;
            }
            owned.push_back(
                make_criterion(model, p.flip_arm, p.criterion, p.energy).detector->clone());
            detectors.push_back(owned.back().get());
            counted.push_back(i);
        }
        ensemble_options o;
        o.energy = std::get<2>(k);
        o.time = std::get<1>(k);
        o.rtol = options.rtol;
        o.atol = options.rtol;
        o.chaos = false;
        const auto run = [&](const ensemble_options& x) {
            for (auto& d : owned)  // fresh detectors: simulate_trajectory starts them
                d = d->clone();
            for (std::size_t d = 0; d < owned.size(); ++d)
                detectors[d] = owned[d].get();
            const trajectory_result r =
                simulate_trajectory(model, std::get<0>(k), x, index, detectors);
            if (r.status != rk_status::ok)
                throw input_error(file.string() + ":" + std::to_string(rows[members.front()].line) +
                                  ": flipflux could not integrate this state (" +
                                  to_string(r.status) + ")");
            return r;
        };
        const trajectory_result tight = run(o);
        ensemble_options loose = o;  // another method at a looser tolerance
        loose.method = integration_method::dopri5;
        loose.rtol = loose.atol = 1e-9;
        const trajectory_result other = run(loose);
        ++index;
        for (std::size_t d = 0; d < counted.size(); ++d) {
            rows[counted[d]].reference = tight.flips(d);
            rows[counted[d]].stable = tight.flips(d) == other.flips(d);
        }
    }
}

std::string describe(const paired_row& p) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "line %d%s%s%s: arm %s %s, E = %s, T = %.10g: candidate %llu flips, flipflux "
                  "%llu",
                  p.line, p.name.empty() ? "" : " (trajectory ", p.name.c_str(),
                  p.name.empty() ? "" : ")", to_string(p.flip_arm).c_str(), p.criterion.c_str(),
                  p.energy_text.c_str(), p.time, static_cast<unsigned long long>(p.flips),
                  static_cast<unsigned long long>(p.reference));
    return buf;
}

}  // namespace

bool paired_check_report::passed() const {
    if (groups.empty()) return false;
    return std::none_of(groups.begin(), groups.end(),
                        [](const paired_group& g) { return g.what == paired_group::status::fail; });
}

paired_check_report check_paired_ensemble(const double_pendulum<double>& model,
                                          const std::filesystem::path& candidate,
                                          const paired_check_options& options) {
    std::vector<paired_row> rows = read_rows(candidate, model);
    count_flips(model, candidate, rows, options);
    paired_check_report report;
    report.options = options;
    std::map<std::tuple<std::string, std::string, double>, std::vector<const paired_row*>> groups;
    std::vector<std::tuple<std::string, std::string, double>> order;
    for (const paired_row& p : rows) {
        const auto k = std::make_tuple(p.criterion, to_string(p.flip_arm), p.energy);
        if (!groups.count(k)) order.push_back(k);
        groups[k].push_back(&p);
        if (report.first_difference.empty() && p.flips != p.reference)
            report.first_difference = describe(p);
    }
    for (const auto& k : order) {
        const std::vector<const paired_row*>& g = groups[k];
        paired_group out;
        out.criterion = std::get<0>(k);
        out.arm = std::get<1>(k);
        out.energy = g.front()->energy_text;
        out.trajectories = g.size();
        const double n = static_cast<double>(g.size());
        double sum = 0, cand = 0, ref = 0;
        for (const paired_row* p : g) {
            const double d = static_cast<double>(p->flips) - static_cast<double>(p->reference);
            sum += d;
            cand += static_cast<double>(p->flips);
            ref += static_cast<double>(p->reference);
            out.stable += p->stable;
            if (p->flips == p->reference) {
                ++out.identical;
                continue;
            }
            out.unexpected += p->stable;
            if (out.first_difference.empty())
                out.first_difference = describe(*p), out.first_line = p->line;
        }
        out.mean_difference = sum / n;
        out.candidate_mean = cand / n;
        out.flipflux_mean = ref / n;
        double ss = 0;
        for (const paired_row* p : g) {
            const double d = static_cast<double>(p->flips) - static_cast<double>(p->reference);
            ss += (d - out.mean_difference) * (d - out.mean_difference);
        }
        out.standard_error = g.size() > 1 ? std::sqrt(ss / (n - 1) / n) : 0;
        // the mean test: t = d / se has Student's law with n - 1 degrees of freedom (se from the
        // pairs themselves); graded by its two-sided tail probability as the normal z would be
        // (z 3 and 5), so that a few chaotic pairs do not fail a correct simulator. No spread
        // (n = 1, or every difference alike): no mean test; the pairs decide.
        out.z = out.standard_error > 0 ? out.mean_difference / out.standard_error : 0;
        double z = 0;  // the normal z of the same tail probability
        if (out.standard_error > 0) {
            const boost::math::students_t t_law(n - 1);
            const boost::math::normal_distribution<double> normal;
            const double tail = boost::math::cdf(boost::math::complement(t_law, std::abs(out.z)));
            z = tail > 0 ? boost::math::quantile(boost::math::complement(normal, tail))
                         : std::numeric_limits<double>::infinity();
        }
        out.mean_z = z;
        const double allowed = 1 + 0.05 * static_cast<double>(out.stable);
        out.what = z >= options.fail_z || static_cast<double>(out.unexpected) > allowed
                       ? paired_group::status::fail
                   : z >= options.warn_z || out.unexpected > 0 ? paired_group::status::warn
                                                               : paired_group::status::pass;
        report.groups.push_back(out);
    }
    return report;
}

std::string format_paired_check(const paired_check_report& r) {
    std::size_t pass = 0, warn = 0, fail = 0, n = 0;
    for (const paired_group& g : r.groups) {
        n += g.trajectories;
        pass += g.what == paired_group::status::pass;
        warn += g.what == paired_group::status::warn;
        fail += g.what == paired_group::status::fail;
    }
    std::string out;
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "summary: %zu groups (criterion, arm, energy), %zu paired counts: %zu pass, %zu "
                  "warn, %zu FAIL -> %s\n",
                  r.groups.size(), n, pass, warn, fail, r.passed() ? "PASSED" : "FAILED");
    out += buf;
    std::snprintf(buf, sizeof buf,
                  "tests: mean: t = mean paired difference / its std.error, its Student tail "
                  "graded as a normal z (warn >= %g, FAIL >= %g; no spread: no mean test); pairs: "
                  "counts that differ where flipflux's two integrations (DOP853 rtol 1e-12, "
                  "DOPRI5 rtol 1e-9) agree (warn 1, FAIL more than 1 + 5 %% of those)\n",
                  r.options.warn_z, r.options.fail_z);
    out += buf;
    out += "first difference: " +
           (r.first_difference.empty() ? std::string("none (every count identical)")
                                       : r.first_difference) +
           "\n";
    std::snprintf(buf, sizeof buf,
                  "%-8s %-3s %-8s %-6s %-10s %-17s %-12s %-13s %-11s %-11s %-8s %s\n", "crit.",
                  "arm", "energy", "trajs", "identical", "differ/stable", "cand. mean",
                  "flipflux mean", "mean diff.", "std.error", "t", "status");
    out += buf;
    for (const paired_group& g : r.groups) {
        const double allowed = 1 + 0.05 * static_cast<double>(g.stable);
        // each test's own grade, where it is not a pass
        std::string why;
        if (g.mean_z >= r.options.warn_z)
            why = g.mean_z >= r.options.fail_z ? "mean FAIL" : "mean warn";
        if (g.unexpected > 0)
            why += std::string(why.empty() ? "" : ", ") +
                   (static_cast<double>(g.unexpected) > allowed ? "pairs FAIL" : "pairs warn");
        char z[32];
        std::snprintf(z, sizeof z, "%+.2f", g.z);
        std::snprintf(buf, sizeof buf,
                      "%-8s %-3s %-8s %-6zu %-10zu %-17s %-12.6f %-13.6f %+-11.4f %-11.3e %-8s "
                      "%s%s\n",
                      g.criterion.c_str(), g.arm.c_str(), g.energy.c_str(), g.trajectories,
                      g.identical,
                      (std::to_string(g.unexpected) + "/" + std::to_string(g.stable)).c_str(),
                      g.candidate_mean, g.flipflux_mean, g.mean_difference, g.standard_error, z,
                      g.what == paired_group::status::pass   ? "pass"
                      : g.what == paired_group::status::warn ? "warn"
                                                             : "FAIL",
                      why.empty() ? "" : (" (" + why + ")").c_str());
        out += buf;
    }
    return out;
}

}  // namespace flipflux
