/**
 * @file fault_plan_fuzz.cpp
 * @brief libFuzzer target for the fault-plan file parser (tools::parse_fault_plan).
 *
 * The input is the file's text. Properties: a plan and no error, or no plan
 * and an error naming the source; every fault and command of an accepted plan
 * is within the limits given (tiles below the tile count, times within the
 * run), rates within 0 .. kMaxFaultRate; and a plan survives its own
 * formatting: format -> parse gives a plan that formats to the same text.
 */
#include "tests/fuzz/fuzz_check.hpp"
#include "tools/common/mission/fault_plan.hpp"

#include <cmath>
#include <string>
#include <string_view>

namespace {

constexpr std::uint32_t kTiles = 64U;
constexpr double kDurationS = 120.0;

void check_limits(const tools::FaultPlan& p) {
  for (const tools::FaultPlanItem& it : p.items) {
    fuzz::require(std::isfinite(it.t_s) && it.t_s >= 0.0 && it.t_s <= kDurationS, "fault time within the run");
    fuzz::require(!it.role.empty() || it.tile < kTiles, "fault tile below the tile count");
    fuzz::require(it.kind < bsp::FaultKind::kCount, "known fault kind");
    fuzz::require(std::isfinite(it.shift), "finite shift");
  }
  for (const tools::PlanCommand& c : p.commands) {
    fuzz::require(std::isfinite(c.t_s) && c.t_s >= 0.0 && c.t_s <= kDurationS, "command time within the run");
  }
  for (const double r : p.rates) {
    fuzz::require(std::isfinite(r) && r >= 0.0 && r <= tools::kMaxFaultRate, "rate within 0 .. kMaxFaultRate");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.toml";
  const tools::FaultPlanResult r = tools::parse_fault_plan(text, source, kTiles, kDurationS);
  fuzz::require(r.ok() == r.error.empty(), "a plan xor an error");
  if (!r.ok()) {
    fuzz::require(r.error.rfind(source, 0) == 0, "the error names the source");
    return 0;
  }
  check_limits(*r.plan);
  const std::string formatted = tools::format_fault_plan(*r.plan);
  const tools::FaultPlanResult again = tools::parse_fault_plan(formatted, "<formatted>", kTiles, kDurationS);
  if (!again.ok()) {
    std::fprintf(stderr, "formatted plan refused: %s\n%s\n", again.error.c_str(), formatted.c_str());
  }
  fuzz::require(again.ok(), "a formatted plan parses");
  check_limits(*again.plan);
  fuzz::require(tools::format_fault_plan(*again.plan) == formatted, "format -> parse -> format is the same text");
  return 0;
}
