/**
 * @file health_messages.hpp
 * @brief The tile-health messages on udn::kFtChanHealth between the health agents and the
 *        tile-health supervisor: boot reports, heartbeats, self-tests, results bad, parks, replacements,
 *        and the watcher's questions to the supervisor's neighbours.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/port.hpp"
#include "fdir/message_kind.hpp"
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
 * The health messages' fields, and their declarations (fdir/message_kind.hpp):
 * msg::encode() writes one, msg::decode() refuses, leaving its output as it
 * was, words that are not exactly that message with every field in its
 * documented range (tiles below bsp::kMaxTiles, a boot cause of
 * bsp::BootCause, channels below udn::kFtAllChannels, flags 0 or 1), and a
 * receiver dispatches on the tag (msg::dispatch). The roles are the
 * deployment's: it routes the kinds it lists (msg::routed).
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
/** What a coordinator asks for a worker whose results stay wrong (word 3 of kMsgResultsBad). */
enum class ResultsAction : std::uint32_t {
  kReset = kResultsReset,
  kReplace = kResultsReplace,
};
struct ResultsBad {
  bsp::TileId coordinator = 0U;
  bsp::TileId worker = 0U;
  ResultsAction action = ResultsAction::kReset;
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

namespace detail {
namespace m = msg;
inline constexpr std::uint32_t kLastTile = bsp::kMaxTiles - 1U;
inline constexpr std::uint32_t kLastChannel = udn::kFtAllChannels - 1U;
inline constexpr auto kLastCause = static_cast<std::uint32_t>(bsp::BootCause::kOther);
/** Replaced: the spare is a tile or none. */
constexpr bool spare_or_none(std::span<const std::uint32_t> w) noexcept { return w[2] < bsp::kMaxTiles || w[2] == bsp::kNoTile; }
/** Boot report and heartbeat: one layout, two tags. */
constexpr auto boot_report(std::uint32_t tag, const char* name) noexcept {
  return m::kind<TileBootReport>({.tag = tag, .name = name, .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
                                 m::u32("tile", &TileBootReport::tile, 1, 0U, kLastTile),
                                 m::u32("cause", &TileBootReport::cause, 2, 0U, kLastCause));
}
}  // namespace detail

inline constexpr auto kBootedMsg = detail::boot_report(kMsgBooted, "fdir_booted");
inline constexpr auto kAliveMsg = detail::boot_report(kMsgAlive, "fdir_alive");

inline constexpr auto kSelfTestMsg = detail::m::kind<SelfTestRequest>(
    {.tag = kMsgSelfTest, .name = "fdir_self_test", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("round", &SelfTestRequest::round, 1), detail::m::u32("seed", &SelfTestRequest::seed, 2));

inline constexpr auto kSelfTestResultMsg = detail::m::kind<SelfTestResult>(
    {.tag = kMsgSelfTestResult, .name = "fdir_self_test_result", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("tile", &SelfTestResult::tile, 1, 0U, detail::kLastTile),
    detail::m::u32("round", &SelfTestResult::round, 2), detail::m::u32("digest", &SelfTestResult::digest, 3));

inline constexpr auto kResultsBadMsg = detail::m::kind<ResultsBad>(
    {.tag = kMsgResultsBad, .name = "fdir_results_bad", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("coordinator", &ResultsBad::coordinator, 1, 0U, detail::kLastTile),
    detail::m::u32("worker", &ResultsBad::worker, 2, 0U, detail::kLastTile),
    detail::m::u32("action", &ResultsBad::action, 3, kResultsReset, kResultsReplace),
    detail::m::u32("boot_slot", &ResultsBad::boot_slot, 4, 0U, kNoSlot - 1U),
    detail::m::u32("answer_channel", &ResultsBad::answer_channel, 5, 0U, detail::kLastChannel));

inline constexpr auto kParkMsg = detail::m::kind<ParkRequest>(
    {.tag = kMsgPark, .name = "fdir_park", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("asker", &ParkRequest::asker, 1, 0U, detail::kLastTile),
    detail::m::u32("tile", &ParkRequest::tile, 2, 0U, detail::kLastTile),
    detail::m::bits("off", &ParkRequest::off, 3, 0, 32, 0U, 1U),
    detail::m::u32("answer_channel", &ParkRequest::answer_channel, 4, 0U, detail::kLastChannel));

/** The answers to a park and to a replacement go to the channel the asker named: the deployment routes them. */
inline constexpr auto kParkDoneMsg = detail::m::kind<ParkDone>(
    {.tag = kMsgParkDone, .name = "fdir_park_done", .channel = msg::kNoChannel, .from = 0U, .to = 0U},
    detail::m::u32("tile", &ParkDone::tile, 1, 0U, detail::kLastTile), detail::m::bits("off", &ParkDone::off, 2, 0, 32, 0U, 1U));

inline constexpr auto kReplacedMsg = detail::m::kind<Replaced>(
    {.tag = kMsgReplaced, .name = "fdir_replaced", .channel = msg::kNoChannel, .from = 0U, .to = 0U,
     .check = detail::spare_or_none, .rule = "spare below the tile count or none (0xFFFFFFFF)"},
    detail::m::u32("old_tile", &Replaced::old_tile, 1, 0U, detail::kLastTile), detail::m::u32("spare", &Replaced::spare, 2));

inline constexpr auto kHearQueryMsg = detail::m::kind<HearQuery>(
    {.tag = kMsgHearQuery, .name = "fdir_hear_query", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("asker", &HearQuery::asker, 1, 0U, detail::kLastTile),
    detail::m::u32("subject", &HearQuery::subject, 2, 0U, detail::kLastTile));

inline constexpr auto kHearAnswerMsg = detail::m::kind<HearAnswer>(
    {.tag = kMsgHearAnswer, .name = "fdir_hear_answer", .channel = udn::kFtChanHealth, .from = 0U, .to = 0U},
    detail::m::u32("tile", &HearAnswer::tile, 1, 0U, detail::kLastTile),
    detail::m::u32("subject", &HearAnswer::subject, 2, 0U, detail::kLastTile),
    detail::m::u32("hearing", &HearAnswer::hearing, 3, 0U, static_cast<std::uint32_t>(udn::Heard::kNotProbed)));

static_assert(kBootedMsg.info.words == kBootedWords && kAliveMsg.info.words == kAliveWords &&
                  kSelfTestMsg.info.words == kSelfTestWords && kSelfTestResultMsg.info.words == kSelfTestResultWords &&
                  kResultsBadMsg.info.words == kResultsBadWords && kParkMsg.info.words == kParkWords &&
                  kParkDoneMsg.info.words == kParkDoneWords && kReplacedMsg.info.words == kReplacedWords &&
                  kHearQueryMsg.info.words == kHearQueryWords && kHearAnswerMsg.info.words == kHearAnswerWords,
              "the declarations cover the health messages' documented words");

}  // namespace fdir
