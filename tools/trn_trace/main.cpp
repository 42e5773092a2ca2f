/**
 * @file main.cpp
 * @brief trn_trace: reads trace dumps (trn_mission --trace-dump FILE), prints them and names the first
 *        event where two runs part: the question behind every "same seed, different hash".
 *
 *   trn_trace print FILE [--from I] [--count N]   events as text, one a line
 *   trn_trace hash FILE                           events and the trace hash they fold to
 *   trn_trace diff A B [--context N]              the first differing event (time, tile, kind, values),
 *                                                 with N events before it and after it on each side
 * Exit status: 0 (diff: the same events), 1 (diff: they differ), 2 (bad input).
 */
#include "bsp_tile64/emu/profile.hpp"
#include "tools/common/cli_checks.hpp"
#include "tools/common/mission/run_folder.hpp"
#include "tools/common/mission/trace_dump.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>

namespace {

/** The chip the dumps were flown on (--chip), to show times in seconds too. */
const bsp::ChipProfile* g_chip = &bsp::kTile64;

double clock_hz() { return static_cast<double>(g_chip->clock_hz); }

std::optional<tools::TraceDump> load(const std::string& path) {
  std::string error;
  std::optional<tools::TraceDump> d = tools::read_trace_dump(path, error);
  if (!d.has_value()) {
    std::fprintf(stderr, "trn_trace: %s\n", error.c_str());
  }
  return d;
}

void print_range(const char* prefix, const tools::TraceDump& d, std::size_t from, std::size_t to) {
  for (std::size_t i = from; i < to && i < d.events.size(); ++i) {
    std::printf("%s%s\n", prefix, tools::format_trace_event(i, d.events[i], clock_hz()).c_str());
  }
}

int print_cmd(const std::string& path, std::size_t from, std::size_t count) {
  const std::optional<tools::TraceDump> d = load(path);
  if (!d.has_value()) {
    return 2;
  }
  print_range("", *d, from, count == 0U ? d->events.size() : from + count);
  return 0;
}

int hash_cmd(const std::string& path) {
  const std::optional<tools::TraceDump> d = load(path);
  if (!d.has_value()) {
    return 2;
  }
  std::printf("%s: %zu events, trace hash %s\n", path.c_str(), d->events.size(),
              tools::trace_hash_hex(d->hash).c_str());
  return 0;
}

int diff_cmd(const std::string& pa, const std::string& pb, std::size_t context) {
  const std::optional<tools::TraceDump> a = load(pa);
  const std::optional<tools::TraceDump> b = load(pb);
  if (!a.has_value() || !b.has_value()) {
    return 2;
  }
  std::printf("a: %s: %zu events, trace hash %s\n", pa.c_str(), a->events.size(),
              tools::trace_hash_hex(a->hash).c_str());
  std::printf("b: %s: %zu events, trace hash %s\n", pb.c_str(), b->events.size(),
              tools::trace_hash_hex(b->hash).c_str());
  const std::optional<std::size_t> at = tools::first_difference(a->events, b->events);
  if (!at.has_value()) {
    std::printf("the same %zu events\n", a->events.size());
    return 0;
  }
  const std::size_t i = *at;
  if (i == a->events.size() || i == b->events.size()) {
    std::printf("the same first %zu events; %s ends there\n", i, i == a->events.size() ? "a" : "b");
  } else {
    std::printf("first difference at event #%zu (the %zu before it are the same)\n", i, i);
  }
  std::printf("before it (both):\n");
  print_range("    ", *a, i - std::min(i, context), i);
  std::printf("from it:\n");
  print_range("  a ", *a, i, i + context + 1U);
  print_range("  b ", *b, i, i + context + 1U);
  return 1;
}

int run(int argc, char** argv) {
  CLI::App app{"trn_trace: print trace dumps and find where two runs first differ"};
  app.require_subcommand(1);
  std::string file;
  std::size_t from = 0U;
  std::size_t count = 0U;
  std::string chip = "tile64";
  app.add_option("--chip", chip, "Chip the dumps were flown on, for their times in seconds (default tile64)")
      ->check(CLI::IsMember({"tile64", "maestro"}));
  CLI::App* pr = app.add_subcommand("print", "Print a dump's events, one a line");
  pr->add_option("file", file, "Trace dump (trn_mission --trace-dump)")->required();
  pr->add_option("--from", from, "First event index (default 0)")->check(tools::kWholeNumber);
  pr->add_option("--count", count, "Events to print (default: all)")->check(tools::kWholeNumber);
  CLI::App* hs = app.add_subcommand("hash", "Count a dump's events and fold them into the trace hash");
  hs->add_option("file", file, "Trace dump")->required();
  std::string a;
  std::string b;
  std::size_t context = 5U;
  CLI::App* df = app.add_subcommand("diff", "Name the first event where two dumps differ");
  df->add_option("a", a, "First trace dump")->required();
  df->add_option("b", b, "Second trace dump")->required();
  df->add_option("--context", context, "Events shown before and after the difference (default 5)")
      ->check(tools::kWholeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  g_chip = bsp::find_profile(chip);
  if (pr->parsed()) {
    return print_cmd(file, from, count);
  }
  if (hs->parsed()) {
    return hash_cmd(file);
  }
  return diff_cmd(a, b, context);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "trn_trace: %s\n", e.what());
    return 2;
  }
}
