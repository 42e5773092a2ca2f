/**
 * @file landmark_product.cpp
 * @brief The ground's landmark table: written by the ground tool, checked and copied by the coordinator.
 */
#include "trn/tasks/vision/landmark_product.hpp"

#include "udn/crc32c.hpp"

#include <cstring>

namespace trn::tasks {

namespace {

/** The header's bytes before header_crc. */
std::uint32_t header_crc_of(const LandmarkProductHeader& h) noexcept {
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the header's bytes
  const auto* b = reinterpret_cast<const std::uint8_t*>(&h);
  return udn::crc32c_bytes(std::span<const std::uint8_t>(b, offsetof(LandmarkProductHeader, header_crc)));
}

bool same_params(const vision::SelectParams& a, const vision::SelectParams& b) noexcept {
  return a.patch_px == b.patch_px && a.cell_px == b.cell_px && a.stride_px == b.stride_px &&
         a.margin_px == b.margin_px && a.cell_inset_px == b.cell_inset_px &&
         a.min_separation_px == b.min_separation_px && a.min_corner == b.min_corner && a.min_stddev == b.min_stddev &&
         a.dense_cell_px == b.dense_cell_px && a.dense_cell_inset_px == b.dense_cell_inset_px;
}

bool same_layer(const LandmarkProductHeader& h, const ProductLayer& l) noexcept {
  return h.layer_width == l.width && h.layer_height == l.height && h.geo.m_per_px == l.geo.m_per_px &&
         h.geo.x0_m == l.geo.x0_m && h.geo.y0_m == l.geo.y0_m;
}

/** Every record's centre inside the layer (the records read one by one from the product's bytes). */
bool records_inside(std::span<const std::uint8_t> items, std::uint32_t n, const ProductLayer& l) noexcept {
  bool ok = true;
  for (std::uint32_t i = 0; i < n && ok; ++i) {
    vision::Landmark lm{};
    std::memcpy(&lm, items.data() + static_cast<std::size_t>(i) * sizeof lm, sizeof lm);
    ok = lm.col_px >= 0 && lm.col_px < l.width && lm.row_px >= 0 && lm.row_px < l.height;
  }
  return ok;
}

/** CRC work: two integer operations and half a memory word per byte (udn's slicing tables). */
void charge_crc(std::size_t bytes, bsp::Work& work) noexcept {
  work.int_ops += 2ULL * bytes;
  work.mem_words += bytes / 2U;
}

}  // namespace

bool landmark_product_write(const vision::LandmarkTable& table, const vision::SelectParams& params,
                            const ProductLayer& layer, std::span<std::uint8_t> out) noexcept {
  const std::uint32_t n = table.count <= vision::kMaxLandmarks ? table.count : vision::kMaxLandmarks;
  if (out.size() < landmark_product_bytes(n)) {
    return false;
  }
  LandmarkProductHeader h{};
  h.count = n;
  h.first_tight = table.first_tight < n ? table.first_tight : n;
  h.layer_width = layer.width;
  h.layer_height = layer.height;
  h.geo = layer.geo;
  h.params = params;
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): the records' bytes
  const auto* items = reinterpret_cast<const std::uint8_t*>(table.items);
  const std::size_t item_bytes = static_cast<std::size_t>(n) * sizeof(vision::Landmark);
  h.items_crc = udn::crc32c_bytes(std::span<const std::uint8_t>(items, item_bytes));
  h.header_crc = header_crc_of(h);
  std::memcpy(out.data(), &h, sizeof h);
  if (item_bytes > 0U) {
    std::memcpy(out.data() + sizeof h, items, item_bytes);
  }
  return true;
}

ProductCheck landmark_product_load(std::span<const std::uint8_t> bytes, const vision::SelectParams& params,
                                   const ProductLayer& layer, vision::LandmarkTable& table, bsp::Work& work) noexcept {
  if (bytes.size() < sizeof(LandmarkProductHeader)) {
    return ProductCheck::kTooShort;
  }
  LandmarkProductHeader h{};
  std::memcpy(&h, bytes.data(), sizeof h);
  charge_crc(sizeof h, work);
  if (h.magic != kLandmarkProductMagic || h.version != kLandmarkProductVersion || h.header_crc != header_crc_of(h)) {
    return ProductCheck::kBadHeader;
  }
  if (!same_params(h.params, params)) {
    return ProductCheck::kOtherSettings;
  }
  if (!same_layer(h, layer)) {
    return ProductCheck::kOtherMap;
  }
  if (h.count > vision::kMaxLandmarks || h.first_tight > h.count) {
    return ProductCheck::kBadRecords;
  }
  if (bytes.size() < landmark_product_bytes(h.count)) {
    return ProductCheck::kTooShort;
  }
  const std::size_t item_bytes = static_cast<std::size_t>(h.count) * sizeof(vision::Landmark);
  const std::span<const std::uint8_t> items = bytes.subspan(sizeof h, item_bytes);
  charge_crc(item_bytes, work);
  if (udn::crc32c_bytes(items) != h.items_crc) {
    return ProductCheck::kBadRecords;
  }
  // Checked in place (DDR), record by record; copied only once every one is inside the layer.
  if (!records_inside(items, h.count, layer)) {
    return ProductCheck::kBadRecords;
  }
  work.mem_words += item_bytes / 4U;
  work.int_ops += 4ULL * h.count;
  if (item_bytes > 0U) {
    std::memcpy(table.items, items.data(), item_bytes);
  }
  table.count = h.count;
  table.first_tight = h.first_tight;
  std::memset(table.keep, 0, sizeof table.keep);
  work.mem_words += item_bytes / 2U;  // read and written, 4-byte words
  return ProductCheck::kOk;
}

}  // namespace trn::tasks
