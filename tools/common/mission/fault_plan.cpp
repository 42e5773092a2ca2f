/**
 * @file fault_plan.cpp
 * @brief Fault-plan parser (toml++), the demonstration plan, arming the injector, and fault descriptions.
 */
#include "tools/common/mission/fault_plan.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/devices/device_bus.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/udn_hw.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/tile_map.hpp"
#include "tools/common/mission/run_folder.hpp"

#include "tools/common/text.hpp"
#include "tools/common/toml_input.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <fstream>
#include <initializer_list>
#include <sstream>

namespace tools {
namespace {

// Indexed by bsp::FaultKind.
constexpr std::array<const char*, kFaultKinds> kKindNames = {
    "core_hang", "core_reset", "sdc", "seu", "watchdog_fail", "packet_bit_flip", "switch_fail", "link_fail",
};
static_assert(static_cast<std::size_t>(bsp::FaultKind::kLinkFail) == kFaultKinds - 1U,
              "a new fault kind needs a name here, its keys below and a line in docs/FAULT_PLANS.md");

// Indexed by bsp::UdnDir.
constexpr std::array<const char*, bsp::kUdnDirs> kDirNames = {"east", "west", "north", "south"};

/** The keys of one kind beyond t_s, kind and tile. */
struct KindKeys {
  std::array<const char*, 5> keys;
};

// Indexed by bsp::FaultKind; nullptr ends a list.
constexpr std::array<KindKeys, kFaultKinds> kKindKeys = {{
    {{nullptr, nullptr, nullptr, nullptr, nullptr}},      // core_hang
    {{nullptr, nullptr, nullptr, nullptr, nullptr}},      // core_reset
    {{"point", "channel", "bit", "shift", nullptr}},      // sdc
    {{"offset", "bit", "carve", "position", nullptr}},    // seu
    {{nullptr, nullptr, nullptr, nullptr, nullptr}},      // watchdog_fail
    {{"word", "bit", nullptr, nullptr, nullptr}},         // packet_bit_flip
    {{nullptr, nullptr, nullptr, nullptr, nullptr}},      // switch_fail
    {{"direction", nullptr, nullptr, nullptr, nullptr}},  // link_fail
}};

constexpr std::array<const char*, 13> kAllFaultKeys = {"t_s",  "kind", "tile",     "channel", "offset", "word",    "bit",
                                                       "role", "instance", "carve", "point", "shift", "position"};

/** Roles a plan can name (every role of the tile map but spare). */
std::vector<trn::tasks::Role> plan_roles() {
  using trn::tasks::Role;
  return {Role::kTrnSupervisor, Role::kVisionCoordinator, Role::kIo,           Role::kFilter,
          Role::kVision,         Role::kFilterReplica,     Role::kFilterSupervisor, Role::kVisionSupervisor};
}

std::string role_list() {
  std::string out;
  for (const trn::tasks::Role r : plan_roles()) {
    out += (out.empty() ? "" : ", ") + std::string(trn::tasks::role_name(r));
  }
  return out;
}

std::optional<trn::tasks::Role> role_from_name(const std::string& name) {
  for (const trn::tasks::Role r : plan_roles()) {
    if (name == trn::tasks::role_name(r)) {
      return r;
    }
  }
  return std::nullopt;
}

std::string point_list() {
  std::string out;
  for (const trn::tasks::SdcPoint& p : trn::tasks::kSdcPoints) {
    out += (out.empty() ? "" : ", ") + std::string(p.name);
  }
  return out;
}

std::string shift_points() {
  std::string out;
  for (const trn::tasks::SdcPoint& p : trn::tasks::kSdcPoints) {
    out += p.shifts ? (out.empty() ? "" : ", ") + std::string(p.name) : "";
  }
  return out;
}

/** Largest |shift| a plan takes (pixels at match_position: far beyond any matcher's error). */
constexpr double kMaxShift = 1000.0;

const trn::tasks::SdcPoint* point_from_name(const std::string& name) {
  for (const trn::tasks::SdcPoint& p : trn::tasks::kSdcPoints) {
    if (name == p.name) {
      return &p;
    }
  }
  return nullptr;
}

/** The roles whose tiles publish at @p p, as names. */
std::string publishers_of(const trn::tasks::SdcPoint& p) {
  std::string out;
  for (const trn::tasks::Role r : plan_roles()) {
    if ((p.roles & trn::tasks::role_bit(r)) != 0U) {
      out += (out.empty() ? "" : ", ") + std::string(trn::tasks::role_name(r));
    }
  }
  return out;
}

std::string fmt(double v) { return format_number(v); }

std::string kind_list() {
  std::string out;
  for (const char* n : kKindNames) {
    out += (out.empty() ? "" : ", ") + std::string(n);
  }
  return out;
}

std::string keys_of(bsp::FaultKind k) {
  std::string out = "t_s, kind, tile or role (and instance)";
  for (const char* key : kKindKeys[static_cast<std::size_t>(k)].keys) {
    if (key != nullptr) {
      out += ", " + std::string(key);
    }
  }
  return out;
}

bool kind_uses(bsp::FaultKind k, std::string_view key) {
  if (key == "t_s" || key == "kind" || key == "tile" || key == "role" || key == "instance") {
    return true;
  }
  const KindKeys& kk = kKindKeys[static_cast<std::size_t>(k)];
  return std::any_of(kk.keys.begin(), kk.keys.end(), [key](const char* c) { return c != nullptr && key == c; });
}

bool known_fault_key(std::string_view key) {
  return key == "direction" ||
         std::any_of(kAllFaultKeys.begin(), kAllFaultKeys.end(), [key](const char* c) { return key == c; });
}

struct Limits {
  std::uint32_t tile_count;
  double max_time_s;
  const trn::tasks::Deployment* dep;  ///< the chip's roles: which tile runs what, how many vision tiles
};

/** The kind of an entry (read first: it decides which keys are allowed). */
bool read_kind(const toml::table& t, const std::string& where, bsp::FaultKind& kind, std::vector<std::string>& errors) {
  const toml::node* node = t.get("kind");
  if (node == nullptr) {
    errors.push_back(cat({where, ": missing key kind (allowed: ", kind_list(), ")"}));
    return false;
  }
  if (!node->is_string()) {
    errors.push_back(where + " kind: wrong type: expected a string");
    return false;
  }
  const std::string name = node->as_string()->get();
  const std::optional<bsp::FaultKind> k = fault_kind_from_name(name);
  if (!k) {
    errors.push_back(cat({where, " kind: unknown fault kind \"", name, "\" (allowed: ", kind_list(), ")"}));
    return false;
  }
  kind = *k;
  return true;
}

/** One key of an entry whose kind uses it; returns an error text (empty when set). */
std::string read_fault_key(const std::string& key, const toml::node& node, const Limits& lim, FaultPlanItem& item) {
  std::int64_t v = 0;
  std::string e;
  if (key == "t_s") {
    e = read_float(node, 0.0, lim.max_time_s, " s (the run's duration)", item.t_s);
  } else if (key == "tile") {
    e = read_int(node, 0, static_cast<std::int64_t>(lim.tile_count) - 1, v);
    item.tile = static_cast<bsp::TileId>(v);
  } else if (key == "channel") {
    e = read_int(node, 0, static_cast<std::int64_t>(bsp::kAnyChannel) - 1, v);
    item.channel = static_cast<std::uint32_t>(v);
  } else if (key == "offset") {
    e = read_int(node, 0, static_cast<std::int64_t>(bsp::kTileRamBytes) - 1, v);
    item.offset = static_cast<std::uint64_t>(v);
  } else if (key == "position") {
    e = read_float(node, 0.0, std::nextafter(1.0, 0.0), " (a fraction of the tile's upset space, or of its carve)",
                   item.position);
  } else if (key == "word") {
    e = read_int(node, 0, static_cast<std::int64_t>(bsp::kUdnMaxPacketWords) - 1, v);
    item.offset = static_cast<std::uint64_t>(v);
  } else if (key == "bit") {
    const std::int64_t hi = item.kind == bsp::FaultKind::kSeu             ? 7
                            : item.kind == bsp::FaultKind::kPacketBitFlip ? 31
                                                                          : std::int64_t{kMaxSdcBit};
    e = read_int(node, 0, hi, v);
    item.bit = static_cast<std::uint32_t>(v);
  } else if (key == "shift") {
    e = read_float(node, -kMaxShift, kMaxShift, " (the value's unit: pixels at match_position)", item.shift);
    if (e.empty() && item.shift == 0.0) {
      e = "0 changes nothing: a lasting error needs a non-zero shift";
    }
  } else if (key == "role") {
    if (!node.is_string()) {
      return "wrong type: expected a string (" + role_list() + ")";
    }
    const std::string r = node.as_string()->get();
    if (!role_from_name(r)) {
      return "unknown role \"" + r + "\" (allowed: " + role_list() + ")";
    }
    item.role = r;
  } else if (key == "point") {
    if (!node.is_string()) {
      return "wrong type: expected a string (" + point_list() + ")";
    }
    const std::string name = node.as_string()->get();
    const trn::tasks::SdcPoint* p = point_from_name(name);
    if (p == nullptr) {
      return "unknown point \"" + name + "\" (allowed: " + point_list() + ")";
    }
    item.channel = p->channel;
  } else if (key == "carve") {
    if (!node.is_string()) {
      return "wrong type: expected a string (a carve of the tile's RAM, as `make size` lists them)";
    }
    const std::string c = node.as_string()->get();
    if (c.empty() || c.size() >= bsp::kCarveNameMax) {
      return "carve name \"" + c + "\": 1 to " + std::to_string(bsp::kCarveNameMax - 1U) + " characters";
    }
    item.carve = c;
  } else if (key == "instance") {
    const trn::tasks::Role of = item.role == "filter_replica" ? trn::tasks::Role::kFilterReplica : trn::tasks::Role::kVision;
    e = read_int(node, 0, static_cast<std::int64_t>(trn::tasks::count_role(*lim.dep, of)) - 1, v);
    item.instance = static_cast<std::uint32_t>(v);
  } else if (key == "direction") {
    if (!node.is_string()) {
      return "wrong type: expected a string (east, west, north, south)";
    }
    const std::string d = node.as_string()->get();
    const auto* it = std::find_if(kDirNames.begin(), kDirNames.end(), [&d](const char* n) { return d == n; });
    if (it == kDirNames.end()) {
      return "unknown direction \"" + d + "\" (allowed: east, west, north, south)";
    }
    item.param = static_cast<std::uint64_t>(it - kDirNames.begin());
  }
  return e;
}

/**
 * An sdc is delivered only where flight code publishes: the point (or raw
 * channel) must be one, and the tile or role named must publish there (a
 * tile is judged by its role in the tile map).
 */
void check_sdc_target(const std::string& where, const toml::table& t, const FaultPlanItem& item, const Limits& lim,
                      std::vector<std::string>& errors) {
  if (t.get("point") != nullptr && t.get("channel") != nullptr) {
    errors.push_back(where + " point: an sdc names a point or a channel, not both");
    return;
  }
  const std::optional<trn::tasks::Role> named = role_from_name(item.role);
  const trn::tasks::Role role = named                                 ? *named
                                : trn::tasks::tile_role(*lim.dep, item.tile);
  const std::string target = named ? "role " + item.role
                                   : cat({"tile ", std::to_string(item.tile), " (", trn::tasks::role_name(role), ")"});
  if (item.channel == bsp::kAnyChannel && t.get("shift") != nullptr) {
    errors.push_back(cat({where, " shift: a lasting error names its point (allowed at: ", shift_points(), ")"}));
    return;
  }
  if (item.channel == bsp::kAnyChannel) {
    const bool publishes = std::any_of(trn::tasks::kSdcPoints.begin(), trn::tasks::kSdcPoints.end(),
                                       [role](const trn::tasks::SdcPoint& p) {
                                         return (p.roles & trn::tasks::role_bit(role)) != 0U;
                                       });
    if (!publishes) {
      errors.push_back(cat({where, " tile: ", target, " publishes nothing an sdc could corrupt"}));
    }
    return;
  }
  const trn::tasks::SdcPoint* p = trn::tasks::sdc_point_of_channel(item.channel);
  if (p == nullptr) {
    errors.push_back(cat({where, " channel: no flight code publishes on channel ", std::to_string(item.channel),
                          " (name a point instead: ", point_list(), ")"}));
    return;
  }
  if ((p->roles & trn::tasks::role_bit(role)) == 0U) {
    errors.push_back(cat({where, t.get("point") != nullptr ? " point: " : " channel: ", target,
                          " never publishes at ", p->name, " (published by: ", publishers_of(*p), ")"}));
  }
  if (t.get("shift") != nullptr && !p->shifts) {
    errors.push_back(cat({where, " shift: ", p->name, " does not start with a number a shift could move (allowed at: ",
                          shift_points(), ")"}));
  }
  if (t.get("shift") != nullptr && t.get("bit") != nullptr) {
    errors.push_back(where + " bit: a shift is a lasting error, not a bit flip: name one of bit and shift");
  }
}

void parse_fault(const std::string& source, std::size_t index, const toml::table& t, const Limits& lim,
                 FaultPlan& plan, std::vector<std::string>& errors) {
  const std::string where = cat({source, ": [[fault]] #", std::to_string(index + 1U), " (line ",
                                 std::to_string(t.source().begin.line), ")"});
  FaultPlanItem item{};
  if (!read_kind(t, where, item.kind, errors)) {
    return;
  }
  const std::string kname = fault_kind_name(item.kind);
  const std::size_t before = errors.size();
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    if (key == "kind") {
      continue;
    }
    if (!kind_uses(item.kind, key)) {
      errors.push_back(known_fault_key(key)
                           ? cat({where, " ", key, ": not used by ", kname, " (allowed keys for ", kname, ": ",
                                  keys_of(item.kind), ")"})
                           : cat({where, " ", key, ": unknown key (allowed keys for ", kname, ": ",
                                  keys_of(item.kind), ")"}));
      continue;
    }
    const std::string e = read_fault_key(key, node, lim, item);
    if (!e.empty()) {
      errors.push_back(cat({where, " ", key, ": ", e}));
    }
  }
  if (t.get("tile") == nullptr && t.get("role") == nullptr) {
    errors.push_back(cat({where, ": missing key tile (allowed 0 .. ", std::to_string(lim.tile_count - 1U),
                          ") or role (", role_list(), ")"}));
  }
  if (t.get("tile") != nullptr && t.get("role") != nullptr) {
    errors.push_back(where + " role: a fault names a tile or a role, not both");
  }
  if (t.get("position") != nullptr && t.get("offset") != nullptr) {
    errors.push_back(where + " position: names where the byte is, as offset does: name one of them");
  }
  if (t.get("instance") != nullptr && item.role != "vision" && item.role != "filter_replica") {
    errors.push_back(where + " instance: only with role = \"vision\" or \"filter_replica\" (which of its tiles)");
  }
  if (item.role == "filter_replica" && item.instance >= trn::tasks::count_role(trn::tasks::Role::kFilterReplica)) {
    errors.push_back(cat({where, " instance: ", std::to_string(item.instance), " is out of range: allowed 0 .. ",
                          std::to_string(trn::tasks::count_role(trn::tasks::Role::kFilterReplica) - 1U),
                          " (the filter's replicas)"}));
  }
  if (item.kind == bsp::FaultKind::kSdc && errors.size() == before) {
    check_sdc_target(where, t, item, lim, errors);
  }
  if (item.kind == bsp::FaultKind::kLinkFail && t.get("direction") == nullptr) {
    errors.push_back(where + ": missing key direction (allowed: east, west, north, south)");
  }
  if (errors.size() == before) {
    plan.items.push_back(item);
  }
}

void parse_rates(const std::string& source, const toml::table& t, FaultPlan& plan, std::vector<std::string>& errors) {
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    const std::optional<bsp::FaultKind> kind = fault_kind_from_name(key);
    if (!kind) {
      errors.push_back(cat({source, ": [rates] ", key, ": unknown fault kind (allowed: ", kind_list(), ")"}));
      continue;
    }
    const std::string e = read_float(node, 0.0, kMaxFaultRate, " faults per tile per second",
                                     plan.rates[static_cast<std::size_t>(*kind)]);
    if (!e.empty()) {
      errors.push_back(cat({source, ": [rates] ", key, ": ", e}));
    }
  }
}

void parse_faults(const std::string& source, const toml::node& node, const Limits& lim, FaultPlan& plan,
                  std::vector<std::string>& errors) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr || !arr->is_array_of_tables()) {
    errors.push_back(source + ": fault: must be an array of tables ([[fault]] entries)");
    return;
  }
  if (arr->size() > bsp::kFaultPlanCapacity) {
    errors.push_back(cat({source, ": [[fault]]: ", std::to_string(arr->size()),
                          " entries are more than the injector holds (allowed 0 .. ",
                          std::to_string(bsp::kFaultPlanCapacity), ")"}));
    return;
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    parse_fault(source, i, *arr->get(i)->as_table(), lim, plan, errors);
  }
}

constexpr std::array<std::pair<const char*, std::uint32_t>, 6> kCommandNames{{
    {"filter_tmr", trn::tasks::kCmdFilterTmr},
    {"filter_simplex", trn::tasks::kCmdFilterSimplex},
    {"reliability_normal", trn::tasks::kCmdReliabilityNormal},
    {"reliability_high", trn::tasks::kCmdReliabilityHigh},
    {"power_full", trn::tasks::kCmdPowerFull},
    {"power_save", trn::tasks::kCmdPowerSave},
}};
constexpr const char* kCommandList = "filter_tmr, filter_simplex, reliability_normal, reliability_high, power_full, power_save";

void parse_command(const std::string& where, const toml::table& t, const Limits& lim, FaultPlan& plan,
                   std::vector<std::string>& errors) {
  PlanCommand c{};
  const std::size_t before = errors.size();
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    if (key == "t_s") {
      const std::string e = read_float(node, 0.0, lim.max_time_s, " s", c.t_s);
      if (!e.empty()) {
        errors.push_back(cat({where, " t_s: ", e}));
      }
    } else if (key == "name") {
      const std::string n = node.is_string() ? node.as_string()->get() : std::string();
      const auto* it = std::find_if(kCommandNames.begin(), kCommandNames.end(),
                                    [&n](const auto& p) { return n == p.first; });
      if (it == kCommandNames.end()) {
        errors.push_back(cat({where, " name: unknown command \"", n, "\" (allowed: ", kCommandList, ")"}));
      } else {
        c.name = n;
        c.code = it->second;
      }
    } else {
      errors.push_back(cat({where, " ", key, ": unknown key (allowed keys for a command: t_s, name)"}));
    }
  }
  if (t.get("name") == nullptr) {
    errors.push_back(cat({where, ": missing key name (allowed: ", kCommandList, ")"}));
  }
  if (errors.size() == before) {
    plan.commands.push_back(c);
  }
}

void parse_commands(const std::string& source, const toml::node& node, const Limits& lim, FaultPlan& plan,
                    std::vector<std::string>& errors) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr || !arr->is_array_of_tables()) {
    errors.push_back(source + ": command: must be an array of tables ([[command]] entries)");
    return;
  }
  if (arr->size() > std::size_t{bsp::kCommandFifoDepth} * 4U) {
    errors.push_back(cat({source, ": [[command]]: ", std::to_string(arr->size()), " entries (allowed 0 .. ",
                          std::to_string(bsp::kCommandFifoDepth * 4U), ")"}));
    return;
  }
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::table& t = *arr->get(i)->as_table();
    parse_command(cat({source, ": [[command]] #", std::to_string(i + 1U), " (line ",
                       std::to_string(t.source().begin.line), ")"}),
                  t, lim, plan, errors);
  }
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) {
    out += (out.empty() ? "" : "\n") + l;
  }
  return out;
}

/** TOML basic string: quotes, backslashes and control characters escaped. */
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20U || u == 0x7FU) {
      std::array<char, 8> buf{};
      (void)std::snprintf(buf.data(), buf.size(), "\\u%04x", static_cast<unsigned>(u));
      out += buf.data();
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/** A float that reads back bit for bit, always with a decimal point or exponent. */
std::string toml_float(double v) {
  std::array<char, 40> buf{};
  (void)std::snprintf(buf.data(), buf.size(), "%.17g", v);
  std::string s(buf.data());
  if (s.find_first_of(".eEn") == std::string::npos) {
    s += ".0";
  }
  return s;
}

}  // namespace

std::vector<std::string> fault_plan_role_names() {
  std::vector<std::string> out;
  for (const trn::tasks::Role r : plan_roles()) {
    out.emplace_back(trn::tasks::role_name(r));
  }
  return out;
}

std::string fault_kind_name(bsp::FaultKind k) {
  const auto i = static_cast<std::size_t>(k);
  return i < kFaultKinds ? kKindNames[i] : "unknown_kind_" + std::to_string(i);
}

std::optional<bsp::FaultKind> fault_kind_from_name(std::string_view name) {
  for (std::size_t i = 0; i < kFaultKinds; ++i) {
    if (name == kKindNames[i]) {
      return static_cast<bsp::FaultKind>(i);
    }
  }
  return std::nullopt;
}

std::string link_direction_name(std::uint64_t dir) { return dir < bsp::kUdnDirs ? kDirNames[dir] : "?"; }

FaultPlanResult parse_fault_plan(std::string_view text, const std::string& source, std::uint32_t tile_count,
                                 double max_time_s, const trn::tasks::Deployment& dep) {
  FaultPlanResult r;
  if (tile_count == 0U || tile_count > dep.tiles() || !(std::isfinite(max_time_s) && max_time_s >= 0.0)) {
    r.error = source + ": cannot check the plan: the chip has no tiles or the run's duration is invalid";
    return r;
  }
  toml::table root;
  if (!parse_toml(text, source, root, r.error)) {
    return r;
  }
  FaultPlan plan;
  std::vector<std::string> errors;
  const Limits lim{tile_count, max_time_s, &dep};
  for (const auto& [k, node] : root) {
    const std::string key(k.str());
    if (key == "name") {
      if (!node.is_string()) {
        errors.push_back(source + ": name: wrong type: expected a string");
      } else {
        plan.name = node.as_string()->get();
      }
    } else if (key == "fault") {
      parse_faults(source, node, lim, plan, errors);
    } else if (key == "command") {
      parse_commands(source, node, lim, plan, errors);
    } else if (key == "rates") {
      if (!node.is_table()) {
        errors.push_back(source + ": rates: must be a table ([rates])");
      } else {
        parse_rates(source, *node.as_table(), plan, errors);
      }
    } else {
      errors.push_back(cat({source, ": ", key, ": unknown key (allowed at the top: name, [[fault]], [[command]], [rates])"}));
    }
  }
  if (!errors.empty()) {
    r.error = join_lines(errors);
    return r;
  }
  r.plan = std::move(plan);
  return r;
}

FaultPlanResult load_fault_plan(const std::string& path, const trn::tasks::Deployment& dep, double max_time_s) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    FaultPlanResult r;
    r.error = path + ": cannot open fault plan file: " + std::strerror(errno);
    return r;
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    FaultPlanResult r;
    r.error = path + ": cannot read fault plan file";
    return r;
  }
  return parse_fault_plan(text.str(), path, dep.tiles(), max_time_s, dep);
}

namespace {
/** Jobs of the demonstration whose outputs two replicas corrupt (one every 100 ms from 33 s). */
constexpr std::uint32_t kDemoNoMajorityJobs = 8U;
}  // namespace

FaultPlan demo_fault_plan(const trn::tasks::Deployment& dep) {
  const DemoTiles tiles = demo_tiles(dep);
  const bsp::TileId kVisionCoordinator = tiles.vision_coordinator;
  const bsp::TileId kFilter = tiles.filter;
  const bsp::TileId kVisionA = tiles.vision_a;
  const bsp::TileId kVisionB = tiles.vision_b;
  FaultPlan p;
  p.name = "demo";
  // Flips on the senders of fault-tolerant traffic: each hits the next packet
  // the tile sends, which the receiver's code corrects. Word 5 is past the
  // header words, so the packet still reaches its destination to be corrected.
  struct Flip {
    double t_s;
    bsp::TileId tile;
    std::uint32_t bit;
  };
  const std::array<Flip, 8> flips = {{
      {5.0, kVisionCoordinator, 3U},
      {9.0, kFilter, 11U},
      {13.0, kVisionA, 19U},
      {17.0, kVisionB, 27U},
      {24.0, kVisionCoordinator, 7U},
      {28.0, kFilter, 15U},
      {32.0, kVisionA, 23U},
      {35.0, kVisionB, 30U},
  }};
  for (const Flip& f : flips) {
    FaultPlanItem it{};
    it.t_s = f.t_s;
    it.kind = bsp::FaultKind::kPacketBitFlip;
    it.tile = f.tile;
    it.offset = 5U;
    it.bit = f.bit;
    p.items.push_back(it);
  }
  FaultPlanItem sw{};
  sw.t_s = 20.0;
  sw.kind = bsp::FaultKind::kSwitchFail;
  sw.tile = tiles.failed_switch;
  p.items.push_back(sw);
  // Reliability raised by telecommand: the supervisors make the filter a TMR; one replica's output is corrupted (outvoted), another hangs
  // (excluded, reset by its watchdog, re-seeded with the voted state), then the voter hangs.
  p.commands.push_back(PlanCommand{10.0, "reliability_high", trn::tasks::kCmdReliabilityHigh});
  FaultPlanItem sdc{};
  sdc.t_s = 15.0;
  sdc.kind = bsp::FaultKind::kSdc;
  sdc.role = "filter_replica";
  sdc.instance = 1U;
  sdc.channel = trn::tasks::kNavChannel;
  sdc.bit = 70U;
  p.items.push_back(sdc);
  FaultPlanItem hang{};
  hang.t_s = 26.0;
  hang.kind = bsp::FaultKind::kCoreHang;
  hang.role = "filter_replica";
  hang.instance = 2U;
  p.items.push_back(hang);
  // The voter's own tile hangs: reset by its watchdog, it goes on voting from its place in DDR,
  // and no job's solution is lost.
  FaultPlanItem voter{};
  voter.t_s = 30.5;
  voter.kind = bsp::FaultKind::kCoreHang;
  voter.role = "filter";
  p.items.push_back(voter);
  // Then two replicas' outputs corrupted in the same job, every 100 ms: no majority. The filter
  // supervisor starts the TMR again from a fresh seed, then has no way left and escalates; the TRN
  // supervisor accepts the simplex filter for the rest of the descent (reported).
  for (std::uint32_t k = 0; k < kDemoNoMajorityJobs; ++k) {
    for (std::uint32_t replica = 0; replica < 2U; ++replica) {
      FaultPlanItem two{};
      two.t_s = 33.0 + 0.1 * static_cast<double>(k);
      two.kind = bsp::FaultKind::kSdc;
      two.role = "filter_replica";
      two.instance = replica;
      two.channel = trn::tasks::kNavChannel;
      two.bit = 70U + replica;
      p.items.push_back(two);
    }
  }
  return p;
}

double demo_fault_plan_end_s() {
  double end = 0.0;
  for (const FaultPlanItem& it : demo_fault_plan(trn::tasks::kTile64Deployment).items) {
    end = std::max(end, it.t_s);
  }
  return end;
}

namespace {

/** A planned fault that names a role: added to the injector when it is nearly due. */
struct RoleFault {
  bsp::FaultSpec spec;
  trn::tasks::Role role;
  std::uint32_t instance;
};

std::vector<RoleFault> g_role_faults;  // sorted by cycle; filled before the flight, read by the hook
std::size_t g_role_next = 0U;

/** The tile that runs @p role now (the supervisor's directory for the roles that move). */
bsp::TileId role_tile(trn::tasks::Role role, std::uint32_t instance) {
  using trn::tasks::Role;
  switch (role) {
    case Role::kVisionCoordinator: return trn::tasks::slot_tile_now(trn::tasks::kSlotCoordinator);
    case Role::kIo: return trn::tasks::slot_tile_now(trn::tasks::kSlotIo);
    case Role::kFilter: return trn::tasks::slot_tile_now(trn::tasks::kSlotFilter);
    case Role::kFilterReplica: return trn::tasks::slot_tile_now(trn::tasks::kSlotReplica0 + instance);
    case Role::kTrnSupervisor: return trn::tasks::slot_tile_now(trn::tasks::kSlotTrnSupervisor);
    case Role::kFilterSupervisor: return trn::tasks::slot_tile_now(trn::tasks::kSlotFilterSupervisor);
    case Role::kVisionSupervisor: return trn::tasks::slot_tile_now(trn::tasks::kSlotVisionSupervisor);
    case Role::kVision: {
      std::uint32_t seen = 0U;
      const trn::tasks::Deployment& dep = *trn::tasks::image_config().deployment;
      for (bsp::TileId t = 0; t < dep.tiles(); ++t) {
        if (trn::tasks::tile_role(dep, t) == Role::kVision && seen++ == instance) {
          return t;
        }
      }
      return bsp::kNoTile;
    }
    default: return bsp::kNoTile;
  }
}

/** Barrier hook: role faults due within two quanta get their tile now and go to the injector. */
void add_due_role_faults(bsp::Cycles barrier) noexcept {
  const bsp::Cycles horizon = barrier + 2U * bsp::board_config().quantum_cycles;
  for (; g_role_next < g_role_faults.size() && g_role_faults[g_role_next].spec.cycle <= horizon; ++g_role_next) {
    RoleFault& f = g_role_faults[g_role_next];
    f.spec.tile = role_tile(f.role, f.instance);
    (void)bsp::fault_plan_add(f.spec);  // a role no tile runs is refused (kBadTile): nothing to hit
  }
}

}  // namespace

bool arm_fault_plan(const FaultPlan& plan, double clock_hz, std::string& error) {
  g_role_faults.clear();
  g_role_next = 0U;
  if (!(std::isfinite(clock_hz) && clock_hz > 0.0)) {
    error = "fault plan " + plan.name + ": invalid clock frequency " + fmt(clock_hz);
    return false;
  }
  for (std::size_t i = 0; i < plan.items.size(); ++i) {
    const FaultPlanItem& it = plan.items[i];
    const std::string what = cat({"fault plan ", plan.name, ": fault #", std::to_string(i + 1U), " (",
                                  fault_kind_name(it.kind), " on tile ", std::to_string(it.tile), " at ", fmt(it.t_s),
                                  " s)"});
    if (!(std::isfinite(it.t_s) && it.t_s >= 0.0)) {
      error = what + ": invalid time";
      return false;
    }
    if (it.kind == bsp::FaultKind::kLinkFail && it.param >= bsp::kUdnDirs) {
      error = what + ": invalid link direction " + std::to_string(it.param) + " (allowed 0 .. 3)";
      return false;
    }
    bsp::FaultSpec s{};
    s.cycle = static_cast<bsp::Cycles>(std::llround(it.t_s * clock_hz));
    s.kind = it.kind;
    s.tile = it.tile;
    s.channel = it.channel;
    s.offset = it.offset;
    s.bit = it.bit;
    s.param = it.param;
    s.shift = it.shift;
    s.position = it.position;
    (void)std::snprintf(s.carve.data(), s.carve.size(), "%s", it.carve.c_str());
    if (!it.role.empty()) {
      const std::optional<trn::tasks::Role> r = role_from_name(it.role);
      if (!r) {
        error = what + ": unknown role " + it.role;
        return false;
      }
      g_role_faults.push_back(RoleFault{s, *r, it.instance});
      continue;
    }
    const bsp::FaultError e = bsp::fault_plan_add(s);
    if (e == bsp::FaultError::kBadTile) {
      error = what + ": the board has no such tile (tiles 0 .. " + std::to_string(bsp::tile_count() - 1U) + ")";
      return false;
    }
    if (e != bsp::FaultError::kOk) {
      error = what + (e == bsp::FaultError::kFull
                          ? ": the injector's plan is full (" + std::to_string(bsp::kFaultPlanCapacity) + " entries)"
                          : std::string(": refused by the injector"));
      return false;
    }
  }
  if (!g_role_faults.empty()) {
    std::stable_sort(g_role_faults.begin(), g_role_faults.end(),
                     [](const RoleFault& a, const RoleFault& b) { return a.spec.cycle < b.spec.cycle; });
    if (bsp::add_barrier_hook(&add_due_role_faults) != bsp::BoardError::kOk) {
      error = "fault plan " + plan.name + ": no barrier hook left for the faults that name a role";
      return false;
    }
  }
  for (const PlanCommand& c : plan.commands) {
    if (bsp::schedule_command(c.t_s, c.code, 0U) != bsp::DeviceBusError::kOk) {
      error = cat({"fault plan ", plan.name, ": [[command]] ", c.name, " at ", fmt(c.t_s),
                   " s: refused by the uplink (no devices attached)"});
      return false;
    }
  }
  for (std::size_t k = 0; k < kFaultKinds; ++k) {
    if (plan.rates[k] == 0.0) {
      continue;  // a zero rate draws nothing: a plan without rates leaves the injector's stream untouched
    }
    if (bsp::fault_set_rate(static_cast<bsp::FaultKind>(k), plan.rates[k]) != bsp::FaultError::kOk) {
      error = cat({"fault plan ", plan.name, ": [rates] ", kKindNames[k], ": ", fmt(plan.rates[k]),
                   " refused by the injector (allowed: a finite rate >= 0)"});
      return false;
    }
  }
  return true;
}

std::string format_fault_plan(const FaultPlan& plan) {
  std::string out = "# fault plan (docs/FAULT_PLANS.md)\nname = " + toml_string(plan.name) + "\n";
  for (const FaultPlanItem& it : plan.items) {
    out += "\n[[fault]]\nt_s = " + toml_float(it.t_s) + "\nkind = \"" + fault_kind_name(it.kind) + "\"\n";
    out += it.role.empty() ? "tile = " + std::to_string(it.tile) + "\n"
                           : "role = " + toml_string(it.role) + "\n" +
                                 (it.role == "vision" || it.role == "filter_replica"
                                      ? "instance = " + std::to_string(it.instance) + "\n"
                                      : "");
    switch (it.kind) {
      case bsp::FaultKind::kSdc:
        if (const trn::tasks::SdcPoint* p = trn::tasks::sdc_point_of_channel(it.channel); p != nullptr) {
          out += "point = " + toml_string(p->name) + "\n";
        } else if (it.channel != bsp::kAnyChannel) {
          out += "channel = " + std::to_string(it.channel) + "\n";
        }
        out += it.shift != 0.0 ? "shift = " + toml_float(it.shift) + "\n" : "";
        break;
      case bsp::FaultKind::kSeu:
        out += it.carve.empty() ? "" : "carve = " + toml_string(it.carve) + "\n";
        out += it.offset != bsp::kRandomOffset ? "offset = " + std::to_string(it.offset) + "\n" : "";
        out += it.position >= 0.0 ? "position = " + toml_float(it.position) + "\n" : "";
        break;
      case bsp::FaultKind::kPacketBitFlip:
        out += it.offset != bsp::kRandomOffset ? "word = " + std::to_string(it.offset) + "\n" : "";
        break;
      case bsp::FaultKind::kLinkFail:
        out += "direction = \"" + link_direction_name(it.param) + "\"\n";
        break;
      default:
        break;
    }
    const bool has_bit = it.kind == bsp::FaultKind::kSdc || it.kind == bsp::FaultKind::kSeu ||
                         it.kind == bsp::FaultKind::kPacketBitFlip;
    out += has_bit && it.bit != bsp::kRandomBit ? "bit = " + std::to_string(it.bit) + "\n" : "";
  }
  for (const PlanCommand& c : plan.commands) {
    out += "\n[[command]]\nt_s = " + toml_float(c.t_s) + "\nname = " + toml_string(c.name) + "\n";
  }
  std::string rates;
  for (std::size_t k = 0; k < kFaultKinds; ++k) {
    if (plan.rates[k] != 0.0) {
      rates += cat({kKindNames[k], " = ", toml_float(plan.rates[k]), "\n"});
    }
  }
  if (!rates.empty()) {
    out += "\n[rates]\n" + rates;
  }
  return out;
}

std::string describe_fault(const bsp::FaultRecord& r) {
  const bool applied = r.status == bsp::FaultStatus::kApplied;
  std::string s = fault_kind_name(r.spec.kind);
  switch (r.spec.kind) {
    case bsp::FaultKind::kSeu:
      if (applied) {
        std::array<char, 64> buf{};
        (void)std::snprintf(buf.data(), buf.size(), " RAM offset 0x%llx bit %u",
                            static_cast<unsigned long long>(r.offset), r.bit);
        s += buf.data();
      }
      if (r.spec.carve[0] != '\0') {
        s += " (in carve \"" + std::string(r.spec.carve.data()) + "\")";
      } else if (applied && r.carve != nullptr) {
        s += " (in \"" + std::string(r.carve) + "\")";
      }
      s += r.upset == bsp::UpsetModel::kHostCrash ? ": host state in control data, modelled as a crash of the tile"
           : r.crashed                              ? ": control data, modelled as a crash of the tile"
                                                    : "";
      break;
    case bsp::FaultKind::kSdc:
      if (const trn::tasks::SdcPoint* p = trn::tasks::sdc_point_of_channel(r.spec.channel); p != nullptr) {
        s += " at " + std::string(p->name) + " (channel " + std::to_string(r.spec.channel) + ")";
      } else {
        s += r.spec.channel == bsp::kAnyChannel ? " any channel" : " channel " + std::to_string(r.spec.channel);
      }
      if (r.spec.shift != 0.0) {
        s += cat({" shift ", fmt(r.spec.shift), ", lasting (", std::to_string(r.hits), " values changed)"});
      } else {
        s += applied ? " value bit " + std::to_string(r.bit) : "";
      }
      break;
    case bsp::FaultKind::kPacketBitFlip:
      s += applied ? " word " + std::to_string(r.offset) + " bit " + std::to_string(r.bit) + " of a packet sent"
                   : " of the next packet sent";
      break;
    case bsp::FaultKind::kLinkFail:
      s += " " + link_direction_name(r.spec.param) + " link";
      break;
    default:
      break;
  }
  s += r.random ? " (random)" : " (planned)";
  switch (r.status) {
    case bsp::FaultStatus::kScheduled:
      s += ": scheduled, not yet due";
      break;
    case bsp::FaultStatus::kArmed:
      s += ": armed, nothing to corrupt came by";
      break;
    case bsp::FaultStatus::kSkipped:
      s += ": skipped (could not apply on this tile)";
      break;
    case bsp::FaultStatus::kUnsupported:
      s += ": unsupported (no handler for this kind)";
      break;
    case bsp::FaultStatus::kApplied:
      break;
  }
  return s;
}

std::size_t log_injections(std::span<const bsp::FaultRecord> records, double clock_hz, EventLog& log) {
  std::size_t injected = 0U;
  for (const bsp::FaultRecord& r : records) {
    const bool applied = r.status == bsp::FaultStatus::kApplied;
    const bsp::Cycles at = applied ? r.applied_cycle : r.spec.cycle;
    const double t_s = static_cast<double>(at) / clock_hz;
    // A full log drops the line (counted by the log), never the count.
    (void)log.add(t_s, applied ? EventCategory::kInject : EventCategory::kInfo, r.spec.tile, describe_fault(r));
    injected += applied ? 1U : 0U;
  }
  return injected;
}

}  // namespace tools
