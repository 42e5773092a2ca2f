/**
 * @file landmark_product_test.cpp
 * @brief The ground's landmark table: written and read back whole, and refused, with its reason,
 *        when any part of it does not fit the coordinator's map and settings.
 */
#include "trn/tasks/vision/landmark_product.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "udn/crc32c.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

namespace {

using trn::tasks::ProductCheck;

struct Fixture {
  std::unique_ptr<trn::vision::LandmarkTable> table = std::make_unique<trn::vision::LandmarkTable>();
  trn::vision::SelectParams params = trn::tasks::coord_select_params();
  trn::tasks::ProductLayer layer{2656, 2656, trn::vision::MapGeometry{6.0, -7965.0, 7965.0}};
  std::vector<std::uint8_t> bytes;

  Fixture() {
    table->count = 300U;
    table->first_tight = 210U;  // the last 90 are the dense set
    for (std::uint32_t i = 0; i < table->count; ++i) {
      trn::vision::Landmark& lm = table->items[i];
      lm.col_px = static_cast<std::int32_t>(40U + 7U * i);
      lm.row_px = static_cast<std::int32_t>(50U + 5U * i);
      lm.p_m[0] = 1.5 * i;
      lm.p_m[1] = -2.25 * i;
      lm.p_m[2] = 100.0 + i;
      lm.corner = 5.0F + static_cast<float>(i);
      lm.stddev = 4.0F + static_cast<float>(i) * 0.5F;
    }
    bytes.resize(trn::tasks::landmark_product_bytes(table->count));
    EXPECT_TRUE(trn::tasks::landmark_product_write(*table, params, layer, bytes));
  }

  ProductCheck load(trn::vision::LandmarkTable& out) const {
    bsp::Work w{};
    return trn::tasks::landmark_product_load(bytes, params, layer, out, w);
  }
};

TEST(LandmarkProduct, WrittenAndReadBackWholeWithItsWorkCharged) {
  const Fixture f;
  auto out = std::make_unique<trn::vision::LandmarkTable>();
  bsp::Work w{};
  ASSERT_EQ(trn::tasks::landmark_product_load(f.bytes, f.params, f.layer, *out, w), ProductCheck::kOk);
  ASSERT_EQ(out->count, f.table->count);
  EXPECT_EQ(out->first_tight, 210U) << "the dense set comes with it";
  EXPECT_EQ(std::memcmp(out->items, f.table->items, f.table->count * sizeof(trn::vision::Landmark)), 0);
  EXPECT_GT(w.int_ops, 2U * f.table->count * sizeof(trn::vision::Landmark)) << "the CRCs are charged";
  EXPECT_GT(w.mem_words, f.table->count * sizeof(trn::vision::Landmark) / 4U) << "and the copy";
  std::vector<std::uint8_t> small(f.bytes.size() - 1U);
  EXPECT_FALSE(trn::tasks::landmark_product_write(*f.table, f.params, f.layer, small));
}

TEST(LandmarkProduct, EveryMisfitIsRefusedWithItsReasonAndTheTableUntouched) {
  auto out = std::make_unique<trn::vision::LandmarkTable>();
  out->count = 7U;
  {
    Fixture f;
    f.bytes.resize(f.bytes.size() - 1U);
    EXPECT_EQ(f.load(*out), ProductCheck::kTooShort);
    f.bytes.resize(10U);
    EXPECT_EQ(f.load(*out), ProductCheck::kTooShort);
  }
  {
    Fixture f;
    f.bytes[0] ^= 1U;  // magic
    EXPECT_EQ(f.load(*out), ProductCheck::kBadHeader);
  }
  {
    Fixture f;
    f.bytes[offsetof(trn::tasks::LandmarkProductHeader, count)] ^= 1U;  // a header field under its CRC
    EXPECT_EQ(f.load(*out), ProductCheck::kBadHeader);
  }
  {
    Fixture f;
    f.params.cell_px = 28;
    EXPECT_EQ(f.load(*out), ProductCheck::kOtherSettings);
  }
  {
    Fixture f;
    f.params.dense_cell_px = 0;  // one set here, two on the ground
    EXPECT_EQ(f.load(*out), ProductCheck::kOtherSettings);
  }
  {
    Fixture f;  // a dense set starting past the records, under a valid header CRC
    trn::tasks::LandmarkProductHeader h{};
    std::memcpy(&h, f.bytes.data(), sizeof h);
    h.first_tight = h.count + 1U;
    // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the header's bytes
    const auto* b = reinterpret_cast<const std::uint8_t*>(&h);
    h.header_crc = udn::crc32c_bytes(std::span<const std::uint8_t>(b, offsetof(trn::tasks::LandmarkProductHeader, header_crc)));
    std::memcpy(f.bytes.data(), &h, sizeof h);
    EXPECT_EQ(f.load(*out), ProductCheck::kBadRecords);
  }
  {
    Fixture f;
    f.layer.geo.m_per_px = 4.0;
    EXPECT_EQ(f.load(*out), ProductCheck::kOtherMap);
    f.layer = trn::tasks::ProductLayer{2656, 2600, trn::vision::MapGeometry{6.0, -7965.0, 7965.0}};
    EXPECT_EQ(f.load(*out), ProductCheck::kOtherMap);
  }
  {
    Fixture f;
    f.bytes[sizeof(trn::tasks::LandmarkProductHeader) + 123U * sizeof(trn::vision::Landmark) + 17U] ^= 0x40U;
    EXPECT_EQ(f.load(*out), ProductCheck::kBadRecords);
  }
  {
    Fixture f;  // a landmark outside the layer, written with a valid CRC: the range check refuses it
    f.table->items[12].col_px = 5000;
    ASSERT_TRUE(trn::tasks::landmark_product_write(*f.table, f.params, f.layer, f.bytes));
    EXPECT_EQ(f.load(*out), ProductCheck::kBadRecords);
  }
  EXPECT_EQ(out->count, 7U) << "a refused product leaves the table as it was";
}

}  // namespace
