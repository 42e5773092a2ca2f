/**
 * @file supervisor.cpp
 * @brief The supervisor framework's decisions (see supervisor.hpp).
 */
#include "fdir/supervisor.hpp"

#include "fdir/event_log.hpp"

namespace fdir {
namespace {

const AlternativeList* list_of(const SupervisorSpec& spec, std::uint8_t constraint, std::uint8_t level) noexcept {
  if (constraint >= kMaxConstraints || level >= kMaxLevels) {
    return nullptr;
  }
  const AlternativeList& l = spec.plan[constraint][level];
  return l.count <= kMaxAlternatives ? &l : nullptr;
}

/** Applies the alternative at the constraint's index (the state is on a level with a list). */
SupDecision apply_current(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                          const AlternativeList& l, ApplyReason why, std::uint32_t child) noexcept {
  ConstraintState& c = st.c[constraint];
  const std::uint8_t alt = l.alt[c.index];
  c.phase = ConstraintPhase::kTrying;
  c.settle_left = spec.settle;
  c.bad = 0U;
  c.good = 0U;
  ++st.applied;
  report(EventId::kSupApply, spec.id, static_cast<std::uint32_t>(constraint) | (static_cast<std::uint32_t>(why) << 8U),
         alt, static_cast<std::uint32_t>(c.level) | ((child & 0xFFFFU) << 8U));
  return SupDecision{SupAction::kApply, constraint, c.level, alt};
}

/** The current alternative failed: the next one, or one escalation when there is none. */
SupDecision move_on(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint, const AlternativeList& l,
                    ApplyReason why, std::uint32_t child) noexcept {
  ConstraintState& c = st.c[constraint];
  if (static_cast<std::uint32_t>(c.index) + 1U < l.count) {
    ++c.index;
    return apply_current(spec, st, constraint, l, why, child);
  }
  c.phase = ConstraintPhase::kEscalated;
  c.bad = 0U;
  c.good = 0U;
  ++st.escalations;
  report(EventId::kSupEscalated, spec.id, constraint, c.level, spec.parent);
  return SupDecision{SupAction::kEscalate, constraint, c.level, kNoAlternative};
}

/** Starts @p level of @p constraint at its first alternative (met at once when the list is empty). */
SupDecision start_level(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint, std::uint8_t level,
                        const AlternativeList& l, ApplyReason why, std::uint32_t child) noexcept {
  ConstraintState& c = st.c[constraint];
  c.level = level;
  c.index = 0U;
  if (l.count == 0U) {
    c.phase = ConstraintPhase::kMet;
    c.bad = 0U;
    c.good = 0U;
    c.settle_left = 0U;
    report(EventId::kSupMet, spec.id, constraint, kNoAlternative, level);
    return SupDecision{SupAction::kNone, constraint, level, kNoAlternative};
  }
  return apply_current(spec, st, constraint, l, why, child);
}

}  // namespace

bool supervisor_spec_ok(const SupervisorSpec& s) noexcept {
  if (s.debounce < 1U) {
    return false;
  }
  for (const auto& levels : s.plan) {
    for (const AlternativeList& l : levels) {
      if (l.count > kMaxAlternatives) {
        return false;
      }
    }
  }
  return true;
}

SupDecision supervisor_policy(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                              std::uint8_t level, std::uint32_t from) noexcept {
  const AlternativeList* l = list_of(spec, constraint, level);
  if (l == nullptr) {
    return SupDecision{};
  }
  ConstraintState& c = st.c[constraint];
  if (c.phase != ConstraintPhase::kIdle && c.level == level) {
    return SupDecision{SupAction::kNone, constraint, level, kNoAlternative};  // the same policy again
  }
  report(EventId::kSupPolicy, spec.id, constraint, level, from);
  c.from = from;
  return start_level(spec, st, constraint, level, *l, ApplyReason::kPolicy, 0U);
}

bool supervisor_takes_held(const SupervisorState& st, std::uint8_t constraint) noexcept {
  if (constraint >= kMaxConstraints) {
    return false;
  }
  const ConstraintState& c = st.c[constraint];
  return c.phase == ConstraintPhase::kIdle || c.from == kFromDefault;
}

SupDecision supervisor_judge(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                             bool met) noexcept {
  if (constraint >= kMaxConstraints) {
    return SupDecision{};
  }
  ConstraintState& c = st.c[constraint];
  const AlternativeList* l = list_of(spec, constraint, c.level);
  if (l == nullptr || c.phase == ConstraintPhase::kIdle || l->count == 0U) {
    return SupDecision{};
  }
  if (c.settle_left > 0U) {
    --c.settle_left;
    return SupDecision{};
  }
  const SupDecision none{SupAction::kNone, constraint, c.level, kNoAlternative};
  if (met) {
    c.bad = 0U;
    ++c.good;
    if (c.phase != ConstraintPhase::kMet && c.good >= spec.debounce) {
      c.phase = ConstraintPhase::kMet;
      report(EventId::kSupMet, spec.id, constraint, l->alt[c.index], c.level);
    }
    return none;
  }
  c.good = 0U;
  ++c.bad;
  if (c.phase == ConstraintPhase::kEscalated || c.bad < spec.debounce) {
    return none;
  }
  report(EventId::kSupNotMet, spec.id, constraint, l->alt[c.index], c.level);
  return move_on(spec, st, constraint, *l, ApplyReason::kNotMet, 0U);
}

SupDecision supervisor_escalation(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                                  std::uint8_t level, std::uint32_t child) noexcept {
  const AlternativeList* l = list_of(spec, constraint, level);
  if (l == nullptr) {
    return SupDecision{};
  }
  ConstraintState& c = st.c[constraint];
  if (l->count == 0U && !(c.phase == ConstraintPhase::kEscalated && c.level == level)) {
    c.level = level;  // nothing to try at this level: straight up
    c.index = 0U;
    return move_on(spec, st, constraint, *l, ApplyReason::kEscalation, child);
  }
  if (c.phase == ConstraintPhase::kIdle || c.level != level) {
    return start_level(spec, st, constraint, level, *l, ApplyReason::kEscalation, child);
  }
  if (c.phase == ConstraintPhase::kEscalated || l->count == 0U) {
    return SupDecision{SupAction::kNone, constraint, level, kNoAlternative};
  }
  report(EventId::kSupNotMet, spec.id, constraint, l->alt[c.index], c.level);
  return move_on(spec, st, constraint, *l, ApplyReason::kEscalation, child);
}

std::uint8_t supervisor_current(const SupervisorSpec& spec, const SupervisorState& st, std::uint8_t constraint) noexcept {
  if (constraint >= kMaxConstraints) {
    return kNoAlternative;
  }
  const ConstraintState& c = st.c[constraint];
  const AlternativeList* l = list_of(spec, constraint, c.level);
  if (l == nullptr || c.phase == ConstraintPhase::kIdle || c.phase == ConstraintPhase::kEscalated ||
      c.index >= l->count) {
    return kNoAlternative;
  }
  return l->alt[c.index];
}

}  // namespace fdir
