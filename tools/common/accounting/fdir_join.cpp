/**
 * @file fdir_join.cpp
 * @brief Flight events collected into the run log; detections and recoveries joined to the ground truth.
 */
#include "tools/common/accounting/fdir_join.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/emu/profile.hpp"
#include "tools/common/accounting/event_tables.hpp"
#include "tools/common/accounting/event_text.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>

namespace tools {
namespace {

using fdir::EventId;

double seconds(bsp::Cycles c, double clock_hz) { return static_cast<double>(c) / clock_hz; }

EventCategory category_of(const fdir::Event& e) {
  if ((e.steps & fdir::kStepDetect) != 0U) {
    return EventCategory::kDetect;
  }
  if ((e.steps & fdir::kStepIsolate) != 0U) {
    return EventCategory::kIsolate;
  }
  if ((e.steps & fdir::kStepRecover) != 0U) {
    return EventCategory::kRecover;
  }
  return EventCategory::kInfo;
}

}  // namespace

const char* tile_health_name(TileHealth h) noexcept {
  switch (h) {
    case TileHealth::kSuspect: return "suspect";
    case TileHealth::kRecovered: return "recovered";
    case TileHealth::kFailed: return "failed";
    case TileHealth::kOk: break;
  }
  return "ok";
}

std::size_t describe_flight_event(const fdir::Event& e, std::span<char> out) noexcept {
  if (out.empty()) {
    return 0U;
  }
  const fdir::EventInfo* info = tools::event_info(e.id);
  if (info == nullptr) {
    const int n = std::snprintf(out.data(), out.size(), "unknown: id 0x%04x, subject %u, cause %u, %u, %u",
                                static_cast<unsigned>(e.id), e.subject, e.cause, e.a, e.b);
    return n > 0 ? std::min(static_cast<std::size_t>(n), out.size() - 1U) : 0U;
  }
  const int head = std::snprintf(out.data(), out.size(), "%s: ", info->name);
  const std::size_t used = head > 0 ? std::min(static_cast<std::size_t>(head), out.size() - 1U) : 0U;
  return used + format_event_text(*info, e, out.subspan(used));
}

std::string describe_flight_event(const fdir::Event& e) {
  std::array<char, kEventTextBytes> buf{};
  const std::size_t n = describe_flight_event(e, buf);
  return std::string(buf.data(), n);
}

FlightEventCollector::FlightEventCollector(std::size_t capacity) { events_.reserve(capacity); }

void FlightEventCollector::take(const fdir::Event& e) noexcept {
  switch (event_code(e.id)) {
    case event_code(EventId::kSwitchFailed):
    case event_code(EventId::kTransitFailed):
    case event_code(EventId::kLinkOrSwitchFailed): health_[e.subject % bsp::kMaxTiles] = TileHealth::kFailed; break;
    case event_code(EventId::kWorkerSilent):
    case event_code(EventId::kCoreSuspect):
    case event_code(EventId::kNeighbourSuspect):
    case event_code(EventId::kWatchdogExpired):
    case event_code(EventId::kResultsSuspect):
    case event_code(EventId::kTileReset):
      if (e.subject < bsp::kMaxTiles && health_[e.subject] != TileHealth::kFailed) {
        health_[e.subject] = TileHealth::kSuspect;
      }
      break;
    case event_code(EventId::kTileLost):
      health_[e.subject % bsp::kMaxTiles] = TileHealth::kFailed;
      break;
    case event_code(EventId::kRoleMoved):
      health_[e.cause % bsp::kMaxTiles] = TileHealth::kFailed;
      break;
    case event_code(EventId::kRoleRestored):
      health_[e.a % bsp::kMaxTiles] = TileHealth::kRecovered;
      break;
    case event_code(EventId::kWorkerBack):
    case event_code(EventId::kResultsConsistent):
    case event_code(EventId::kTileRecovered):
    case event_code(EventId::kTileRebooted):
      if (e.subject < bsp::kMaxTiles) {
        health_[e.subject] = TileHealth::kRecovered;
      }
      break;
    case event_code(trn::ev::kFrameDone):
      ++frames_;
      matches_ += e.b;
      break;
    default: break;
  }
}

void FlightEventCollector::poll(double clock_hz, EventLog& log) noexcept {
  for (bsp::TileId t = 0; t < bsp::kMaxTiles; ++t) {
    const std::uint64_t written = fdir::event_log_written(t);
    for (; next_[t] < written; ++next_[t]) {
      fdir::Event e{};
      if (!fdir::event_log_read(t, next_[t], &e)) {
        ++lost_;  // overwritten before this poll
        continue;
      }
      take(e);
      if (events_.size() < events_.capacity()) {
        events_.push_back(e);
      } else {
        ++lost_;
      }
      if (e.id == trn::ev::kFrameDone) {
        continue;  // one a second: the summary counts them, the log stays readable
      }
      std::array<char, kEventTextBytes> text{};
      const std::size_t n = describe_flight_event(e, text);
      (void)log.add(seconds(e.cycle, clock_hz), category_of(e), e.tile, std::string_view(text.data(), n));
    }
  }
}

}  // namespace tools
