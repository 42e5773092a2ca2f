/**
 * @file status.hpp
 * @brief Error values returned by the vision algorithms.
 */
#pragma once

#include <cstdint>

namespace trn::vision {

enum class Status : std::uint8_t {
  kOk,
  kBadInput,   ///< an invalid view, or sizes that do not fit each other
  kTooLarge,   ///< the input exceeds a fixed buffer's capacity
};

}  // namespace trn::vision
