/**
 * @file supervisor.hpp
 * @brief The supervisor framework: a node of a supervisor tree holds, per constraint and level, an
 *        ordered list of alternative ways to meet it, applies them in turn, judges the result, and
 *        escalates to its parent when none works. Policies come down, escalations go up.
 *
 * A supervisor owns children (tasks, tiles, lower supervisors). A constraint
 * (reliability, power, capacity) arrives from the parent as a policy: a level,
 * 0 the least demanding. The node applies the first alternative its plan lists
 * for that level, lets it settle, and judges it from what it observes (the
 * owner says "met" or "not met" once per check). `debounce` verdicts of not met
 * in a row move it to the next alternative; when the list is exhausted it
 * escalates once to its parent and waits for a new policy. Met verdicts after a
 * failure (debounced the same way) make it met again. A repeated policy at the
 * same level changes nothing (policies are debounced by value). A child's
 * escalation reaches the parent as a demand on one of the parent's own
 * constraints: the parent tries its alternatives for it (an escalation is
 * already debounced below, so each one moves the parent on by one).
 *
 * Containment follows from the shape: a node only hears its parent's policies
 * and its own children's escalations, so a fault its alternatives handle never
 * leaves it. Levels of the flight hierarchy map onto it: a tile's own recovery
 * (its task, below any node), the tile's supervisor, the TRN supervisor at the
 * top, then the hardware watchdog, then safe mode reported to the vehicle
 * (the top node's last alternative).
 *
 * The framework decides; the owner acts (sends the messages, powers the
 * tiles) and writes nothing itself: every step is an event written here on the
 * node's tile (sup_policy, sup_apply, sup_not_met, sup_escalated, sup_met).
 * Plain data in the owner's carved state; no allocation, bounded loops.
 */
#pragma once

#include "fdir/message_kind.hpp"

#include <array>
#include <cstdint>

namespace fdir {

inline constexpr std::uint32_t kMaxConstraints = 4U;
inline constexpr std::uint32_t kMaxLevels = 3U;
inline constexpr std::uint32_t kMaxAlternatives = 4U;
/** Parent of the top node. */
inline constexpr std::uint8_t kNoSupervisor = 0xFFU;
inline constexpr std::uint8_t kNoAlternative = 0xFFU;

/** The constraints of the TRN tree (a node may use any id below kMaxConstraints). */
enum class Constraint : std::uint8_t {
  kReliability = 0,  ///< level 0 normal (simplex filter), 1 high (the filter in TMR)
  kPower = 1,        ///< level 0 full (every tile that may be needed on), 1 save (tiles not needed off)
  kCapacity = 2,     ///< vision: level 0 full image rate, 1 half rate
};
inline constexpr std::uint8_t kReliabilityNormal = 0U;
inline constexpr std::uint8_t kReliabilityHigh = 1U;
inline constexpr std::uint8_t kPowerFull = 0U;
inline constexpr std::uint8_t kPowerSave = 1U;
inline constexpr std::uint8_t kCapacityFull = 0U;
inline constexpr std::uint8_t kCapacityHalfRate = 1U;

/** Who a policy came from (the b field of sup_policy): a node id, or one of these. */
inline constexpr std::uint32_t kFromPhase = 0x100U;   ///< the mission phase table
inline constexpr std::uint32_t kFromGround = 0x101U;  ///< a telecommand
inline constexpr std::uint32_t kFromDefault = 0x102U; ///< the node's own default, before any policy came

/** The ordered alternatives of one constraint at one level (ids the owner gives meaning to). */
struct AlternativeList {
  std::uint8_t count = 0U;
  std::array<std::uint8_t, kMaxAlternatives> alt{};
};

struct SupervisorSpec {
  std::uint8_t id = 0U;                  ///< the node (events' subject)
  std::uint8_t parent = kNoSupervisor;   ///< where escalations go
  std::uint32_t debounce = 2U;           ///< not-met (or met) verdicts in a row before the node moves (>= 1)
  std::uint32_t settle = 1U;             ///< verdicts ignored after an alternative is applied (it takes effect)
  std::array<std::array<AlternativeList, kMaxLevels>, kMaxConstraints> plan{};
};

/** A spec is usable: debounce >= 1, every list within kMaxAlternatives. */
bool supervisor_spec_ok(const SupervisorSpec& s) noexcept;

enum class ConstraintPhase : std::uint8_t {
  kIdle,       ///< no policy yet
  kTrying,     ///< an alternative applied, not yet judged met
  kMet,        ///< the current alternative meets the level
  kEscalated,  ///< every alternative failed; the parent was told
};

struct ConstraintState {
  ConstraintPhase phase = ConstraintPhase::kIdle;
  std::uint8_t level = 0U;
  std::uint8_t index = 0U;        ///< the alternative in use (index into the level's list)
  std::uint32_t settle_left = 0U;
  std::uint32_t bad = 0U;         ///< not-met verdicts in a row
  std::uint32_t good = 0U;        ///< met verdicts in a row
  std::uint32_t from = 0U;        ///< where the level's policy came from (a node, kFromPhase, kFromGround, kFromDefault)
};

struct SupervisorState {
  std::array<ConstraintState, kMaxConstraints> c{};
  std::uint32_t applied = 0U;      ///< alternatives applied
  std::uint32_t escalations = 0U;  ///< escalations sent up
};

enum class SupAction : std::uint8_t {
  kNone,
  kApply,     ///< apply `alternative` for `constraint` at `level`
  kEscalate,  ///< tell the parent `constraint` cannot be met at `level`
};

struct SupDecision {
  SupAction action = SupAction::kNone;
  std::uint8_t constraint = 0U;
  std::uint8_t level = 0U;
  std::uint8_t alternative = kNoAlternative;
};

/** Why an alternative is applied (the cause field of sup_apply, high byte). */
enum class ApplyReason : std::uint8_t { kPolicy = 0, kNotMet = 1, kEscalation = 2 };

/**
 * A policy for @p constraint at @p level from @p from (a node id, kFromPhase,
 * kFromGround). A new level starts at its first alternative; the same level
 * again changes nothing. A level whose list is empty needs nothing: met at once.
 */
SupDecision supervisor_policy(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                              std::uint8_t level, std::uint32_t from) noexcept;

/**
 * The owner's verdict on @p constraint: is the current alternative meeting its
 * level? Ignored while idle or settling. Not met `debounce` times in a row: the
 * next alternative (kApply), or, exhausted, one escalation (kEscalate); while
 * escalated, further failures change nothing until a new policy.
 */
SupDecision supervisor_judge(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                             bool met) noexcept;

/**
 * A child's escalation, as a demand on this node's @p constraint at @p level:
 * idle (or at another level), the node starts at the level's first
 * alternative; already on it, the current alternative is taken as failed and
 * the node moves on (or escalates in turn). @p child names the child in the event.
 */
SupDecision supervisor_escalation(const SupervisorSpec& spec, SupervisorState& st, std::uint8_t constraint,
                                  std::uint8_t level, std::uint32_t child) noexcept;

/** The alternative in use for @p constraint (kNoAlternative when idle or none). */
std::uint8_t supervisor_current(const SupervisorSpec& spec, const SupervisorState& st, std::uint8_t constraint) noexcept;

/**
 * Whether a policy the parent holds for this node (sent again, kMsgPolicyHeld)
 * is taken for @p constraint: when the node holds none (it restarted from its
 * image) or only its own default. A policy it took from elsewhere (the
 * ground) stands until a new policy comes.
 */
bool supervisor_takes_held(const SupervisorState& st, std::uint8_t constraint) noexcept;

/** Policy and escalation messages between nodes (words; the owner picks the channel). */
inline constexpr std::uint32_t kMsgPolicy = 0x504F4C31U;    ///< "POL1" [1] constraint [2] level [3] from
inline constexpr std::uint32_t kMsgPolicyHeld = 0x504F4C32U;  ///< "POL2" the parent's policy again; same words
inline constexpr std::uint32_t kMsgEscalate = 0x45534331U;  ///< "ESC1" [1] constraint [2] level [3] child node
inline constexpr std::uint32_t kSupMsgWords = 4U;

/**
 * A policy, a held policy or an escalation (the kind, by its tag, says which):
 * constraint below kMaxConstraints, level below kMaxLevels. Each is declared
 * below (fdir/message_kind.hpp): msg::encode() writes it, msg::decode()
 * refuses, leaving its output as it was, words that are not exactly that kind
 * with its fields in range, and a receiver dispatches on the tag.
 */
struct SupMessage {
  std::uint8_t constraint = 0U;
  std::uint8_t level = 0U;
  std::uint32_t from = 0U;  ///< policy: where it came from; escalation: the child node
};

namespace detail {
/** The three kinds share their layout; the owner picks the channel, the deployment the roles (msg::routed). */
constexpr auto sup_message(std::uint32_t tag, const char* name) noexcept {
  return msg::kind<SupMessage>({.tag = tag, .name = name, .channel = msg::kNoChannel, .from = 0U, .to = 0U},
                               msg::u32("constraint", &SupMessage::constraint, 1, 0U, kMaxConstraints - 1U),
                               msg::u32("level", &SupMessage::level, 2, 0U, kMaxLevels - 1U),
                               msg::u32("from", &SupMessage::from, 3));
}
}  // namespace detail

inline constexpr auto kPolicyMsg = detail::sup_message(kMsgPolicy, "fdir_policy");
inline constexpr auto kPolicyHeldMsg = detail::sup_message(kMsgPolicyHeld, "fdir_policy_held");
inline constexpr auto kEscalateMsg = detail::sup_message(kMsgEscalate, "fdir_escalate");
static_assert(kPolicyMsg.info.words == kSupMsgWords, "the declaration covers the documented words");

}  // namespace fdir
