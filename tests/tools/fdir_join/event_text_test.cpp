/**
 * @file event_text_test.cpp
 * @brief An event's text comes from the template its declaration carries: every template is
 *        well formed and names only fields the event declares; the template language itself.
 */
#include "tools/common/accounting/event_text.hpp"
#include "tools/common/accounting/event_tables.hpp"
#include "trn/events.hpp"
#include "tools/common/accounting/fdir_join.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

namespace {

using fdir::EventId;

fdir::Event ev(EventId id, std::uint32_t subject, std::uint32_t cause = 0U, std::uint32_t a = 0U,
               std::uint32_t b = 0U) {
  fdir::Event e{};
  e.id = id;
  e.subject = subject;
  e.cause = cause;
  e.a = a;
  e.b = b;
  return e;
}

/** An event declared with @p text (for the language's own tests). */
std::string fill(const char* text, const fdir::Event& e) {
  fdir::EventInfo info = *tools::event_info(trn::ev::kFrameDone);
  info.text = text;
  std::array<char, 256> buf{};
  const std::size_t n = tools::format_event_text(info, e, buf);
  return std::string(buf.data(), n);
}

/** Fields of "subject / cause / a / b" the event's args declare. */
std::size_t declared_fields(const std::string& args) {
  std::size_t n = 1U;
  for (std::size_t at = args.find(" / "); at != std::string::npos; at = args.find(" / ", at + 3U)) {
    ++n;
  }
  return n;
}

/** The highest field a template names: 0 s, 1 c, 2 a, 3 b; -1 for none. */
int highest_field(const std::string& text) {
  int hi = -1;
  for (std::size_t i = 0; i + 1U < text.size(); ++i) {
    if (text[i] != '{') {
      continue;
    }
    const char f = text[i + 1U];
    const int k = f == 's' ? 0 : f == 'c' ? 1 : f == 'a' ? 2 : f == 'b' ? 3 : -1;
    hi = std::max(hi, k);
  }
  return hi;
}

TEST(EventText, EveryTemplateIsWellFormed) {
  for (const fdir::EventInfo& e : tools::all_events()) {
    EXPECT_EQ(tools::check_event_text(e.text), "") << e.name;
  }
}

TEST(EventText, EveryTemplateNamesOnlyTheFieldsItsEventDeclares) {
  for (const fdir::EventInfo& e : tools::all_events()) {
    ASSERT_NE(e.args, nullptr) << e.name;
    EXPECT_LT(highest_field(e.text), static_cast<int>(declared_fields(e.args))) << e.name << ": " << e.args;
  }
}

TEST(EventText, NoEventTextShowsAFaultWhateverItsFields) {
  // Any field values, sane or not, fill every template without a placeholder left or a fault shown.
  constexpr std::array<std::uint32_t, 8> kValues{0U, 1U, 2U, 3U, 0x100U, 0xFFFFU, 0x8000'0002U, fdir::kUnknown};
  for (const fdir::EventInfo& info : tools::all_events()) {
    for (const std::uint32_t v : kValues) {
      const std::string t = tools::describe_flight_event(ev(info.id, v, v, v, v));
      EXPECT_EQ(t.rfind(std::string(info.name) + ": ", 0), 0U) << t;
      EXPECT_EQ(t.find('{'), std::string::npos) << t;
      EXPECT_EQ(t.find('}'), std::string::npos) << t;
    }
  }
}

TEST(EventText, TextsReadAsTheFlightMeantThem) {
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kTileReset, 18U, 0U, 1U, 3U)),
            "tile_reset: tile 18 reset by the supervisor (reset 1 of at most 3)");
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kTileReset, 18U, 2U, 1U, 3U)),
            "tile_reset: tile 18 reset by the supervisor: its results stayed wrong");
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kTileLost, 5U, 0x100U)),
            "tile_lost: tile 5 cut off: its switch is declared failed; retired, its roles go to spares");
  EXPECT_EQ(tools::describe_flight_event(ev(trn::ev::kTmrNoMajority, 700U, 7U, 7U, 0x1514'1300U)),
            "tmr_no_majority: no majority at job 700 (different 0x7, missing 0x0; replicas on tiles 19, 20, 21): "
            "nothing delivered");
  EXPECT_EQ(tools::describe_flight_event(ev(trn::ev::kFilterSettingsBad, 700U, 6U, 1U)),
            "filter_settings_bad: the filter's settings in RAM (camera, process noise) changed by the end of job "
            "700: not delivered, built again from the image");
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kAbftCorrected, 1U, (5U << 16U) | 3U, (1U << 16U) | 1U, 1U)),
            "abft_corrected: product 1: element (5, 3) wrong, right after 1 recomputation(s)");
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kSupApply, 2U, 0U | (2U << 8U), 3U, 1U | (0U << 8U))),
            "sup_apply: filter_supervisor: filter in TMR for reliability high (escalation from trn_supervisor)");
  EXPECT_EQ(tools::describe_flight_event(ev(EventId::kPacketDamaged, fdir::kUnknown, 2U, 1U)),
            "packet_damaged: packet from tile ? damaged beyond correction: NACK sent");
}

TEST(EventText, ThePhraseOfAValueAndTheLastForAnyLarger) {
  EXPECT_EQ(fill("{c|zero|one|more}", ev(trn::ev::kFrameDone, 0U, 0U)), "zero");
  EXPECT_EQ(fill("{c|zero|one|more}", ev(trn::ev::kFrameDone, 0U, 1U)), "one");
  EXPECT_EQ(fill("{c|zero|one|more}", ev(trn::ev::kFrameDone, 0U, 9U)), "more");
  EXPECT_EQ(fill("x{c||y}z", ev(trn::ev::kFrameDone, 0U, 0U)), "xz") << "an empty phrase";
}

TEST(EventText, PhrasesHoldFieldsAndPhrases) {
  EXPECT_EQ(fill("{a|none|{a} of {b|none|{b} {c|x|y}}}", ev(trn::ev::kFrameDone, 0U, 1U, 2U, 3U)), "2 of 3 y");
}

TEST(EventText, SelectorsFormatsAndBitWords) {
  const fdir::Event e = ev(trn::ev::kFrameDone, 0x1234'5678U, 0x8000'0005U, 0U, 0x0A0B'0C0DU);
  EXPECT_EQ(fill("{s.hi} {s.lo}", e), "4660 22136");
  EXPECT_EQ(fill("{b.b0} {b.b1} {b.b2} {b.b3}", e), "13 12 11 10");
  EXPECT_EQ(fill("{c.top} {c.rest}", e), "1 5");
  EXPECT_EQ(fill("{s:x}", e), "0x12345678");
  EXPECT_EQ(fill("{c&p|q|r}", e), "p, r");
  EXPECT_EQ(fill("{a&p|q|r}", e), "");
  EXPECT_EQ(fill("{s}", ev(trn::ev::kFrameDone, fdir::kUnknown)), "?");
  EXPECT_EQ(fill("{s@node} {a@alternative}", ev(trn::ev::kFrameDone, 2U, 0U, 3U)), "filter_supervisor filter in TMR");
}

TEST(EventText, ABadTemplateIsRefusedByTheCheckAndShownAsSuch) {
  EXPECT_NE(tools::check_event_text("{x}"), "");
  EXPECT_NE(tools::check_event_text("{s"), "");
  EXPECT_NE(tools::check_event_text("s}"), "");
  EXPECT_NE(tools::check_event_text("{s.zz}"), "");
  EXPECT_NE(tools::check_event_text("{s:d}"), "");
  EXPECT_NE(tools::check_event_text("{s@nosuchtype}"), "");
  EXPECT_NE(tools::check_event_text("{s&a|{b}}"), "");
  EXPECT_NE(tools::check_event_text("{s|{c|{a|{b|{s|x}}}}}"), "") << "nested past the formatter's depth";
  EXPECT_NE(tools::check_event_text(""), "");
  EXPECT_EQ(tools::check_event_text("{s|{c|{a|{b|x}}}}"), "");
  EXPECT_EQ(fill("a {x} b", ev(trn::ev::kFrameDone, 0U)), "a {?} b");
  EXPECT_EQ(fill("a {s@nosuchtype} b", ev(trn::ev::kFrameDone, 0U)), "a {?} b");
}

TEST(EventText, ATextLongerThanItsBufferIsCutAndTerminated) {
  fdir::EventInfo info = *tools::event_info(trn::ev::kFrameDone);
  info.text = "0123456789{s}0123456789";
  std::array<char, 8> buf{};
  const std::size_t n = tools::format_event_text(info, ev(trn::ev::kFrameDone, 42U), buf);
  EXPECT_EQ(n, 7U);
  EXPECT_EQ(std::string(buf.data()), "0123456");
}

}  // namespace
