// Validating a simulator's trajectory (validation/trajectory_check.hpp, docs/validating.md).
#include "flipflux/validation/trajectory_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/study/criteria.hpp"

namespace flipflux {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

/// Significant digits of a decimal text, trailing zeros not counted ("0.50" has 1).
int significant_digits(const std::string& text) {
    const std::size_t e = text.find_first_of("eE");
    std::string digits;
    for (std::size_t i = 0; i < std::min(e, text.size()); ++i)
        if (std::isdigit(static_cast<unsigned char>(text[i]))) digits += text[i];
    const std::size_t first = digits.find_first_not_of('0');
    if (first == std::string::npos) return 0;
    const std::size_t last = digits.find_last_not_of('0');
    return static_cast<int>(last - first + 1);
}

struct flip_row {
    double time;
    int direction;
    int line;
};

using stream_key = std::pair<std::string, std::string>;  // arm, criterion

struct event_file {
    std::map<stream_key, std::vector<flip_row>> streams;
    std::vector<std::string> criteria;  ///< in the file's rows, in order of appearance
    bool double_digits = true;          ///< every time has at most 17 significant digits
    bool has_state_column = false;
    bool has_criterion_column = false;
};

event_file read_events(const std::filesystem::path& file, const event_comparison_options& o,
                       bool reference) {
    const csv_table t = read_csv(file);
    const int tc = column_index(t, "time"), ac = column_index(t, "arm"),
              cc = column_index(t, "criterion"), dc = column_index(t, "direction"),
              sc = column_index(t, "state");
    if (tc < 0 || ac < 0 || dc < 0 || (reference && cc < 0))
        throw input_error(file.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name the columns time, arm, " +
                          (reference ? "criterion, direction" : "direction[, criterion]"));
    if (reference && sc < 0 && !o.state.empty())
        throw input_error::about("state", "'" + o.state +
                                              "' names a trajectory, but the reference '" +
                                              file.string() + "' has no state column");
    if (reference && sc >= 0 && o.state.empty())
        throw input_error::about("state", "the reference '" + file.string() +
                                              "' lists several trajectories: choose one");
    event_file out;
    out.has_state_column = sc >= 0;
    out.has_criterion_column = cc >= 0;
    bool found = false;
    for (const csv_row& r : t.rows) {
        const std::string at = file.string() + ":" + std::to_string(r.line) + ": ";
        if (r.fields.size() != t.header.size()) throw input_error(at + "wrong number of fields");
        if (sc >= 0 && !o.state.empty() && r.fields[sc] != o.state) continue;
        found = true;
        const double time = finite_field(r.fields[tc], "time", at);
        out.double_digits = out.double_digits && significant_digits(r.fields[tc]) <= 17;
        // numbers as NumPy writes them (1.0, -1.0, 2.0); anything else is an input error, not a
        // stream of its own that "differs"
        const std::string& d = r.fields[dc];
        if (!is_decimal_number(d) || std::abs(finite_field(d, "direction", at)) != 1)
            throw input_error(at + "direction '" + d + "' is not 1 or -1");
        const int direction = finite_field(d, "direction", at) > 0 ? 1 : -1;
        const std::string& a = r.fields[ac];
        const double arm_number = is_decimal_number(a) ? finite_field(a, "arm", at) : 0;
        if (arm_number != 1 && arm_number != 2)
            throw input_error(at + "arm '" + a + "' is not 1 or 2");
        const std::optional<std::string> named =
            cc < 0 ? std::optional<std::string>(default_criterion())
                   : criterion_named(r.fields[cc]);
        if (!named)
            throw input_error(at + "criterion '" + r.fields[cc] + "' is not " +
                              criterion_alternatives());
        const std::string& criterion = *named;
        if (std::find(out.criteria.begin(), out.criteria.end(), criterion) == out.criteria.end())
            out.criteria.push_back(criterion);
        out.streams[{arm_number == 1 ? "1" : "2", criterion}].push_back({time, direction, r.line});
    }
    if (reference && !o.state.empty() && !found)
        throw input_error::about("state",
                                 "'" + o.state + "' has no rows in '" + file.string() + "'");
    for (auto& [k, v] : out.streams)
        std::stable_sort(v.begin(), v.end(),
                         [](const flip_row& x, const flip_row& y) { return x.time < y.time; });
    return out;
}

struct state_row {
    double t;
    std::array<double, 4> x;
    int line;
};

const std::array<const char*, 4> state_names{"theta1", "theta2", "l1", "l2"};

/// The rows of a states CSV (of `state` when the file has a state column).
std::vector<state_row> read_states(const std::filesystem::path& file, const std::string& state,
                                   bool& double_digits) {
    const csv_table t = read_csv(file);
    const int tc = column_index(t, "t"), sc = column_index(t, "state");
    std::array<int, 4> xc{};
    for (std::size_t i = 0; i < 4; ++i)
        xc[i] = column_index(t, state_names[i]);
    if (tc < 0 || std::find(xc.begin(), xc.end(), -1) != xc.end())
        throw input_error(file.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name the columns t, theta1, theta2, l1, l2");
    if (sc >= 0 && state.empty())
        throw input_error::about("state", "the states file '" + file.string() +
                                              "' lists several trajectories: choose one");
    std::vector<state_row> out;
    for (const csv_row& r : t.rows) {
        const std::string at = file.string() + ":" + std::to_string(r.line) + ": ";
        if (r.fields.size() != t.header.size()) throw input_error(at + "wrong number of fields");
        if (sc >= 0 && r.fields[sc] != state) continue;
        state_row s{finite_field(r.fields[tc], "t", at), {}, r.line};
        if (!(s.t >= 0)) throw input_error(at + "t '" + r.fields[tc] + "' must be >= 0");
        for (std::size_t i = 0; i < 4; ++i) {
            s.x[i] = finite_field(r.fields[xc[i]], state_names[i], at);
            double_digits = double_digits && significant_digits(r.fields[xc[i]]) <= 17;
        }
        out.push_back(s);
    }
    if (out.empty())
        throw input_error(file.string() + ": no states" +
                          (state.empty() ? std::string() : " of '" + state + "'"));
    return out;
}

/// The golden data's files beside a reference events file with a state column.
struct golden_beside {
    std::optional<double> time;  ///< provenance.json's "time": the trajectories' T
    std::filesystem::path states;
    std::filesystem::path horizons;
};

golden_beside golden_files_beside(const std::filesystem::path& reference) {
    golden_beside g;
    const std::filesystem::path dir = reference.parent_path();
    std::error_code ec;
    if (std::filesystem::is_regular_file(dir / "states.csv", ec)) g.states = dir / "states.csv";
    if (std::filesystem::is_regular_file(dir / "double_horizons.csv", ec))
        g.horizons = dir / "double_horizons.csv";
    if (std::filesystem::is_regular_file(dir / "provenance.json", ec)) {
        const nlohmann::json j = nlohmann::json::parse(
            read_input_file(dir / "provenance.json", "provenance"), nullptr, false);
        if (j.is_object() && j.contains("time") && j["time"].is_string() &&
            is_decimal_number(j["time"].get<std::string>())) {
            const double t = parse_real<double>(j["time"].get<std::string>(), "time");
            if (std::isfinite(t) && t > 0) g.time = t;
        }
    }
    return g;
}

/// The double horizon of `state` at the time tolerance (the tabulated tolerance at or below it,
/// for one accuracy class; NaN when the table lacks the state or the tolerance is below every
/// tabulated one (nothing measured there).
double double_horizon_of(const std::filesystem::path& table, const std::string& state,
                         double tolerance, const std::string& accuracy) {
    const csv_table t = read_csv(table);
    const int sc = column_index(t, "state"), tc = column_index(t, "time_tolerance"),
              ac = column_index(t, "accuracy"), hc = column_index(t, "horizon");
    if (sc < 0 || tc < 0 || ac < 0 || hc < 0)
        throw input_error(table.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name state, time_tolerance, accuracy, horizon");
    double best_tol = -1, best = std::nan("");
    for (const csv_row& r : t.rows) {
        const std::string at = table.string() + ":" + std::to_string(r.line) + ": ";
        if (r.fields.size() != t.header.size()) throw input_error(at + "wrong number of fields");
        if (r.fields[sc] != state || r.fields[ac] != accuracy) continue;
        const double tol = finite_field(r.fields[tc], "time_tolerance", at);
        const double h = finite_field(r.fields[hc], "horizon", at);
        if (tol <= tolerance * (1 + 1e-12) && tol > best_tol) best_tol = tol, best = h;
    }
    return best_tol > 0 ? best : std::nan("");
}

std::string time_text(double t) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", t);
    return buf;
}

std::string describe(const flip_row* r) {
    if (!r) return "none";
    char buf[96];
    std::snprintf(buf, sizeof buf, "t = %.17g, direction %+d (line %d)", r->time, r->direction,
                  r->line);
    return buf;
}

}  // namespace

event_comparison compare_flip_events(const std::filesystem::path& candidate,
                                     const std::filesystem::path& reference,
                                     const event_comparison_options& o) {
    if (!(o.time_tolerance > 0)) throw input_error::about("time-tol", "must be positive");
    if (!(o.until >= 0)) throw input_error::about("until", "must be >= 0");
    if (!(o.state_tolerance >= 0)) throw input_error::about("state-tol", "must be >= 0");
    const event_file cand = read_events(candidate, o, false), ref = read_events(reference, o, true);
    event_comparison out;
    out.double_horizon = out.double_horizon_limit = std::nan("");
    out.first_difference_time = infinity;

    // criteria: the candidate's unless insisted on
    out.criteria = o.criteria;
    if (out.criteria.empty()) {
        out.criteria_inferred = true;
        // no criterion column: upright; a column but no rows: the reference's (said below)
        out.criteria = !cand.criteria.empty()       ? cand.criteria
                       : !cand.has_criterion_column ? std::vector<std::string>{default_criterion()}
                                                    : ref.criteria;
        out.criteria_from_reference = cand.criteria.empty() && cand.has_criterion_column;
    }
    for (std::string& c : out.criteria)
        c = criterion_named(c).value_or(c);

    // the states and the ends of the trajectories
    const golden_beside golden =
        ref.has_state_column ? golden_files_beside(reference) : golden_beside{};
    const std::filesystem::path ref_states_file =
        !o.reference_states.empty() ? o.reference_states : golden.states;
    bool cand_double = cand.double_digits, ref_double = true;
    std::vector<state_row> cand_states, ref_states;
    if (!o.candidate_states.empty())
        cand_states = read_states(o.candidate_states, o.state, cand_double);
    if (!ref_states_file.empty() && !o.candidate_states.empty())
        ref_states = read_states(ref_states_file, o.state, ref_double);
    out.candidate_double = cand_double;
    out.reference_states_known = !ref_states_file.empty();

    double ref_end = infinity, cand_end = infinity;
    const bool cand_end_known = !cand_states.empty();
    std::string ref_end_from, cand_end_from;
    if (golden.time) {
        ref_end = *golden.time;
        ref_end_from = "its provenance.json";
    } else if (!ref_states.empty()) {
        ref_end = 0;
        for (const state_row& s : ref_states)
            ref_end = std::max(ref_end, s.t);
        ref_end_from = "its last state";
    }
    if (!cand_states.empty()) {
        cand_end = 0;
        for (const state_row& s : cand_states)
            cand_end = std::max(cand_end, s.t);
        cand_end_from = "its last state";
    }
    const double state_tol = o.state_tolerance > 0 ? o.state_tolerance : o.time_tolerance;
    if (!golden.horizons.empty() && !o.state.empty()) {
        // the horizons were measured with events and states at one tolerance: the tighter one
        const double tol =
            cand_states.empty() ? o.time_tolerance : std::min(o.time_tolerance, state_tol);
        out.double_horizon = double_horizon_of(golden.horizons, o.state, tol, "rtol-1e-12");
        out.double_horizon_limit = double_horizon_of(golden.horizons, o.state, tol, "limit");
    }

    // the horizon: events and states before it are compared (at an end of the trajectories,
    // up to it)
    bool inclusive = true;
    if (o.until > 0) {
        out.horizon = o.until;
        out.horizon_note = "up to t = " + time_text(o.until) + " (" + o.name("until") + ")";
        if (o.until > ref_end)
            out.horizon_note += ", beyond the reference's end t = " + time_text(ref_end) + " (" +
                                ref_end_from + "): nothing after it is compared";
    } else {
        out.horizon = std::min(ref_end, cand_end);
        std::string ends;
        if (ref_end < infinity)
            ends += "reference " + time_text(ref_end) + " (" + ref_end_from + ")";
        if (cand_end < infinity)
            ends += (ends.empty() ? "" : ", ") + std::string("candidate ") + time_text(cand_end) +
                    " (" + cand_end_from + ")";
        if (out.horizon < infinity)
            out.horizon_note = "up to t = " + time_text(out.horizon) +
                               ", the common horizon of the trajectories (" + ends + ")";
        else
            out.horizon_note =
                "every event (the trajectories' ends are unknown: " + o.name("until") +
                " T, or the states files, say where they end)";
        if (cand_double && !golden.horizons.empty() && !o.state.empty() &&
            !std::isfinite(out.double_horizon))
            out.horizon_note += "; no double horizon of " + o.state +
                                " is tabulated at or below this tolerance (nothing tells a bug "
                                "from chaos there)";
        if (cand_double && std::isfinite(out.double_horizon) && out.double_horizon < out.horizon) {
            out.horizon = out.double_horizon;
            inclusive = false;
            out.horizon_note = "before t = " + time_text(out.double_horizon) +
                               ", the double horizon of " + o.state +
                               " at this time tolerance (the candidate's numbers are "
                               "double precision; data/golden/trajectories/double_horizons.csv: a "
                               "correct simulator at rtol 1e-12 agrees up to there, chaos parts "
                               "them after it); " +
                               o.name("until") + " overrides";
        }
    }
    const auto before = [&](double t) { return inclusive ? t <= out.horizon : t < out.horizon; };

    // events, stream by stream
    const auto wanted = [&](const stream_key& k) {
        return std::find(out.criteria.begin(), out.criteria.end(), k.second) != out.criteria.end();
    };
    std::map<stream_key, int> keys;
    for (const auto& [k, v] : cand.streams)
        if (wanted(k)) keys[k] = 0;
    for (const auto& [k, v] : ref.streams)
        if (wanted(k)) keys[k] = 0;
    static const std::vector<flip_row> none;
    const auto note_difference = [&](double when, const std::string& what) {
        out.differs = true;
        if (when < out.first_difference_time) {
            out.first_difference_time = when;
            out.first_difference = what;
        }
    };
    for (const auto& [k, unused_value] : keys) {
        const auto ci = cand.streams.find(k), ri = ref.streams.find(k);
        const std::vector<flip_row>& c = ci == cand.streams.end() ? none : ci->second;
        const std::vector<flip_row>& r = ri == ref.streams.end() ? none : ri->second;
        event_stream_summary s{k.first, k.second, 0, 0, 0, 0};
        // a candidate event counts when it or its reference partner lies before the horizon
        for (std::size_t j = 0; j < c.size(); ++j)
            s.candidate += before(c[j].time) || (j < r.size() && before(r[j].time));
        for (const flip_row& e : r)
            s.reference += before(e.time);
        for (std::size_t i = 0;; ++i) {
            const flip_row* rr = i < r.size() && before(r[i].time) ? &r[i] : nullptr;
            const flip_row* cr = i < c.size() ? &c[i] : nullptr;
            // a candidate event beyond the horizon, or just before it with its reference
            // partner just after, is not a difference (nor counted: it was not compared)
            if (!rr && (!cr || !before(cr->time + o.time_tolerance))) {
                for (std::size_t j = i; j < c.size(); ++j)
                    s.candidate -= before(c[j].time) || (j < r.size() && before(r[j].time));
                break;
            }
            if (rr && cr && cr->direction == rr->direction &&
                std::abs(cr->time - rr->time) <= o.time_tolerance) {
                s.max_time_difference =
                    std::max(s.max_time_difference, std::abs(cr->time - rr->time));
                s.agreeing = i + 1;
                continue;
            }
            const double when = std::min(cr ? cr->time : infinity, rr ? rr->time : infinity);
            // events are paired in order: say when the difference is a missed or an extra event
            const auto agree = [&](const flip_row* x, const flip_row* y) {
                return x && y && x->direction == y->direction &&
                       std::abs(x->time - y->time) <= o.time_tolerance;
            };
            std::string why;  // one or two missed (a grazing pair) or extra events
            for (std::size_t skip = 1; skip <= 2 && why.empty(); ++skip) {
                const std::string n = skip == 1 ? "an event" : "two events";
                if (cr && i + skip < r.size() && agree(cr, &r[i + skip]))
                    why = " (the candidate misses " + n +
                          " of the reference from t = " + time_text(r[i].time) + ")";
                else if (rr && i + skip < c.size() && agree(&c[i + skip], rr))
                    why = " (the candidate has " + n + " more, from t = " + time_text(c[i].time) +
                          ")";
            }
            if (why.empty() && !cr && !cand_end_known)
                why = " (if the candidate stopped before t = " + time_text(rr->time) +
                      ", say where: its " + o.name("states") + ", or " + o.name("until") + ")";
            note_difference(when, "arm " + k.first + " " + k.second + " event " +
                                      std::to_string(i + 1) + ": candidate " + describe(cr) +
                                      "; reference " + describe(rr) + why);
            break;
        }
        out.streams.push_back(s);
    }

    // states at the reference's sample times
    for (const state_row& cs : cand_states) {
        const auto match =
            std::find_if(ref_states.begin(), ref_states.end(), [&](const state_row& rs) {
                return std::abs(rs.t - cs.t) <= 1e-9 * std::max(1.0, std::abs(rs.t));
            });
        if (match == ref_states.end() || !before(cs.t)) {
            ++out.states_not_compared;
            out.states_not_compared_at +=
                (out.states_not_compared_at.empty() ? "" : ", ") + time_text(cs.t);
            continue;
        }
        state_row_check row{cs.t, 0, state_names[0], cs.line, true};
        for (std::size_t i = 0; i < 4; ++i) {
            double d = cs.x[i] - match->x[i];
            if (i < 2) d = std::remainder(d, 2 * std::numbers::pi);  // wrapped angles agree
            if (std::abs(d) > row.max_difference || std::isnan(d))
                row.max_difference = std::abs(d), row.component = state_names[i];
        }
        row.agrees = row.max_difference <= state_tol;
        if (!row.agrees) {
            char buf[256];
            std::snprintf(buf, sizeof buf,
                          "the state at t = %.10g (candidate line %d): %s differs by %.3e "
                          "(state tolerance %g)",
                          cs.t, cs.line, row.component.c_str(), row.max_difference, state_tol);
            note_difference(cs.t, buf);
        }
        out.states.push_back(row);
    }

    // where a difference falls relative to the double horizon
    if (std::isfinite(out.double_horizon) && !o.state.empty()) {
        const std::string h = "the double horizon t = " + time_text(out.double_horizon) + " of " +
                              o.state +
                              " at this time tolerance (simulators at rtol 1e-12 or better";
        const std::string limit =
            std::isfinite(out.double_horizon_limit)
                ? "; " + time_text(out.double_horizon_limit) + " at the double limit)"
                : ")";
        const bool maybe_stopped =
            !cand_end_known && out.first_difference.find("candidate none") != std::string::npos;
        if (out.differs && out.first_difference_time < out.double_horizon)
            out.verdict = "the first difference is before " + h + limit +
                          (maybe_stopped ? ": a bug, not chaos, unless the candidate stopped "
                                           "there (its " +
                                               o.name("states") + ", or " + o.name("until") +
                                               ", say where it ended)"
                                         : ": a bug, not chaos");
        else if (out.differs && out.double_horizon >= ref_end)
            out.verdict = "the first difference is at t = " + time_text(out.first_difference_time) +
                          ", where none of the measured double runs parted from the reference (" +
                          h + limit +
                          " is its end): the candidate's error there is larger than theirs (the "
                          "Taylor route at the double limit, DOP853 and DOPRI5 at rtol 1e-12); a "
                          "tighter tolerance, or a looser " +
                          o.name("time_tol") + " / " + o.name("state_tol") +
                          ", tells a loose integrator from a bug";
        else if (out.differs)
            out.verdict = "the first difference is after " + h + limit +
                          ": what chaos does to a correct double-precision run, not evidence of "
                          "a bug; compare before the horizon (the default without " +
                          o.name("until") + ")";
        else if (!cand_double)
            out.verdict =
                "the candidate's numbers carry more than double's 17 digits: compared "
                "over the common horizon, not only up to " +
                h + limit;
    }
    return out;
}

std::string format_event_comparison(const event_comparison& c, const event_comparison_options& o) {
    std::string out;
    char buf[512];
    std::size_t cand = 0, ref = 0, agree = 0;
    for (const auto& s : c.streams) {
        cand += s.candidate;
        ref += s.reference;
        agree += s.agreeing;
    }
    std::snprintf(buf, sizeof buf,
                  "summary: %zu candidate events, %zu reference events, %zu agree (time "
                  "tolerance %g) -> %s\n",
                  cand, ref, agree, o.time_tolerance, c.differs ? "DIFFER" : "AGREE");
    out += buf;
    std::string criteria;
    for (const std::string& k : c.criteria)
        criteria += (criteria.empty() ? "" : ",") + k;
    out += "compared: criteria " + (criteria.empty() ? std::string("(none)") : criteria) +
           (!c.criteria_inferred ? " (" + o.name("criteria") + ")"
            : c.criteria_from_reference
                ? std::string(" (the reference's: the candidate reports no event)")
                : " (those the candidate reports; " + o.name("criteria") + " insists on others)") +
           "; " + c.horizon_note + "\n";
    if (c.differs) out += "first difference: " + c.first_difference + "\n";
    if (!c.differs && agree == 0 && c.states.empty())
        out +=
            "note: nothing was compared (no event and no state before the horizon): this "
            "AGREE says nothing; " +
            o.name("until") + " or a looser " + o.name("time_tol") + " compares more\n";
    if (!c.verdict.empty()) out += "verdict: " + c.verdict + "\n";
    std::snprintf(buf, sizeof buf, "%-4s %-9s %-10s %-10s %-9s %s\n", "arm", "criterion",
                  "candidate", "reference", "agreeing", "max |dt| (agreeing)");
    out += buf;
    for (const auto& s : c.streams) {
        std::string dt = "-";  // no agreeing event: nothing to bound
        if (s.agreeing > 0) {
            std::snprintf(buf, sizeof buf, "%.3e", s.max_time_difference);
            dt = buf;
        }
        std::snprintf(buf, sizeof buf, "%-4s %-9s %-10zu %-10zu %-9zu %s\n", s.arm.c_str(),
                      s.criterion.c_str(), s.candidate, s.reference, s.agreeing, dt.c_str());
        out += buf;
    }
    if (!o.candidate_states.empty()) {
        if (c.states.empty())
            out += "states: none compared (" + std::to_string(c.states_not_compared) +
                   " candidate rows after the horizon or at no reference sample time" +
                   (!c.reference_states_known && c.states_not_compared > 0
                        ? "; " + o.name("reference_states") + " gives the reference's"
                        : std::string()) +
                   ")\n";
        for (const auto& s : c.states) {
            std::snprintf(buf, sizeof buf, "state t = %-10.6g max |difference| %.3e (%s) -> %s\n",
                          s.t, s.max_difference, s.component.c_str(),
                          s.agrees ? "agrees" : "DIFFERS");
            out += buf;
        }
        if (!c.states.empty() && c.states_not_compared > 0)
            out += "states not compared (after the horizon or at no reference sample time): t = " +
                   c.states_not_compared_at + "\n";
    }
    return out;
}

}  // namespace flipflux
