// Scenes: declarative TOML files naming what to compute (see docs/scenes.md for the schema).
//
// A scene declares the model, the precision, energy grids and the requested outputs: predictions
// (phase volumes, fluxes, rates), saddle-orbit families, Monte Carlo ensembles, golden data, the
// accuracy report and the reproduction report. `load_scene` validates everything up front: an
// unknown key, a wrong type, an out-of-range value or malformed TOML is a scene_error naming the
// file, the line and the key. Numbers are kept as decimal text and parsed later in the working
// precision (a TOML float is read back as its shortest round-trip decimal, which is the text the
// user wrote whenever it has at most 17 significant digits; quote a number to give more digits).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/settings.hpp"

namespace flipflux {

/// A scene file error: "FILE:LINE: KEY: what is wrong".
class scene_error : public input_error {
  public:
    using input_error::input_error;
};

/// Energies as decimal text: an explicit list, or a grid from..to (inclusive) by step.
struct energy_grid {
    std::vector<std::string> values;  ///< explicit values (when not a grid)
    std::string from, to, step;       ///< grid (when `values` is empty)
    bool is_grid() const { return values.empty(); }
};

using model_spec = model_text;

struct predictions_spec {
    std::vector<std::string> quantities;  ///< registry names, e.g. "rate-saddle"
    std::vector<int> arms{2};
    energy_grid energies;
    int line = 0;
};

struct orbits_spec {
    std::vector<int> arms{2};
    energy_grid energies;
    int curve_samples = 0;  ///< > 0: write each orbit's curve with this many samples
    int line = 0;
};

/// A run setting's default in a scene (study/settings.hpp's table).
inline std::string scene_default(std::string_view field) {
    return setting_default(run_setting_named(field), settings_surface::scene);
}

/// A scene's arm, from its number (1 or 2: the loader checked it).
inline arm arm_of(int number) {
    return arm_numbered(number).value();
}

/// The longest ensemble name (it becomes file names under the output directory).
inline constexpr std::size_t max_ensemble_name = 100;

struct ensemble_spec {
    std::string name;
    int arm = 2;
    std::vector<std::string> criteria = criterion_names();
    energy_grid energies;
    long long trajectories = std::stoll(scene_default("trajectories"));
    /// Independent replicates of `trajectories` each (simulation_request::replicates): every
    /// statistic pooled over R x trajectories and with its spread over the replicates.
    long long replicates = std::stoll(scene_default("replicates"));
    std::string time = scene_default("time");
    unsigned long long seed = std::stoull(scene_default("seed"));
    std::string rtol = scene_default("rtol");
    std::string atol = scene_default("atol");  ///< 0: equal to rtol (ensemble_options::atol)
    std::string integrator = scene_default("method");
    std::string estimator = scene_default("estimator");  ///< "long" (the paper's) or "short"
    std::string reference_time = scene_default("reference_time");  ///< > 0: PQI at this length
    bool chaos = scene_default("chaos") == "true";  ///< classify trajectories (Lyapunov exponent)
    /// lambda_T above this (units sqrt(alpha / A)) is chaotic (ensemble_options::chaos_threshold)
    std::string chaos_threshold = scene_default("chaos_threshold");
    /// Write every crossing time (residence_E<label>_<criterion>.csv); the report's residence-time
    /// figure reads them. Without it only the residence statistics (ensemble JSON, histograms).
    bool residence_times = false;
    bool histogram = false;  ///< the ensemble whose per-trajectory rates the report histograms
    /// An island census (docs/theory.md, "The island census"): the name of the ensemble whose
    /// chaotic sub-ensemble this census's regular fraction and regular rate predict. The plan
    /// requires another seed than the tested ensemble's (no shared trajectory), its arm, the
    /// chaos indicator, and energies among the tested ensemble's.
    std::string census_of;
    /// The name of a census whose classification this ensemble re-measures at another T: the
    /// census's seed and chaos threshold, energies among the census's, trajectories (index
    /// blocks from 0) at most the census's; the report pairs trajectories by index.
    std::string classification_check_of;
    /// The run settings as the scene gave them, by the settings table's field (study/settings.hpp;
    /// absent: the scene's default), `method` resolved: what the typed fields above were read
    /// from, and what ensemble_settings() checks into the simulation request.
    settings_text settings;
    int line = 0;
};

/// [[trajectory]]: one trajectory from a canonical state with its flip events, at double by the
/// ensemble's route (study/trajectory.hpp) -> trajectory-<name>.csv (states) and
/// trajectory-<name>-events.csv, the files `flipflux trajectory --out/--events` writes.
struct trajectory_spec {
    std::string name;
    std::vector<std::string> state;  ///< th1, th2, l1, l2 as decimal text
    std::string time = "20";
    std::string sample_interval = "0.05";
    std::vector<std::string> criteria = criterion_names();
    std::vector<int> arms{1, 2};
    std::string rtol = "1e-12";
    int line = 0;
};

struct golden_spec {
    std::string dir = "data/golden";
    std::vector<std::string> quantities;            ///< empty: every registered quantity
    precision value_precision = mp_precision(100);  ///< of the values (certified in half of it)
    /// CPU seconds each evaluation of a row may take (golden_options::max_seconds; decimal text,
    /// >= 0, "0": no bound)
    std::string max_seconds = "0";
    int line = 0;
};

struct accuracy_spec {
    std::string out = "docs/accuracy.md";
    std::vector<std::string> quantities;  ///< empty: every registered quantity
    /// Markdown files appended verbatim after the measured tables (e.g. benchmark figures)
    std::vector<std::string> appendices;
    /// a method slower than this (seconds per evaluation, measured or estimated from the lower
    /// precisions) is not measured in a precision or the higher ones (decimal text, > 0)
    std::string max_seconds = "120";
    /// the report's columns
    std::vector<precision> precisions{precision{real_kind::double_}, precision{real_kind::quad},
                                      mp_precision(50), mp_precision(100)};
    int line = 0;
};

/// [viewer]: the interactive saddle-orbit viewer, <output>/viewer.html (study/saddle_viewer.hpp).
struct viewer_spec {
    std::vector<int> arms{1, 2};
    int energies_per_arm = 30;  ///< orbits per arm, evenly over (E_s, E_max)
    int samples = 161;          ///< points per orbit over one period
    int grid = 121;             ///< potential grid points per axis (1 mod 6)
    int line = 0;
};

struct report_spec {
    std::string dir = "docs/reproduction";
    /// output directories of other scenes (other pendulums) the report also draws: their rates
    /// against their predictions (the paper's Appendix C); a missing one is noted, not an error
    std::vector<std::string> other_runs;
    int line = 0;
};

struct scene {
    std::filesystem::path file;
    std::string name, description;
    std::filesystem::path output;  ///< output directory
    int output_line = 0;           ///< the line of [scene] output (error messages)
    std::string precision_text = "double";
    precision prec = precision{real_kind::double_};
    /// [scene] orbit_integrator: "taylor" or "gauss-legendre" for every saddle orbit of the scene
    /// (families, tables, orbit quantities); "" = the precision's default
    std::string orbit_integrator;
    model_spec model;
    bool custom_model = false;
    std::optional<predictions_spec> predictions;
    std::optional<orbits_spec> orbits;
    std::vector<ensemble_spec> ensembles;
    std::vector<trajectory_spec> trajectories;
    std::optional<golden_spec> golden;
    std::optional<accuracy_spec> accuracy;
    std::optional<report_spec> report;
    std::optional<viewer_spec> viewer;
};

/// Reads and validates a scene file; throws scene_error ("FILE:LINE: KEY: ...").
scene load_scene(const std::filesystem::path& file);

/// Parses scene text (for tests); `file` is only used in error messages.
scene parse_scene(const std::string& text, const std::filesystem::path& file);

/// The energies as decimal text: explicit values as written; a grid's points from + i step
/// computed in mp:100 and written with 40 significant digits, so that 2.05 .. 5.95 by 0.05 gives
/// "2.05", "2.1", ..., "5.95" — the decimals meant, each parsed later in the working precision
/// (never a sum rounded in double). Throws scene_error naming `where`.
std::vector<std::string> energy_texts(const energy_grid& grid, const std::string& where);

/// The energies of a grid in Real: energy_texts, each parsed in Real (correctly rounded).
template <class Real>
std::vector<energy_level<Real>> energies_of(const energy_grid& grid, const std::string& where);

#define FLIPFLUX_SCENE_EXTERN(R)                                                    \
    extern template std::vector<energy_level<R>> energies_of<R>(const energy_grid&, \
                                                                const std::string&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_SCENE_EXTERN)
#undef FLIPFLUX_SCENE_EXTERN

}  // namespace flipflux
