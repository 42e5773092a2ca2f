/**
 * @file settings_copy.hpp
 * @brief A role's settings as its tile uses them: copied from the image into the tile's RAM
 *        under a CRC-32C, checked before they are used, built again from the image when an
 *        upset changed them.
 *
 * The image (a task's configuration) is what the tile booted from and is not
 * changed by an upset of the tile's RAM; the copy in RAM is. A role that keeps
 * its settings this way carves the copy by name (so a plan can aim an upset
 * at it), seals it at set-up, and checks it where a wrong setting would give
 * a wrong result (for the vision coordinator: as a frame starts and before its
 * batch leaves; for a vision tile: before and after each unit). The filter
 * keeps its own settings the same way in its EKF (trn/filter/filter_core.hpp,
 * core_settings_changed()).
 *
 * Flight code: T is plain data (its bytes are its value); the CRC is charged
 * at 8 integer operations and one memory word per 32-bit word.
 */
#pragma once

#include "bsp_tile64/api/work.hpp"
#include "udn/crc32c.hpp"

#include <cstdint>
#include <span>
#include <type_traits>

namespace trn::tasks {

template <class T>
struct SettingsCopy {
  static_assert(std::is_trivially_copyable_v<T>, "settings are plain data");
  T s;
  std::uint32_t crc;
};

/** The work of a CRC over @p bytes bytes. */
inline bsp::Work settings_crc_work(std::size_t bytes) noexcept {
  const std::uint64_t words = (bytes + 3U) / 4U;
  return bsp::Work{8ULL * words, 0U, 0U, 0U, words};
}

template <class T>
std::uint32_t settings_crc(const T& s) noexcept {
  return udn::crc32c_bytes(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(&s), sizeof(T)));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): a plain value's bytes
}

/** Copies @p from (the image's) into @p c and seals it; charges @p work. */
template <class T>
void settings_seal(SettingsCopy<T>& c, const T& from, bsp::Work& work) noexcept {
  c.s = from;
  c.crc = settings_crc(c.s);
  work += settings_crc_work(sizeof(T));
  work.mem_words += sizeof(T) / 4U;
}

/** True when @p c is as it was sealed; charges @p work. */
template <class T>
bool settings_intact(const SettingsCopy<T>& c, bsp::Work& work) noexcept {
  work += settings_crc_work(sizeof(T));
  return settings_crc(c.s) == c.crc;
}

}  // namespace trn::tasks
