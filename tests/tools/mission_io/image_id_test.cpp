/**
 * @file image_id_test.cpp
 * @brief A mission image's identity is its ELF build ID: a copy with another modification time is
 *        the same build; a file without one is known by its size and time; a missing file by nothing.
 */
#include "tools/common/mission/image_id.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

class ImageId : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("image_id_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ImageId, ACopyOfTheImageIsTheSameBuildAndAnotherFileIsNot) {
  const std::string own = tools::own_image_identity();
  ASSERT_EQ(own.rfind("gnu-", 0), 0U) << own << ": the test binary carries a GNU build ID";
  EXPECT_EQ(own.size(), 4U + 40U) << "a 20-byte SHA-1 build ID in hex";
  const fs::path copy = dir_ / "copy";
  fs::copy_file(fs::read_symlink("/proc/self/exe"), copy);
  fs::last_write_time(copy, fs::file_time_type::clock::now() - std::chrono::hours(24));
  EXPECT_EQ(tools::image_identity(copy.string()), own) << "another path and time, the same build";

  const fs::path text = dir_ / "not_elf";
  std::ofstream(text) << "no ELF here\n";
  const std::string id = tools::image_identity(text.string());
  EXPECT_EQ(id.rfind("12@", 0), 0U) << id << ": size and time when there is no build ID";
  EXPECT_EQ(tools::image_identity((dir_ / "missing").string()), "");
}

}  // namespace
