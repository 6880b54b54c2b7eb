// flipflux: the command-line tool. A thin layer: each subcommand parses its options, calls the
// library in the requested precision and prints JSON (or writes files atomically).
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "common.hpp"
#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/plugin.hpp"
#include "flipflux/core/version.hpp"

namespace {

// A standard stream closed by the caller (`flipflux model >&-`) is reopened at once, so that no
// file the program opens later takes its descriptor and receives the output meant for it. A closed
// stdout becomes /dev/full: whatever is printed there fails, and the final check reports it.
bool reopen_closed_standard_streams() {
    bool stdout_closed = false;
    for (int fd = 0; fd <= 2; ++fd) {
        if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
        if (fd == 1) stdout_closed = true;
        const int opened = fd == 1 ? ::open("/dev/full", O_WRONLY) : ::open("/dev/null", O_RDWR);
        if (opened != fd && opened >= 0) {
            ::dup2(opened, fd);
            ::close(opened);
        }
    }
    return stdout_closed;
}

// Every byte printed on stdout must have reached it: exit status 1 and one line otherwise
// (`flipflux eval omega --energy 3 > /dev/full` must not exit 0).
int checked_exit(int status, bool stdout_closed) {
    std::cout.flush();
    const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
    if (!failed) return status;
    const int err = errno;
    std::fprintf(stderr, "flipflux: error: cannot write the standard output (%s)\n",
                 stdout_closed ? "it is closed" : std::strerror(err));
    return status == 0 || status == 2 ? 1 : status;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace flipflux;
    const bool stdout_closed = reopen_closed_standard_streams();
    CLI::App app{"flipflux: verified flip-rate predictions for the double pendulum", "flipflux"};
    app.set_version_flag(
        "--version", std::string("flipflux ") + version_string() + " (git " + git_commit() + ")");
    app.require_subcommand(1);
    for (const auto& c : cli::commands())
        c.setup(app);
    cli::apply_number_grammar(app);
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
                             cli::one_line(argv[1]).c_str(), known.c_str());
                return 2;
            }
        }
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return checked_exit(app.exit(e), stdout_closed);
    } catch (const CLI::CallForAllHelp& e) {
        return checked_exit(app.exit(e), stdout_closed);
    } catch (const CLI::CallForVersion& e) {
        return checked_exit(app.exit(e), stdout_closed);
    } catch (const CLI::RequiredError& e) {
        // a mistyped option (`--energyy 3`) is named rather than the option it failed to give
        for (const CLI::App* sub : app.get_subcommands())
            for (const std::string& extra : sub->remaining())
                if (!extra.empty() && extra[0] == '-') {
                    std::fprintf(stderr,
                                 "flipflux: error: '%s' is not an option of '%s' (see %s --help)\n",
                                 cli::one_line(extra).c_str(), sub->get_name().c_str(),
                                 sub->get_name().c_str());
                    return 2;
                }
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 2;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 2;
    } catch (const input_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::error_text(e).c_str());
        return 2;
    } catch (const certification_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 1;
    } catch (const convergence_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 1;
    } catch (const output_error& e) {
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 1;
    } catch (const plugin_error& e) {  // an installation without its plugins (core/plugin.hpp)
        std::fprintf(stderr, "flipflux: error: %s\n", cli::one_line(e.what()).c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "flipflux: internal error: %s\n", cli::one_line(e.what()).c_str());
        return 1;
    }
    return checked_exit(cli::exit_status(), stdout_closed);
}
