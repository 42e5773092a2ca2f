/**
 * @file vision_worker.cpp
 * @brief A vision tile: runs the work units of the coordinator, answers with matches.
 */
#include "trn/tasks/vision_worker.hpp"

#include "bsp_tile64/devices/map_product.hpp"
#include "bsp_tile64/memory.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "trn/match.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/vision_shared.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <new>

namespace trn::tasks {
namespace {

/** Idle poll period of a vision tile: units come once a frame, and each idle wake costs two context switches. */
constexpr k::Ticks kWorkerIdleTicks = 4;

std::array<VisionWorkerStats, bsp::kMaxTiles> g_worker_stats{};

struct WorkerState {
  const VisionWorkerConfig* cfg;
  vision::MapView fine;
  vision::MapView coarse;
  vision::LandmarkWorkspace* ws;
  std::array<std::uint32_t, kResultHeaderWords + kMaxLandmarksPerUnit * kMatchWords> out;
};

bool worker_set_up(WorkerState& st) noexcept {
  const bsp::MapProductHeader* product = bsp::map_product_find();
  if (product == nullptr || vision::map_view(product, bsp::kMapLayerFine, st.fine) != vision::Status::kOk) {
    return false;
  }
  if (vision::map_view(product, bsp::kMapLayerCoarse, st.coarse) != vision::Status::kOk) {
    return false;
  }
  for (std::size_t i = 0; i < 3U; ++i) {
    st.fine.descent_sun_m[i] = st.cfg->descent_sun_m[i];
    st.coarse.descent_sun_m[i] = st.cfg->descent_sun_m[i];
  }
  bsp::MemError err = bsp::MemError::kOk;
  st.ws = bsp::carve_array<vision::LandmarkWorkspace>(bsp::Region{bsp::current_tile()}, 1, "vision_ws", &err);
  if (err != bsp::MemError::kOk) {
    return false;
  }
  ::new (st.ws) vision::LandmarkWorkspace{};
  return true;
}

/** A landmark's checked correlations that found a wrong surface, as events (this tile computed them). */
void report_checks(const vision::LandmarkDiag& d, std::uint16_t landmark, std::uint32_t frame) noexcept {
  if (!d.check_failed && d.recomputes == 0U) {
    return;
  }
  fdir::report(d.check_failed ? fdir::EventId::kCorrelationFailed : fdir::EventId::kCorrelationCorrected, landmark,
               static_cast<std::uint32_t>(d.first_check), frame, d.recomputes);
}

/** Matches the landmarks of unit @p m; returns the result's length in words (0: bad unit). */
std::uint32_t run_unit(WorkerState& st, VisionWorkerStats& stats, const udn::FtMessage& m) noexcept {
  const std::uint32_t n = m.data[3];
  const vision::LandmarkTable* table = landmark_table_find();
  if (m.data[0] != kMsgUnit || n > kMaxLandmarksPerUnit || m.data_words != kUnitHeaderWords + n || table == nullptr) {
    return 0U;
  }
  const std::span<const std::uint32_t> w(m.data.data(), m.data_words);
  vision::PosePrior prior{};
  prior.t_s = detail::get_f64(w, 4);
  const std::uint64_t offset = static_cast<std::uint64_t>(w[6]) | (static_cast<std::uint64_t>(w[7]) << 32U);
  const std::uint32_t width = w[8] & 0xFFFFU;
  const std::uint32_t height = w[8] >> 16U;
  for (std::size_t i = 0; i < 3U; ++i) {
    prior.p_m[i] = detail::get_f64(w, 9U + 2U * i);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    prior.q_mb[i] = detail::get_f64(w, 15U + 2U * i);
  }
  const std::uint8_t* pixels = ddr_at(offset, static_cast<std::uint64_t>(width) * height);
  if (pixels == nullptr) {
    return 0U;
  }
  const vision::ConstImageU8 image{pixels, static_cast<std::int32_t>(width), static_cast<std::int32_t>(height),
                                   static_cast<std::int32_t>(width)};
  std::uint32_t matched = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto index = static_cast<std::uint16_t>(w[kUnitHeaderWords + i] & 0xFFFFU);
    const auto radius = static_cast<std::int32_t>(w[kUnitHeaderWords + i] >> 16U);
    Match match{};
    bool accepted = false;
    vision::LandmarkDiag diag{};
    bsp::Work work{};
    const vision::Status s = vision::match_landmark(image, st.cfg->camera, prior, st.fine, *table, index, radius,
                                                    *st.ws, match, accepted, diag, work);
    bsp::consume(work);
    report_checks(diag, index, m.data[1]);
    ++stats.landmarks;
    if (s == vision::Status::kOk && accepted) {
      match.tile = static_cast<std::uint16_t>(bsp::current_tile());
      match.frame = m.data[1];
      match.t_s = prior.t_s;
      pack_match(match, std::span<std::uint32_t, kMatchWords>(st.out.data() + kResultHeaderWords + static_cast<std::size_t>(matched) * kMatchWords,
                                                              kMatchWords));
      ++matched;
    }
  }
  st.out[0] = kMsgResult;
  st.out[1] = m.data[1];
  st.out[2] = m.data[2];
  st.out[3] = n;
  st.out[4] = matched;
  stats.matches += matched;
  return kResultHeaderWords + matched * kMatchWords;
}

/** A band of the coarse map to relight into the shared copy; answered when done. */
void relight_request(WorkerState& st, VisionWorkerStats& stats, const udn::FtMessage& m) noexcept {
  const std::uint8_t* relit = ddr_find(kRelitCarveName);
  const vision::ConstImageU8 src = st.coarse.image;
  const auto row0 = static_cast<std::int32_t>(m.data[1]);
  const auto rows = static_cast<std::int32_t>(m.data[2]);
  // The copy is the coordinator's carve, laid out like the layer.
  const vision::ImageU8 dst{const_cast<std::uint8_t*>(relit), src.width, src.height, src.width};  // NOLINT(cppcoreguidelines-pro-type-const-cast): shared DDR buffer
  if (relit == nullptr || !relight_band(st.coarse, st.cfg->descent_sun_m, dst, row0, rows)) {
    ++stats.bad_units;
    return;
  }
  const std::array<std::uint32_t, kRelightWords> w{kMsgRelightDone, m.data[1], m.data[2]};
  if (udn::endpoint_send(m.source, kChanResult, w, kVisionSendTicks) != udn::FtError::kOk) {
    ++stats.send_failed;
  }
}

}  // namespace

void vision_worker_main(void* arg) noexcept {
  const bsp::TileId self = bsp::current_tile();
  VisionWorkerStats& stats = g_worker_stats[self];
  stats = VisionWorkerStats{};
  const auto* cfg = static_cast<const VisionWorkerConfig*>(arg);
  bsp::MemError err = bsp::MemError::kOk;
  auto* st = bsp::carve_control_array<WorkerState>(bsp::Region{self}, 1, "vision_task", &err);
  if (cfg == nullptr || err != bsp::MemError::kOk || !udn::endpoint_wait_ready(100)) {
    return;
  }
  ::new (st) WorkerState{};
  st->cfg = cfg;
  if (!worker_set_up(*st)) {
    return;
  }
  udn::FtMessage m{};
  for (;;) {
    k::checkin();
    if (udn::endpoint_receive(kChanControl, m) != udn::FtError::kOk) {
      k::sleep(kWorkerIdleTicks);
      continue;
    }
    if (m.data_words == kRelightWords && m.data[0] == kMsgRelight) {
      relight_request(*st, stats, m);
      continue;
    }
    const std::uint32_t words = run_unit(*st, stats, m);
    if (words == 0U) {
      ++stats.bad_units;
      continue;
    }
    ++stats.units;
    // The result as sent is a published result: where a corrupted match is injected.
    (void)bsp::publish_filter(kVisionMatchesChannel, st->out.data(), std::size_t{words} * sizeof(std::uint32_t));
    if (udn::endpoint_send(m.source, kChanResult, std::span<const std::uint32_t>(st->out.data(), words), kVisionSendTicks) !=
        udn::FtError::kOk) {
      ++stats.send_failed;
    }
  }
}

VisionWorkerStats vision_worker_stats(bsp::TileId tile) noexcept {
  return tile < bsp::kMaxTiles ? g_worker_stats[tile] : VisionWorkerStats{};
}

}  // namespace trn::tasks
