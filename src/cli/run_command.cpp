// flipflux run [--dry-run] SCENE: compute what a scene file asks for, and nothing else.
#include <iostream>

#include "common.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux::cli {
namespace {

struct run_state {
    std::string file;
    bool dry_run = false;
};

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<run_state>();
    CLI::App* sub = app.add_subcommand(
        "run", "Run a scene file (TOML, see docs/scenes.md): compute exactly what it requests");
    sub->add_option("scene", s->file, "the scene file")->required();
    sub->add_flag("--dry-run", s->dry_run, "print the plan without computing anything");
    sub->callback([s] {
        const scene sc = load_scene(s->file);
        const plan p = make_plan(sc);
        print_plan(sc, p, std::cout);
        if (s->dry_run) return;
        (void)execute_plan(sc, p, std::cout);
    });
});

}  // namespace
}  // namespace flipflux::cli
