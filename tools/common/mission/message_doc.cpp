/**
 * @file message_doc.cpp
 * @brief The declared message kinds as Markdown rows.
 */
#include "tools/common/mission/message_doc.hpp"

#include "trn/tasks/messages.hpp"
#include "trn/tasks/tile_map.hpp"

#include <cstdint>
#include <sstream>

namespace tools {

namespace {

namespace m = fdir::msg;

std::string tag_text(std::uint32_t tag) {
  if (tag == m::kNoTag) {
    return "none";
  }
  std::string s = "`";
  for (std::uint32_t i = 0; i < 4U; ++i) {
    s += static_cast<char>((tag >> (24U - 8U * i)) & 0xFFU);
  }
  return s + "`";
}

std::string channel_text(std::uint32_t c) {
  if (c == m::kNoChannel) {
    return "(record)";
  }
  return c < trn::tasks::kChannelNames.size() ? std::string(trn::tasks::kChannelNames[c]) : std::to_string(c);
}

std::string roles_text(std::uint32_t mask) {
  std::string s;
  for (const trn::tasks::RoleDecl& r : trn::tasks::kRoles) {
    if ((mask & trn::tasks::role_bit(r.role)) != 0U) {
      s += (s.empty() ? "" : ", ") + std::string(r.name);
    }
  }
  return s.empty() ? "-" : s;
}

std::string type_text(const m::FieldInfo& f) {
  switch (f.type) {
    case m::Type::kF64: return "f64";
    case m::Type::kU64: return "u64";
    case m::Type::kF32: return "f32";
    case m::Type::kI32: return "i32";
    case m::Type::kZero: return "zero";
    case m::Type::kBool: return "bool";
    case m::Type::kU32: return f.bits == 32U ? "u32" : "u" + std::to_string(f.bits);
  }
  return "?";
}

/** "[4..5] t_s f64", "[2] width_px u16 bits 0..15 in 1..65535". */
std::string field_text(const m::FieldInfo& f) {
  std::ostringstream o;
  const std::uint32_t last = f.word + f.count * m::words_of(f) - 1U;
  o << "[" << unsigned{f.word};
  if (last != f.word) {
    o << ".." << last;
  }
  o << "] " << f.name;
  if (f.count > 1U) {
    o << "[" << unsigned{f.count} << "]";
  }
  o << " " << type_text(f);
  if (f.bits < 32U) {
    o << " bits " << unsigned{f.shift} << ".." << (f.shift + f.bits - 1U);
  }
  if (!m::full_range(f) && f.type != m::Type::kZero) {
    o << " in " << f.min << ".." << f.max;
  }
  return o.str();
}

std::string group_count_text(const m::KindView& k) {
  const m::GroupInfo& g = k.info->group;
  return g.count_field == m::kNoCount ? std::to_string(g.fixed_count) : std::string(k.fields[g.count_field].name);
}

std::string fields_text(const m::KindView& k) {
  const m::KindInfo& i = *k.info;
  std::string head;
  std::string each;
  for (const m::FieldInfo& f : k.fields) {
    std::string& to = f.in_group ? each : head;
    to += (to.empty() ? "" : "; ") + field_text(f);
  }
  const m::GroupInfo& g = i.group;
  if (g.elem_words != 0U) {
    head += "; then " + group_count_text(k) + " x " + (g.record != nullptr ? std::string(g.record) : "(" + each + ")");
  }
  if (i.check != nullptr) {
    head += std::string("; rule: ") + i.rule;
  }
  return head;
}

std::string words_text(const m::KindView& k) {
  const m::KindInfo& i = *k.info;
  const m::GroupInfo& g = i.group;
  if (g.elem_words == 0U) {
    return std::to_string(i.words);
  }
  const std::string count = group_count_text(k);
  return std::to_string(i.words) + " + " + count + " x " + std::to_string(g.elem_words);
}

}  // namespace

std::string message_kinds_markdown() {
  std::ostringstream o;
  for (const m::KindView& k : trn::tasks::kMessageKinds) {
    const m::KindInfo& i = *k.info;
    o << "| `" << i.name << "` | " << tag_text(i.tag) << " | " << channel_text(i.channel) << " | " << roles_text(i.from)
      << " | " << roles_text(i.to) << " | " << words_text(k) << " | " << fields_text(k) << " |\n";
  }
  return o.str();
}

}  // namespace tools
