/**
 * @file event_text.cpp
 * @brief A flight event's text from its declared template: the template language's interpreter
 *        and the value types it names.
 */
#include "tools/common/accounting/event_text.hpp"

#include "fdir/supervisor.hpp"
#include "trn/filter/state_check.hpp"
#include "trn/match.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <string_view>

namespace tools {
namespace {

/** Text written into a caller's buffer, always NUL-terminated, cut to fit. */
class Out {
 public:
  explicit Out(std::span<char> b) noexcept : b_(b) {
    if (!b_.empty()) {
      b_[0] = '\0';
    }
  }
  void put(std::string_view s) noexcept {
    for (const char ch : s) {
      if (n_ + 1U >= b_.size()) {
        return;
      }
      b_[n_++] = ch;
      b_[n_] = '\0';
    }
  }
  void number(std::uint32_t v, bool hex) noexcept {
    std::array<char, 16> t{};
    (void)std::snprintf(t.data(), t.size(), hex ? "0x%x" : "%u", v);
    put(t.data());
  }
  [[nodiscard]] std::size_t size() const noexcept { return n_; }

 private:
  std::span<char> b_;
  std::size_t n_ = 0U;
};

// ---- the value types a template names with @type

const char* node_name(std::uint32_t n) noexcept {
  switch (n) {
    case trn::tasks::kNodeTrn: return "trn_supervisor";
    case trn::tasks::kNodeVision: return "vision_supervisor";
    case trn::tasks::kNodeFilter: return "filter_supervisor";
    case fdir::kNoSupervisor: return "the vehicle";
    default: return "?";
  }
}

const char* level_name(std::uint32_t constraint, std::uint32_t level) noexcept {
  if (level >= 2U) {
    return "?";
  }
  switch (constraint) {
    case 0U: return level == 0U ? "normal" : "high";
    case 1U: return level == 0U ? "full" : "save";
    case 2U: return level == 0U ? "full rate" : "half rate";
    default: return "?";
  }
}

void type_node(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept { o.put(node_name(v)); }

void type_constraint(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  o.put(v == 0U ? "reliability" : v == 1U ? "power" : v == 2U ? "capacity" : "?");
}

/** A level of the constraint in the cause's low byte. */
void type_level(const fdir::Event& e, std::uint32_t v, Out& o) noexcept { o.put(level_name(e.cause & 0xFFU, v)); }

void type_alternative(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  switch (v) {
    case trn::tasks::kAltDelegate: o.put("hand the policy down"); return;
    case trn::tasks::kAltSimplex: o.put("filter simplex"); return;
    case trn::tasks::kAltTmr: o.put("filter in TMR"); return;
    case trn::tasks::kAltTmrReseed: o.put("TMR again from a fresh seed"); return;
    case trn::tasks::kAltFullRate: o.put("every frame on the healthy vision tiles"); return;
    case trn::tasks::kAltHalfRate: o.put("half the image rate"); return;
    case trn::tasks::kAltAcceptSimplex: o.put("accept the simplex filter (reliability lowered, reported)"); return;
    case trn::tasks::kAltReplicasOn: o.put("the filter's replicas powered"); return;
    case trn::tasks::kAltReplicasParked: o.put("the replicas off while the filter is simplex"); return;
    default: o.put("nothing to do"); return;
  }
}

/** Where a policy came from: a node, the phase table, the ground or the node's default. */
void type_from(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  o.put(v == fdir::kFromPhase     ? "the mission phase"
        : v == fdir::kFromGround  ? "a telecommand"
        : v == fdir::kFromDefault ? "its default"
                                  : node_name(v));
}

void type_state_check(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  o.put(trn::filter::state_check_name(static_cast<trn::filter::StateCheck>(v)));
}

/** A value of the state check in the cause: thousandths of its unit (millionths for the attitude norm). */
void type_state_value(const fdir::Event& e, std::uint32_t v, Out& o) noexcept {
  static constexpr std::array<const char*, 10> kUnit{"", "", "", "m/s", "m", "", "m", "m/s", "rad", ""};
  const bool norm = e.cause == static_cast<std::uint32_t>(trn::filter::StateCheck::kAttitudeNorm);
  const char* unit = e.cause < kUnit.size() ? kUnit[e.cause] : "";
  std::array<char, 40> t{};
  (void)std::snprintf(t.data(), t.size(), "%.*f%s%s", norm ? 6 : 3, v / (norm ? 1e6 : 1e3),
                      unit[0] != '\0' ? " " : "", unit);
  o.put(t.data());
}

/** Where a checked product was wrong (the cause: row << 16 | column; a: bad rows << 16 | bad columns). */
void type_abft_where(const fdir::Event& e, std::uint32_t v, Out& o) noexcept {
  const std::uint32_t row = v >> 16U;
  const std::uint32_t col = v & 0xFFFFU;
  std::array<char, 96> t{};
  if (col == fdir::kAbftColNotChecked && (e.a >> 16U) == 1U) {
    (void)std::snprintf(t.data(), t.size(), "row %u off its checksum (rows checked)", row);
  } else if (col == fdir::kAbftColNotChecked) {
    (void)std::snprintf(t.data(), t.size(), "%u rows off their checksums, the worst %u (rows checked)", e.a >> 16U,
                        row);
  } else if (row != 0xFFFFU && col != 0xFFFFU) {
    (void)std::snprintf(t.data(), t.size(), "element (%u, %u) wrong", row, col);
  } else {
    (void)std::snprintf(t.data(), t.size(), "%u row(s) and %u column(s) off their checksums", e.a >> 16U,
                        e.a & 0xFFFFU);
  }
  o.put(t.data());
}

/** A landmark, or the coarse stage's correlation. */
void type_landmark(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  if (v == trn::kCoarseLandmark) {
    o.put("the coarse stage");
    return;
  }
  o.put("landmark ");
  if (v == fdir::kUnknown) {
    o.put("?");
  } else {
    o.number(v, false);
  }
}

/** Thousandths of a pixel, as pixels. */
void type_mpx(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  std::array<char, 24> t{};
  (void)std::snprintf(t.data(), t.size(), "%.3f", v / 1e3);
  o.put(t.data());
}

/** A window of measurements: how many (low 16 bits) and how many of them rejected (high 16 bits). */
void type_rejected_of(const fdir::Event& /*e*/, std::uint32_t v, Out& o) noexcept {
  std::array<char, 48> t{};
  (void)std::snprintf(t.data(), t.size(), "%u of %u rejected", v >> 16U, v & 0xFFFFU);
  o.put(t.data());
}

using TypeFn = void (*)(const fdir::Event&, std::uint32_t, Out&) noexcept;
struct TextType {
  const char* name;
  TypeFn fn;
};

constexpr std::array<TextType, 11> kTypes{{
    {"node", type_node},
    {"constraint", type_constraint},
    {"level", type_level},
    {"alternative", type_alternative},
    {"from", type_from},
    {"state_check", type_state_check},
    {"state_value", type_state_value},
    {"abft_where", type_abft_where},
    {"landmark", type_landmark},
    {"mpx", type_mpx},
    {"rejected_of", type_rejected_of},
}};

constexpr std::array<const char*, kTypes.size()> type_names() noexcept {
  std::array<const char*, kTypes.size()> n{};
  for (std::size_t i = 0; i < kTypes.size(); ++i) {
    n[i] = kTypes[i].name;
  }
  return n;
}
constexpr std::array<const char*, kTypes.size()> kTypeNames = type_names();

const TextType* type_named(std::string_view name) noexcept {
  for (const TextType& t : kTypes) {
    if (name == t.name) {
      return &t;
    }
  }
  return nullptr;
}

// ---- the template language

/** Nesting of phrases within phrases the formatter follows. */
constexpr std::size_t kMaxDepth = 4U;
/** Segments the formatter holds at once: the text and one per level of phrases. */
constexpr std::size_t kStackSegments = 5U;
static_assert(kStackSegments == kMaxDepth + 1U);

/** Where the brace opened at @p s[0] closes; npos if it does not. */
std::size_t closing_brace(std::string_view s) noexcept {
  std::size_t depth = 0U;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '{') {
      ++depth;
    } else if (s[i] == '}' && --depth == 0U) {
      return i;
    }
  }
  return std::string_view::npos;
}

/** The @p index-th of the '|'-separated parts of @p s at depth 0, the last if there are fewer. */
std::string_view part(std::string_view s, std::uint32_t index) noexcept {
  std::size_t depth = 0U;
  std::size_t begin = 0U;
  std::uint32_t at = 0U;
  for (std::size_t i = 0; i < s.size(); ++i) {
    depth += s[i] == '{' ? 1U : 0U;
    depth -= s[i] == '}' && depth > 0U ? 1U : 0U;
    if (s[i] == '|' && depth == 0U) {
      if (at == index) {
        return s.substr(begin, i - begin);
      }
      ++at;
      begin = i + 1U;
    }
  }
  return s.substr(begin);
}

/** Parts of @p s at depth 0 (1 when there is no separator). */
std::uint32_t part_count(std::string_view s) noexcept {
  std::size_t depth = 0U;
  std::uint32_t n = 1U;
  for (const char ch : s) {
    depth += ch == '{' ? 1U : 0U;
    depth -= ch == '}' && depth > 0U ? 1U : 0U;
    n += ch == '|' && depth == 0U ? 1U : 0U;
  }
  return n;
}

/** A placeholder's field and selector, parsed. */
struct Field {
  char letter = '\0';
  std::string_view selector;
  char op = '\0';          ///< '\0' decimal, ':' format, '@' type, '|' phrases, '&' bit words
  std::string_view rest;   ///< after the operator
  bool ok = false;
};

Field parse_field(std::string_view spec) noexcept {
  Field f{};
  if (spec.empty() || (spec[0] != 's' && spec[0] != 'c' && spec[0] != 'a' && spec[0] != 'b')) {
    return f;
  }
  f.letter = spec[0];
  std::size_t i = 1U;
  if (i < spec.size() && spec[i] == '.') {
    std::size_t j = i + 1U;
    while (j < spec.size() && ((spec[j] >= 'a' && spec[j] <= 'z') || (spec[j] >= '0' && spec[j] <= '9'))) {
      ++j;
    }
    f.selector = spec.substr(i + 1U, j - i - 1U);
    i = j;
  }
  if (i < spec.size()) {
    f.op = spec[i];
    f.rest = spec.substr(i + 1U);
  }
  f.ok = f.op == '\0' || f.op == ':' || f.op == '@' || f.op == '|' || f.op == '&';
  return f;
}

bool selector_known(std::string_view sel) noexcept {
  return sel.empty() || sel == "hi" || sel == "lo" || sel == "b0" || sel == "b1" || sel == "b2" || sel == "b3" ||
         sel == "top" || sel == "rest";
}

/** The field's value after its selector. */
std::uint32_t field_value(const fdir::Event& e, const Field& f) noexcept {
  const std::uint32_t v = f.letter == 's' ? e.subject : f.letter == 'c' ? e.cause : f.letter == 'a' ? e.a : e.b;
  const std::string_view s = f.selector;
  if (s == "hi") {
    return v >> 16U;
  }
  if (s == "lo") {
    return v & 0xFFFFU;
  }
  if (s.size() == 2U && s[0] == 'b' && s[1] >= '0' && s[1] <= '3') {
    return (v >> (8U * static_cast<std::uint32_t>(s[1] - '0'))) & 0xFFU;
  }
  if (s == "top") {
    return v >> 31U;
  }
  if (s == "rest") {
    return v & 0x7FFF'FFFFU;
  }
  return v;
}

/** Writes the words of @p v's set bits among the '|'-separated @p words, joined by ", ". */
void bit_words(std::string_view words, std::uint32_t v, Out& o) noexcept {
  const std::uint32_t n = std::min(part_count(words), 32U);
  bool first = true;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (((v >> i) & 1U) != 0U) {
      o.put(first ? "" : ", ");
      o.put(part(words, i));
      first = false;
    }
  }
}

}  // namespace

std::size_t format_event_text(const fdir::EventInfo& info, const fdir::Event& e, std::span<char> out) noexcept {
  Out o(out);
  std::array<std::string_view, kStackSegments> stack{};
  std::size_t depth = 0U;
  stack[depth++] = info.text != nullptr ? std::string_view(info.text) : std::string_view();
  while (depth > 0U) {
    std::string_view& seg = stack[depth - 1U];
    if (seg.empty()) {
      --depth;
      continue;
    }
    const std::size_t open = seg.find('{');
    if (open != 0U) {
      o.put(seg.substr(0, open));
      seg.remove_prefix(open == std::string_view::npos ? seg.size() : open);
      continue;
    }
    const std::size_t close = closing_brace(seg);
    const Field f = parse_field(seg.substr(1U, close == std::string_view::npos ? 0U : close - 1U));
    seg.remove_prefix(close == std::string_view::npos ? seg.size() : close + 1U);
    if (!f.ok || !selector_known(f.selector)) {
      o.put("{?}");
      continue;
    }
    const std::uint32_t v = field_value(e, f);
    const TextType* type = f.op == '@' ? type_named(f.rest) : nullptr;
    if (f.op == '|' && depth < stack.size()) {
      stack[depth] = part(f.rest, v);
      ++depth;
    } else if (f.op == '&') {
      bit_words(f.rest, v, o);
    } else if (type != nullptr) {
      type->fn(e, v, o);
    } else if (f.op == '\0' && f.selector.empty() && v == fdir::kUnknown) {
      o.put("?");
    } else if (f.op == '\0' || (f.op == ':' && f.rest == "x")) {
      o.number(v, f.op == ':');
    } else {
      o.put("{?}");
    }
  }
  return o.size();
}

std::string check_event_text(const char* text) {
  if (text == nullptr || text[0] == '\0') {
    return "no text";
  }
  // Each entry: a segment to check and its nesting depth.
  std::array<std::pair<std::string_view, std::size_t>, 64> todo{};
  std::size_t n = 0U;
  todo[n++] = {std::string_view(text), 0U};
  while (n > 0U) {
    auto [seg, depth] = todo[--n];
    for (std::size_t i = 0; i < seg.size(); ++i) {
      if (seg[i] == '}') {
        return "a '}' closes nothing in \"" + std::string(seg) + "\"";
      }
      if (seg[i] != '{') {
        continue;
      }
      const std::size_t close = closing_brace(seg.substr(i));
      if (close == std::string_view::npos) {
        return "a '{' is not closed in \"" + std::string(seg) + "\"";
      }
      const std::string_view spec = seg.substr(i + 1U, close - 1U);
      const Field f = parse_field(spec);
      if (!f.ok || !selector_known(f.selector)) {
        return "\"{" + std::string(spec) + "}\" is not a field (s c a b), a selector and a format";
      }
      if ((f.op == ':' && f.rest != "x") || (f.op == '@' && type_named(f.rest) == nullptr)) {
        return "\"{" + std::string(spec) + "}\": unknown format or type";
      }
      if (f.op == '&' && f.rest.find('{') != std::string_view::npos) {
        return "\"{" + std::string(spec) + "}\": bit words cannot hold fields";
      }
      if (f.op == '|') {
        if (depth + 1U > kMaxDepth) {
          return "\"{" + std::string(spec) + "}\": phrases nested too deep";
        }
        const std::uint32_t parts = part_count(f.rest);
        for (std::uint32_t p = 0; p < parts && n < todo.size(); ++p) {
          todo[n++] = {part(f.rest, p), depth + 1U};
        }
      }
      i += close;
    }
  }
  return "";
}

std::span<const char* const> event_text_types() noexcept { return kTypeNames; }

}  // namespace tools
