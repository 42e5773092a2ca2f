/**
 * @file vision_shared.cpp
 * @brief The DDR lookups and the band relight the coordinator and the vision tiles share.
 */
#include "trn/tasks/vision/vision_shared.hpp"
#include "trn/events.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "bsp_tile64/api/work.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"

#include <cstring>
#include <span>

namespace trn::tasks {

void band_rows(std::int32_t height, std::uint32_t i, std::uint32_t n, std::int32_t& row0, std::int32_t& rows) noexcept {
  const std::int32_t per = (height + static_cast<std::int32_t>(n) - 1) / static_cast<std::int32_t>(n);
  row0 = per * static_cast<std::int32_t>(i);
  rows = row0 >= height ? 0 : (height - row0 < per ? height - row0 : per);
}

bool relight_band(const vision::MapView& map, const double sun_m[3], vision::ImageU8 relit, std::int32_t row0,
                  std::int32_t rows) noexcept {
  if (rows <= 0) {
    return true;
  }
  const std::int32_t end = row0 + rows;
  for (std::int32_t r = row0; r < end; r += kRelightStepRows) {  // at most rows / kRelightStepRows + 1 steps
    const std::int32_t n = end - r < kRelightStepRows ? end - r : kRelightStepRows;
    bsp::Work work{};
    const vision::ImageU8 step = relit.sub(0, r, relit.width, n);
    const bool ok = step.valid() && vision::relight_region(map, 0, r, sun_m, step, work) == vision::Status::kOk;
    bsp::consume(work);
    k::checkin();
    if (!ok) {
      return false;
    }
  }
  return true;
}

const std::uint8_t* ddr_at(std::uint64_t offset, std::uint64_t bytes) noexcept {
  const std::span<std::byte> ddr = bsp::region_span(bsp::Region{bsp::Region::kDdr});
  if (offset > ddr.size() || bytes > ddr.size() - offset) {
    return nullptr;
  }
  return reinterpret_cast<const std::uint8_t*>(ddr.data() + offset);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): DDR bytes
}

const std::uint8_t* ddr_find_sized(const char* what, std::size_t& bytes) noexcept {
  const bsp::Region ddr{bsp::Region::kDdr};
  bytes = 0U;
  for (const bsp::CarveRecord& r : bsp::region_carves(ddr)) {
    if (r.what != nullptr && std::strcmp(r.what, what) == 0) {
      bytes = static_cast<std::size_t>(r.bytes);
      return reinterpret_cast<const std::uint8_t*>(bsp::region_span(ddr).data() + r.offset);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
    }
  }
  return nullptr;
}

const std::uint8_t* ddr_find(const char* what) noexcept {
  std::size_t bytes = 0U;
  return ddr_find_sized(what, bytes);
}

std::uint8_t* ddr_carve_named(const char* what, std::size_t bytes, std::size_t align) noexcept {
  const bsp::Region ddr{bsp::Region::kDdr};
  for (const bsp::CarveRecord& r : bsp::region_carves(ddr)) {
    if (r.what != nullptr && std::strcmp(r.what, what) == 0) {
      return r.bytes == bytes ? reinterpret_cast<std::uint8_t*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
                                    bsp::region_span(ddr).data() + r.offset)
                              : nullptr;
    }
  }
  const bsp::Carve c = bsp::carve(ddr, bytes, align, what);
  return c.error == bsp::MemError::kOk ? reinterpret_cast<std::uint8_t*>(c.ptr)  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
                                       : nullptr;
}

CoarseBandSlot* coarse_band_slot(std::uint32_t index) noexcept {
  auto* slots = reinterpret_cast<CoarseBandSlots*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      const_cast<std::uint8_t*>(ddr_find(kCoarseBandCarveName)));  // NOLINT(cppcoreguidelines-pro-type-const-cast): shared DDR slots
  return slots == nullptr || index > kCoordinatorBandSlot ? nullptr : &slots->slot[index];
}

std::int32_t coarse_band_rows_max(const vision::CoarsePrepared& prep) noexcept {
  const std::int32_t sw = prep.surface_w;
  const std::int32_t ww = prep.window.width;
  const std::int32_t th = prep.tmpl.height;
  if (sw < 1 || ww < 1 || th < 1) {
    return 0;
  }
  // A band of r rows needs (ww + 1) (r + th) integral entries and sw r surface values.
  const std::int64_t by_integral = kCoarseBandEntries / (ww + 1) - th;
  const std::int64_t by_surface = kCoarseBandValues / sw;
  const std::int64_t r = by_integral < by_surface ? by_integral : by_surface;
  return r < 1 ? 0 : static_cast<std::int32_t>(r < kCoarseBandMaxRows ? r : kCoarseBandMaxRows);
}

const vision::LandmarkTable* landmark_table_find() noexcept {
  return reinterpret_cast<const vision::LandmarkTable*>(ddr_find(kLandmarkCarveName));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
}

void report_correlation_checks(bool failed, std::uint32_t recomputes, vision::CorrelationCheck first,
                               std::uint16_t landmark, std::uint32_t frame) noexcept {
  if (!failed && recomputes == 0U) {
    return;
  }
  trn::report(failed ? ev::kCorrelationFailed : ev::kCorrelationCorrected, landmark,
               static_cast<std::uint32_t>(first), frame, recomputes);
}

}  // namespace trn::tasks
