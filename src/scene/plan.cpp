// Scene plans: what to compute (make_plan), and printing it (--dry-run).
#include "flipflux/scene/plan.hpp"

#include <limits.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/quantities/registry.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/saddle_viewer.hpp"
#include "flipflux/study/settings.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/trajectory.hpp"

namespace flipflux {

std::size_t plan::count(plan_step::kind k) const {
    return static_cast<std::size_t>(
        std::count_if(steps.begin(), steps.end(), [k](const plan_step& s) { return s.what == k; }));
}

bool needs_saddle_orbit(const std::string& quantity) {
    return find_quantity(quantity).needs_saddle_orbit;
}

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
    std::string out;
    for (const auto& x : v)
        out += (out.empty() ? "" : sep) + x;
    return out;
}

/// Energies as text, with the value in double for ordering and domain filtering.
struct energy_entry {
    double value;
    std::string text;
};

std::vector<energy_entry> expand(const energy_grid& g, const std::string& where) {
    std::vector<energy_entry> out;
    for (const std::string& text : energy_texts(g, where))
        out.push_back({parse_real<double>(text, where), text});
    return out;
}

std::string range_text(const std::vector<std::string>& energies) {
    if (energies.empty()) return "no energies";
    if (energies.size() == 1) return "E = " + energies.front();
    return std::to_string(energies.size()) + " energies, E = " + energies.front() + " .. " +
           energies.back();
}

[[noreturn]] void fail(const scene& s, int line, const std::string& key, const std::string& what) {
    throw scene_error(s.file.string() + ":" + std::to_string(line) + ": " + key + ": " + what);
}

/// No energy of a grid given twice (compared in the working precision: the same number written
/// twice would be computed, and written, twice).
void check_distinct(const energy_grid& g, precision prec, const scene& s, int line,
                    const std::string& key) {
    dispatch(prec, [&]<class Real>() {
        const std::vector<std::string> texts = energy_texts(g, key);
        std::vector<std::pair<Real, std::size_t>> v;
        for (std::size_t i = 0; i < texts.size(); ++i)
            v.emplace_back(parse_real<Real>(texts[i], key), i);
        std::sort(v.begin(), v.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        for (std::size_t i = 1; i < v.size(); ++i)
            if (v[i].first == v[i - 1].first)
                fail(s, line, key,
                     "E = " + texts[std::max(v[i].second, v[i - 1].second)] +
                         " is given twice (as '" + texts[std::min(v[i].second, v[i - 1].second)] +
                         "')");
    });
}

/// A directory the run will write to: not a file, its nearest existing ancestor a writable
/// directory, no name longer than the file system allows; checked without creating anything.
void check_output_dir(const std::filesystem::path& dir, const scene& s, int line,
                      const std::string& key) {
    const std::string text = "'" + dir.string() + "'";
    if (dir.string().size() >= PATH_MAX) fail(s, line, key, text + " is too long a path");
    for (const auto& part : dir)
        if (part.string().size() > NAME_MAX)
            fail(s, line, key, text + " has a name longer than " + std::to_string(NAME_MAX));
    std::error_code ec;
    std::filesystem::path p = dir.empty() ? std::filesystem::path(".") : dir;
    while (!std::filesystem::exists(p, ec)) {
        if (!p.has_parent_path() || p.parent_path() == p) {
            p = ".";
            break;
        }
        p = p.parent_path();
    }
    if (!std::filesystem::is_directory(p, ec))
        fail(s, line, key, text + " cannot be a directory: '" + p.string() + "' is a file");
    if (::access(p.c_str(), W_OK | X_OK) != 0)
        fail(s, line, key, text + " is not writable ('" + p.string() + "' is not)");
    // the permission bits do not tell all (root passes access() on /proc, a read-only mount):
    // create and remove a folder there, as the run's own creation would (nothing is left)
    std::string probe = (p / ".flipflux-plan-XXXXXX").string();
    if (::mkdtemp(probe.data()) == nullptr)
        fail(s, line, key,
             text + " cannot be created ('" + p.string() + "': " + std::strerror(errno) + ")");
    ::rmdir(probe.c_str());
}

/// Everything about an ensemble that needs no computation: its energies above the saddle energy
/// of every criterion's arm, distinct, and what its trajectories will hold within memory.
void check_ensemble(const scene& s, std::size_t i, const double_pendulum<double>& model) {
    const ensemble_spec& x = s.ensembles[i];
    const std::string key = "ensemble[" + std::to_string(i) + "]";
    check_distinct(x.energies, precision{real_kind::double_}, s, x.line, key + ".energies");
    const arm a = arm_of(x.arm);
    for (const std::string& text : energy_texts(x.energies, key + ".energies")) {
        const double e = parse_real<double>(text, key + ".energies");
        if (!(e > 0)) fail(s, x.line, key + ".energies", "E = " + text + " must be > 0");
        try {
            check_trajectory_work(model, e, parse_real<double>(x.time, key + ".time"), "time");
        } catch (const input_error& err) {
            fail(s, x.line, key + ".time", err.detail());
        }
        for (const std::string& c : x.criteria) {
            const double threshold = criterion_threshold(model, a, c);
            if (!(e > threshold))
                fail(s, x.line, key + ".energies",
                     "E = " + text + " is at or below arm " + std::to_string(x.arm) +
                         "'s saddle energy " + to_decimal(threshold) + " (criterion " + c +
                         " cannot flip)");
            if (const double ceiling = criterion_ceiling(model, a, c); !(e < ceiling))
                fail(s, x.line, key + ".energies", criterion_ceiling_text(e, ceiling, a, c));
        }
    }
    // the short estimator spends trajectories x time on trajectories of simulation_request's
    // default short_time
    double n = static_cast<double>(x.trajectories) * static_cast<double>(x.replicates);
    // (the simulation refuses a short time longer than the time: so does the plan, before the
    // scene's other steps run)
    if (x.estimator == "short" &&
        parse_real<double>(x.time, key + ".time") < simulation_request{}.short_time)
        fail(s, x.line, key + ".time",
             "'" + x.time + "' is shorter than the short estimator's trajectories (" +
                 to_decimal(simulation_request{}.short_time) + "): use estimator = \"long\"");
    if (x.estimator == "short")
        n = std::ceil(n * parse_real<double>(x.time, key + ".time") /
                      simulation_request{}.short_time);
    try {
        check_memory(key + ".trajectories", std::to_string(x.trajectories),
                     n * trajectory_record_bytes(x.criteria.size()),
                     to_decimal(n) + " trajectory records");
    } catch (const input_error& e) {
        fail(s, x.line, key + ".trajectories", e.detail());
    }
}

/// A [[trajectory]]: its state's energy bounds the work of its integration (as for ensembles).
void check_trajectory(const scene& s, std::size_t i, const double_pendulum<double>& model) {
    const trajectory_spec& t = s.trajectories[i];
    const std::string key = "trajectory[" + std::to_string(i) + "]";
    phase_point<double> x{};
    for (std::size_t k = 0; k < 4; ++k)
        x[k] = k < 2 ? parse_angle<double>(t.state[k], key + ".state")
                     : parse_real<double>(t.state[k], key + ".state");
    try {
        check_trajectory_work(model, model.hamiltonian(x),
                              parse_real<double>(t.time, key + ".time"), "time");
    } catch (const input_error& err) {
        fail(s, t.line, err.field().empty() ? std::string("model") : key + ".time", err.detail());
    }
    // the request's own checks, as the run makes them (its sample interval, rtol, criteria)
    trajectory_request<double> q;
    q.state = x;
    q.time = parse_real<double>(t.time, key + ".time");
    q.sample_interval = parse_real<double>(t.sample_interval, key + ".sample_interval");
    q.rtol = parse_real<double>(t.rtol, key + ".rtol");
    q.criteria = t.criteria;
    for (int a : t.arms)
        q.arms.push_back(arm_of(a));
    try {
        check_trajectory_request(q);
    } catch (const input_error& err) {
        fail(s, t.line, key + "." + (err.field().empty() ? std::string("state") : err.field()),
             err.detail());
    }
}

/// The checks of a scene that need no computation (so that --dry-run promises only what run
/// does): names, duplicates, domains, memory, output directories.
bool same_trajectories(const ensemble_spec& a, const ensemble_spec& b);

/// The island census's cross-references (ensemble_spec::census_of, classification_check_of).
void check_census(const scene& s, std::size_t i) {
    const ensemble_spec& x = s.ensembles[i];
    const std::string key = "ensemble[" + std::to_string(i) + "]";
    const auto find = [&](const std::string& name, const std::string& field) {
        for (const ensemble_spec& y : s.ensembles)
            if (y.name == name && &y != &x) return &y;
        fail(s, x.line, key + "." + field, "'" + name + "' names no other ensemble of the scene");
    };
    const auto energies_within = [&](const ensemble_spec& y, const std::string& field) {
        std::set<double> theirs;
        for (const std::string& t : energy_texts(y.energies, "energies"))
            theirs.insert(parse_real<double>(t, "energies"));
        for (const std::string& t : energy_texts(x.energies, "energies"))
            if (!theirs.count(parse_real<double>(t, "energies")))
                fail(s, x.line, key + "." + field,
                     "E = " + t + " is not an energy of ensemble '" + y.name + "'");
    };
    if (!x.census_of.empty()) {
        const ensemble_spec& y = *find(x.census_of, "census_of");
        if (!x.chaos || !y.chaos)
            fail(s, x.line, key + ".census_of",
                 "a census and the ensemble it tests need chaos = true (the classification)");
        if (parse_real<double>(x.chaos_threshold, "chaos_threshold") !=
            parse_real<double>(y.chaos_threshold, "chaos_threshold"))
            fail(s, x.line, key + ".census_of",
                 "the census classifies with chaos_threshold " + x.chaos_threshold +
                     ", ensemble '" + y.name + "' with " + y.chaos_threshold +
                     ": one classification must split both");
        if (x.arm != y.arm)
            fail(s, x.line, key + ".census_of",
                 "the census counts arm " + std::to_string(x.arm) + ", ensemble '" + y.name +
                     "' arm " + std::to_string(y.arm));
        // no trajectory in common: another seed than the tested ensemble's and than every
        // ensemble whose trajectories it shares (each trajectory is a function of (seed, E, i))
        for (const ensemble_spec& z : s.ensembles)
            if (z.seed == x.seed && (&z == &y || (same_trajectories(z, y) && &z != &x)))
                fail(s, x.line, key + ".seed",
                     "'" + std::to_string(x.seed) + "' is the seed of ensemble '" + z.name +
                         "': a census must share no trajectory with the ensemble it tests");
        energies_within(y, "census_of");
    }
    if (!x.classification_check_of.empty()) {
        const ensemble_spec& y = *find(x.classification_check_of, "classification_check_of");
        if (y.census_of.empty())
            fail(s, x.line, key + ".classification_check_of",
                 "'" + y.name + "' is not a census (it has no census_of)");
        if (x.seed != y.seed || !x.chaos || x.chaos_threshold != y.chaos_threshold ||
            x.trajectories * x.replicates > y.trajectories * y.replicates)
            fail(s, x.line, key + ".classification_check_of",
                 "a classification check re-integrates census '" + y.name +
                     "''s trajectories: the same seed and chaos threshold, chaos = true, and at "
                     "most its number of trajectories");
        energies_within(y, "classification_check_of");
    }
}

/// One file or folder a run writes, with the scene key that asks for it.
struct scene_output {
    std::filesystem::path path;
    std::string key;
    int line = 0;
    bool folder = false;
};

/// Every path the run of the scene writes (execute.cpp's ctx.write and its folders): the one list
/// the collision and destination checks below run over.
std::vector<scene_output> scene_outputs(const scene& s) {
    std::vector<scene_output> out;
    const auto add = [&](const std::filesystem::path& p, const std::string& key, int line,
                         bool folder = false) {
        out.push_back({p, key, line, folder});
    };
    add(s.output / "run.json", "scene.output", s.output_line);
    if (s.predictions) add(s.output / "predictions.csv", "predictions", s.predictions->line);
    if (s.orbits)
        for (int a : s.orbits->arms) {
            add(s.output / ("orbits-arm" + std::to_string(a) + ".csv"), "orbits", s.orbits->line);
            add(s.output / ("orbit-curves-arm" + std::to_string(a) + ".csv"), "orbits",
                s.orbits->line);
        }
    for (std::size_t i = 0; i < s.ensembles.size(); ++i) {
        const ensemble_spec& x = s.ensembles[i];
        const std::string key = "ensemble[" + std::to_string(i) + "].name";
        add(s.output / ("ensemble-" + x.name + ".json"), key, x.line);
        add(s.output / ("ensemble-" + x.name), key, x.line, true);
        add(s.output / ("ensemble-" + x.name + ".checkpoint"), key, x.line);
    }
    for (std::size_t i = 0; i < s.trajectories.size(); ++i) {
        const trajectory_spec& t = s.trajectories[i];
        const std::string key = "trajectory[" + std::to_string(i) + "].name";
        add(s.output / ("trajectory-" + t.name + ".csv"), key, t.line);
        add(s.output / ("trajectory-" + t.name + "-events.csv"), key, t.line);
    }
    if (s.viewer) add(s.output / "viewer.html", "viewer", s.viewer->line);
    if (s.accuracy) add(s.accuracy->out, "accuracy.out", s.accuracy->line);
    if (s.golden) {
        add(std::filesystem::path(s.golden->dir) / "golden.csv", "golden.dir", s.golden->line);
        add(std::filesystem::path(s.golden->dir) / "provenance.json", "golden.dir", s.golden->line);
    }
    return out;
}

/// No two outputs on one path (nor a file where a folder of the run goes), no output that is a
/// folder or another non-file where a file goes, and no symbolic link inside the output folder
/// on the way to one (the run writes inside its folder only): all before anything is computed.
void check_outputs(const scene& s) {
    const std::vector<scene_output> outs = scene_outputs(s);
    std::error_code ec;
    const auto normal = [&ec](const std::filesystem::path& p) {
        return std::filesystem::absolute(p, ec).lexically_normal();
    };
    std::map<std::filesystem::path, const scene_output*> seen;
    for (const scene_output& o : outs) {
        const auto [it, fresh] = seen.emplace(normal(o.path), &o);
        if (!fresh)
            fail(s, o.line, o.key,
                 "writes '" + o.path.string() + "', which " + it->second->key + " (line " +
                     std::to_string(it->second->line) + ") writes too: rename one of them");
    }
    // nor another key's file inside a folder the run fills (golden.dir = "out/ensemble-a")
    for (const scene_output& f : outs) {
        if (!f.folder) continue;
        const std::filesystem::path folder = normal(f.path);
        for (const scene_output& o : outs) {
            if (&o == &f || o.key == f.key) continue;
            const std::filesystem::path rel = normal(o.path).lexically_relative(folder);
            if (!rel.empty() && *rel.begin() != ".." && rel != ".")
                fail(s, o.line, o.key,
                     "writes '" + o.path.string() + "' inside '" + f.path.string() +
                         "', the folder " + f.key + " (line " + std::to_string(f.line) +
                         ") fills: choose another path");
        }
    }
    const std::filesystem::path root = normal(s.output);
    for (const scene_output& o : outs) {
        const std::filesystem::path p = normal(o.path);
        // inside the output folder: no component below it may be a symbolic link
        const std::filesystem::path rel = p.lexically_relative(root);
        if (!rel.empty() && *rel.begin() != "..") {
            std::filesystem::path at = root;
            for (const auto& part : rel) {
                at /= part;
                if (std::filesystem::is_symlink(std::filesystem::symlink_status(at, ec)))
                    fail(s, o.line, o.key,
                         "'" + at.string() +
                             "' is a symbolic link: a scene writes only inside its output "
                             "folder, and follows no link out of it (remove it)");
            }
        }
        const auto st = std::filesystem::status(p, ec);
        if (!std::filesystem::exists(st)) continue;
        if (o.folder && !std::filesystem::is_directory(st))
            fail(s, o.line, o.key,
                 "'" + o.path.string() + "' is not a folder, where the run " + "writes one");
        if (!o.folder && !std::filesystem::is_regular_file(st))
            fail(s, o.line, o.key,
                 "'" + o.path.string() + "' is " +
                     (std::filesystem::is_directory(st) ? "a folder" : "not a regular file") +
                     ", where the run writes a file");
    }
}

void check_scene(const scene& s, const double_pendulum<double>& model) {
    check_output_dir(s.output, s, s.output_line, "scene.output");
    check_outputs(s);
    if (s.predictions)
        check_distinct(s.predictions->energies, s.prec, s, s.predictions->line,
                       "predictions.energies");
    if (s.orbits) check_distinct(s.orbits->energies, s.prec, s, s.orbits->line, "orbits.energies");
    for (std::size_t i = 0; i < s.ensembles.size(); ++i)
        check_ensemble(s, i, model);
    for (std::size_t i = 0; i < s.ensembles.size(); ++i)
        check_census(s, i);
    for (std::size_t i = 0; i < s.trajectories.size(); ++i)
        check_trajectory(s, i, model);
    if (s.golden) {
        const golden_spec& g = *s.golden;
        if (s.custom_model)
            fail(s, g.line, "golden",
                 "golden data is defined for the default (egalitarian) pendulum; remove [model] "
                 "or [golden]");
        for (const std::string& q : g.quantities) {
            try {
                (void)find_quantity(q);
            } catch (const input_error& e) {
                fail(s, g.line, "golden.quantities", e.what());
            }
        }
        check_output_dir(g.dir, s, g.line, "golden.dir");
    }
    if (s.accuracy) {
        for (const std::string& q : s.accuracy->quantities) {
            try {
                (void)find_quantity(q);
            } catch (const input_error& e) {
                fail(s, s.accuracy->line, "accuracy.quantities", e.what());
            }
        }
        check_output_dir(std::filesystem::path(s.accuracy->out).parent_path(), s, s.accuracy->line,
                         "accuracy.out");
        for (const std::string& file : s.accuracy->appendices) {  // as the run reads them
            try {
                (void)read_input_file(file, "accuracy.appendices");
            } catch (const input_error& e) {
                fail(s, s.accuracy->line, "accuracy.appendices", e.detail());
            }
        }
    }
    if (s.report) {
        if (!s.predictions && s.ensembles.empty())
            fail(s, s.report->line, "report",
                 "the report needs something to report: [predictions] or [[ensemble]]");
        check_output_dir(s.report->dir, s, s.report->line, "report.dir");
    }
}

/// The energies of arm a's orbits in the scene's [viewer] (study/saddle_viewer.hpp).
std::vector<energy_entry> viewer_energies(const scene& s, const double_pendulum<double>& model,
                                          int a) {
    std::vector<energy_entry> out;
    for (const std::string& text :
         viewer_energy_texts(model, arm_of(a), s.viewer->energies_per_arm))
        out.push_back({parse_real<double>(text, "viewer"), text});
    return out;
}

plan_step viewer_step(const scene& s, const double_pendulum<double>& model) {
    std::vector<std::string> arms;
    plan_step step{plan_step::kind::viewer, 0, {}, {}, {}, 0, {}, s.prec, {}};
    for (int a : s.viewer->arms) {
        arms.push_back(std::to_string(a));
        for (const energy_entry& e : viewer_energies(s, model, a))
            step.energies.push_back(e.text);
    }
    step.description = "saddle-orbit viewer -> " + (s.output / "viewer.html").string() + " (arms " +
                       join(arms) + ", " + std::to_string(s.viewer->energies_per_arm) +
                       " orbits each, " + std::to_string(s.viewer->samples) + " points per orbit)";
    return step;
}

/// Whether two ensembles integrate the same trajectories (then one run serves both; the chaos
/// threshold only classifies them).
bool same_trajectories(const ensemble_spec& a, const ensemble_spec& b) {
    return trajectory_key_of(ensemble_settings(a)) == trajectory_key_of(ensemble_settings(b));
}

}  // namespace

simulation_request ensemble_settings(const ensemble_spec& x) {
    return make_simulation_request(x.settings, settings_surface::scene);
}

plan make_plan(const scene& s) {
    plan p;
    const double_pendulum<double> model = make_model<double>(s.model);
    check_scene(s, model);
    // energies at which each arm's saddle-orbit family is needed
    std::map<std::pair<int, precision>, std::map<double, std::string>> family;
    auto want_orbits = [&](int arm_number, const std::vector<energy_entry>& energies,
                           precision prec) {
        const arm a = arm_of(arm_number);
        for (const auto& e : energies)  // the family's open range, from the exact decimals
            if (const energy_level<double> level = parse_energy_level<double>(e.text, "energy");
                level.above(model.saddle_level(a)) > 0 && level.below(model.maximum_level()) > 0)
                family[{arm_number, prec}].emplace(e.value, e.text);
    };

    std::vector<energy_entry> prediction_energies;
    if (s.predictions) {
        for (const auto& q : s.predictions->quantities) {
            try {
                (void)find_quantity(q);
            } catch (const input_error& e) {
                throw scene_error(s.file.string() + ":" + std::to_string(s.predictions->line) +
                                  ": predictions.quantities: " + e.what());
            }
        }
        prediction_energies = expand(s.predictions->energies, "predictions.energies");
        for (int a : s.predictions->arms)
            for (const auto& q : s.predictions->quantities)
                if (needs_saddle_orbit(q)) want_orbits(a, prediction_energies, s.prec);
    }
    if (s.orbits) {
        const auto energies = expand(s.orbits->energies, "orbits.energies");
        for (int a : s.orbits->arms)
            want_orbits(a, energies, s.prec);
    }
    if (s.viewer)
        for (int a : s.viewer->arms)
            want_orbits(a, viewer_energies(s, model, a), s.prec);
    std::vector<std::vector<energy_entry>> ensemble_energies;
    for (std::size_t i = 0; i < s.ensembles.size(); ++i) {
        const auto& x = s.ensembles[i];
        ensemble_energies.push_back(
            expand(x.energies, "ensemble[" + std::to_string(i) + "].energies"));
        if (std::any_of(x.criteria.begin(), x.criteria.end(),
                        [](const std::string& c) { return criterion(c).needs_saddle_orbit; })) {
            want_orbits(x.arm, ensemble_energies.back(), precision{real_kind::double_});
        }
    }

    for (const auto& [key, energies] : family) {
        const auto [a, prec] = key;
        plan_step step{plan_step::kind::orbit_family, a, {}, {}, {}, 0, {}, prec, {}};
        for (const auto& [v, text] : energies)
            step.energies.push_back(text);
        step.description = "saddle-orbit family of arm " + std::to_string(a) + " in " +
                           precision_name(prec) + " at " + range_text(step.energies) +
                           " (continuation from the saddle; cached on disk)";
        p.steps.push_back(step);
    }
    if (s.predictions) {
        plan_step step{plan_step::kind::predictions, 0, {}, {}, {}, 0, {}, s.prec, {}};
        for (const auto& e : prediction_energies)
            step.energies.push_back(e.text);
        for (const auto& q : s.predictions->quantities) {
            if (!find_quantity(q).per_arm) {
                step.quantities.push_back(q);
                continue;
            }
            for (int a : s.predictions->arms)
                step.quantities.push_back(q + "@" + std::to_string(a));
        }
        step.description = "predictions " + join(step.quantities) + " at " +
                           range_text(step.energies) +
                           " (energies outside a quantity's domain are skipped and listed)";
        p.steps.push_back(step);
    }
    // ensembles with the same trajectories share them (one step, in the order of the first)
    std::vector<bool> grouped(s.ensembles.size(), false);
    for (std::size_t i = 0; i < s.ensembles.size(); ++i) {
        if (grouped[i]) continue;
        const auto& x = s.ensembles[i];
        plan_step step{plan_step::kind::ensemble,     x.arm, {}, {}, x.criteria, i, {},
                       precision{real_kind::double_}, {}};
        std::set<double> seen;
        std::vector<std::string> parts;
        for (std::size_t j = i; j < s.ensembles.size(); ++j) {
            if (grouped[j] || !same_trajectories(x, s.ensembles[j])) continue;
            grouped[j] = true;
            step.ensemble_indices.push_back(j);
            const auto& y = s.ensembles[j];
            for (const auto& e : ensemble_energies[j])
                if (seen.insert(e.value).second) step.energies.push_back(e.text);
            parts.push_back("'" + y.name + "' (arm " + std::to_string(y.arm) + ", " +
                            range_text(energy_texts(y.energies, "ensemble")) + ", criteria " +
                            join(y.criteria) + ")");
        }
        const std::string what =
            (x.replicates > 1 ? std::to_string(x.replicates) + " replicates x " : "") +
            std::to_string(x.trajectories) + " trajectories x T = " + x.time + " at " +
            range_text(step.energies) + ", " + x.integrator + " rtol " + x.rtol +
            (x.atol != "0" ? " atol " + x.atol : "") + ", estimator " + x.estimator +
            (x.chaos ? ", chaos indicator (threshold " + x.chaos_threshold + ")" : "");
        if (parts.size() == 1)
            step.description = "ensemble '" + x.name + "': arm " + std::to_string(x.arm) +
                               ", criteria " + join(x.criteria) + ", " + what;
        else
            step.description =
                "ensembles " + join(parts, " and ") + " on one set of trajectories: " + what;
        p.steps.push_back(step);
    }
    for (std::size_t i = 0; i < s.trajectories.size(); ++i) {
        const trajectory_spec& t = s.trajectories[i];
        plan_step step{plan_step::kind::trajectory,   0, {}, {}, t.criteria, i, {},
                       precision{real_kind::double_}, {}};
        step.description = "trajectory '" + t.name + "' from (" + join(t.state) +
                           "), T = " + t.time + ", criteria " + join(t.criteria) +
                           ", ensemble route (dop853 rtol " + t.rtol + ") -> trajectory-" + t.name +
                           ".csv, trajectory-" + t.name + "-events.csv";
        p.steps.push_back(step);
    }
    if (s.viewer) p.steps.push_back(viewer_step(s, model));
    if (s.golden) {
        p.steps.push_back({plan_step::kind::golden,
                           0,
                           {},
                           s.golden->quantities,
                           {},
                           0,
                           "golden data -> " + s.golden->dir,
                           s.golden->value_precision,
                           {}});
    }
    if (s.accuracy) {
        p.steps.push_back({plan_step::kind::accuracy,
                           0,
                           {},
                           s.accuracy->quantities,
                           {},
                           0,
                           "accuracy report -> " + s.accuracy->out,
                           s.prec,
                           {}});
    }
    if (s.report) {
        p.steps.push_back({plan_step::kind::report,
                           0,
                           {},
                           {},
                           {},
                           0,
                           "reproduction report -> " + s.report->dir,
                           s.prec,
                           {}});
    }
    return p;
}

void print_plan(const scene& s, const plan& p, std::ostream& out) {
    out << "scene " << s.name << " (" << s.file.string() << "), precision "
        << precision_name(s.prec) << ", output " << s.output.string() << "\n";
    int i = 1;
    for (const auto& step : p.steps)
        out << "  " << i++ << ". " << step.description << "\n";
    out << "  saddle-orbit families: " << p.count(plan_step::kind::orbit_family)
        << ", ensembles: " << p.count(plan_step::kind::ensemble) << "\n";
}

}  // namespace flipflux
