/**
 * @file health_table.cpp
 * @brief Debounced thresholds, actions and the action cap.
 */
#include "fdir/health_table.hpp"

#include "fdir/event_log.hpp"

namespace fdir {
namespace {

MonitorStatus verdict(const MonitorSpec& s, std::uint32_t value) noexcept {
  if (value >= s.fatal) {
    return MonitorStatus::kFatal;
  }
  return (s.warn != 0U && value >= s.warn) ? MonitorStatus::kWarn : MonitorStatus::kOk;
}

}  // namespace

MonitorResult monitor_sample(const MonitorSpec& spec, MonitorState& state, std::uint32_t id,
                             std::uint32_t value) noexcept {
  MonitorResult r{state.status, false, false};
  if (!monitor_spec_ok(spec)) {
    report(EventId::kAssertFailed, id, __LINE__);  // a bad table row is a programming error, said once per sample
    return r;
  }
  const MonitorStatus v = verdict(spec, value);
  if (v == state.status) {
    state.same = 0U;
    state.candidate = v;
    return r;
  }
  state.same = (v == state.candidate) ? state.same + 1U : 1U;
  state.candidate = v;
  if (state.same < spec.debounce) {
    return r;
  }
  state.status = v;
  state.same = 0U;
  r.status = v;
  r.changed = true;
  if (v == MonitorStatus::kWarn) {
    report(EventId::kMonitorWarn, id, 0U, value, spec.warn);
  } else if (v == MonitorStatus::kFatal) {
    report(EventId::kMonitorFatal, id, static_cast<std::uint32_t>(spec.action), value, spec.fatal);
    if (state.actions < spec.max_actions) {
      ++state.actions;
      r.act = true;
    } else if (!state.capped) {
      state.capped = true;
      report(EventId::kActionCapped, id, static_cast<std::uint32_t>(spec.action), state.actions, spec.max_actions);
    }
  }
  return r;
}

void monitor_clear(MonitorState& state) noexcept {
  state.status = MonitorStatus::kOk;
  state.candidate = MonitorStatus::kOk;
  state.same = 0U;
}

}  // namespace fdir
