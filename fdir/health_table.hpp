/**
 * @file health_table.hpp
 * @brief Table-driven monitoring (cFS Health & Safety, F Prime Health, PUS service 12): per
 *        monitored thing a warn and a fatal threshold, a debounce count, the action, and a cap
 *        on repeated actions.
 *
 * A monitor is fed one value per check (misses in a row, late pings, a
 * counter's growth). Its status (ok, warn, fatal) changes only after
 * `debounce` identical verdicts in a row, so one odd sample changes nothing.
 * On every change to warn or fatal an event is written (kMonitorWarn,
 * kMonitorFatal); entering fatal asks for the monitor's action, at most
 * `max_actions` times over the mission: after that kActionCapped is written
 * once and the action is no longer asked for, so a fault cannot drive a
 * reset loop. The specs are one constexpr table per user; the states are
 * plain data the user keeps in its own carved state.
 */
#pragma once

#include <cstdint>

namespace fdir {

enum class MonitorStatus : std::uint8_t { kOk = 0, kWarn = 1, kFatal = 2 };

/** What the owner of a monitor does when it turns fatal. */
enum class MonitorAction : std::uint8_t {
  kReport,    ///< nothing more than the event
  kIsolate,   ///< stop using the thing (work goes elsewhere, routes go around)
  kRestart,   ///< restart the tile or task
  kEscalate,  ///< hand it to the supervisor above
};

struct MonitorSpec {
  const char* name;
  std::uint32_t warn;         ///< value >= warn: warn (0: no warn level)
  std::uint32_t fatal;        ///< value >= fatal: fatal (> warn, >= 1)
  std::uint32_t debounce;     ///< identical verdicts in a row before the status changes (>= 1)
  MonitorAction action;
  std::uint32_t max_actions;  ///< times the action may be asked for (>= 1)
};

/** A spec is usable: fatal >= 1, warn below fatal, debounce and cap at least 1. */
constexpr bool monitor_spec_ok(const MonitorSpec& s) noexcept {
  return s.fatal >= 1U && s.warn < s.fatal && s.debounce >= 1U && s.max_actions >= 1U;
}

struct MonitorState {
  MonitorStatus status = MonitorStatus::kOk;
  MonitorStatus candidate = MonitorStatus::kOk;  ///< verdict being debounced
  std::uint32_t same = 0U;                       ///< identical candidate verdicts in a row
  std::uint32_t actions = 0U;                    ///< actions asked for so far
  bool capped = false;
};

struct MonitorResult {
  MonitorStatus status;  ///< after this sample
  bool changed;          ///< the status changed with this sample
  bool act;              ///< take the action now (entered fatal, under the cap)
};

/**
 * Feeds @p value to monitor @p id (the events' subject) with spec @p spec.
 * Writes the events of a change on the current tile. [task]
 */
MonitorResult monitor_sample(const MonitorSpec& spec, MonitorState& state, std::uint32_t id,
                             std::uint32_t value) noexcept;

/** Forgets the status (the thing was replaced), keeping the action count: the cap spans the mission. */
void monitor_clear(MonitorState& state) noexcept;

}  // namespace fdir
