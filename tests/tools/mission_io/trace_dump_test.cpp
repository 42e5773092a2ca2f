/**
 * @file trace_dump_test.cpp
 * @brief Trace dumps: every recorded event is written and read back, folds to the board's hash, costs no
 *        allocation while recording; the first difference of two traces is found; kinds have names.
 */
#include "tools/common/mission/trace_dump.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/emu/trace.hpp"
#include "bsp_tile64/emu/udn_net.hpp"
#include "fdir/event_ids.hpp"
#include "kernel/sched.hpp"
#include "tests/support/heap_probe.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;

fs::path temp_file(const char* name) {
  return fs::temp_directory_path() / (std::string(name) + "_" + std::to_string(::getpid()) + ".trace");
}

/** More events than the writer buffers, so the dump is written in several pieces. */
constexpr std::uint64_t kEvents = 10000U;

TEST(TraceDump, EveryEventIsWrittenAndFoldsToTheBoardsHash) {
  const fs::path p = temp_file("trace_dump_roundtrip");
  bsp::trace_reset();
  tools::TraceDumpWriter w;
  std::string error;
  ASSERT_TRUE(w.open(p.string(), error)) << error;
  const std::uint64_t allocs = test_support::count_allocs([] {
    for (std::uint64_t i = 0; i < kEvents; ++i) {
      bsp::trace_record(i * 7U, static_cast<bsp::TileId>(i % 64U), static_cast<std::uint16_t>(0x1000U + i % 9U),
                        i * i, ~i);
    }
  });
  EXPECT_EQ(allocs, 0U) << "recording into a dump allocates nothing (the heap is sealed in flight)";
  ASSERT_TRUE(w.close(error)) << error;
  EXPECT_EQ(w.events(), kEvents);
  const std::optional<tools::TraceDump> d = tools::read_trace_dump(p.string(), error);
  ASSERT_TRUE(d.has_value()) << error;
  ASSERT_EQ(d->events.size(), kEvents);
  EXPECT_EQ(d->hash, bsp::trace_hash());
  EXPECT_EQ(d->events[9999].time, 9999U * 7U);
  EXPECT_EQ(d->events[9999].tile, 9999U % 64U);
  EXPECT_EQ(d->events[9999].a, 9999U * 9999U);
  EXPECT_EQ(d->events[9999].b, ~std::uint64_t{9999U});
  // After close the sink is gone: later events do not reach the file.
  bsp::trace_record(1U, 0U, 1U, 0U, 0U);
  EXPECT_EQ(tools::read_trace_dump(p.string(), error)->events.size(), kEvents);
  fs::remove(p);
}

TEST(TraceDump, ATruncatedOrForeignFileIsAnError) {
  const fs::path p = temp_file("trace_dump_bad");
  std::string error;
  {
    std::ofstream(p) << "not a trace";
  }
  EXPECT_FALSE(tools::read_trace_dump(p.string(), error).has_value());
  EXPECT_NE(error.find("not a trace dump"), std::string::npos) << error;
  tools::TraceDumpWriter w;
  ASSERT_TRUE(w.open(p.string(), error)) << error;
  bsp::trace_record(5U, 1U, 2U, 3U, 4U);
  ASSERT_TRUE(w.close(error)) << error;
  fs::resize_file(p, fs::file_size(p) - 1U);
  EXPECT_FALSE(tools::read_trace_dump(p.string(), error).has_value());
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
  EXPECT_FALSE(tools::read_trace_dump("/nonexistent/x.trace", error).has_value());
  fs::remove(p);
}

TEST(TraceDump, FirstDifferenceNamesTheFirstEventThatDiffersInAnyField) {
  const std::vector<bsp::TraceEvent> base{{1U, 0U, 1U, 2U, 3U}, {2U, 1U, 1U, 2U, 3U}, {3U, 2U, 1U, 2U, 3U}};
  EXPECT_FALSE(tools::first_difference(base, base).has_value());
  for (int field = 0; field < 5; ++field) {
    std::vector<bsp::TraceEvent> other = base;
    bsp::TraceEvent& e = other[1];
    e.time += field == 0 ? 1U : 0U;
    e.tile += field == 1 ? 1U : 0U;
    e.kind = static_cast<std::uint16_t>(e.kind + (field == 2 ? 1U : 0U));
    e.a += field == 3 ? 1U : 0U;
    e.b += field == 4 ? 1U : 0U;
    EXPECT_EQ(tools::first_difference(base, other), std::optional<std::size_t>{1U}) << "field " << field;
  }
  const std::vector<bsp::TraceEvent> shorter(base.begin(), base.begin() + 2);
  EXPECT_EQ(tools::first_difference(base, shorter), std::optional<std::size_t>{2U});
  EXPECT_EQ(tools::first_difference(shorter, base), std::optional<std::size_t>{2U});
  EXPECT_EQ(tools::fold_trace({}), bsp::trace_initial_hash());
}

TEST(TraceDump, KindsAreNamedWithTheirLayer) {
  EXPECT_EQ(tools::trace_kind_name(static_cast<std::uint16_t>(bsp::BoardEvent::kInit)), "board.init");
  EXPECT_EQ(tools::trace_kind_name(static_cast<std::uint16_t>(bsp::UdnTrace::kBitFlip)), "board.udn_bit_flip");
  EXPECT_EQ(tools::trace_kind_name(static_cast<std::uint16_t>(k::TraceKind::kSwitch)), "kernel.switch");
  EXPECT_EQ(tools::trace_kind_name(static_cast<std::uint16_t>(
                bsp::kTraceFdirBase + (static_cast<std::uint16_t>(trn::ev::kFrameDone) & 0x0FFFU))),
            "fdir.frame_done");
  EXPECT_EQ(tools::trace_kind_name(0x4003U), "trn.0x4003");
  const std::string line = tools::format_trace_event(7U, bsp::TraceEvent{700U, 3U, 0x1001U, 4U, 5U}, 700e6);
  EXPECT_NE(line.find("#7"), std::string::npos) << line;
  EXPECT_NE(line.find("tile 3"), std::string::npos) << line;
  EXPECT_NE(line.find("kernel.switch"), std::string::npos) << line;
}

}  // namespace
