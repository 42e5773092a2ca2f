/**
 * @file scenario_fuzz.cpp
 * @brief libFuzzer target for the scenario file parser (tools::parse_scenario).
 *
 * The input is the file's text. Properties: the parser returns either a
 * scenario and no error, or no scenario and an error that names the source;
 * parsing the same text twice gives the same answer; a scenario it accepts
 * has its phases in time order within the documented ranges. Exceptions may
 * not escape it.
 */
#include "tests/fuzz/fuzz_check.hpp"
#include "tools/common/mission/scenario.hpp"

#include <cmath>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.toml";
  const tools::ScenarioResult r = tools::parse_scenario(text, source);
  fuzz::require(r.ok() == r.error.empty(), "a scenario xor an error");
  if (!r.ok()) {
    fuzz::require(r.error.rfind(source, 0) == 0, "the error names the source");
    const tools::ScenarioResult again = tools::parse_scenario(text, source);
    fuzz::require(!again.ok() && again.error == r.error, "deterministic error");
    return 0;
  }
  const tools::Scenario& s = *r.scenario;
  fuzz::require(!s.phases.empty() && s.phases.size() <= tools::kMaxScenarioPhases, "1 .. kMaxScenarioPhases phases");
  fuzz::require(s.phases[0].start_s == 0.0, "the first phase at 0 s");
  for (std::size_t i = 0; i < s.phases.size(); ++i) {
    fuzz::require(std::isfinite(s.phases[i].start_s) && s.phases[i].start_s >= 0.0, "phase start finite, >= 0");
    fuzz::require(i == 0 || s.phases[i - 1].start_s < s.phases[i].start_s, "phases in time order");
    fuzz::require(s.phases[i].reliability <= 1U && s.phases[i].power <= 1U, "policies 0 or 1");
  }
  const tools::ScenarioResult again = tools::parse_scenario(text, source);
  fuzz::require(again.ok() && again.scenario->seed == s.seed && again.scenario->name == s.name &&
                    again.scenario->phases.size() == s.phases.size(),
                "deterministic scenario");
  return 0;
}
