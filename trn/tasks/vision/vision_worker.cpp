/**
 * @file vision_worker.cpp
 * @brief A vision tile: runs the work units of the coordinator, answers with matches.
 */
#include "trn/tasks/vision/vision_worker.hpp"

#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "kernel/kernel.hpp"
#include "trn/events.hpp"
#include "trn/match.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/settings_copy.hpp"
#include "trn/tasks/vision/vision_shared.hpp"
#include "udn/endpoint.hpp"

#include <array>
#include <new>

namespace trn::tasks {
namespace {

/**
 * Longest sleep of an idle vision tile between two check-ins: units come once
 * a frame, and the delivery of one wakes it (udn::endpoint_wait).
 */
constexpr std::uint32_t kWorkerWaitTicks = 100U;

/** What a vision tile's units use of its configuration, held in its RAM under a CRC (settings_copy.hpp). */
struct WorkerSettings {
  bsp::CameraModel camera;
  double descent_sun_m[3];
};

struct WorkerState {
  const VisionWorkerConfig* cfg;
  SettingsCopy<WorkerSettings>* set;  ///< in this tile's RAM (kWorkerSettingsCarve), carved last
  vision::MapView fine;
  vision::MapView coarse;
  vision::LandmarkWorkspace* ws;
  std::array<std::uint32_t, kResultHeaderWords + kMaxLandmarksPerUnit * kMatchWords> out;
};

/**
 * What an upset of the worker's state does (bsp::ControlLayout): its
 * configuration and workspace pointers, and the views of the map product
 * (host pointers with their extents and the geometry that maps onto them),
 * are host state; the result being built is the tile's own (written whole
 * for each unit before it is sent).
 */
constexpr std::array kWorkerFields{
    BSP_CONTROL_HOST(WorkerState, cfg), BSP_CONTROL_HOST(WorkerState, set), BSP_CONTROL_HOST(WorkerState, fine), BSP_CONTROL_HOST(WorkerState, coarse),
    BSP_CONTROL_HOST(WorkerState, ws),  BSP_CONTROL_STATE(WorkerState, out),
};
constexpr bsp::ControlLayout kWorkerLayout{kWorkerFields, sizeof(WorkerState), alignof(WorkerState)};
static_assert(bsp::control_layout_ok(kWorkerLayout), "every member of WorkerState, pointers as host state");

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

/** Matches the landmarks of unit @p u; returns the result's length in words (0: no landmark table or image). */
std::uint32_t run_unit(WorkerState& st, VisionWorkerStats& stats, const WorkUnit& u) noexcept {
  const vision::LandmarkTable* table = landmark_table_find();
  if (table == nullptr) {
    return 0U;
  }
  const std::uint32_t n = u.n;
  vision::PosePrior prior{};
  prior.t_s = u.t_s;
  const std::uint32_t width = u.width_px;
  const std::uint32_t height = u.height_px;
  for (std::size_t i = 0; i < 3U; ++i) {
    prior.p_m[i] = u.p_m[i];
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    prior.q_mb[i] = u.q_mb_wxyz[i];
  }
  const std::uint8_t* pixels = ddr_at(u.ddr_offset, static_cast<std::uint64_t>(width) * height);
  if (pixels == nullptr) {
    return 0U;
  }
  const vision::ConstImageU8 image{pixels, static_cast<std::int32_t>(width), static_cast<std::int32_t>(height),
                                   static_cast<std::int32_t>(width)};
  std::uint32_t matched = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint16_t index = u.landmark[i];
    const std::int32_t radius = u.radius_px[i];
    Match match{};
    bool accepted = false;
    vision::LandmarkDiag diag{};
    bsp::Work work{};
    const vision::Status s = vision::match_landmark(image, st.set->s.camera, prior, st.fine, *table, index, radius,
                                                    *st.ws, match, accepted, diag, work);
    bsp::consume(work);
    report_correlation_checks(diag.check_failed, diag.recomputes, diag.first_check, index, u.frame);
    ++stats.landmarks;
    if (s == vision::Status::kOk && accepted) {
      match.tile = static_cast<std::uint16_t>(bsp::current_tile());
      match.frame = u.frame;
      match.t_s = prior.t_s;
      (void)fdir::msg::encode(kMatchRecord, match,
                              std::span<std::uint32_t>(st.out.data() + kResultHeaderWords + static_cast<std::size_t>(matched) * kMatchWords,
                                                       kMatchWords));
      ++matched;
    }
  }
  stats.matches += matched;
  // The header after the matches: a record group's words are the caller's, the encoder leaves them.
  const std::size_t words = fdir::msg::encode(kResultMsg, UnitResult{u.frame, u.unit, n, matched, 0U}, st.out);
  // Sealed as computed: the coordinator checks the seal where it takes the matches.
  seal_result(std::span<std::uint32_t>(st.out.data(), words));
  return static_cast<std::uint32_t>(words);
}

/** A band of the coarse map to relight into the shared copy; answered when done. */
void relight_request(WorkerState& st, VisionWorkerStats& stats, bsp::TileId from, const RelightBand& band) noexcept {
  const std::uint8_t* relit = ddr_find(kRelitCarveName);
  const vision::ConstImageU8 src = st.coarse.image;
  const std::int32_t row0 = band.row0;
  const std::int32_t rows = band.rows;
  // The copy is the coordinator's carve, laid out like the layer.
  const vision::ImageU8 dst{const_cast<std::uint8_t*>(relit), src.width, src.height, src.width};  // NOLINT(cppcoreguidelines-pro-type-const-cast): shared DDR buffer
  if (relit == nullptr || !relight_band(st.coarse, st.set->s.descent_sun_m, dst, row0, rows)) {
    ++stats.bad_units;
    return;
  }
  std::array<std::uint32_t, kRelightWords> w{};
  (void)fdir::msg::encode(kRelightDoneMsg, band, w);
  if (udn::endpoint_send(from, kChanResult, w, kVisionSendTicks) != udn::FtError::kOk) {
    ++stats.send_failed;
  }
}

/** Why a band request could not be computed (CoarseBandDone::status beyond vision::Status). */
constexpr std::uint32_t kBandNoSlot = 0xF0U;       ///< no slot or no coarse workspace in DDR
constexpr std::uint32_t kBandBadLayout = 0xF1U;    ///< the request does not describe the workspace's images

/**
 * A band of the coarse stage's surface: the decimated template over the
 * decimated map region, both in the coordinator's coarse workspace (DDR),
 * computed and checked into the band's slot; answered with what the checks found.
 */
void coarse_band_request(VisionWorkerStats& stats, bsp::TileId from, const CoarseBand& b) noexcept {
  CoarseBandSlot* slot = b.slot < kMaxCoarseBands ? coarse_band_slot(b.slot) : nullptr;
  const auto* ws = reinterpret_cast<const vision::CoarseFrameWorkspace*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_find(kCoarseWsCarveName));
  CoarseBandDone done{};
  done.frame = b.frame;
  done.row0 = b.row0;
  done.rows = b.rows;
  if (slot == nullptr || ws == nullptr) {
    done.status = kBandNoSlot;
  } else {
    const vision::ConstImageU8 window = ws->coarse.map_small.cview();
    const vision::ConstImageU8 small = ws->coarse.image_small.cview();
    const vision::ConstImageU8 tmpl = small.sub(b.tmpl_x, b.tmpl_y, b.tmpl_w, b.tmpl_h);
    if (window.width != b.window_w || window.height != b.window_h || !tmpl.valid()) {
      done.status = kBandBadLayout;
    } else {
      vision::BandResult r{};
      bsp::Work work{};
      const vision::Status s = vision::correlate_band(tmpl, window, b.row0, b.rows, slot->buffers(), r, work);
      bsp::consume(work);
      report_correlation_checks(r.check_failed, r.recomputes, r.first_check, kCoarseLandmark, b.frame);
      done.status = static_cast<std::uint32_t>(s);
      done.flat_windows = r.flat_windows;
      done.digest = r.digest;
      done.recomputes = r.recomputes;
      done.check_failed = r.check_failed;
      done.first_check = static_cast<std::uint32_t>(r.first_check);
      if (s == vision::Status::kOk) {
        // The band as it leaves, after its checks: where a corrupted output is injected.
        (void)bsp::publish_filter(kCoarseBandChannel, slot->surface,
                                  static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.rows) * sizeof(float));
      }
    }
  }
  ++stats.coarse_bands;
  std::array<std::uint32_t, kCoarseBandDoneWords> w{};
  (void)fdir::msg::encode(kCoarseBandDoneMsg, done, w);
  if (udn::endpoint_send(from, kChanResult, w, kVisionSendTicks) != udn::FtError::kOk) {
    ++stats.send_failed;
  }
}

/** What a handler of the worker's requests acts on: its state, its statistics, the message. */
struct Inbox {
  WorkerState& st;
  VisionWorkerStats& stats;
  const udn::FtMessage& m;
};

void take_coarse_band(Inbox& in, const CoarseBand& b) noexcept { coarse_band_request(in.stats, in.m.source, b); }

void take_relight(Inbox& in, const RelightBand& b) noexcept { relight_request(in.st, in.stats, in.m.source, b); }

WorkerSettings worker_settings_of(const VisionWorkerConfig& cfg) noexcept {
  WorkerSettings w{};
  w.camera = cfg.camera;
  for (std::size_t i = 0; i < 3U; ++i) {
    w.descent_sun_m[i] = cfg.descent_sun_m[i];
  }
  return w;
}

/**
 * The settings in RAM against their seal, for frame @p frame (@p when: ev::kSettingsAtStart before a
 * unit, ev::kSettingsAtBatch after it, before its result leaves). Changed: built again from the image
 * and reported (tile_settings_bad). @return true if they were intact.
 */
bool check_settings(WorkerState& st, VisionWorkerStats& stats, std::uint32_t when, std::uint32_t frame) noexcept {
  bsp::Work work{};
  const bool intact = settings_intact(*st.set, work);
  if (!intact) {
    settings_seal(*st.set, worker_settings_of(*st.cfg), work);
    ++stats.settings_rebuilt;
    trn::report(ev::kTileSettingsBad, frame, ev::kSettingsOfVisionTile, when, 0U);
  }
  bsp::consume(work);
  return intact;
}

/**
 * A unit, run with settings checked before and after: changed while it ran, it is run again
 * with the rebuilt ones (once; a second change in the same unit is left to the next unit's check
 * and to the coordinator's check of its matches).
 */
std::uint32_t run_checked_unit(WorkerState& st, VisionWorkerStats& stats, const WorkUnit& u) noexcept {
  (void)check_settings(st, stats, ev::kSettingsAtStart, u.frame);
  std::uint32_t words = run_unit(st, stats, u);
  if (words != 0U && !check_settings(st, stats, ev::kSettingsAtBatch, u.frame)) {
    words = run_unit(st, stats, u);
  }
  return words;
}

void take_unit(Inbox& in, const WorkUnit& u) noexcept {
  const std::uint32_t words = run_checked_unit(in.st, in.stats, u);
  if (words == 0U) {
    ++in.stats.bad_units;
    return;
  }
  ++in.stats.units;
  // The result as sent is a published result: where a corrupted match is injected.
  (void)bsp::publish_filter(kVisionMatchesChannel, in.st.out.data(), std::size_t{words} * sizeof(std::uint32_t));
  if (udn::endpoint_send(in.m.source, kChanResult, std::span<const std::uint32_t>(in.st.out.data(), words), kVisionSendTicks) !=
      udn::FtError::kOk) {
    ++in.stats.send_failed;
  }
}

/** The kinds a vision tile takes on kChanControl; anything else there counts as a bad unit. */
constexpr std::array<fdir::msg::Handler<Inbox>, 3> kRequestHandlers{{
    fdir::msg::on<kCoarseBandMsg, &take_coarse_band, Inbox>(),
    fdir::msg::on<kRelightMsg, &take_relight, Inbox>(),
    fdir::msg::on<kUnitMsg, &take_unit, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kRequestHandlers, kChanControl, role_bit(Role::kVision)),
              "the vision tile's handlers are kinds declared for it on kChanControl");

}  // namespace

void vision_worker_main(void* arg) noexcept {
  const bsp::TileId self = bsp::current_tile();
  const auto* cfg = static_cast<const VisionWorkerConfig*>(arg);
  bsp::MemError err = bsp::MemError::kOk;
  auto* st = bsp::carve_control_array<WorkerState>(bsp::Region{self}, 1, kVisionWorkerCarve, &err, &kWorkerLayout);
  if (cfg == nullptr || err != bsp::MemError::kOk || !udn::endpoint_wait_ready(100)) {
    return;
  }
  ::new (st) WorkerState{};
  st->cfg = cfg;
  if (!worker_set_up(*st)) {
    return;
  }
  // The counters' record last: the state and the workspace keep the places they had before.
  VisionWorkerStats* const counters = bsp::carve_record(bsp::Region{self}, kVisionWorkerStatsRecord, &err);
  if (counters == nullptr) {
    return;
  }
  VisionWorkerStats& stats = *counters;
  // The settings its units use, after the counters (every carve before keeps its place).
  st->set = bsp::carve_array<SettingsCopy<WorkerSettings>>(bsp::Region{self}, 1, kWorkerSettingsCarve, &err);
  if (st->set == nullptr) {
    return;
  }
  bsp::Work work{};
  settings_seal(*st->set, worker_settings_of(*cfg), work);
  bsp::consume(work);
  udn::FtMessage m{};
  for (;;) {
    k::checkin();
    if (udn::endpoint_receive(kChanControl, m) != udn::FtError::kOk) {
      (void)udn::endpoint_wait(kChanControl, kWorkerWaitTicks);
      continue;
    }
    Inbox in{*st, stats, m};
    if (fdir::msg::dispatch(kRequestHandlers, std::span<const std::uint32_t>(m.data.data(), m.data_words), in) !=
        fdir::msg::Dispatch::kTaken) {
      ++stats.bad_units;  // not a request of a vision tile, or one out of range
    }
  }
}

const bsp::ControlLayout& vision_worker_state_layout() noexcept { return kWorkerLayout; }

}  // namespace trn::tasks
