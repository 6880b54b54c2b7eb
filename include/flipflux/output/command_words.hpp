// The caller's words for the commands behind a generated file. Golden provenance and the accuracy
// report describe how their numbers were made and where to look further; the library holds no
// command-line text, so the caller that runs them gives its own words (the command line:
// cli::cli_command_words(); a caller that gives none gets descriptions without them).
#pragma once

#include <string>
#include <vector>

namespace flipflux {

struct command_words {
    std::string run_scene;             ///< the command that runs a scene file (its path follows)
    std::string quantity_list;         ///< where the registered quantities are listed
    std::string model_options;         ///< how a pendulum's nine parameters are given
    std::string golden_certify;        ///< the golden run that proves enclosures
    std::string eval_certify;          ///< the evaluation that proves an enclosure
    std::vector<std::string> threads;  ///< how the measuring threads are set (one way each)
};

}  // namespace flipflux
