// Validating a simulator (validation/simulator_check.hpp, docs/validating.md): its ensemble flip
// counts against the predicted rates by the exact identity E[N_tau] = tau f / Omega (a single
// trajectory's events: validation/trajectory_check.hpp).
#include "flipflux/validation/simulator_check.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <vector>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/special_functions/gamma.hpp>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/io/text_table.hpp"
#include "flipflux/study/criteria.hpp"

namespace flipflux {
namespace {

bool parse_count(const std::string& text, std::uint64_t& out) {
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, out);
    return r.ec == std::errc() && r.ptr == end && !text.empty();
}

bool parse_positive(const std::string& text, double& out) {
    if (!is_decimal_number(text)) return false;
    out = parse_real<double>(text, "value");
    return std::isfinite(out) && out > 0;
}

// Var(N_tau) from a pilot ensemble of flipflux's simulator: the sample variance plus three of its
// standard errors (the fourth central moment's estimate). NOTE: no Poisson floor: the counts are
// sub-Poisson where flips are regular (rotating arms above E_max: Var N ~ 0.5 E[N] at E = 8).
struct pilot_key {
    double energy, time;
    std::string criterion;
    arm a;
    auto operator<=>(const pilot_key&) const = default;
};

double pilot_variance(const double_pendulum<double>& model, const pilot_key& k,
                      const ensemble_check_options& o) {
    ensemble_options e;
    e.energy = k.energy;
    e.time = k.time;
    e.trajectories = o.pilot_trajectories;
    e.seed = o.seed;
    e.rtol = o.rtol;
    e.chaos = false;
    // a trajectory that could not finish is refused before minutes of integration (the
    // candidate's time comes from its file)
    check_trajectory_work(model, k.energy, k.time, "time");
    ensemble_criterion c = make_criterion(model, k.a, k.criterion, k.energy);
    const ensemble_result r = run_ensemble(model, e, {c});
    // failed trajectories (stopped before T) are not data, as in every other statistic
    std::vector<double> counts;
    for (const trajectory_result& t : r.trajectories)
        if (t.status == rk_status::ok && !t.abandoned)
            counts.push_back(static_cast<double>(t.flips(0)));
    if (counts.size() < 2)
        throw input_error::about("pilot", "fewer than 2 of its trajectories finished");
    const double P = static_cast<double>(counts.size());
    double mean = 0;
    for (const double n : counts)
        mean += n;
    mean /= P;
    double m2 = 0, m4 = 0;
    for (const double n : counts) {
        const double d = n - mean;
        m2 += d * d;
        m4 += d * d * d * d;
    }
    const double s2 = m2 / (P - 1);
    m4 /= P;
    return s2 + 3 * std::sqrt(std::max(m4 - s2 * s2, 0.0) / P);
}

struct ensemble_columns {
    int criterion, arm, energy, trajectories, time, flips, flips_sq;
};

// Reads one row into x (status malformed with a note when it cannot); returns false then.
bool read_row(const csv_row& row, const csv_table& t, const ensemble_columns& c,
              ensemble_check_entry& x, std::uint64_t& flips_sq, bool& has_flips_sq) {
    if (row.fields.size() != t.header.size()) {
        x.note = "expected " + std::to_string(t.header.size()) + " fields, found " +
                 std::to_string(row.fields.size());
        return false;
    }
    const auto& f = row.fields;
    x.criterion = f[c.criterion];
    x.arm = f[c.arm];
    x.energy = f[c.energy];
    if (!criterion_named(x.criterion) || *criterion_named(x.criterion) != x.criterion)
        x.note = "criterion '" + x.criterion + "' is not " + criterion_alternatives();
    else if (!arm_named(x.arm))
        x.note = "arm '" + x.arm + "' is not 1 or 2";
    else if (!parse_positive(x.energy, x.simulated))
        x.note = "energy '" + x.energy + "' is not a positive number";
    else if (!parse_count(f[c.trajectories], x.trajectories) || x.trajectories < 2)
        x.note = "trajectories '" + f[c.trajectories] + "' is not a whole number >= 2";
    else if (!parse_positive(f[c.time], x.time))
        x.note = "time '" + f[c.time] + "' is not a positive number";
    else if (!parse_count(f[c.flips], x.flips))
        x.note = "flips '" + f[c.flips] + "' is not a whole number";
    has_flips_sq = c.flips_sq >= 0 && !f[c.flips_sq].empty();
    if (x.note.empty() && has_flips_sq) {
        const double n = static_cast<double>(x.flips);
        if (!parse_count(f[c.flips_sq], flips_sq))
            x.note = "flips_sq '" + f[c.flips_sq] + "' is not a whole number";
        else if (static_cast<double>(flips_sq) <
                 std::max(n, n * n / x.trajectories) * (1 - std::numeric_limits<double>::epsilon()))
            x.note = "flips_sq '" + f[c.flips_sq] +
                     "' is below max(flips, flips^2 / trajectories): not a sum of squared counts";
    }
    return x.note.empty();
}

// The least variance of an integer-valued count with mean mu: its values floor(mu) and ceil(mu)
// alone, {mu} (1 - {mu}) ({mu} the fractional part). A floor that holds for any simulator, also
// where a pilot or the candidate saw every trajectory count the same (a zero sample variance).
double least_count_variance(double mu) {
    const double f = mu - std::floor(mu);
    return f * (1 - f);
}

// Grades a row from its z. Where few flips are expected the normal approximation behind z fails
// (a count of 1 where 0.03 are expected is 5 standard errors off, yet happens 3 % of the time),
// so z is then the normal quantile of the count's tail probability under a compound Poisson law
// with the row's mean and variance: bursts of D = max(1, Var N / E N) flips (recrossings come in
// bursts; D = 1 where counts are sub-Poisson, which widens the tail), lambda / D of them
// expected among the M trajectories.
void grade(ensemble_check_entry& x, const ensemble_check_options& o, double variance) {
    using status = ensemble_check_entry::status;
    const double M = static_cast<double>(x.trajectories), mu = x.predicted * x.time;
    const double lambda = M * mu, n = static_cast<double>(x.flips);
    if (x.predicted == 0) {  // no flip possible: exact agreement or none
        x.z = x.flips == 0 ? 0 : std::numeric_limits<double>::infinity();
    } else if (const double D = std::max(1.0, variance / mu); lambda / D < few_flips_expected) {
        const boost::math::normal_distribution<double> normal;
        const double bursts = lambda / D, k = n / D;
        if (n > lambda) {  // P(at least k bursts)
            const double p = boost::math::gamma_p(k, bursts);
            x.z = p >= 0.5 ? 0
                  : p > 0  ? boost::math::quantile(boost::math::complement(normal, p))
                           : std::numeric_limits<double>::infinity();
        } else {  // P(at most k bursts)
            const double p = boost::math::gamma_q(k + 1, bursts);
            x.z = p >= 0.5 ? 0
                  : p > 0  ? boost::math::quantile(normal, p)
                           : -std::numeric_limits<double>::infinity();
        }
        x.note = "few bursts expected (" + to_decimal(bursts, 3) + " of " + to_decimal(D, 3) +
                 " flips): z from the compound Poisson tail";
    } else {
        x.z = (x.simulated - x.predicted) / x.standard_error;
    }
    const double a = std::abs(x.z);
    x.what = a < o.warn_z ? status::pass : a < o.fail_z ? status::warn : status::fail;
}

}  // namespace

std::size_t ensemble_check_report::count(ensemble_check_entry::status s) const {
    return static_cast<std::size_t>(
        std::count_if(entries.begin(), entries.end(), [s](const auto& e) { return e.what == s; }));
}

bool ensemble_check_report::passed() const {
    using status = ensemble_check_entry::status;
    return !entries.empty() && count(status::fail) == 0 && count(status::malformed) == 0 &&
           count(status::no_prediction) == 0;
}

ensemble_check_report check_simulated_ensemble(const double_pendulum<double>& model,
                                               const std::filesystem::path& candidate,
                                               const ensemble_check_options& options) {
    using status = ensemble_check_entry::status;
    if (options.pilot_trajectories < 2)
        throw input_error::about("pilot", "'" + std::to_string(options.pilot_trajectories) +
                                              "' must be at least 2 trajectories");
    // the pilot holds one result per trajectory (flip times included): ~1 KB each, at least
    check_memory("pilot", std::to_string(options.pilot_trajectories),
                 1024.0 * static_cast<double>(options.pilot_trajectories),
                 "the pilot ensemble's trajectories");
    const csv_table t = read_csv(candidate);
    const ensemble_columns c{column_index(t, "criterion"), column_index(t, "arm"),
                             column_index(t, "energy"),    column_index(t, "trajectories"),
                             column_index(t, "time"),      column_index(t, "flips"),
                             column_index(t, "flips_sq")};
    if (c.criterion < 0 || c.arm < 0 || c.energy < 0 || c.trajectories < 0 || c.time < 0 ||
        c.flips < 0)
        throw input_error(candidate.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name the columns criterion, arm, energy, "
                          "trajectories, time, flips");
    ensemble_check_report report;
    report.options = options;
    std::map<pilot_key, double> pilots;  // Var(N_tau) per (E, tau, criterion, arm)
    for (const csv_row& row : t.rows) {
        ensemble_check_entry x;
        x.line = row.line;
        std::uint64_t flips_sq = 0;
        bool has_flips_sq = false;
        if (!read_row(row, t, c, x, flips_sq, has_flips_sq)) {
            report.entries.push_back(x);
            continue;
        }
        const double E = x.simulated, M = static_cast<double>(x.trajectories);
        const arm a = arm_named(x.arm).value();
        try {
            const auto p = criterion_prediction(model, a, x.criterion, E);
            if (!p) throw input_error("no registered rate");
            x.predicted = static_cast<double>(p->value);
        } catch (const std::exception& e) {
            x.what = status::no_prediction;
            x.note = e.what();
            report.entries.push_back(x);
            continue;
        }
        x.simulated = static_cast<double>(x.flips) / (M * x.time);
        double variance = 0;  // of one trajectory's count N_tau
        const double n = static_cast<double>(x.flips);
        const double own =
            has_flips_sq ? (static_cast<double>(flips_sq) - n * n / M) / (M - 1) : 0.0;
        // NOTE: a zero sample variance (every trajectory with the same count: a regularly
        // rotating arm, a short time) says nothing about the count's true variance; the pilot's
        // bound is used then, as without flips_sq
        if (x.predicted == 0) {  // at or below the arm's saddle energy: no flip possible
            x.variance = "none";
        } else if (has_flips_sq && own > 0 && !options.pilot_variance_always) {
            variance = own;
            x.variance = "candidate";
        } else {
            const pilot_key k{E, x.time, x.criterion, a};
            try {
                if (!pilots.count(k)) pilots[k] = pilot_variance(model, k, options);
            } catch (const input_error& e) {
                x.what = status::no_prediction;
                x.note = std::string("no pilot ensemble: ") + e.what();
                report.entries.push_back(x);
                continue;
            }
            variance = pilots[k];
            x.variance = "pilot " + std::to_string(options.pilot_trajectories);
        }
        if (x.predicted > 0)
            variance = std::max(variance, least_count_variance(x.predicted * x.time));
        x.standard_error = std::sqrt(std::max(variance, 0.0) / M) / x.time;
        grade(x, options, variance);
        report.entries.push_back(x);
    }
    return report;
}

std::string format_ensemble_check(const ensemble_check_report& r) {
    using status = ensemble_check_entry::status;
    std::string out;
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "summary: %zu rows: %zu pass, %zu warn, %zu FAIL, %zu malformed, %zu "
                  "no-prediction (pass |z| < %g, warn |z| < %g) -> %s\n",
                  r.entries.size(), r.count(status::pass), r.count(status::warn),
                  r.count(status::fail), r.count(status::malformed), r.count(status::no_prediction),
                  r.options.warn_z, r.options.fail_z, r.passed() ? "PASSED" : "FAILED");
    out += buf;
    text_table table({5, 13, 8, 3, 8, 13, 13, 11, 8, 10});
    table.row({"line", "status", "crit.", "arm", "energy", "simulated", "predicted", "std.error",
               "z", "variance", "note"});
    for (const auto& e : r.entries) {
        const std::vector<std::string> head{std::to_string(e.line), to_string(e.what), e.criterion,
                                            e.arm, e.energy};
        std::vector<std::string> cells = head;
        if (e.what != status::malformed && e.what != status::no_prediction)
            cells.insert(cells.end(),
                         {cell("%.8f", e.simulated), cell("%.8f", e.predicted),
                          cell("%.3e", e.standard_error), cell("%+.2f", e.z), e.variance});
        cells.push_back(e.note);
        table.row(cells);
    }
    return out + table.text();
}

}  // namespace flipflux
