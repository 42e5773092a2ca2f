/**
 * @file health_messages.hpp
 * @brief The tile-health messages on udn::kFtChanHealth between the health agents and the
 *        tile-health supervisor: boot reports, heartbeats, self-tests, results bad, parks, replacements,
 *        and the watcher's questions to the supervisor's neighbours.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "udn/endpoint.hpp"

#include <cstdint>
#include <span>

namespace fdir {

/** No role slot (boot_slot of a tile that was never assigned one). */
inline constexpr std::uint32_t kNoSlot = 0xFFFF'FFFFU;

/** Boot report (udn::kFtChanHealth): [0] kMsgBooted [1] tile [2] bsp::BootCause. */
inline constexpr std::uint32_t kMsgBooted = 0x424F4F54U;  // "BOOT"
inline constexpr std::uint32_t kBootedWords = 3U;

/** Self-test request (supervisor -> agent, kFtChanHealth): [0] kMsgSelfTest [1] round [2] seed. */
inline constexpr std::uint32_t kMsgSelfTest = 0x53545251U;  // "STRQ"
/** Self-test result (agent -> supervisor): [0] kMsgSelfTestResult [1] tile [2] round [3] digest. */
inline constexpr std::uint32_t kMsgSelfTestResult = 0x53545253U;  // "STRS"
inline constexpr std::uint32_t kSelfTestWords = 3U;
inline constexpr std::uint32_t kSelfTestResultWords = 4U;
/** Heartbeat of the supervisor's tile (its agent -> the watcher, kFtChanHealth): [0] kMsgAlive [1] tile [2] bsp::BootCause. */
inline constexpr std::uint32_t kMsgAlive = 0x414C5645U;  // "ALVE"
inline constexpr std::uint32_t kAliveWords = 3U;
/**
 * The watcher's question to a tile beside the supervisor's, when the
 * heartbeat is missing (watcher -> agent, kFtChanHealth): [0] kMsgHearQuery
 * [1] the watcher [2] the supervisor's tile. The answer (agent -> watcher):
 * [0] kMsgHearAnswer [1] the answering tile [2] the supervisor's tile
 * [3] a udn::Heard: whether its endpoint's neighbour probe hears that tile.
 */
inline constexpr std::uint32_t kMsgHearQuery = 0x48524451U;   // "HRDQ"
inline constexpr std::uint32_t kHearQueryWords = 3U;
inline constexpr std::uint32_t kMsgHearAnswer = 0x48524441U;  // "HRDA"
inline constexpr std::uint32_t kHearAnswerWords = 4U;
/**
 * A coordinator's report of a worker whose results stay wrong (fdir/result_trust.hpp; coordinator ->
 * supervisor, kFtChanHealth): [0] kMsgResultsBad [1] coordinator tile [2] worker tile [3] kResultsReset
 * or kResultsReplace [4] the boot slot a replacing spare is to run (boot_slot) [5] the coordinator's
 * channel for the answer. A reset is written kTileReset with cause 2; a replacement switches the
 * worker off for good and a spare on with that boot slot (kRoleMoved, then kRoleRestored at its boot).
 */
inline constexpr std::uint32_t kMsgResultsBad = 0x52424144U;  // "RBAD"
inline constexpr std::uint32_t kResultsBadWords = 6U;
inline constexpr std::uint32_t kResultsReset = 1U;
inline constexpr std::uint32_t kResultsReplace = 2U;
/**
 * Power policy (-> the tile-health supervisor, kFtChanHealth): [0] kMsgPark
 * [1] the asking tile [2] the tile [3] 1 switch it off (park), 0 switch it on
 * (wake) [4] the channel of the answer. A parked tile is not watched and is
 * off by design for every endpoint and the network-health task (its switch
 * still routes); it is switched off kParkOffTicks after the others are told.
 * A woken tile is watched again from its boot report.
 */
inline constexpr std::uint32_t kMsgPark = 0x50524B52U;  // "PRKR"
inline constexpr std::uint32_t kParkWords = 5U;
/** The answer: [0] kMsgParkDone [1] tile [2] 1 off, 0 booted and watched again. */
inline constexpr std::uint32_t kMsgParkDone = 0x50524B44U;  // "PRKD"
inline constexpr std::uint32_t kParkDoneWords = 3U;
/** Ticks between telling the tiles of a park and switching the tile off (the notices arrive first). */
inline constexpr std::uint32_t kParkOffTicks = 20U;

/** The supervisor's answer to a replacement (-> the coordinator's channel): [0] kMsgReplaced [1] old tile [2] spare (kNoTile: none). */
inline constexpr std::uint32_t kMsgReplaced = 0x52504C44U;  // "RPLD"
inline constexpr std::uint32_t kReplacedWords = 3U;
/*
 * The health messages' fields, and their pack_ / unpack_ (health_messages.cpp).
 * An unpack_ returns false, leaving its output as it was, unless the words are
 * exactly that message with every field in its documented range: tiles below
 * bsp::kMaxTiles, a boot cause of bsp::BootCause, channels below
 * udn::kFtAllChannels, flags 0 or 1.
 */
/** kMsgBooted and kMsgAlive: the sending tile and why it last booted. */
struct TileBootReport {
  bsp::TileId tile = 0U;
  bsp::BootCause cause = bsp::BootCause::kPowerOn;
};
struct SelfTestRequest {
  std::uint32_t round = 0U;
  std::uint32_t seed = 0U;
};
struct SelfTestResult {
  bsp::TileId tile = 0U;
  std::uint32_t round = 0U;
  std::uint32_t digest = 0U;
};
struct ResultsBad {
  bsp::TileId coordinator = 0U;
  bsp::TileId worker = 0U;
  bool replace = false;               ///< kResultsReplace (true) or kResultsReset
  std::uint32_t boot_slot = 0U;       ///< not kNoSlot
  std::uint32_t answer_channel = 0U;
};
struct ParkRequest {
  bsp::TileId asker = 0U;
  bsp::TileId tile = 0U;
  bool off = false;                   ///< park (true) or wake
  std::uint32_t answer_channel = 0U;
};
struct ParkDone {
  bsp::TileId tile = 0U;
  bool off = false;
};
struct Replaced {
  bsp::TileId old_tile = 0U;
  bsp::TileId spare = 0U;             ///< bsp::kNoTile: none
};
struct HearQuery {
  bsp::TileId asker = 0U;
  bsp::TileId subject = 0U;
};
struct HearAnswer {
  bsp::TileId tile = 0U;
  bsp::TileId subject = 0U;
  udn::Heard hearing = udn::Heard::kNotProbed;
};
void pack_booted(const TileBootReport& r, std::span<std::uint32_t, kBootedWords> w) noexcept;
[[nodiscard]] bool unpack_booted(std::span<const std::uint32_t> w, TileBootReport& out) noexcept;
void pack_alive(const TileBootReport& r, std::span<std::uint32_t, kAliveWords> w) noexcept;
[[nodiscard]] bool unpack_alive(std::span<const std::uint32_t> w, TileBootReport& out) noexcept;
void pack_self_test(const SelfTestRequest& r, std::span<std::uint32_t, kSelfTestWords> w) noexcept;
[[nodiscard]] bool unpack_self_test(std::span<const std::uint32_t> w, SelfTestRequest& out) noexcept;
void pack_self_test_result(const SelfTestResult& r, std::span<std::uint32_t, kSelfTestResultWords> w) noexcept;
[[nodiscard]] bool unpack_self_test_result(std::span<const std::uint32_t> w, SelfTestResult& out) noexcept;
void pack_results_bad(const ResultsBad& r, std::span<std::uint32_t, kResultsBadWords> w) noexcept;
[[nodiscard]] bool unpack_results_bad(std::span<const std::uint32_t> w, ResultsBad& out) noexcept;
void pack_park(const ParkRequest& r, std::span<std::uint32_t, kParkWords> w) noexcept;
[[nodiscard]] bool unpack_park(std::span<const std::uint32_t> w, ParkRequest& out) noexcept;
void pack_park_done(const ParkDone& r, std::span<std::uint32_t, kParkDoneWords> w) noexcept;
[[nodiscard]] bool unpack_park_done(std::span<const std::uint32_t> w, ParkDone& out) noexcept;
void pack_replaced(const Replaced& r, std::span<std::uint32_t, kReplacedWords> w) noexcept;
[[nodiscard]] bool unpack_replaced(std::span<const std::uint32_t> w, Replaced& out) noexcept;
void pack_hear_query(const HearQuery& r, std::span<std::uint32_t, kHearQueryWords> w) noexcept;
[[nodiscard]] bool unpack_hear_query(std::span<const std::uint32_t> w, HearQuery& out) noexcept;
void pack_hear_answer(const HearAnswer& r, std::span<std::uint32_t, kHearAnswerWords> w) noexcept;
[[nodiscard]] bool unpack_hear_answer(std::span<const std::uint32_t> w, HearAnswer& out) noexcept;

}  // namespace fdir
