/**
 * @file messages.cpp
 * @brief The rules over several fields of the TRN messages that a field's range cannot say
 *        (the declarations are in messages.hpp).
 */
#include "trn/tasks/messages.hpp"

#include <cstdint>

namespace trn::tasks::detail {

bool part_of_frame(std::span<const std::uint32_t> w) noexcept {
  if ((w[2] & 0xFFFFU) >= (w[2] >> 16U)) {
    return false;  // part < parts
  }
  const std::uint32_t n = w[3];  // the decoder checked 1 .. kMatchesPerPart and the size
  for (std::uint32_t i = 0; i < n; ++i) {
    // Word 21 of a packed match is its frame number.
    if (w[kMatchHeaderWords + i * kMatchWords + 21U] != w[1]) {
      return false;
    }
  }
  return true;
}

}  // namespace trn::tasks::detail
