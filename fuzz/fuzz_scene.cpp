// Fuzz target: the scene loader and the plan (scene/scene.hpp, scene/plan.hpp).
#include <cstdint>
#include <string>

#include "flipflux/scene/plan.hpp"
#include "flipflux/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)flipflux::make_plan(flipflux::parse_scene(text, "fuzz.toml"));
    } catch (const flipflux::input_error&) {  // scene_error is an input_error
    }
    return 0;
}
