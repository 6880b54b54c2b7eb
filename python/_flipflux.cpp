// The Python module's native part (flipflux._flipflux, pybind11): thin functions over the library
// that take decimal text and return decimal text, exactly what the command-line tool computes and
// prints (python/flipflux/__init__.py builds the Pythonic interface on them: floats, mpmath
// numbers, NumPy arrays). simulate returns its report as a dict and each energy's tables as NumPy
// arrays, built from the library's structs through a memory sink (study/simulation.hpp's
// energy_sink): no file in between. Every computation runs in a worker thread with the GIL
// released; the calling thread polls for Ctrl-C (PyErr_CheckSignals) and raises KeyboardInterrupt:
// simulate stops its trajectories at the next step (ensemble_options::stop), the other calls
// (seconds, an mp orbit minutes) are abandoned to finish in the background. Bad input raises
// ValueError with the library's one-line message naming the Python keyword ("energy: '...' ...").
// The module links the library only: no command-line code.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <exception>
#include <filesystem>
#include <future>
#include <memory>
#include <thread>

#include "flipflux/core/version.hpp"
#include "flipflux/model/model_json.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/quantities/registry.hpp"
#include "flipflux/study/settings.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"
#include "flipflux/validation/validate.hpp"

namespace py = pybind11;
using namespace flipflux;

namespace {

model_text model_of(const std::map<std::string, std::string>& p) {
    model_text t;
    for (const auto& [key, value] : p) {
        const int i = parameter_index(key);
        if (i < 0) throw input_error(key + ": not a pendulum parameter");
        t.*text_members[static_cast<std::size_t>(i)] = value;
    }
    return t;
}

/// Runs f() in a worker thread with the GIL released, polling for signals every 50 ms. On
/// Ctrl-C: sets *stop (when given) and waits for f to stop, or else abandons f (it finishes in
/// the background; its result is dropped), and raises KeyboardInterrupt.
template <class F>
auto interruptible(F f, std::atomic<int>* stop = nullptr) -> decltype(f()) {
    using result = decltype(f());
    auto task = std::make_shared<std::packaged_task<result()>>(std::move(f));
    std::future<result> done = task->get_future();
    std::thread worker([task] { (*task)(); });
    bool interrupted = false;
    {
        py::gil_scoped_release release;
        while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
            bool signalled = false;
            {
                py::gil_scoped_acquire acquire;
                signalled = PyErr_CheckSignals() != 0;  // sets KeyboardInterrupt
            }
            if (signalled) {
                interrupted = true;
                if (stop != nullptr) {
                    stop->store(SIGINT);
                    done.wait();
                }
                break;
            }
        }
    }
    if (interrupted) {
        if (stop == nullptr) {
            worker.detach();
        } else {
            worker.join();
        }
        throw py::error_already_set();
    }
    worker.join();
    return done.get();
}

py::dict evaluate(const std::string& name, const std::string& energy_text,
                  const std::string& arm_text, const std::string& precision_text,
                  const std::string& method, const std::map<std::string, std::string>& parameters) {
    struct out_t {
        std::string quantity, arm, energy, precision, method, value, error_estimate;
        double seconds = 0;
    };
    const out_t o = interruptible([=] {
        const precision p = parse_precision(precision_text, "precision");
        return dispatch(p, [&]<class Real>() {
            const quantity& q = find_quantity(name);
            const arm a = parse_arm(arm_text, "arm");
            const double_pendulum<Real> model = make_model<Real>(model_of(parameters));
            const energy_level<Real> level = parse_energy_level<Real>(energy_text, "energy");
            const Real& energy = level.value;
            const auto start = std::chrono::steady_clock::now();
            const quantity_value<Real> v = q.evaluate(model, a, level, method);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const std::array<std::string, 2> printed = printed_value(v);
            return out_t{q.name,
                         q.per_arm ? to_string(a) : "",
                         to_decimal(energy),
                         precision_name<Real>(),
                         v.method,
                         printed[0],
                         printed[1],
                         seconds};
        });
    });
    py::dict d;
    d["quantity"] = o.quantity;
    d["arm"] = o.arm.empty() ? py::none() : py::object(py::int_(std::stoi(o.arm)));
    d["energy"] = o.energy;
    d["precision"] = o.precision;
    d["method"] = o.method;
    d["value"] = o.value;
    d["error_estimate"] = o.error_estimate;
    d["seconds"] = o.seconds;
    return d;
}

struct orbit_text {
    std::string precision, energy, period, action, flux, multiplier, stability_index, status,
        error_estimate_period, error_estimate_action, energy_error;
    std::vector<std::array<std::string, 5>> samples;  ///< t, theta1, theta2, l1, l2
};

py::dict saddle_orbit_text(const std::string& energy_text, const std::string& arm_text,
                           const std::string& precision_text, long samples,
                           const std::string& method_text,
                           const std::map<std::string, std::string>& parameters) {
    if (samples < 2 || samples > 10000000)
        throw input_error("samples: '" + std::to_string(samples) +
                          "' is not an integer in [2, 10000000]");
    const orbit_text o = interruptible([=] {
        const precision p = parse_precision(precision_text, "precision");
        return dispatch(p, [&]<class Real>() {
            const arm a = parse_arm(arm_text, "arm");
            const double_pendulum<Real> model = make_model<Real>(model_of(parameters));
            const energy_level<Real> level = parse_energy_level<Real>(energy_text, "energy");
            const Real& energy = level.value;
            orbit_options<Real> options;
            // "periodic", or qualified by the integrator: "symmetric/gauss-legendre"
            const std::size_t slash = method_text.find('/');
            options.method = parse_name<orbit_method>(method_text.substr(0, slash), "method");
            if (slash != std::string::npos)
                options.integrator =
                    parse_name<orbit_integrator>(method_text.substr(slash + 1), "method");
            check_orbit_energy(model, a, level);
            const saddle_orbit<Real> orbit = solve_saddle_orbit(model, a, level, options);
            if (orbit.status == orbit_status::not_converged)
                throw_not_converged(model, a, level, orbit, "orbit");
            orbit_text t{precision_name<Real>(),
                         to_decimal(energy),
                         to_decimal(orbit.period),
                         to_decimal(orbit.action),
                         to_decimal(orbit.flux()),
                         to_decimal(orbit.floquet.multiplier),
                         to_decimal(orbit.floquet.stability_index),
                         std::string(to_string(orbit.status)),
                         to_decimal(orbit.error_estimate_period, 3),
                         to_decimal(orbit.error_estimate_action, 3),
                         to_decimal(orbit.energy_error, 3),
                         {}};
            for (long k = 0; k < samples; ++k) {  // as `flipflux orbit` samples it
                const Real time = orbit.period * k / (samples - 1);
                const phase_point<Real> x =
                    k + 1 == samples ? orbit.start : orbit_state(model, orbit, time);
                t.samples.push_back({to_decimal(time), to_decimal(x[0]), to_decimal(x[1]),
                                     to_decimal(x[2]), to_decimal(x[3])});
            }
            return t;
        });
    });
    py::dict d;
    d["precision"] = o.precision;
    d["energy"] = o.energy;
    d["period"] = o.period;
    d["action"] = o.action;
    d["flux"] = o.flux;
    d["multiplier"] = o.multiplier;
    d["stability_index"] = o.stability_index;
    d["status"] = o.status;
    d["error_estimate_period"] = o.error_estimate_period;
    d["error_estimate_action"] = o.error_estimate_action;
    d["energy_error"] = o.energy_error;
    d["samples"] = o.samples;
    return d;
}

/// A JSON value as the Python object json.loads would make of its text (objects as dicts in their
/// order, integers as int, reals as float, null as None): built from the structs' JSON directly,
/// no text in between.
py::object python_of(const nlohmann::ordered_json& j) {
    switch (j.type()) {
        case nlohmann::ordered_json::value_t::object: {
            py::dict d;
            for (const auto& [key, value] : j.items())
                d[py::str(key)] = python_of(value);
            return py::object(std::move(d));
        }
        case nlohmann::ordered_json::value_t::array: {
            py::list l;
            for (const auto& value : j)
                l.append(python_of(value));
            return py::object(std::move(l));
        }
        case nlohmann::ordered_json::value_t::string:
            return py::str(j.get<std::string>());
        case nlohmann::ordered_json::value_t::boolean:
            return py::bool_(j.get<bool>());
        case nlohmann::ordered_json::value_t::number_integer:
            return py::int_(j.get<std::int64_t>());
        case nlohmann::ordered_json::value_t::number_unsigned:
            return py::int_(j.get<std::uint64_t>());
        case nlohmann::ordered_json::value_t::number_float: {
            const double x = j.get<double>();  // dump() writes a non-finite double as null
            return std::isfinite(x) ? py::object(py::float_(x)) : py::none();
        }
        default:
            return py::none();
    }
}

/// The sink of the Python module: each energy's tables kept in memory (study_files.hpp), made
/// NumPy arrays when the study returns.
class table_sink final : public energy_sink {
  public:
    explicit table_sink(bool residence_times) : residence_times_(residence_times) {}
    bool has(const std::string&) const override { return false; }  // nothing outlives a call
    void put(const ensemble_result& ensemble, const energy_result& summary) override {
        for (energy_table& t : energy_tables(ensemble, summary, residence_times_))
            tables.push_back(std::move(t));
    }
    std::vector<energy_table> tables;

  private:
    bool residence_times_;
};

/// A table as [(column, values)]: integers and reals as NumPy int64 and float64 arrays (NaN where
/// not computed), texts as lists of str.
py::list python_of(const energy_table& t) {
    py::list columns;
    for (const table_column& c : t.columns) {
        py::object values;
        switch (c.type) {
            case table_column::kind::integer: {
                py::array_t<std::int64_t> a(static_cast<py::ssize_t>(c.integers.size()));
                auto w = a.mutable_unchecked<1>();
                for (std::size_t i = 0; i < c.integers.size(); ++i)
                    w(static_cast<py::ssize_t>(i)) = static_cast<std::int64_t>(c.integers[i]);
                values = std::move(a);
                break;
            }
            case table_column::kind::real:
                values =
                    py::array_t<double>(static_cast<py::ssize_t>(c.reals.size()), c.reals.data());
                break;
            case table_column::kind::text:
                values = py::cast(c.texts);
                break;
        }
        columns.append(py::make_tuple(c.name, values));
    }
    return columns;
}

/// simulate(): the report as a dict and each energy's tables by name, from the structs.
py::tuple simulate_tables(const std::map<std::string, std::string>& a,
                          const std::map<std::string, std::string>& parameters) {
    // the library's one builder of run settings (study/settings.hpp), errors naming keywords
    settings_text given;
    for (const auto& [key, value] : a)
        given[key] = value;  // a keyword left None is absent: the table's default
    const double_pendulum<double> model = make_model<double>(model_of(parameters));
    simulation_request q = make_simulation_request(given, settings_surface::python);
    auto sink = std::make_shared<table_sink>(q.residence_times);
    q.sink = sink.get();
    auto stop = std::make_shared<std::atomic<int>>(0);
    q.options.stop = stop.get();
    // the worker holds the sink: an abandoned call cannot outlive it
    std::optional<study_result> run;
    try {
        run = interruptible(
            [model, q, sink] {
                std::optional<study_result> out = simulate(model, q);
                return *out;
            },
            stop.get());
    } catch (const simulation_interrupted& e) {
        if (e.signal() != cpu_bound_stop) throw;
        PyErr_SetString(PyExc_TimeoutError, (std::string("max_seconds: ") + e.what()).c_str());
        throw py::error_already_set();
    }
    const study_result& r = *run;
    nlohmann::ordered_json j = study_json(r);
    j["model"] = model_parameters_json(model);
    py::dict tables;
    for (const energy_table& t : sink->tables)
        tables[py::str(t.name)] = python_of(t);
    return py::make_tuple(python_of(j), tables);
}

/// validate(): the candidate's rows as CSV text held in memory (errors name them "rows:LINE").
py::dict validate_rows(const std::string& rows_csv, const std::string& golden, double rtol,
                       bool allow_missing) {
    if (!(rtol > 0 && rtol < 1))
        throw input_error("rtol: '" + std::to_string(rtol) + "' must be in (0, 1)");
    const validation_report r =
        validate_candidate_table(parse_csv(rows_csv, "rows"), "rows", golden, rtol, allow_missing);
    py::list rows;
    for (const validation_entry& e : r.entries) {
        py::dict row;
        row["status"] = std::string(to_string(e.what));
        row["line"] = e.line;
        row["quantity"] = e.quantity;
        row["arm"] = e.arm;
        row["energy"] = e.energy;
        row["candidate"] = e.candidate;
        row["golden"] = e.golden;
        row["relative_error"] = e.relative_error;
        row["matched_digits"] = e.matched_digits;
        row["certified_digits"] = e.certified_digits;
        row["note"] = e.note;
        rows.append(row);
    }
    py::dict d;
    d["passed"] = r.passed();
    d["rows"] = rows;
    d["report"] = format_report(r, rtol, false, ": allow_missing=True accepts them");
    return d;
}

}  // namespace

PYBIND11_MODULE(_flipflux, m) {
    m.doc() = "flipflux's native layer (use the flipflux package, python/flipflux/__init__.py)";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const input_error& e) {
            std::string message = e.what();  // "keyword: ...", one line
            for (char& c : message)
                if (c == '\n' || c == '\r') c = ' ';
            PyErr_SetString(PyExc_ValueError, message.c_str());
        }
    });
    m.def("version", [] { return std::string(version_string()) + " (git " + git_commit() + ")"; });
    m.def("quantities", [] {
        std::vector<std::tuple<std::string, std::string, std::vector<std::string>, bool>> out;
        for (const quantity& q : quantities())
            out.emplace_back(q.name, q.description, q.methods, q.per_arm);
        return out;
    });
    m.def("parameter_fields", [] {  // (name, default text): the C++ table Pendulum mirrors
        std::vector<std::pair<std::string, std::string>> out;
        for (const parameter_field& f : parameter_fields)
            out.emplace_back(std::string(f.name), std::string(f.default_text));
        return out;
    });
    m.def("run_settings", [] {  // (keyword, default): the settings table's Python side
        std::vector<std::pair<std::string, std::string>> out;
        for (const run_setting& r : run_settings())
            if (!r.keyword.empty())
                out.emplace_back(std::string(r.keyword),
                                 setting_default(r, settings_surface::python));
        return out;
    });
    m.def("evaluate", &evaluate);
    m.def("saddle_orbit", &saddle_orbit_text);
    m.def("simulate", &simulate_tables);
    m.def("validate_rows", &validate_rows);
}
