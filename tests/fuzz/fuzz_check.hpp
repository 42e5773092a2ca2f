/**
 * @file fuzz_check.hpp
 * @brief Helpers shared by the libFuzzer targets: a property check that aborts, and a byte reader.
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace fuzz {

/** Aborts (a crash libFuzzer records with its input) when a property does not hold. */
inline void require(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz property violated: %s\n", what);
    std::abort();
  }
}

/** Takes little-endian values from the input; zeros once it is used up. */
struct Reader {
  const std::uint8_t* p;
  std::size_t left;
  std::uint32_t take(unsigned bytes) {
    std::uint32_t v = 0;
    for (unsigned i = 0; i < bytes && left > 0; ++i, ++p, --left) {
      v |= static_cast<std::uint32_t>(*p) << (8U * i);
    }
    return v;
  }
};

}  // namespace fuzz
