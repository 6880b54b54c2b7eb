// flipflux: the command-line tool. A thin layer: each subcommand parses its options, calls the
// library in the requested precision and prints JSON (or writes files atomically).
#include <cstdio>
#include <exception>
#include <string>

#include "common.hpp"
#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"

int main(int argc, char** argv) {
    using namespace flipflux;
    CLI::App app{"flipflux: verified flip-rate predictions for the double pendulum", "flipflux"};
    app.set_version_flag(
        "--version", std::string("flipflux ") + version_string() + " (git " + git_commit() + ")");
    app.require_subcommand(1);
    for (const auto& c : cli::commands())
        c.setup(app);
    try {
        // a mistyped subcommand is named (CLI11 would only say that one is required)
        if (argc > 1 && argv[1][0] != '-') {
            std::string known;
            bool found = false;
            for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
                found = found || sub->get_name() == argv[1];
                known += (known.empty() ? "" : ", ") + sub->get_name();
            }
            if (!found) {
                std::fprintf(stderr, "flipflux: error: '%s' is not a subcommand (one of: %s)\n",
                             argv[1], known.c_str());
                return 2;
            }
        }
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", e.what());
        return 2;
    } catch (const input_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::error_text(e).c_str());
        return 2;
    } catch (const certification_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "flipflux: internal error: %s\n", e.what());
        return 1;
    }
    return cli::exit_status();
}
