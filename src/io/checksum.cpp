// FNV-1a checksums (io/checksum.hpp).
#include "flipflux/io/checksum.hpp"

namespace flipflux {

std::uint64_t fnv1a64(std::string_view text) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ULL;
    }
    return h;
}

std::string checksum_hex(std::string_view text) {
    static const char* digits = "0123456789abcdef";
    std::uint64_t h = fnv1a64(text);
    std::string hex(16, '0');
    for (int i = 15; i >= 0; --i, h >>= 4)
        hex[static_cast<std::size_t>(i)] = digits[h & 15];
    return hex;
}

}  // namespace flipflux
