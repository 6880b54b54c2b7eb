// The checksum of every file flipflux writes and reads back (checkpoint lines, orbit-cache
// records, the orbit cache's directory key): FNV-1a over the bytes, 64 bits, stable across
// builds and machines. It detects corruption (a truncated or edited record), not tampering.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace flipflux {

/// FNV-1a, 64 bits.
std::uint64_t fnv1a64(std::string_view text);

/// fnv1a64(text) as 16 lowercase hex digits.
std::string checksum_hex(std::string_view text);

}  // namespace flipflux
