/**
 * @file main.cpp
 * @brief GoogleTest entry point shared by every test binary.
 *
 * Adds a listener that fails any test which leaves the heap sealed, so one
 * test's seal cannot leak into the next and hide or invent allocations.
 */
#include "bsp_tile64/emu/host/heap_guard.hpp"

#include <gtest/gtest.h>

namespace {

class HeapSealListener : public ::testing::EmptyTestEventListener {
 public:
  void OnTestEnd(const ::testing::TestInfo& info) override {
    if (bsp::heap::is_sealed()) {
      bsp::heap::unseal();
      ADD_FAILURE() << info.test_suite_name() << "." << info.name() << " left the heap sealed";
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  ::testing::UnitTest::GetInstance()->listeners().Append(new HeapSealListener);  // owned by gtest
  return RUN_ALL_TESTS();
}
