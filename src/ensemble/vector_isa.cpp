// The ensemble's vector instruction set: what the processor has, the automatic choice, and the
// caller's or the environment's (FLIPFLUX_VECTOR_ISA) override (see ensemble.hpp).
#include <atomic>
#include <cstdlib>
#include <string>

#include "flipflux/core/error.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/ensemble/ensemble.hpp"

namespace flipflux {
namespace {

bool processor_has_avx512() {
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") != 0;
    }();
    return has;
}

bool processor_has_avx2() {
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return has;
}

vector_isa automatic_isa() {
    // every processor with AVX-512F, Zen 4 included (bench/results/vector_isa_zen4_2026-11-30.txt)
    if (processor_has_avx512() && processor_has_avx2()) return vector_isa::avx512;
    if (processor_has_avx2()) return vector_isa::avx2;
    return vector_isa::sse2;
}

// The choice of set_ensemble_vector_isa (automatic: none made).
std::atomic<vector_isa> chosen_isa{vector_isa::automatic};

}  // namespace

bool processor_supports(vector_isa isa) {
    switch (isa) {
        case vector_isa::avx512:  // its last lanes run in AVX2 vectors
            return processor_has_avx512() && processor_has_avx2();
        case vector_isa::avx2:
            return processor_has_avx2();
        default:
            return true;
    }
}

void set_ensemble_vector_isa(vector_isa isa) {
    if (!processor_supports(isa))
        throw input_error::about("vector_isa",
                                 "'" + to_string(isa) + "' is not supported by this processor");
    chosen_isa.store(isa);
}

vector_isa ensemble_vector_isa() {
    if (const vector_isa isa = chosen_isa.load(); isa != vector_isa::automatic) return isa;
    const char* env = std::getenv("FLIPFLUX_VECTOR_ISA");
    if (env == nullptr || *env == 0) return automatic_isa();
    const std::string field = "environment variable FLIPFLUX_VECTOR_ISA";
    const vector_isa isa = parse_name<vector_isa>(env, field);
    if (!processor_supports(isa))
        throw input_error::about(field,
                                 "'" + std::string(env) + "' is not supported by this processor");
    return isa == vector_isa::automatic ? automatic_isa() : isa;
}

std::size_t ensemble_lanes_per_thread(vector_isa isa) {
    if (isa == vector_isa::automatic) isa = ensemble_vector_isa();
    return isa == vector_isa::avx512 ? max_thread_lanes
           : isa == vector_isa::avx2 ? max_thread_lanes / 2
                                     : max_thread_lanes / 4;
}

}  // namespace flipflux
