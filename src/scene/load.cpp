// Scene files: TOML -> validated `scene` (schema in docs/scenes.md).
#include <toml++/toml.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/settings.hpp"
#include "table_reader.hpp"

namespace flipflux {

using namespace scene_toml;  // the TOML table reader (table_reader.hpp)

namespace {

void read_model(table_reader& r, model_spec& m) {
    for (std::size_t i = 0; i < parameter_count; ++i)
        if (auto v = r.number(std::string(parameter_fields[i].name))) m.*text_members[i] = *v;
    r.finish();
}

}  // namespace

namespace {

void read_head(table_reader& top, const std::filesystem::path& file, scene& s) {
    const toml::table* head = top.subtable("scene");
    if (head == nullptr) top.fail(nullptr, "scene", "the [scene] table is required");
    table_reader r(*head, file.string(), "scene");
    s.name = r.string("name").value_or(file.stem().string());
    s.description = r.string("description").value_or("");
    const auto out = r.string("output");
    if (!out || out->empty()) r.fail(nullptr, "output", "is required (an output directory)");
    s.output = *out;
    s.output_line = static_cast<int>(r.get("output")->source().begin.line);
    if (auto p = r.string("precision")) {
        s.precision_text = *p;
        try {
            s.prec = parse_precision(*p, "precision");
        } catch (const input_error& e) {
            r.fail(r.get("precision"), "precision", e.what());
        }
    }
    if (auto i = r.string("orbit_integrator")) {
        try {
            (void)parse_name<orbit_integrator>(*i, "orbit_integrator");
        } catch (const input_error& e) {
            r.fail(r.get("orbit_integrator"), "orbit_integrator", e.what());
        }
        s.orbit_integrator = *i;
    }
    r.finish();
}

predictions_spec read_predictions(table_reader& r) {
    predictions_spec p;
    p.line = r.line();
    p.quantities = r.unique_strings("quantities").value_or(std::vector<std::string>{});
    if (p.quantities.empty()) r.fail(nullptr, "quantities", "needs at least one quantity");
    p.arms = r.arms("arms").value_or(p.arms);
    p.energies = r.energies("energies", true);
    r.finish();
    return p;
}

orbits_spec read_orbits(table_reader& r) {
    orbits_spec o;
    o.line = r.line();
    o.arms = r.arms("arms").value_or(o.arms);
    o.energies = r.energies("energies", true);
    o.curve_samples = static_cast<int>(r.integer("curve_samples", 0, 1000000).value_or(0));
    r.finish();
    return o;
}

/// An ensemble's name becomes file names under the scene's output (ensemble-NAME.json, a CSV
/// folder, a checkpoint): one path component of letters, digits, '.', '_' and '-', not starting
/// with '.', at most max_ensemble_name characters; nothing can lead outside the output folder.
void check_ensemble_name(table_reader& r, const std::string& name) {
    if (!is_plain_name(name, max_ensemble_name))
        r.fail(r.get("name"), "name",
               "'" + name + "' is not a valid ensemble name (one path component: 1 to " +
                   std::to_string(max_ensemble_name) +
                   " letters, digits, '.', '_' or '-', not starting with '.')");
}

/// One [[ensemble]] table; `index` counts from 1 (the default name).
ensemble_spec read_ensemble(table_reader& r, int index) {
    ensemble_spec x;
    x.line = r.line();
    x.name = r.string("name").value_or("ensemble" + std::to_string(index));
    check_ensemble_name(r, x.name);
    x.arm = r.arms("arm").value_or(std::vector<int>{2}).front();
    if (auto c = r.unique_strings("criteria")) {
        if (c->empty()) r.fail(r.get("criteria"), "criteria", "needs at least one criterion");
        for (const auto& name : *c) {
            try {
                check_criterion_name(name);
            } catch (const input_error& e) {
                r.fail(r.get("criteria"), "criteria", e.detail());
            }
        }
        x.criteria = *c;
    }
    x.energies = r.energies("energies", true);
    // the run settings: read as text by the settings table's scene keys, checked once by
    // make_simulation_request (study/settings.hpp) below, as the command line's and Python's are
    settings_text given;
    for (const run_setting& setting : run_settings()) {
        const std::string key(setting.scene_key);
        if (key.empty() || key == "energies" || key == "arm" || key == "criteria") continue;
        if (std::optional<std::string> text = r.setting_text(key, setting.kind))
            given.emplace(setting.field, std::move(*text));
    }
    const auto text_of = [&given](std::string_view field, const std::string& otherwise) {
        const auto it = given.find(field);
        return it != given.end() ? it->second : otherwise;
    };
    x.time = text_of("time", x.time);
    x.rtol = text_of("rtol", x.rtol);
    x.atol = text_of("atol", x.atol);
    x.integrator = text_of("method", x.integrator);
    x.estimator = text_of("estimator", x.estimator);
    x.chaos_threshold = text_of("chaos_threshold", x.chaos_threshold);
    x.reference_time = text_of("reference_time", x.reference_time);
    x.residence_times = r.boolean("residence_times").value_or(false);
    x.histogram = r.boolean("histogram").value_or(false);
    x.census_of = r.string("census_of").value_or("");
    x.classification_check_of = r.string("classification_check_of").value_or("");
    // the run settings' one check (study/settings.hpp), naming the scene's key
    try {
        const simulation_request q = make_simulation_request(given, settings_surface::scene);
        x.trajectories = static_cast<long long>(q.options.trajectories);
        x.replicates = static_cast<long long>(q.replicates);
        x.seed = q.options.seed;
        x.chaos = q.options.chaos;
        // `auto` resolved here: plans, sharing and run.json name the integrator
        x.integrator = to_string(q.options.method);
        given["method"] = x.integrator;
        x.settings = std::move(given);
    } catch (const input_error& e) {
        r.fail(r.get(e.field()), e.field(), e.detail());
    }
    r.finish();
    return x;
}

/// One [[trajectory]] table; `index` counts from 1 (the default name).
trajectory_spec read_trajectory(table_reader& r, int index) {
    trajectory_spec t;
    t.line = r.line();
    t.name = r.string("name").value_or("trajectory" + std::to_string(index));
    check_ensemble_name(r, t.name);
    if (auto state = r.numbers("state", 4))
        t.state = *state;
    else
        r.fail(nullptr, "state", "is required: [theta1, theta2, l1, l2]");
    t.time = r.number("time").value_or(t.time);
    if (t.time.front() == '-' || !(parse_real<double>(t.time, "time") > 0))
        r.fail(r.get("time"), "time", "'" + t.time + "' must be > 0");
    t.sample_interval = r.number("sample_interval").value_or(t.sample_interval);
    if (t.sample_interval.front() == '-' ||
        !(parse_real<double>(t.sample_interval, "sample_interval") >= 0))
        r.fail(r.get("sample_interval"), "sample_interval",
               "'" + t.sample_interval + "' must be >= 0");
    if (auto c = r.unique_strings("criteria")) {
        for (const auto& name : *c) {
            try {
                check_criterion_name(name);
            } catch (const input_error& e) {
                r.fail(r.get("criteria"), "criteria", e.detail());
            }
        }
        t.criteria = *c;
    }
    t.arms = r.arms("arms").value_or(t.arms);
    t.rtol = r.number("rtol").value_or(t.rtol);
    if (const std::string p = rtol_problem(parse_real<double>(t.rtol, "rtol"), t.rtol); !p.empty())
        r.fail(r.get("rtol"), "rtol", p);
    r.finish();
    return t;
}

// The scene's [[key]] tables (ensembles, trajectories): each read by `read(reader, index)` (index
// from 1) into `out`; their names must differ, since a name is where the outputs go.
template <class Spec, class Read>
void read_named_tables(table_reader& top, const std::string& fname, const std::string& key,
                       Read&& read, std::vector<Spec>& out) {
    const toml::node* n = top.get(key);
    if (n == nullptr) return;
    const toml::array* list = n->as_array();
    if (list == nullptr || !list->is_array_of_tables())
        top.fail(n, key, "expected [[" + key + "]] tables");
    int index = 0;
    for (const toml::node& e : *list) {
        table_reader r(*e.as_table(), fname, key + "[" + std::to_string(index++) + "]");
        out.push_back(read(r, index));
        for (std::size_t j = 0; j + 1 < out.size(); ++j)
            if (out[j].name == out.back().name)
                r.fail(r.get("name"), "name",
                       "'" + out.back().name + "' is already the name of the " + key + " at line " +
                           std::to_string(out[j].line) +
                           " (their outputs would overwrite each other)");
    }
}

golden_spec read_golden(table_reader& r) {
    golden_spec g;
    g.line = r.line();
    g.dir = r.string("dir").value_or(g.dir);
    g.quantities = r.unique_strings("quantities").value_or(g.quantities);
    if (auto p = r.string("precision")) {
        try {
            g.value_precision = parse_precision(*p, "precision");
            (void)golden_check_precision(g.value_precision);
        } catch (const input_error& e) {
            r.fail(r.get("precision"), "precision", e.what());
        }
    }
    if (auto m = r.number("max_seconds")) {
        if (const double x = std::strtod(m->c_str(), nullptr); !(x >= 0 && std::isfinite(x)))
            r.fail(r.get("max_seconds"), "max_seconds",
                   "'" + *m + "' must be finite and >= 0 (0: no bound)");
        g.max_seconds = *m;
    }
    r.finish();
    return g;
}

accuracy_spec read_accuracy(table_reader& r) {
    accuracy_spec a;
    a.line = r.line();
    a.out = r.string("out").value_or(a.out);
    a.quantities = r.unique_strings("quantities").value_or(a.quantities);
    a.appendices = r.strings("appendices").value_or(a.appendices);
    if (auto m = r.number("max_seconds")) {
        if (const double x = std::strtod(m->c_str(), nullptr); !(x > 0 && std::isfinite(x)))
            r.fail(r.get("max_seconds"), "max_seconds", "'" + *m + "' must be finite and > 0");
        a.max_seconds = *m;
    }
    if (auto list = r.strings("precisions")) {
        std::string text;
        for (const std::string& item : *list)
            text += (text.empty() ? "" : ",") + item;
        try {
            a.precisions = parse_precision_list(text, "precisions");
        } catch (const input_error& e) {
            r.fail(r.get("precisions"), "precisions", e.what());
        }
    }
    r.finish();
    return a;
}

viewer_spec read_viewer(table_reader& r) {
    viewer_spec v;
    v.line = r.line();
    v.arms = r.arms("arms").value_or(v.arms);
    v.energies_per_arm =
        static_cast<int>(r.integer("energies_per_arm", 1, 1000).value_or(v.energies_per_arm));
    v.samples = static_cast<int>(r.integer("samples", 8, 100000).value_or(v.samples));
    v.grid = static_cast<int>(r.integer("grid", 7, 2001).value_or(v.grid));
    if (v.grid % 6 != 1)
        r.fail(r.get("grid"), "grid",
               std::to_string(v.grid) +
                   " is not 1 more than a multiple of 6 (the grid's nodes fall on the multiples "
                   "of pi/2)");
    r.finish();
    return v;
}

report_spec read_report(table_reader& r) {
    report_spec rep;
    rep.line = r.line();
    rep.dir = r.string("dir").value_or(rep.dir);
    rep.other_runs = r.strings("other_runs").value_or(rep.other_runs);
    for (const std::string& d : rep.other_runs)
        if (d.empty() || d.find('\'') != std::string::npos)
            r.fail(r.get("other_runs"), "other_runs",
                   "'" + d +
                       "' is not a directory name the report can be given (empty or with a quote)");
    r.finish();
    return rep;
}

// The TOML reader recurses once per part of a dotted key or table header: 50,000 parts overflow
// the stack. Keys and headers are counted lexically before parsing (docs/limits.md).
constexpr std::size_t max_key_parts = 64;
constexpr std::uintmax_t max_scene_bytes = std::uintmax_t{16} << 20;

void check_key_depth(const std::string& text, const std::string& fname) {
    // A lexical pass: strings, comments and multi-line strings skipped; the open arrays and
    // inline tables of a value kept on a stack. Keys are read at a line's start (outside any
    // open array or table: a header or a key) and after '{' or ',' directly inside an inline
    // table; there each '.' is a part.
    std::size_t line = 1;
    std::size_t parts = 1;
    bool in_key = true;      // reading a key (or a [header]) up to its '=' (or ']')
    char quote = 0;          // inside a one-line string: its quote
    bool multiline = false;  // inside a """ or ''' string
    char multiline_quote = 0;
    bool comment = false;  // after a '#' outside a string
    std::string open;      // the value's open containers: '[' arrays, '{' inline tables
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            comment = false;
            quote = 0;
            if (!multiline && open.empty()) {
                in_key = true;
                parts = 1;
            }
            continue;
        }
        if (comment) continue;
        if (multiline) {
            if (c == multiline_quote && text.compare(i, 3, std::string(3, c)) == 0) {
                multiline = false;
                i += 2;
            } else if (c == '\\' && multiline_quote == '"') {
                ++i;
            }
            continue;
        }
        if (quote != 0) {
            if (c == '\\' && quote == '"')
                ++i;  // an escaped character in a basic string
            else if (c == quote)
                quote = 0;
            continue;
        }
        if ((c == '"' || c == '\'') && !in_key && text.compare(i, 3, std::string(3, c)) == 0) {
            multiline = true;
            multiline_quote = c;
            i += 2;
            continue;
        }
        if (c == '"' || c == '\'') {
            quote = c;
            continue;
        }
        if (c == '#') {
            comment = true;
            continue;
        }
        if (in_key) {
            if (c == '=' || c == ']') {
                in_key = false;
            } else if (c == '}' && !open.empty() && open.back() == '{') {  // an empty table {}
                open.pop_back();
                in_key = false;
            } else if (c == '.' && ++parts > max_key_parts) {
                throw scene_error(fname + ":" + std::to_string(line) +
                                  ": a key or table header with more than " +
                                  std::to_string(max_key_parts) + " dotted parts (docs/limits.md)");
            }
            continue;
        }
        if (c == '[' || c == '{') {
            open += c;
            if (c == '{') {
                in_key = true;
                parts = 1;
            }
        } else if ((c == ']' || c == '}') && !open.empty()) {
            open.pop_back();
        } else if (c == ',' && !open.empty() && open.back() == '{') {
            in_key = true;
            parts = 1;
        }
    }
}

}  // namespace

scene parse_scene(const std::string& text, const std::filesystem::path& file) {
    const std::string fname = file.string();
    check_key_depth(text, fname);
    struct text_scope {
        explicit text_scope(const std::string& t) { scene_text = &t; }
        ~text_scope() { scene_text = nullptr; }
        text_scope(const text_scope&) = delete;
        text_scope& operator=(const text_scope&) = delete;
    } source(text);
    toml::table root;
    try {
        root = toml::parse(text, fname);
    } catch (const toml::parse_error& e) {
        throw scene_error(fname + ":" + std::to_string(e.source().begin.line) +
                          ": malformed TOML: " + std::string(e.description()));
    }
    scene s;
    s.file = file;
    table_reader top(root, fname, "");
    read_head(top, file, s);
    if (const toml::table* t = top.subtable("model")) {
        table_reader r(*t, fname, "model");
        read_model(r, s.model);
        s.custom_model = true;
        try {
            (void)make_model<double>(s.model);
        } catch (const input_error& e) {
            top.fail(t, "model", e.what());
        }
    }
    if (const toml::table* t = top.subtable("predictions")) {
        table_reader r(*t, fname, "predictions");
        s.predictions = read_predictions(r);
    }
    if (const toml::table* t = top.subtable("orbits")) {
        table_reader r(*t, fname, "orbits");
        s.orbits = read_orbits(r);
    }
    read_named_tables(top, fname, "ensemble", read_ensemble, s.ensembles);
    read_named_tables(top, fname, "trajectory", read_trajectory, s.trajectories);
    if (const toml::table* t = top.subtable("golden")) {
        table_reader r(*t, fname, "golden");
        s.golden = read_golden(r);
    }
    if (const toml::table* t = top.subtable("accuracy")) {
        table_reader r(*t, fname, "accuracy");
        s.accuracy = read_accuracy(r);
    }
    if (const toml::table* t = top.subtable("report")) {
        table_reader r(*t, fname, "report");
        s.report = read_report(r);
    }
    if (const toml::table* t = top.subtable("viewer")) {
        table_reader r(*t, fname, "viewer");
        s.viewer = read_viewer(r);
    }
    top.finish();
    return s;
}

scene load_scene(const std::filesystem::path& file) {
    std::string text;
    try {
        text = read_input_file(file, "scene", max_scene_bytes);
    } catch (const input_error& e) {
        throw scene_error(e.detail());
    }
    return parse_scene(text, file);
}

}  // namespace flipflux
