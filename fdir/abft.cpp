/**
 * @file abft.cpp
 * @brief Events of the checked products (see abft.hpp).
 */
#include "fdir/abft.hpp"

#include "fdir/event_log.hpp"

namespace fdir {

void abft_report(const AbftSite& site, const AbftResult& r) noexcept {
  const auto pos = [](int v) noexcept { return v < 0 ? 0xFFFFU : static_cast<std::uint32_t>(v) & 0xFFFFU; };
  const std::uint32_t where = (pos(r.row) << 16U) | (site.rows_only ? kAbftColNotChecked : pos(r.col));
  const std::uint32_t bad = (r.bad_rows << 16U) | (r.bad_cols & 0xFFFFU);
  report(r.verdict == AbftVerdict::kFailed ? EventId::kAbftFailed : EventId::kAbftCorrected, site.id, where, bad,
         r.recomputes);
}

}  // namespace fdir
