/**
 * @file health_messages.cpp
 * @brief Word layouts of the tile-health messages (boot, heartbeat, self-test, results bad,
 *        park, replacement): pack, and unpack with every field checked.
 */
#include "fdir/health_messages.hpp"

#include "udn/ft_link.hpp"

namespace fdir {

namespace {

bool is_tile(std::uint32_t t) noexcept { return t < bsp::kMaxTiles; }
bool is_channel(std::uint32_t c) noexcept { return c < udn::kFtAllChannels; }
bool is_cause(std::uint32_t c) noexcept { return c <= static_cast<std::uint32_t>(bsp::BootCause::kOther); }

void pack_boot_report(std::uint32_t tag, const TileBootReport& r, std::span<std::uint32_t, 3> w) noexcept {
  w[0] = tag;
  w[1] = r.tile;
  w[2] = static_cast<std::uint32_t>(r.cause);
}

bool unpack_boot_report(std::uint32_t tag, std::span<const std::uint32_t> w, TileBootReport& out) noexcept {
  if (!udn::is_message(w, tag, 3U) || !is_tile(w[1]) || !is_cause(w[2])) {
    return false;
  }
  out = TileBootReport{w[1], static_cast<bsp::BootCause>(w[2])};
  return true;
}

}  // namespace

static_assert(kBootedWords == 3U && kAliveWords == 3U, "boot report and heartbeat share their layout");

void pack_booted(const TileBootReport& r, std::span<std::uint32_t, kBootedWords> w) noexcept {
  pack_boot_report(kMsgBooted, r, w);
}
bool unpack_booted(std::span<const std::uint32_t> w, TileBootReport& out) noexcept {
  return unpack_boot_report(kMsgBooted, w, out);
}
void pack_alive(const TileBootReport& r, std::span<std::uint32_t, kAliveWords> w) noexcept {
  pack_boot_report(kMsgAlive, r, w);
}
bool unpack_alive(std::span<const std::uint32_t> w, TileBootReport& out) noexcept {
  return unpack_boot_report(kMsgAlive, w, out);
}

void pack_self_test(const SelfTestRequest& r, std::span<std::uint32_t, kSelfTestWords> w) noexcept {
  w[0] = kMsgSelfTest;
  w[1] = r.round;
  w[2] = r.seed;
}

bool unpack_self_test(std::span<const std::uint32_t> w, SelfTestRequest& out) noexcept {
  if (!udn::is_message(w, kMsgSelfTest, kSelfTestWords)) {
    return false;
  }
  out = SelfTestRequest{w[1], w[2]};
  return true;
}

void pack_self_test_result(const SelfTestResult& r, std::span<std::uint32_t, kSelfTestResultWords> w) noexcept {
  w[0] = kMsgSelfTestResult;
  w[1] = r.tile;
  w[2] = r.round;
  w[3] = r.digest;
}

bool unpack_self_test_result(std::span<const std::uint32_t> w, SelfTestResult& out) noexcept {
  if (!udn::is_message(w, kMsgSelfTestResult, kSelfTestResultWords) || !is_tile(w[1])) {
    return false;
  }
  out = SelfTestResult{w[1], w[2], w[3]};
  return true;
}

void pack_results_bad(const ResultsBad& r, std::span<std::uint32_t, kResultsBadWords> w) noexcept {
  w[0] = kMsgResultsBad;
  w[1] = r.coordinator;
  w[2] = r.worker;
  w[3] = r.replace ? kResultsReplace : kResultsReset;
  w[4] = r.boot_slot;
  w[5] = r.answer_channel;
}

bool unpack_results_bad(std::span<const std::uint32_t> w, ResultsBad& out) noexcept {
  if (!udn::is_message(w, kMsgResultsBad, kResultsBadWords) || !is_tile(w[1]) || !is_tile(w[2]) ||
      (w[3] != kResultsReset && w[3] != kResultsReplace) || w[4] == kNoSlot || !is_channel(w[5])) {
    return false;
  }
  out = ResultsBad{w[1], w[2], w[3] == kResultsReplace, w[4], w[5]};
  return true;
}

void pack_park(const ParkRequest& r, std::span<std::uint32_t, kParkWords> w) noexcept {
  w[0] = kMsgPark;
  w[1] = r.asker;
  w[2] = r.tile;
  w[3] = r.off ? 1U : 0U;
  w[4] = r.answer_channel;
}

bool unpack_park(std::span<const std::uint32_t> w, ParkRequest& out) noexcept {
  if (!udn::is_message(w, kMsgPark, kParkWords) || !is_tile(w[1]) || !is_tile(w[2]) || w[3] > 1U || !is_channel(w[4])) {
    return false;
  }
  out = ParkRequest{w[1], w[2], w[3] == 1U, w[4]};
  return true;
}

void pack_park_done(const ParkDone& r, std::span<std::uint32_t, kParkDoneWords> w) noexcept {
  w[0] = kMsgParkDone;
  w[1] = r.tile;
  w[2] = r.off ? 1U : 0U;
}

bool unpack_park_done(std::span<const std::uint32_t> w, ParkDone& out) noexcept {
  if (!udn::is_message(w, kMsgParkDone, kParkDoneWords) || !is_tile(w[1]) || w[2] > 1U) {
    return false;
  }
  out = ParkDone{w[1], w[2] == 1U};
  return true;
}

void pack_replaced(const Replaced& r, std::span<std::uint32_t, kReplacedWords> w) noexcept {
  w[0] = kMsgReplaced;
  w[1] = r.old_tile;
  w[2] = r.spare;
}

bool unpack_replaced(std::span<const std::uint32_t> w, Replaced& out) noexcept {
  if (!udn::is_message(w, kMsgReplaced, kReplacedWords) || !is_tile(w[1]) || (!is_tile(w[2]) && w[2] != bsp::kNoTile)) {
    return false;
  }
  out = Replaced{w[1], w[2]};
  return true;
}

void pack_hear_query(const HearQuery& r, std::span<std::uint32_t, kHearQueryWords> w) noexcept {
  w[0] = kMsgHearQuery;
  w[1] = r.asker;
  w[2] = r.subject;
}

bool unpack_hear_query(std::span<const std::uint32_t> w, HearQuery& out) noexcept {
  if (!udn::is_message(w, kMsgHearQuery, kHearQueryWords) || !is_tile(w[1]) || !is_tile(w[2])) {
    return false;
  }
  out = HearQuery{w[1], w[2]};
  return true;
}

void pack_hear_answer(const HearAnswer& r, std::span<std::uint32_t, kHearAnswerWords> w) noexcept {
  w[0] = kMsgHearAnswer;
  w[1] = r.tile;
  w[2] = r.subject;
  w[3] = static_cast<std::uint32_t>(r.hearing);
}

bool unpack_hear_answer(std::span<const std::uint32_t> w, HearAnswer& out) noexcept {
  if (!udn::is_message(w, kMsgHearAnswer, kHearAnswerWords) || !is_tile(w[1]) || !is_tile(w[2]) ||
      w[3] > static_cast<std::uint32_t>(udn::Heard::kNotProbed)) {
    return false;
  }
  out = HearAnswer{w[1], w[2], static_cast<udn::Heard>(w[3])};
  return true;
}

}  // namespace fdir
