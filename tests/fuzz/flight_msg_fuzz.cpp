/**
 * @file flight_msg_fuzz.cpp
 * @brief libFuzzer target for every decoder of a message that crosses tiles: the endpoint's
 *        (udn), the tile-health and supervisor messages (fdir), the TRN tasks' (trn).
 *
 * Input: [0] which decoder (modulo their number) [1] flags (bit 0: put the
 * decoder's tag in word 0; bit 1: cut or pad to the decoder's usual length)
 * then the words, little-endian, at most udn::kFtMaxDataWords. The flags let
 * the fuzzer reach the field checks past the tag and length tests.
 * Properties, for each decoder: a refused message leaves the output exactly as
 * it was (every byte); an accepted one has every field within the documented
 * range, and encoding what was decoded gives back the very words received
 * (the words of a group of records, which the encoder leaves to its caller, aside).
 */
#include "fdir/supervisor.hpp"
#include "fdir/tile_health.hpp"
#include "tests/fuzz/fuzz_check.hpp"
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <cstring>
#include <span>
#include <vector>

namespace {

using Words = std::span<const std::uint32_t>;
using fuzz::require;

/**
 * Runs @p unpack into an output filled with a byte pattern; refused: the bytes
 * are unchanged; accepted: @p accepted(out) checks the ranges and the repacking.
 */
template <class T, class Unpack, class Accepted>
void run(Words w, Unpack unpack, Accepted accepted) {
  static_assert(std::is_trivially_copyable_v<T>);
  alignas(T) std::array<unsigned char, sizeof(T)> raw{};
  raw.fill(0xA5U);
  T out{};
  std::memcpy(&out, raw.data(), sizeof(T));
  if (!unpack(w, out)) {
    require(std::memcmp(&out, raw.data(), sizeof(T)) == 0, "a refused message leaves the output as it was");
    return;
  }
  accepted(out);
}

/** True if @p packed (a fixed-size packing) is exactly @p w. */
template <std::size_t N>
bool same(const std::array<std::uint32_t, N>& packed, Words w) {
  return w.size() == N && std::equal(packed.begin(), packed.end(), w.begin());
}

bool tile_ok(std::uint32_t t) { return t < bsp::kMaxTiles; }

void udn_suspect(Words w) {
  run<udn::SuspectReport>(w, udn::unpack_suspect, [&](const udn::SuspectReport& r) {
    require(r.reporter < udn::kRouteMaxTiles && r.suspect < udn::kRouteMaxTiles && r.reporter != r.suspect, "suspect ranges");
    std::array<std::uint32_t, udn::kSuspectWords> p{};
    udn::pack_suspect(r, p);
    require(same(p, w), "suspect repacks");
  });
}

void udn_transit(Words w) {
  run<udn::TransitReport>(w, udn::unpack_transit, [&](const udn::TransitReport& r) {
    require(r.prober < udn::kRouteMaxTiles && r.target < udn::kRouteMaxTiles, "transit ranges");
    std::array<std::uint32_t, udn::kTransitWords> p{};
    udn::pack_transit(r, p);
    require(same(p, w), "transit repacks");
  });
}

void udn_fault_map(Words w) {
  run<udn::FaultMap>(w, udn::unpack_fault_map, [&](const udn::FaultMap& m) {
    const std::uint32_t tiles = m.cols * m.rows;
    require(m.cols >= 1U && m.rows >= 1U && tiles <= udn::kRouteMaxTiles, "fault map grid");
    for (std::uint32_t t = 0; t < udn::kRouteMaxTiles; ++t) {
      const bool on_grid = t < tiles;
      require(on_grid || (((m.failed_tiles | m.no_forward) >> t) & 1U) == 0U, "fault map tiles on the grid");
      require(m.failed_links[t] < 16U && (on_grid || m.failed_links[t] == 0U), "fault map links");
    }
    std::array<std::uint32_t, udn::kFaultMapWords> p{};
    udn::pack_fault_map(m, p);
    require(same(p, w), "fault map repacks");
  });
}

void udn_role_move(Words w) {
  run<udn::RoleMove>(w, udn::unpack_role_move, [&](const udn::RoleMove& m) {
    require(m.slot < udn::kRoleSlots && m.tile < udn::kRouteMaxTiles && m.version != 0U, "role move ranges");
    std::array<std::uint32_t, udn::kRoleMoveWords> p{};
    udn::pack_role_move(m, p);
    require(same(p, w), "role move repacks");
  });
}

void udn_parked(Words w) {
  run<udn::ParkedSet>(w, udn::unpack_parked, [&](const udn::ParkedSet& s) {
    require(s.serial != 0U, "parked serial");
    std::array<std::uint32_t, udn::kParkedWords> p{};
    udn::pack_parked(s, p);
    require(same(p, w), "parked repacks");
  });
}

/**
 * A declared kind's decoder (fdir/message_kind.hpp): @p in_range(out) checks
 * the ranges of an accepted message, and encoding it must give back the very
 * words received.
 */
template <const auto& K, class InRange>
void kind(Words w, const char* what, InRange in_range) {
  using T = typename std::remove_cvref_t<decltype(K)>::Message;
  const auto decode = [](Words x, T& out) { return fdir::msg::decode(K, x, out); };
  run<T>(w, decode, [&](const T& out) {
    require(in_range(out), what);
    // The encoder leaves a group of records (matches, a solution) to the caller: those words come as they were.
    std::vector<std::uint32_t> p(w.size(), 0xA5A5'A5A5U);
    if (K.info.group.record != nullptr) {
      std::copy(w.begin() + K.info.words, w.end(), p.begin() + K.info.words);
    }
    require(fdir::msg::encode(K, out, p) == w.size() && std::equal(p.begin(), p.end(), w.begin()), what);
  });
}

template <const auto& K>
void fdir_boot(Words w) {
  kind<K>(w, "boot report", [](const fdir::TileBootReport& r) { return tile_ok(r.tile) && r.cause <= bsp::BootCause::kOther; });
}

void fdir_self_test(Words w) {
  kind<fdir::kSelfTestMsg>(w, "self-test", [](const fdir::SelfTestRequest& /*r*/) { return true; });
}

void fdir_self_test_result(Words w) {
  kind<fdir::kSelfTestResultMsg>(w, "self-test result", [](const fdir::SelfTestResult& r) { return tile_ok(r.tile); });
}

void fdir_results_bad(Words w) {
  kind<fdir::kResultsBadMsg>(w, "results bad", [](const fdir::ResultsBad& r) {
    return tile_ok(r.coordinator) && tile_ok(r.worker) && r.boot_slot != fdir::kNoSlot &&
           r.answer_channel < udn::kFtAllChannels &&
           (r.action == fdir::ResultsAction::kReset || r.action == fdir::ResultsAction::kReplace);
  });
}

void fdir_park(Words w) {
  kind<fdir::kParkMsg>(w, "park", [](const fdir::ParkRequest& r) {
    return tile_ok(r.asker) && tile_ok(r.tile) && r.answer_channel < udn::kFtAllChannels;
  });
}

void fdir_park_done(Words w) {
  kind<fdir::kParkDoneMsg>(w, "park done", [](const fdir::ParkDone& r) { return tile_ok(r.tile); });
}

void fdir_hear_query(Words w) {
  kind<fdir::kHearQueryMsg>(w, "hear query", [](const fdir::HearQuery& r) { return tile_ok(r.asker) && tile_ok(r.subject); });
}

void fdir_hear_answer(Words w) {
  kind<fdir::kHearAnswerMsg>(w, "hear answer", [](const fdir::HearAnswer& r) {
    return tile_ok(r.tile) && tile_ok(r.subject) && r.hearing <= udn::Heard::kNotProbed;
  });
}

void fdir_replaced(Words w) {
  kind<fdir::kReplacedMsg>(w, "replaced", [](const fdir::Replaced& r) {
    return tile_ok(r.old_tile) && (tile_ok(r.spare) || r.spare == bsp::kNoTile);
  });
}

template <const auto& K>
void fdir_sup(Words w) {
  kind<K>(w, "supervisor message", [](const fdir::SupMessage& m) {
    return m.constraint < fdir::kMaxConstraints && m.level < fdir::kMaxLevels;
  });
}

namespace tt = trn::tasks;

template <const auto& K>
void trn_any(Words w) {
  kind<K>(w, "repacks", [](const auto& /*m*/) { return true; });
}

void trn_sup_command(Words w) {
  kind<tt::kSupCommandMsg>(w, "supervisor command", [](const tt::SupCommand& c) {
    return c.code == tt::kCmdFilterTmr || c.code == tt::kCmdFilterSimplex;
  });
}

void trn_filter_status(Words w) {
  kind<tt::kFilterStatusMsg>(w, "filter status",
                             [](const tt::FilterStatus& f) { return f.mode <= tt::kFilterModeStopping && f.voting < 8U; });
}

void trn_vision_status(Words w) {
  kind<tt::kVisionStatusMsg>(w, "vision status", [](const tt::VisionStatus& v) {
    return v.healthy <= v.listed && (v.rate_div == 1U || v.rate_div == 2U);
  });
}

void trn_vision_rate(Words w) {
  kind<tt::kVisionRateMsg>(w, "rate divisor", [](const tt::VisionRate& r) { return r.div == 1U || r.div == 2U; });
}

template <const auto& K>
void trn_relight(Words w) {
  kind<K>(w, "band rows", [](const tt::RelightBand& b) { return b.row0 >= 0 && b.rows >= 0; });
}

void trn_coarse_band(Words w) {
  kind<tt::kCoarseBandMsg>(w, "coarse band", [](const tt::CoarseBand& b) {
    return b.row0 >= 0 && b.rows >= 0 && b.window_w >= 1 && b.window_h >= 1 && b.tmpl_w >= 1 && b.tmpl_h >= 1;
  });
}

void trn_coarse_band_done(Words w) {
  kind<tt::kCoarseBandDoneMsg>(w, "coarse band done", [](const tt::CoarseBandDone& d) {
    return d.row0 >= 0 && d.rows >= 0 && d.flat_windows >= 0 && d.status <= 0xFFU && d.first_check <= 0xFFU;
  });
}

void trn_frame(Words w) {
  kind<tt::kFrameMsg>(w, "frame size", [](const tt::FrameNotice& f) {
    return f.width_px >= 1U && f.width_px <= 0xFFFFU && f.height_px >= 1U && f.height_px <= 0xFFFFU;
  });
}

void trn_unit(Words w) {
  kind<tt::kUnitMsg>(w, "unit", [&](const tt::WorkUnit& u) {
    return u.n <= tt::kMaxLandmarksPerUnit && u.width_px <= 0xFFFFU && u.height_px <= 0xFFFFU &&
           w.size() == tt::kUnitHeaderWords + u.n;
  });
}

void trn_result(Words w) {
  kind<tt::kResultMsg>(w, "result", [&](const tt::UnitResult& r) {
    return r.m <= tt::kMaxLandmarksPerUnit && r.m <= r.tried && w.size() == tt::kResultHeaderWords + r.m * tt::kMatchWords;
  });
}

void trn_match_part(Words w) {
  kind<tt::kMatchesMsg>(w, "match part", [&](const tt::MatchPart& p) {
    bool ok = p.part < p.parts && p.n >= 1U && p.n <= tt::kMatchesPerPart && w.size() == tt::kMatchHeaderWords + p.n * tt::kMatchWords;
    for (std::uint32_t i = 0; ok && i < p.n; ++i) {
      const Words m = w.subspan(tt::kMatchHeaderWords + i * tt::kMatchWords, tt::kMatchWords);
      ok = fdir::msg::read(tt::kMatchRecord, m).frame == p.frame;  // every match of the part's frame
    }
    return ok;
  });
}

void trn_replica_hello(Words w) {
  kind<tt::kReplicaHelloMsg>(w, "replica index", [](const tt::ReplicaHello& h) { return h.replica < tt::kReplicas; });
}

void trn_replica_out(Words w) {
  kind<tt::kReplicaOutMsg>(w, "replica index", [](const tt::ReplicaOut& o) { return o.replica < tt::kReplicas; });
}

struct Decoder {
  void (*fn)(Words);
  std::uint32_t tag;
  std::uint32_t words;  ///< usual length (0: none fixed)
};

const Decoder kDecoders[] = {
    {udn_suspect, udn::kMsgSuspect, udn::kSuspectWords},
    {udn_transit, udn::kMsgTransit, udn::kTransitWords},
    {udn_fault_map, udn::kMsgFaultMap, udn::kFaultMapWords},
    {udn_role_move, udn::kMsgRoleMove, udn::kRoleMoveWords},
    {udn_parked, udn::kMsgParked, udn::kParkedWords},
    {fdir_boot<fdir::kBootedMsg>, fdir::kMsgBooted, fdir::kBootedWords},
    {fdir_boot<fdir::kAliveMsg>, fdir::kMsgAlive, fdir::kAliveWords},
    {fdir_self_test, fdir::kMsgSelfTest, fdir::kSelfTestWords},
    {fdir_self_test_result, fdir::kMsgSelfTestResult, fdir::kSelfTestResultWords},
    {fdir_results_bad, fdir::kMsgResultsBad, fdir::kResultsBadWords},
    {fdir_park, fdir::kMsgPark, fdir::kParkWords},
    {fdir_park_done, fdir::kMsgParkDone, fdir::kParkDoneWords},
    {fdir_replaced, fdir::kMsgReplaced, fdir::kReplacedWords},
    {fdir_hear_query, fdir::kMsgHearQuery, fdir::kHearQueryWords},
    {fdir_hear_answer, fdir::kMsgHearAnswer, fdir::kHearAnswerWords},
    {fdir_sup<fdir::kPolicyMsg>, fdir::kMsgPolicy, fdir::kSupMsgWords},
    {fdir_sup<fdir::kPolicyHeldMsg>, fdir::kMsgPolicyHeld, fdir::kSupMsgWords},
    {fdir_sup<fdir::kEscalateMsg>, fdir::kMsgEscalate, fdir::kSupMsgWords},
    {trn_any<tt::kCommandMsg>, tt::kMsgCommand, tt::kCommandWords},
    {trn_sup_command, tt::kMsgSupCommand, tt::kSupCommandWords},
    {trn_filter_status, tt::kMsgFilterStatus, tt::kFilterStatusWords},
    {trn_vision_status, tt::kMsgVisionStatus, tt::kVisionStatusWords},
    {trn_vision_rate, tt::kMsgVisionRate, tt::kVisionRateWords},
    {trn_relight<tt::kRelightMsg>, tt::kMsgRelight, tt::kRelightWords},
    {trn_relight<tt::kRelightDoneMsg>, tt::kMsgRelightDone, tt::kRelightWords},
    {trn_coarse_band, tt::kMsgCoarseBand, tt::kCoarseBandWords},
    {trn_coarse_band_done, tt::kMsgCoarseBandDone, tt::kCoarseBandDoneWords},
    {trn_any<tt::kNavMsg>, tt::kMsgNav, tt::kNavWords},
    {trn_frame, tt::kMsgFrame, tt::kFrameNoticeWords},
    {trn_any<tt::kImuMsg>, 0U, tt::kImuWords},
    {trn_unit, tt::kMsgUnit, 0U},
    {trn_result, tt::kMsgResult, 0U},
    {trn_match_part, tt::kMsgMatches, 0U},
    {trn_replica_hello, tt::kMsgReplicaHello, tt::kReplicaHelloWords},
    {trn_replica_out, tt::kMsgReplicaOut, tt::kReplicaOutWords},
};
constexpr std::size_t kDecoderCount = sizeof kDecoders / sizeof kDecoders[0];

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  const Decoder& d = kDecoders[data[0] % kDecoderCount];
  const std::uint8_t flags = data[1];
  fuzz::Reader r{data + 2, size - 2};
  std::size_t n = r.left / 4U;
  if ((flags & 2U) != 0U && d.words != 0U) {
    n = d.words;
  }
  n = n < udn::kFtMaxDataWords ? n : udn::kFtMaxDataWords;
  std::vector<std::uint32_t> w(n);
  for (auto& x : w) {
    x = r.take(4);
  }
  if ((flags & 1U) != 0U && d.tag != 0U && !w.empty()) {
    w[0] = d.tag;
  }
  d.fn(w);
  return 0;
}
