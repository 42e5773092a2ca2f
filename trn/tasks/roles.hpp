/**
 * @file roles.hpp
 * @brief The deployment's roles (what a tile runs) and their role slots, apart from the tile
 *        map so that the message declarations (messages.hpp) can name who sends and who
 *        receives. A new role is declared here (its Role and, if it moves, its slot) and in
 *        tile_map.hpp (where it boots, its task table, what its configuration names).
 */
#pragma once

#include "udn/endpoint.hpp"

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

/**
 * Role slots of the messaging role directory (udn::RoleDirectory): a sender
 * to one of these roles asks the directory where it runs now, the configured
 * tile being the answer until a role has a directory entry.
 */
inline constexpr std::uint32_t kSlotCoordinator = 0U;
inline constexpr std::uint32_t kSlotIo = 1U;
inline constexpr std::uint32_t kSlotFilter = 2U;
/** The filter's TMR replicas: slots kSlotReplica0 .. kSlotReplica0 + 2. */
inline constexpr std::uint32_t kSlotReplica0 = 3U;
/** The filter and vision supervisors (trn/tasks/supervisors/supervisors.hpp). */
inline constexpr std::uint32_t kSlotFilterSupervisor = 6U;
inline constexpr std::uint32_t kSlotVisionSupervisor = 7U;
/**
 * The TRN supervisor's tile (tile health, network health, the top of the
 * supervisor tree): reports, boot reports and escalations follow it when its
 * watcher moves it to its standby (fdir/health_agent.hpp).
 */
inline constexpr std::uint32_t kSlotTrnSupervisor = 8U;
/**
 * Not a directory slot (the first number past them): the boot slot
 * (fdir::boot_slot) of a spare switched on to take the place of a vision tile
 * whose matches stayed wrong. Nobody sends to it by slot; the coordinator
 * learns the spare's tile from the supervisor.
 */
inline constexpr std::uint32_t kSlotVisionPool = udn::kRoleSlots;

}  // namespace trn::tasks
