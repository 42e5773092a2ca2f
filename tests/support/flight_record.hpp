/**
 * @file flight_record.hpp
 * @brief Tests read a task's counters as the host does: its declared record, out of its tile's RAM.
 */
#pragma once

#include "bsp_tile64/api/memory.hpp"
#include "tools/common/mission/ram_record.hpp"

#include <gtest/gtest.h>

#include <string>

namespace test_support {

/** Record @p rec of @p tile as the flight left it (tools::read_record); a test failure and T{} when it is not there. */
template <class T>
T flight_record(bsp::TileId tile, const bsp::RamRecord<T>& rec) {
  T out{};
  std::string error;
  EXPECT_TRUE(tools::read_record(tile, rec, out, error)) << error;
  return out;
}

}  // namespace test_support
