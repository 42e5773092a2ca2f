/**
 * @file message_kinds_test.cpp
 * @brief The declared message kinds (trn/tasks/messages.hpp, fdir/health_messages.hpp,
 *        fdir/supervisor.hpp, fdir/message_kind.hpp): every kind round-trips, refuses each
 *        field out of its range, no tag twice, dispatch by tag, and the table in
 *        docs/ARCHITECTURE.md is the declaration.
 */
#include "trn/tasks/messages.hpp"

#include "build_info.hpp"
#include "tools/common/mission/message_doc.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace {

namespace tt = trn::tasks;
namespace m = fdir::msg;

constexpr std::uint64_t kSeed = 0x5EED'0055ULL;
/** More words than any declared group takes (5 matches of 22, or one solution of 48). */
constexpr std::uint32_t kMaxGroupWords = 124U;

struct Rng {
  std::uint64_t s;
  std::uint64_t next() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return s >> 11U;
  }
  std::uint32_t in(std::uint32_t lo, std::uint32_t hi) {
    return lo + static_cast<std::uint32_t>(next() % (std::uint64_t{hi} - lo + 1U));
  }
};

/** Raw bits of a value of @p f in its range (floats finite: a double member would quiet a NaN float). */
std::uint64_t raw_in_range(const m::FieldInfo& f, Rng& r) {
  switch (f.type) {
    case m::Type::kF64: return std::bit_cast<std::uint64_t>(static_cast<double>(r.in(0U, 1000000U)) / 7.0 - 5e4);
    case m::Type::kF32: return std::bit_cast<std::uint32_t>(static_cast<float>(r.in(0U, 1000U)) / 3.0F);
    case m::Type::kU64: return r.next() ^ (r.next() << 40U);
    default: return r.in(f.min, f.max);
  }
}

void put(const m::FieldInfo& f, std::vector<std::uint32_t>& w, std::size_t at, std::uint64_t raw) {
  if (f.bits == 64U) {
    w[at] = static_cast<std::uint32_t>(raw);
    w[at + 1U] = static_cast<std::uint32_t>(raw >> 32U);
    return;
  }
  w[at] = (w[at] & ~(m::mask_of(f) << f.shift)) | ((static_cast<std::uint32_t>(raw) & m::mask_of(f)) << f.shift);
}

std::size_t word_of(const m::KindInfo& k, const m::FieldInfo& f, std::size_t e) {
  return f.in_group ? k.words + e * k.group.elem_words + f.word : f.word + e * m::words_of(f);
}

/** Words of a valid message of @p k with @p count group elements (a draw the kind's rule refuses is drawn again). */
std::vector<std::uint32_t> valid_words(const m::KindView& k, Rng& r, std::uint32_t count) {
  const m::KindInfo& i = *k.info;
  std::vector<std::uint32_t> w(m::words_with(i, count), 0U);
  for (int attempt = 0; attempt < 1000; ++attempt) {
    for (std::uint32_t& x : w) {
      x = static_cast<std::uint32_t>(r.next());
    }
    if (i.tag != m::kNoTag) {
      w[0] = i.tag;
    }
    for (const m::FieldInfo& f : k.fields) {
      const std::size_t n = f.in_group ? count : f.count;
      for (std::size_t e = 0; e < n; ++e) {
        put(f, w, word_of(i, f, e), raw_in_range(f, r));
      }
    }
    if (i.group.count_field != m::kNoCount) {
      const m::FieldInfo& c = k.fields[i.group.count_field];
      put(c, w, c.word, count);
    }
    if (i.group.record != nullptr && std::strcmp(i.group.record, "match") == 0) {
      for (std::uint32_t e = 0; e < count; ++e) {
        w[i.words + e * i.group.elem_words + 21U] = w[1];  // a match of the message's frame
      }
    }
    if (std::strcmp(i.name, "fdir_replaced") == 0) {
      w[2] = (r.next() & 1U) != 0U ? bsp::kNoTile : r.in(0U, bsp::kMaxTiles - 1U);  // its rule: a tile or none
    }
    if (m::valid(k, w)) {
      return w;
    }
  }
  ADD_FAILURE() << i.name << ": no valid draw in 1000 (seed " << kSeed << ")";
  return w;
}

/** Counts of group elements to try: each the count field allows, or the fixed count. */
std::vector<std::uint32_t> counts_of(const m::KindView& k) {
  const m::GroupInfo& g = k.info->group;
  if (g.elem_words == 0U || g.count_field == m::kNoCount) {
    return {g.fixed_count};
  }
  std::vector<std::uint32_t> c;
  for (std::uint32_t n = k.fields[g.count_field].min; n <= k.fields[g.count_field].max; ++n) {
    c.push_back(n);
  }
  return c;
}

template <typename K>
void round_trips(const K& k, Rng& r) {
  SCOPED_TRACE(k.info.name);
  for (const std::uint32_t count : counts_of(m::view(k))) {
    for (int draw = 0; draw < 20; ++draw) {
      const std::vector<std::uint32_t> w = valid_words(m::view(k), r, count);
      typename K::Message msg{};
      ASSERT_TRUE(m::decode(k, w, msg)) << "count " << count << " seed " << kSeed;
      // The encoder leaves a record group's words to the caller: start from them, garbage otherwise.
      std::vector<std::uint32_t> again(w.size(), 0xA5A5'A5A5U);
      if (k.info.group.record != nullptr) {
        again = w;
        std::fill(again.begin(), again.begin() + k.info.words, 0xA5A5'A5A5U);
      }
      EXPECT_EQ(m::encode(k, msg, again), w.size());
      EXPECT_EQ(again, w) << "count " << count << " seed " << kSeed;
    }
  }
}

/** The declared words of @p msg (what a refused decode must leave as it was). */
template <typename K>
std::vector<std::uint32_t> words_of_message(const K& k, const typename K::Message& msg) {
  std::vector<std::uint32_t> w(k.info.words + std::size_t{kMaxGroupWords}, 0U);
  w.resize(m::encode(k, msg, w));
  return w;
}

template <typename K>
void refuses_out_of_range(const K& k, Rng& r) {
  SCOPED_TRACE(k.info.name);
  const m::KindView v = m::view(k);
  const std::uint32_t count = counts_of(v).back();
  const std::vector<std::uint32_t> good = valid_words(v, r, count);
  typename K::Message msg{};
  const typename K::Message before = msg;
  for (const m::FieldInfo& f : k.rows) {
    if (m::full_range(f) || (f.in_group && count == 0U)) {
      continue;  // nothing a decoder could refuse in this field
    }
    std::vector<std::uint32_t> bad = good;
    const bool above = f.max < m::mask_of(f);
    ASSERT_TRUE(above || f.min > 0U) << f.name;
    put(f, bad, word_of(k.info, f, 0U), above ? std::uint64_t{f.max} + 1U : std::uint64_t{f.min} - 1U);
    if (static_cast<int>(&f - k.rows.data()) == k.info.group.count_field) {
      continue;  // a count out of range also changes the size: the size check below covers it
    }
    EXPECT_FALSE(m::decode(k, bad, msg)) << f.name;
    EXPECT_EQ(words_of_message(k, msg), words_of_message(k, before)) << f.name << ": a refused decode writes nothing";
  }
  std::vector<std::uint32_t> longer = good;
  longer.push_back(0U);
  EXPECT_FALSE(m::decode(k, longer, msg));
  EXPECT_FALSE(m::decode(k, std::span<const std::uint32_t>(good).first(good.size() - 1U), msg));
  if (k.info.tag != m::kNoTag) {
    std::vector<std::uint32_t> other = good;
    other[0] ^= 1U;
    EXPECT_FALSE(m::decode(k, other, msg));
  }
}

const auto kTyped = std::tie(tt::kMatchRecord, tt::kImuMsg, tt::kCommandMsg, tt::kNavMsg, tt::kFrameMsg, tt::kUnitMsg,
                             tt::kResultMsg, tt::kMatchesMsg, tt::kRelightMsg, tt::kRelightDoneMsg, tt::kCoarseBandMsg,
                             tt::kCoarseBandDoneMsg, tt::kReplicaHelloMsg, tt::kReplicaOutMsg, tt::kSupCommandMsg,
                             tt::kFilterStatusMsg, tt::kVisionStatusMsg, tt::kVisionRateMsg, tt::kReplacedOnControl,
                             tt::kParkDoneOnControl, tt::kPolicyOnControl, tt::kPolicyHeldOnControl, tt::kEscalateOnControl);
/** fdir's own kinds (fdir/health_messages.hpp, fdir/supervisor.hpp), the ones TRN does not route as well. */
const auto kFdirTyped = std::tie(fdir::kBootedMsg, fdir::kAliveMsg, fdir::kSelfTestMsg, fdir::kSelfTestResultMsg,
                                 fdir::kResultsBadMsg, fdir::kParkMsg, fdir::kParkDoneMsg, fdir::kReplacedMsg,
                                 fdir::kHearQueryMsg, fdir::kHearAnswerMsg, fdir::kPolicyMsg, fdir::kPolicyHeldMsg,
                                 fdir::kEscalateMsg);

TEST(MessageKinds, EveryDeclaredKindRoundTripsBitForBit) {
  Rng r{kSeed};
  std::apply([&](const auto&... k) { (round_trips(k, r), ...); }, kTyped);
  std::apply([&](const auto&... k) { (round_trips(k, r), ...); }, kFdirTyped);
  // Every kind of the table is among the typed kinds tried.
  std::set<std::string> typed;
  std::apply([&](const auto&... k) { (typed.insert(k.info.name), ...); }, kTyped);
  for (const m::KindView& k : tt::kMessageKinds) {
    EXPECT_EQ(typed.count(k.info->name), 1U) << k.info->name;
  }
  EXPECT_EQ(typed.size(), tt::kMessageKinds.size());
}

TEST(MessageKinds, EveryFieldOutOfItsRangeIsRefusedUntouched) {
  Rng r{kSeed + 1U};
  std::apply([&](const auto&... k) { (refuses_out_of_range(k, r), ...); }, kTyped);
  std::apply([&](const auto&... k) { (refuses_out_of_range(k, r), ...); }, kFdirTyped);
}

TEST(MessageKinds, NoTwoKindsShareATagAndEveryTaggedKindHasAChannel) {
  std::set<std::uint32_t> tags;
  for (const m::KindView& k : tt::kMessageKinds) {
    if (k.info->tag == m::kNoTag) {
      continue;
    }
    EXPECT_TRUE(tags.insert(k.info->tag).second) << k.info->name;
    EXPECT_LT(k.info->channel, tt::kChannelNames.size()) << k.info->name;
    EXPECT_NE(k.info->from, 0U) << k.info->name;
    EXPECT_NE(k.info->to, 0U) << k.info->name;
  }
  EXPECT_EQ(tags.size(), 21U);
}

struct Seen {
  int frames = 0;
  int rates = 0;
};
void on_frame(Seen& s, const tt::FrameNotice& /*f*/) noexcept { ++s.frames; }
void on_rate(Seen& s, const tt::VisionRate& /*r*/) noexcept { ++s.rates; }

TEST(MessageKinds, DispatchLooksTheTagUpOnceAndRefusesWhatItsKindRefuses) {
  constexpr std::array<m::Handler<Seen>, 2> kTable{{m::on<tt::kFrameMsg, &on_frame, Seen>(), m::on<tt::kVisionRateMsg, &on_rate, Seen>()}};
  static_assert(m::handlers_fit(kTable, tt::kChanControl, tt::role_bit(tt::Role::kVisionCoordinator)));
  static_assert(!m::handlers_fit(kTable, tt::kChanResult, tt::role_bit(tt::Role::kVisionCoordinator)));
  Seen s{};
  std::array<std::uint32_t, tt::kFrameNoticeWords> f{};
  (void)fdir::msg::encode(tt::kFrameMsg, tt::FrameNotice{7U, 640U, 480U, 0U, 1.5, 64U}, f);
  EXPECT_EQ(m::dispatch(kTable, f, s), m::Dispatch::kTaken);
  const std::array<std::uint32_t, 2> rate{tt::kMsgVisionRate, 3U};  // divisor out of range
  EXPECT_EQ(m::dispatch(kTable, rate, s), m::Dispatch::kRefused);
  const std::array<std::uint32_t, 2> unknown{tt::kMsgRelight, 0U};
  EXPECT_EQ(m::dispatch(kTable, unknown, s), m::Dispatch::kUnknown);
  EXPECT_EQ(m::dispatch(kTable, std::span<const std::uint32_t>(), s), m::Dispatch::kUnknown);
  EXPECT_EQ(s.frames, 1);
  EXPECT_EQ(s.rates, 0);
}

TEST(MessageKinds, TheTableInArchitectureMdIsTheDeclaration) {
  std::ifstream f(std::string(build_info::kRepoRoot) + "/docs/ARCHITECTURE.md");
  ASSERT_TRUE(f) << "docs/ARCHITECTURE.md";
  std::string line;
  std::string doc;
  bool in = false;
  while (std::getline(f, line)) {
    if (line == "## Message kinds") {
      in = true;
    } else if (in && line.rfind("## ", 0) == 0) {
      break;
    } else if (in && line.rfind("| `", 0) == 0) {
      doc += line + "\n";
    }
  }
  const std::string want = tools::message_kinds_markdown();
  EXPECT_EQ(doc, want) << "docs/ARCHITECTURE.md, \"Message kinds\", should hold these rows (make docs-messages writes them):\n"
                       << want;
}

}  // namespace
