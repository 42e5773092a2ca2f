/**
 * @file accusation_test.cpp
 * @brief Whom each event accuses and of what (tools/common/accounting/accusation.hpp): the table's class, refined by the
 *        fields where one id says two things.
 */
#include "tools/common/accounting/accusation.hpp"
#include "tools/common/accounting/event_tables.hpp"
#include "trn/events.hpp"

#include "build_info.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using fdir::Diagnosis;
using fdir::EventId;

fdir::Event ev(EventId id, bsp::TileId writer, std::uint32_t subject, std::uint32_t cause = 0U, std::uint32_t a = 0U,
               std::uint32_t b = 0U) {
  fdir::Event e{};
  e.id = id;
  e.tile = writer;
  e.subject = subject;
  e.cause = cause;
  e.a = a;
  e.b = b;
  return e;
}

TEST(Accusation, EveryDetectionOfATileSaysWhatItAccuses) {
  // Every event that is a detection of the table either accuses with a class or is a notice the
  // join reads otherwise (a delivery given up, a level not met): listed here so a new id must choose.
  for (const fdir::EventInfo& e : tools::all_events()) {
    if ((e.steps & fdir::kStepDetect) == 0U || e.diagnosis != Diagnosis::kNone) {
      continue;
    }
    const bool notice = e.id == EventId::kPacketGaveUp || e.id == EventId::kRouteUnreachable ||
                        e.id == EventId::kForwardUnreachable || e.id == EventId::kPacketSettled ||
                        e.id == trn::ev::kVisionSetUpFailed || e.id == trn::ev::kLandmarkProductRefused ||
                        e.id == EventId::kMonitorWarn || e.id == EventId::kMonitorFatal ||
                        e.id == EventId::kTileLost || e.id == trn::ev::kImuGap || e.id == EventId::kSupNotMet;
    EXPECT_TRUE(notice) << e.name << " detects, but accuses nothing";
  }
}

TEST(Accusation, TheFieldsRefineTheClass) {
  EXPECT_EQ(tools::accusation_of(ev(trn::ev::kTmrOutvoted, 18U, 20U, 700U, 1U, 1U)).diagnosis, Diagnosis::kWrongResult);
  EXPECT_EQ(tools::accusation_of(ev(trn::ev::kTmrOutvoted, 18U, 20U, 700U, 1U, 2U)).diagnosis, Diagnosis::kCoreSilent);
  EXPECT_EQ(tools::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 3U)).diagnosis, Diagnosis::kCoreCrashed);
  EXPECT_EQ(tools::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 2U)).diagnosis, Diagnosis::kCoreSilent);
  EXPECT_EQ(tools::accusation_of(ev(EventId::kTileRebooted, 0U, 12U, 1U)).diagnosis, Diagnosis::kNone);
  EXPECT_EQ(tools::accusation_of(ev(trn::ev::kCoarseBandRedone, 1U, 30U, 4U)).diagnosis, Diagnosis::kWrongResult);
  EXPECT_EQ(tools::accusation_of(ev(trn::ev::kCoarseBandRedone, 1U, 30U, 2U)).diagnosis, Diagnosis::kSuspicion);
  EXPECT_EQ(tools::accusation_of(ev(trn::ev::kCoarseBandRedone, 1U, 30U, 1U)).diagnosis, Diagnosis::kNone);
}

TEST(Accusation, TheTilesNamed) {
  const tools::Accusation overdue = tools::accusation_of(ev(EventId::kTaskOverdue, 35U, 2U, 35U));
  ASSERT_EQ(overdue.count, 1U);
  EXPECT_EQ(overdue.tiles[0], 35U) << "the task's tile (cause), not its id";
  const tools::Accusation link = tools::accusation_of(ev(EventId::kLinkFailed, 0U, 51U, 52U));
  EXPECT_EQ(link.count, 2U);
  EXPECT_TRUE(link.names(51U) && link.names(52U));
  const tools::Accusation own = tools::accusation_of(ev(trn::ev::kFilterStateBad, 18U, 300U, 6U));
  EXPECT_TRUE(own.names(18U) && own.count == 1U) << "the writer, about itself";
  // Replicas 0 and 2 different: tiles 19 and 21 named, 20 not.
  const std::uint32_t tiles = (19U << 8U) | (20U << 16U) | (21U << 24U);
  const tools::Accusation vote = tools::accusation_of(ev(trn::ev::kTmrNoMajority, 18U, 700U, 0U, 5U, tiles));
  EXPECT_EQ(vote.count, 2U);
  EXPECT_TRUE(vote.names(19U) && vote.names(21U) && !vote.names(20U));
  EXPECT_EQ(tools::accusation_of(ev(EventId::kPacketDamaged, 1U, fdir::kUnknown)).count, 0U)
      << "a packet accuses no tile";
  EXPECT_EQ(tools::accusation_of(ev(EventId::kWatchdogExpired, 0U, fdir::kUnknown)).count, 0U);
  EXPECT_FALSE(tools::is_diagnosis(tools::accusation_of(ev(EventId::kNeighbourSuspect, 31U, 30U)).diagnosis));
  EXPECT_STREQ(tools::diagnosis_name(Diagnosis::kSwitchOrLink), "switch_or_link");
}

/** "detect, isolate" for the step bits, "-" for none (as docs/FDIR.md writes them). */
std::string steps_text(std::uint8_t steps) {
  std::string t;
  for (const auto& [bit, name] : {std::pair{fdir::kStepDetect, "detect"}, std::pair{fdir::kStepIsolate, "isolate"},
                                  std::pair{fdir::kStepRecover, "recover"}}) {
    if ((steps & bit) != 0U) {
      t += t.empty() ? name : std::string(", ") + name;
    }
  }
  return t.empty() ? "-" : t;
}

std::string accuses_text(const fdir::EventInfo& e) {
  if (e.diagnosis == Diagnosis::kNone) {
    return "-";
  }
  std::string t = tools::diagnosis_name(e.diagnosis);
  switch (e.accused) {
    case fdir::Accused::kNobody: return t;
    case fdir::Accused::kSubject: return t + " (subject)";
    case fdir::Accused::kCause: return t + " (cause)";
    case fdir::Accused::kWriter: return t + " (writer)";
    case fdir::Accused::kSubjectAndCause: return t + " (subject and cause)";
    case fdir::Accused::kReplicas: return t + " (replicas named)";
  }
  return "?";
}

/** The cells of a Markdown table row; "\\|" is a '|' inside a cell. */
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  const auto flush = [&out, &cell] {
    const auto b = cell.find_first_not_of(' ');
    const auto e = cell.find_last_not_of(' ');
    out.push_back(b == std::string::npos ? std::string{} : cell.substr(b, e - b + 1U));
    cell.clear();
  };
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1U < row.size() && row[i + 1U] == '|') {
      cell += '|';
      ++i;
    } else if (row[i] == '|') {
      flush();
    } else {
      cell += row[i];
    }
  }
  flush();
  return out;
}

// The event table of docs/FDIR.md is the declaration's, row for row: the same ids, names, steps,
// accusations and fields, each id once.
TEST(EventDocs, TheTableInFdirMdIsTheDeclaration) {
  std::ifstream f(std::string(build_info::kRepoRoot) + "/docs/FDIR.md");
  ASSERT_TRUE(f) << "docs/FDIR.md";
  std::map<std::string, std::vector<std::string>> rows;  // id -> cells
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("| 0x", 0) != 0) {
      continue;
    }
    const std::vector<std::string> c = cells(line);
    ASSERT_GE(c.size(), 6U) << line;
    EXPECT_TRUE(rows.emplace(c[1], c).second) << c[1] << " twice in docs/FDIR.md";
  }
  EXPECT_EQ(rows.size(), tools::event_count());
  for (const fdir::EventInfo& e : tools::all_events()) {
    std::array<char, 8> id{};
    (void)std::snprintf(id.data(), id.size(), "0x%04X", static_cast<unsigned>(e.id));
    const auto r = rows.find(id.data());
    ASSERT_NE(r, rows.end()) << e.name << " (" << id.data() << ") is not in docs/FDIR.md";
    EXPECT_EQ(r->second[2], e.name) << id.data();
    EXPECT_EQ(r->second[3], steps_text(e.steps)) << e.name;
    EXPECT_EQ(r->second[4], accuses_text(e)) << e.name;
    EXPECT_EQ(r->second[5], e.args) << e.name;
  }
}

}  // namespace
