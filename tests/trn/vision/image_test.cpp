/**
 * @file image_test.cpp
 * @brief Image views address the right pixels, sub-views refuse rectangles outside, and
 *        fixed images resize only within their capacity.
 */
#include "trn/vision/image.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace {

namespace tv = trn::vision;

TEST(Image, ViewAndSubViewAddressThePixelsOfAStridedBuffer) {
  static std::uint8_t buf[10 * 6];
  for (int i = 0; i < 60; ++i) buf[i] = static_cast<std::uint8_t>(i);
  const tv::ConstImageU8 v{buf, 8, 6, 10};  // 8 used columns of 10
  ASSERT_TRUE(v.valid());
  EXPECT_EQ(v.at(3, 2), 23);
  const tv::ConstImageU8 s = v.sub(2, 1, 4, 3);
  ASSERT_TRUE(s.valid());
  EXPECT_EQ(s.stride, 10);
  EXPECT_EQ(s.at(0, 0), 12);
  EXPECT_EQ(s.at(3, 2), 35);
  EXPECT_TRUE(v.contains(7, 5));
  EXPECT_FALSE(v.contains(8, 0));
  EXPECT_FALSE(v.contains(-1, 0));
}

TEST(Image, SubViewOutsideTheImageIsInvalid) {
  static std::uint8_t buf[8 * 8];
  const tv::ConstImageU8 v{buf, 8, 8, 8};
  EXPECT_FALSE(v.sub(5, 0, 4, 1).valid());
  EXPECT_FALSE(v.sub(0, 7, 1, 2).valid());
  EXPECT_FALSE(v.sub(-1, 0, 2, 2).valid());
  EXPECT_FALSE(v.sub(0, 0, 0, 2).valid());
  EXPECT_TRUE(v.sub(4, 4, 4, 4).valid());
  EXPECT_FALSE(tv::ConstImageU8{}.valid());
}

TEST(Image, FixedImageResizesWithinCapacityOnly) {
  static tv::FixedImage<float, 16, 8> img;
  EXPECT_FALSE(img.cview().valid());  // before the first resize
  EXPECT_TRUE(img.resize(16, 8));
  EXPECT_FALSE(img.resize(17, 8));
  EXPECT_FALSE(img.resize(4, 0));
  EXPECT_EQ(img.width(), 16);
  ASSERT_TRUE(img.resize(5, 3));
  const tv::ImageF32 v = img.view();
  EXPECT_EQ(v.width, 5);
  EXPECT_EQ(v.height, 3);
  EXPECT_EQ(v.stride, 16);
  v.at(4, 2) = 2.5F;
  EXPECT_EQ(img.cview().at(4, 2), 2.5F);
}

}  // namespace
