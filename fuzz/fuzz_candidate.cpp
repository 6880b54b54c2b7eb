// Fuzz target: the candidate CSV that `flipflux validate` reads (io/csv.hpp, validation/
// validate.hpp), against a small golden table written once, and its '# pendulum:' header
// (validation/candidate_pendulum.hpp) matched against the bundled-style golden sets; the same
// bytes as a simulator's events and states (validation/trajectory_check.hpp, against a golden-like
// reference with provenance, states and double horizons) and as initial states
// (study/study_files.hpp, simulate --initial-states).
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/study/study_files.hpp"
#include "flipflux/validation/candidate_pendulum.hpp"
#include "flipflux/validation/trajectory_check.hpp"
#include "flipflux/validation/validate.hpp"

namespace {
const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                  ("flipflux_fuzz_candidate_" + std::to_string(getpid()));
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool ready = [] {
        std::filesystem::create_directories(dir / "golden");
        std::ofstream(dir / "golden" / "provenance.json")
            << R"({"pendulum": "egalitarian", "parameters": {"m1": "1", "m2": "1", "L1": "1",)"
               R"( "L2": "1", "a1": "1", "a2": "1", "I1": "0", "I2": "0", "g": "1"}})";
        std::ofstream(dir / "golden" / "golden.csv")
            << "quantity,arm,energy,value,digits,method\n"
               "flux-upright,2,3,2.71828182845904523536028747135266249775,38,elliptic\n"
               "omega,,3,1.5,20,elliptic\n";
        std::filesystem::create_directories(dir / "trajectories");
        std::ofstream(dir / "trajectories" / "provenance.json") << R"({"time": "10"})";
        std::ofstream(dir / "trajectories" / "events.csv")
            << "state,time,arm,criterion,direction,digits\n"
               "a,1.5,2,upright,1,50\na,2.5,1,approx,-1,50\n";
        std::ofstream(dir / "trajectories" / "states.csv")
            << "state,t,theta1,theta2,l1,l2,digits\na,10,0.1,3.2,-0.5,0.25,50\n";
        std::ofstream(dir / "trajectories" / "double_horizons.csv")
            << "state,time_tolerance,accuracy,horizon,parted_by\n"
               "a,1e-6,rtol-1e-12,8,x\na,1e-6,limit,9,\n";
        return true;
    }();
    (void)ready;
    std::ofstream(dir / "candidate.csv", std::ios::binary)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    try {
        if (const auto d = flipflux::read_declared_pendulum(dir / "candidate.csv"))
            (void)flipflux::golden_set_for(dir / "golden", d->parameters, d->where);
    } catch (const flipflux::input_error&) {
    }
    for (bool allow_missing : {false, true}) {
        try {
            const auto r = flipflux::validate_candidate(dir / "candidate.csv", dir / "golden",
                                                        1e-12, allow_missing);
            (void)flipflux::format_report(r, 1e-12);
        } catch (const flipflux::input_error&) {
        }
    }
    try {
        flipflux::event_comparison_options o;
        o.state = "a";
        o.candidate_states = dir / "candidate.csv";
        const auto c = flipflux::compare_flip_events(dir / "candidate.csv",
                                                     dir / "trajectories/events.csv", o);
        (void)flipflux::format_event_comparison(c, o);
    } catch (const flipflux::input_error&) {
    }
    try {
        static const flipflux::double_pendulum<double> model;
        (void)flipflux::read_initial_states(dir / "candidate.csv", model);
    } catch (const flipflux::input_error&) {
    }
    return 0;
}
