/**
 * @file supervisor_test.cpp
 * @brief The supervisor framework (FDIR-SUP-xx): alternatives tried in order, escalation when they
 *        are exhausted, debounce of verdicts and policies, and containment in a three-node tree.
 */
#include "fdir/supervisor.hpp"

#include "tests/fdir/fdir_fixture.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <vector>

namespace {

using fdir::Constraint;
using fdir::SupAction;
using fdir::SupDecision;

constexpr auto kRel = static_cast<std::uint8_t>(Constraint::kReliability);
constexpr auto kCap = static_cast<std::uint8_t>(Constraint::kCapacity);

fdir::AlternativeList alts(std::initializer_list<std::uint8_t> ids) {
  fdir::AlternativeList l{};
  for (std::uint8_t a : ids) {
    l.alt[l.count++] = a;
  }
  return l;
}

/** A node with reliability level 1 tried as alternatives 10, 11, 12 and level 0 needing nothing. */
fdir::SupervisorSpec three_ways(std::uint32_t debounce, std::uint32_t settle) {
  fdir::SupervisorSpec s{};
  s.id = 2U;
  s.parent = 0U;
  s.debounce = debounce;
  s.settle = settle;
  s.plan[kRel][1] = alts({10U, 11U, 12U});
  return s;
}

std::vector<fdir::Event> g_events;

std::uint32_t count_of(fdir::EventId id) {
  std::uint32_t n = 0;
  for (const fdir::Event& e : g_events) {
    n += e.id == id ? 1U : 0U;
  }
  return n;
}

// FDIR-SUP-01: a policy applies the first alternative; failures move through the list in order.
void tried_in_order() {
  const fdir::SupervisorSpec spec = three_ways(1U, 0U);
  fdir::SupervisorState st{};
  SupDecision d = fdir::supervisor_policy(spec, st, kRel, 1U, fdir::kFromPhase);
  EXPECT_EQ(d.action, SupAction::kApply);
  EXPECT_EQ(d.alternative, 10U);
  d = fdir::supervisor_judge(spec, st, kRel, false);
  EXPECT_EQ(d.action, SupAction::kApply);
  EXPECT_EQ(d.alternative, 11U);
  d = fdir::supervisor_judge(spec, st, kRel, true);  // 11 works
  EXPECT_EQ(d.action, SupAction::kNone);
  EXPECT_EQ(fdir::supervisor_current(spec, st, kRel), 11U);
  EXPECT_EQ(st.c[kRel].phase, fdir::ConstraintPhase::kMet);
  d = fdir::supervisor_judge(spec, st, kRel, false);  // fails later: on to 12, never back to 10
  EXPECT_EQ(d.alternative, 12U);
  g_events = fdir_test::events_of(0);
}

TEST(Supervisor, AlternativesAreTriedInOrder) {
  fdir_test::run_on_tile0(&tried_in_order);
  EXPECT_EQ(count_of(fdir::EventId::kSupPolicy), 1U);
  EXPECT_EQ(count_of(fdir::EventId::kSupApply), 3U);
  EXPECT_EQ(count_of(fdir::EventId::kSupNotMet), 2U);
  EXPECT_EQ(count_of(fdir::EventId::kSupMet), 1U);
}

// FDIR-SUP-02: exhausted, the node escalates once, and stays quiet until a new policy.
void escalates_when_exhausted() {
  const fdir::SupervisorSpec spec = three_ways(1U, 0U);
  fdir::SupervisorState st{};
  (void)fdir::supervisor_policy(spec, st, kRel, 1U, 0U);
  (void)fdir::supervisor_judge(spec, st, kRel, false);
  (void)fdir::supervisor_judge(spec, st, kRel, false);
  SupDecision d = fdir::supervisor_judge(spec, st, kRel, false);
  EXPECT_EQ(d.action, SupAction::kEscalate);
  EXPECT_EQ(d.level, 1U);
  EXPECT_EQ(fdir::supervisor_current(spec, st, kRel), fdir::kNoAlternative);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
  }
  EXPECT_EQ(st.escalations, 1U);
  // The parent lowers the demand: level 0 needs nothing and is met at once.
  d = fdir::supervisor_policy(spec, st, kRel, 0U, 0U);
  EXPECT_EQ(d.action, SupAction::kNone);
  EXPECT_EQ(st.c[kRel].phase, fdir::ConstraintPhase::kMet);
  // Raised again, the list starts over from its first alternative.
  d = fdir::supervisor_policy(spec, st, kRel, 1U, 0U);
  EXPECT_EQ(d.alternative, 10U);
  g_events = fdir_test::events_of(0);
}

TEST(Supervisor, EscalatesOnceWhenEveryAlternativeFailed) {
  fdir_test::run_on_tile0(&escalates_when_exhausted);
  EXPECT_EQ(count_of(fdir::EventId::kSupEscalated), 1U);
  ASSERT_FALSE(g_events.empty());
  for (const fdir::Event& e : g_events) {
    if (e.id == fdir::EventId::kSupEscalated) {
      EXPECT_EQ(e.subject, 2U);
      EXPECT_EQ(e.cause, kRel);
      EXPECT_EQ(e.b, 0U);  // the parent
    }
  }
}

// FDIR-SUP-03: verdicts are debounced (one odd one changes nothing), the settle time is honoured,
// and the same policy twice is one policy.
void debounced() {
  const fdir::SupervisorSpec spec = three_ways(3U, 2U);
  fdir::SupervisorState st{};
  (void)fdir::supervisor_policy(spec, st, kRel, 1U, 0U);
  EXPECT_EQ(fdir::supervisor_policy(spec, st, kRel, 1U, 0U).action, SupAction::kNone);
  // Two verdicts ignored while the alternative settles.
  EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
  EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
  // Two failures, a success, two failures: never three in a row.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
    EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
    EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, true).action, SupAction::kNone);
  }
  EXPECT_EQ(fdir::supervisor_current(spec, st, kRel), 10U);
  EXPECT_EQ(st.c[kRel].phase, fdir::ConstraintPhase::kTrying);  // never three good in a row either
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).action, SupAction::kNone);
  }
  EXPECT_EQ(fdir::supervisor_judge(spec, st, kRel, false).alternative, 11U);  // the third in a row
  g_events = fdir_test::events_of(0);
}

TEST(Supervisor, VerdictsAndPoliciesAreDebounced) {
  fdir_test::run_on_tile0(&debounced);
  EXPECT_EQ(count_of(fdir::EventId::kSupPolicy), 1U);
  EXPECT_EQ(count_of(fdir::EventId::kSupNotMet), 1U);
}

/**
 * A three-node tree (0 TRN at the top, 1 vision, 2 filter) wired by a message
 * queue as the tiles would be: policies down, escalations up.
 */
struct Tree {
  std::array<fdir::SupervisorSpec, 3> spec{};
  std::array<fdir::SupervisorState, 3> st{};
  std::array<std::uint32_t, 3> decisions{};  ///< decisions each node took (applies and escalations)
  std::vector<std::uint8_t> safe_mode;      ///< constraints the top gave up on
  struct Msg {
    bool up;
    std::uint8_t to;
    std::uint8_t from;
    std::uint8_t constraint;
    std::uint8_t level;
  };
  std::deque<Msg> q;

  Tree() {
    for (std::uint8_t i = 0; i < 3; ++i) {
      spec[i].id = i;
      spec[i].parent = i == 0U ? fdir::kNoSupervisor : 0U;
      spec[i].debounce = 2U;
      spec[i].settle = 0U;
    }
    spec[1].plan[kCap][0] = alts({1U, 2U});  // vision: the healthy tiles, then the spares
    spec[2].plan[kRel][1] = alts({1U});      // filter: TMR
    spec[0].plan[kCap][0] = alts({1U, 2U});  // TRN, on vision's escalation: half rate, then degraded
  }
  void act(std::uint8_t node, const SupDecision& d) {
    if (d.action == SupAction::kNone) {
      return;
    }
    ++decisions[node];
    if (d.action == SupAction::kEscalate) {
      if (spec[node].parent == fdir::kNoSupervisor) {
        safe_mode.push_back(d.constraint);
      } else {
        q.push_back({true, spec[node].parent, node, d.constraint, d.level});
      }
    }
  }
  void drain() {
    for (std::uint32_t n = 0; n < 100U && !q.empty(); ++n) {
      const Msg m = q.front();
      q.pop_front();
      act(m.to, m.up ? fdir::supervisor_escalation(spec[m.to], st[m.to], m.constraint, m.level, m.from)
                     : fdir::supervisor_policy(spec[m.to], st[m.to], m.constraint, m.level, m.from));
    }
  }
  void judge(std::uint8_t node, std::uint8_t constraint, bool met) {
    act(node, fdir::supervisor_judge(spec[node], st[node], constraint, met));
    drain();
  }
};

// FDIR-SUP-04: a vision fault its own alternatives handle stays in the vision node; one they cannot
// handle reaches the top, and never the filter node.
void containment() {
  Tree t;
  t.q.push_back({false, 1U, 0U, kCap, 0U});
  t.q.push_back({false, 2U, 0U, kRel, 1U});
  t.drain();
  t.judge(2U, kRel, true);
  t.judge(2U, kRel, true);
  const std::array<std::uint32_t, 3> start = t.decisions;
  // Vision loses tiles: its first way fails twice, its second (the spares) works.
  t.judge(1U, kCap, false);
  t.judge(1U, kCap, false);
  t.judge(1U, kCap, true);
  t.judge(1U, kCap, true);
  EXPECT_EQ(t.decisions[1], start[1] + 1U);
  EXPECT_EQ(t.decisions[0], start[0]) << "a fault vision handled reached the top";
  EXPECT_EQ(t.decisions[2], start[2]);
  // More lost than the spares cover: vision escalates, the top chooses, the filter hears nothing.
  t.judge(1U, kCap, false);
  t.judge(1U, kCap, false);
  EXPECT_EQ(t.decisions[1], start[1] + 2U);
  EXPECT_EQ(t.decisions[0], start[0] + 1U);
  EXPECT_EQ(fdir::supervisor_current(t.spec[0], t.st[0], kCap), 1U);  // half rate
  EXPECT_EQ(t.decisions[2], start[2]);
  EXPECT_EQ(t.st[2].c[kRel].phase, fdir::ConstraintPhase::kMet);
  // Another escalation: the top's next way (degraded); a third: safe mode, reported.
  t.q.push_back({true, 0U, 1U, kCap, 0U});
  t.drain();
  EXPECT_EQ(fdir::supervisor_current(t.spec[0], t.st[0], kCap), 2U);
  EXPECT_TRUE(t.safe_mode.empty());
  t.q.push_back({true, 0U, 1U, kCap, 0U});
  t.drain();
  ASSERT_EQ(t.safe_mode.size(), 1U);
  EXPECT_EQ(t.safe_mode[0], kCap);
  EXPECT_EQ(t.decisions[2], start[2]);
}

TEST(Supervisor, AFaultStopsAtTheNodeThatOwnsItAndEscalationsSkipSiblings) { fdir_test::run_on_tile0(&containment); }

TEST(Supervisor, SpecsAreChecked) {
  fdir::SupervisorSpec s = three_ways(1U, 0U);
  EXPECT_TRUE(fdir::supervisor_spec_ok(s));
  s.debounce = 0U;
  EXPECT_FALSE(fdir::supervisor_spec_ok(s));
  s = three_ways(1U, 0U);
  s.plan[kCap][0].count = fdir::kMaxAlternatives + 1U;
  EXPECT_FALSE(fdir::supervisor_spec_ok(s));
}

}  // namespace
