/**
 * @file roles.hpp
 * @brief The deployment's roles (what a tile runs), apart from the tile map so that
 *        the message declarations (messages.hpp) can name who sends and who receives.
 */
#pragma once

#include <cstdint>

namespace trn::tasks {

enum class Role : std::uint8_t {
  kSpare,
  kTrnSupervisor,
  kVisionCoordinator,
  kFilterSupervisor,
  kIo,
  kFilter,
  kVision,
  kFilterReplica,
  kVisionSupervisor,
};

/** Bit per Role (1 << Role): a set of roles as a mask, as the SDC points and the message declarations name them. */
constexpr std::uint32_t role_bit(Role r) noexcept { return 1U << static_cast<std::uint32_t>(r); }

}  // namespace trn::tasks
