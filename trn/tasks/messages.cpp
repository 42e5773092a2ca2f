/**
 * @file messages.cpp
 * @brief The rules over several fields of the TRN messages that a field's range cannot say
 *        (the declarations are in messages.hpp).
 */
#include "trn/tasks/messages.hpp"

#include "bsp_tile64/api/port.hpp"
#include "udn/crc32c.hpp"

#include <array>
#include <cstdint>

namespace trn::tasks {
namespace {

/** CRC-32C of @p w with its seal word taken as 0; charges about 8 operations and a load a word. */
std::uint32_t seal_of(std::span<const std::uint32_t> w) noexcept {
  constexpr std::array<std::uint32_t, 1> kZero{0U};
  std::uint32_t crc = udn::crc32c_words(w.first(kSealWord));
  crc = udn::crc32c_words_continue(crc, kZero);
  crc = udn::crc32c_words_continue(crc, w.subspan(kSealWord + 1U));
  bsp::consume(bsp::Work{8ULL * w.size(), 0U, 0U, 0U, w.size()});
  return crc;
}

}  // namespace

void seal_result(std::span<std::uint32_t> w) noexcept {
  if (w.size() > kSealWord) {
    w[kSealWord] = seal_of(w);
  }
}

bool result_sealed(std::span<const std::uint32_t> w) noexcept {
  return w.size() > kSealWord && seal_of(w) == w[kSealWord];
}

}  // namespace trn::tasks

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
