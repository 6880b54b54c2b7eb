// Counter-based random numbers for reproducible ensembles (Random123's Philox4x64-10, Salmon et
// al., SC'11). Every random number of trajectory i is a pure function of
//     key     = (seed, bits of the energy as an IEEE double)
//     counter = (i, stream purpose, block number, 0)
// so a trajectory's initial condition depends only on (seed, energy, index): results are
// bit-identical for any number of threads or processes and any order of evaluation.
#pragma once

#include <Random123/philox.h>

#include <bit>
#include <cstdint>

namespace flipflux {

/// What a stream is used for (the counter's second word), so that uses never share numbers.
enum class random_purpose : std::uint64_t { initial_condition = 0, tangent_vector = 1, test = 2 };

class philox_stream {
  public:
    philox_stream(std::uint64_t seed, double energy, std::uint64_t index,
                  random_purpose purpose = random_purpose::initial_condition)
        : key_{{seed, std::bit_cast<std::uint64_t>(energy)}},
          ctr_{{index, static_cast<std::uint64_t>(purpose), 0, 0}} {}

    /// The next 64 random bits.
    std::uint64_t bits() {
        if (used_ == 4) {
            block_ = generator_(ctr_, key_);
            ctr_.v[2] += 1;
            used_ = 0;
        }
        return block_.v[used_++];
    }

    /// Uniform in [0, 1): the top 53 bits scaled by 2^-53 (every value is a multiple of 2^-53).
    double uniform() { return static_cast<double>(bits() >> 11) * 0x1.0p-53; }

    /// Number of 4-word blocks generated so far.
    std::uint64_t blocks() const { return ctr_.v[2]; }

  private:
    using engine = r123::Philox4x64;
    engine generator_{};
    engine::key_type key_;
    engine::ctr_type ctr_;
    engine::ctr_type block_{};
    int used_ = 4;
};

}  // namespace flipflux
