/**
 * @file vision_coord.cpp
 * @brief Vision coordinator: frame planning, distribution to the vision tiles, gathering.
 */
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/events.hpp"

#include "trn/tasks/vision/landmark_product.hpp"

#include "bsp_tile64/api/map_product.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/event_log.hpp"
#include "fdir/liveness.hpp"
#include "fdir/tile_health.hpp"
#include "kernel/kernel.hpp"
#include "trn/match.hpp"
#include "trn/tasks/vision/landmark_product.hpp"
#include "trn/tasks/vision/match_deal.hpp"
#include "trn/tasks/messages.hpp"
#include "trn/tasks/sdc_points.hpp"
#include "trn/tasks/settings_copy.hpp"
#include "trn/tasks/vision/vision_shared.hpp"
#include "trn/vision/match_consistency.hpp"
#include "udn/endpoint.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <span>

namespace trn::tasks {
namespace {

/** The largest image-rate divisor the vision supervisor sends (VisionRate: 1 or 2). */
constexpr std::uint32_t kMaxRateDiv = 2U;
/** Solutions the coordinator keeps (10 ms apart: 0.64 s). */
constexpr std::uint32_t kNavRing = 64;
/** Messages drained per channel per pass (the receive queues hold kFtRxDepth each). */
constexpr std::uint32_t kDrainPerPass = 64;

struct Unit {
  bsp::TileId tile;
  std::uint32_t planned;
  bool sent;
  bool answered;
};

/**
 * The coordinator's vision tile list, kept in DDR (carve kTileListCarveName):
 * a coordinator restarted or moved to a spare goes on with the replacements
 * made before (its other state, the trust of each tile, starts afresh: a
 * tile still wrong is found again in its next frame).
 */
struct TileListRecord {
  std::uint32_t magic;  ///< kTileListMagic once written
  std::uint32_t count;  ///< cfg->vision_count it was written for
  std::array<bsp::TileId, kMaxVisionTiles> tiles;
};
constexpr std::uint32_t kTileListMagic = 0x564C5354U;  // "VLST"
constexpr const char* kTileListCarveName = "vision_tile_list";

/** Why the coordinator computes a band itself (kCoarseBandRedone's cause). */
enum class BandRedo : std::uint32_t { kNone = 0, kNotSent = 1, kNoAnswer = 2, kFailed = 3, kCopyWrong = 4 };

/** One band of a coarse frame's surface: the rows, the tile it was dealt to, what came of it. */
struct CoarseBandJob {
  std::int32_t row0;
  std::int32_t rows;
  bsp::TileId tile;
  bool answered;  ///< not waited for any more (answered, or never sent)
  bool done;      ///< its rows are in the gathered surface, checked
  BandRedo why;   ///< why not done, once answered
};

/** The coarse surface being gathered (in the coarse workspace's correlator buffers). */
struct CoarseGather {
  vision::ImageF32 surface;
  std::uint64_t digest;      ///< sum of the gathered bands' digests
  std::int32_t flat_windows;
  std::uint32_t recomputes;
  std::uint32_t pending;     ///< bands not answered yet
};

struct CoordState {
  const VisionCoordConfig* cfg;
  SettingsCopy<CoordSettings>* set;  ///< the settings frames use, in this tile's RAM (kCoordSettingsCarve)
  vision::MapView fine;
  vision::MapView coarse_map;
  vision::LandmarkTable* table;
  vision::CoarseFrameWorkspace* coarse_ws;
  vision::PlanScratch* plan_scratch;
  std::array<CoarseBandJob, kMaxCoarseBands> bands;
  std::uint32_t band_count;
  CoarseGather gather;
  std::array<filter::NavOutput, kNavRing> nav;
  std::uint32_t nav_count;  ///< solutions received (ring index = count % kNavRing)
  bool have_pending;
  FrameNotice pending;
  bool busy;
  std::uint32_t apply_job;  ///< the filter job that takes this frame's batch
  FrameNotice frame;
  bsp::Cycles frame_start;
  k::Ticks deadline;
  std::array<Unit, kMaxVisionTiles> units;
  std::uint32_t unit_count;
  std::array<vision::PlannedLandmark, kMaxMatchesPerFrame> planned;
  std::array<Match, kMaxMatchesPerFrame + 1U> matches;  ///< [0] the coarse match when there is one
  std::uint32_t match_count;
  fdir::Liveness live;  ///< misses in a row per vision tile, isolation and probe rounds
  std::uint32_t frames_planned;
  vision::ImageU8 relit;  ///< the coarse layer relit to the descent sun (DDR)
  std::array<bool, kMaxVisionTiles> band_done;
  std::array<bsp::TileId, kMaxVisionTiles> tiles;  ///< the vision tiles now (a replacing spare in its tile's place)
  TileListRecord* list;         ///< the same in DDR
  vision::PosePrior prior;      ///< the frame's prior after the coarse stage (where the consistency fit starts)
  fdir::ResultTrust trust;      ///< per vision tile: are its matches used
  vision::ConsistencyWork cws;
  std::array<bool, kMaxMatchesPerFrame> failed;  ///< per fine match of the frame: off the fitted pose
  std::array<std::uint16_t, kMaxMatchesPerFrame + 1U> order;  ///< order_matches(): the match each place takes
  std::array<bool, kMaxMatchesPerFrame + 1U> placed;          ///< order_matches(): places filled
  std::uint32_t rate_div;       ///< the vision supervisor's image rate: a frame whose seq it does not divide is left out
  double ready_s;               ///< when the set-up ended: a frame captured before is not processed
};

// What an upset of the coordinator's state does (bsp::ControlLayout). Its configuration, the
// views of the map product and of its DDR workspaces (host pointers with their extents and the
// geometry that maps onto them) and the DDR tile list's address are host state: an upset there is
// modelled as a crash of the tile. Everything else is the tile's own and is flipped for real:
// check_coord() bounds every count, index and divisor the coordinator follows, each use takes
// them bounded (an upset can land between the check and the use), and a value no valid state
// holds is reported (coord_state_bad) and reset.
constexpr std::array kUnitFields{BSP_CONTROL_STATE(Unit, tile), BSP_CONTROL_STATE(Unit, planned),
                                 BSP_CONTROL_STATE(Unit, sent), BSP_CONTROL_STATE(Unit, answered)};
constexpr bsp::ControlLayout kUnitLayout{kUnitFields, sizeof(Unit), alignof(Unit)};
static_assert(bsp::control_layout_ok(kUnitLayout), "every member of Unit");

constexpr std::array kBandJobFields{BSP_CONTROL_STATE(CoarseBandJob, row0), BSP_CONTROL_STATE(CoarseBandJob, rows),
                                    BSP_CONTROL_STATE(CoarseBandJob, tile), BSP_CONTROL_STATE(CoarseBandJob, answered),
                                    BSP_CONTROL_STATE(CoarseBandJob, done), BSP_CONTROL_STATE(CoarseBandJob, why)};
constexpr bsp::ControlLayout kBandJobLayout{kBandJobFields, sizeof(CoarseBandJob), alignof(CoarseBandJob)};
static_assert(bsp::control_layout_ok(kBandJobLayout), "every member of CoarseBandJob");

constexpr std::array kGatherFields{BSP_CONTROL_HOST(CoarseGather, surface), BSP_CONTROL_STATE(CoarseGather, digest),
                                   BSP_CONTROL_STATE(CoarseGather, flat_windows),
                                   BSP_CONTROL_STATE(CoarseGather, recomputes), BSP_CONTROL_STATE(CoarseGather, pending)};
constexpr bsp::ControlLayout kGatherLayout{kGatherFields, sizeof(CoarseGather), alignof(CoarseGather)};
static_assert(bsp::control_layout_ok(kGatherLayout), "every member of CoarseGather, the surface's view as host state");

constexpr std::array kNoticeFields{BSP_CONTROL_STATE(FrameNotice, seq),    BSP_CONTROL_STATE(FrameNotice, width_px),
                                   BSP_CONTROL_STATE(FrameNotice, height_px), BSP_CONTROL_STATE(FrameNotice, status),
                                   BSP_CONTROL_STATE(FrameNotice, t_s),    BSP_CONTROL_STATE(FrameNotice, ddr_offset)};
constexpr bsp::ControlLayout kNoticeLayout{kNoticeFields, sizeof(FrameNotice), alignof(FrameNotice)};
static_assert(bsp::control_layout_ok(kNoticeLayout), "every member of FrameNotice");

constexpr std::array kPlannedFields{
    BSP_CONTROL_STATE(vision::PlannedLandmark, landmark), BSP_CONTROL_STATE(vision::PlannedLandmark, u_px),
    BSP_CONTROL_STATE(vision::PlannedLandmark, v_px), BSP_CONTROL_STATE(vision::PlannedLandmark, radius_px)};
constexpr bsp::ControlLayout kPlannedLayout{kPlannedFields, sizeof(vision::PlannedLandmark),
                                            alignof(vision::PlannedLandmark)};
static_assert(bsp::control_layout_ok(kPlannedLayout), "every member of PlannedLandmark");

constexpr std::array kMatchFields{BSP_CONTROL_STATE(Match, w_c),      BSP_CONTROL_STATE(Match, p_m),
                                  BSP_CONTROL_STATE(Match, u_px),     BSP_CONTROL_STATE(Match, v_px),
                                  BSP_CONTROL_STATE(Match, sigma_px), BSP_CONTROL_STATE(Match, quality),
                                  BSP_CONTROL_STATE(Match, landmark), BSP_CONTROL_STATE(Match, tile),
                                  BSP_CONTROL_STATE(Match, frame),    BSP_CONTROL_STATE(Match, t_s)};
constexpr bsp::ControlLayout kMatchLayout{kMatchFields, sizeof(Match), alignof(Match)};
static_assert(bsp::control_layout_ok(kMatchLayout), "every member of Match");

constexpr std::array kLivenessConfigFields{BSP_CONTROL_STATE(fdir::LivenessConfig, suspect_after_misses),
                                           BSP_CONTROL_STATE(fdir::LivenessConfig, probe_every)};
constexpr bsp::ControlLayout kLivenessConfigLayout{kLivenessConfigFields, sizeof(fdir::LivenessConfig),
                                                   alignof(fdir::LivenessConfig)};
static_assert(bsp::control_layout_ok(kLivenessConfigLayout), "every member of LivenessConfig");
constexpr std::array kLivenessFields{BSP_CONTROL_NESTED(fdir::Liveness, config, kLivenessConfigLayout),
                                     BSP_CONTROL_STATE(fdir::Liveness, count), BSP_CONTROL_STATE(fdir::Liveness, tile),
                                     BSP_CONTROL_STATE(fdir::Liveness, misses)};
constexpr bsp::ControlLayout kLivenessLayout{kLivenessFields, sizeof(fdir::Liveness), alignof(fdir::Liveness)};
static_assert(bsp::control_layout_ok(kLivenessLayout), "every member of Liveness");

constexpr std::array kTrustConfigFields{
    BSP_CONTROL_STATE(fdir::ResultTrustConfig, window), BSP_CONTROL_STATE(fdir::ResultTrustConfig, min_failed),
    BSP_CONTROL_STATE(fdir::ResultTrustConfig, reset_after), BSP_CONTROL_STATE(fdir::ResultTrustConfig, probation),
    BSP_CONTROL_STATE(fdir::ResultTrustConfig, bias_window), BSP_CONTROL_STATE(fdir::ResultTrustConfig, bias_min),
    BSP_CONTROL_STATE(fdir::ResultTrustConfig, bias_sigmas), BSP_CONTROL_STATE(fdir::ResultTrustConfig, bias_floor_mpx),
    BSP_CONTROL_STATE(fdir::ResultTrustConfig, bias_clip_mpx)};
constexpr bsp::ControlLayout kTrustConfigLayout{kTrustConfigFields, sizeof(fdir::ResultTrustConfig),
                                                alignof(fdir::ResultTrustConfig)};
static_assert(bsp::control_layout_ok(kTrustConfigLayout), "every member of ResultTrustConfig");
constexpr std::array kTrustFields{
    BSP_CONTROL_NESTED(fdir::ResultTrust, config, kTrustConfigLayout), BSP_CONTROL_STATE(fdir::ResultTrust, count),
    BSP_CONTROL_STATE(fdir::ResultTrust, tile),       BSP_CONTROL_STATE(fdir::ResultTrust, state),
    BSP_CONTROL_STATE(fdir::ResultTrust, checked),    BSP_CONTROL_STATE(fdir::ResultTrust, failed),
    BSP_CONTROL_STATE(fdir::ResultTrust, rounds_bad), BSP_CONTROL_STATE(fdir::ResultTrust, clean),
    BSP_CONTROL_STATE(fdir::ResultTrust, round),      BSP_CONTROL_STATE(fdir::ResultTrust, sum_u),
    BSP_CONTROL_STATE(fdir::ResultTrust, sum_v),      BSP_CONTROL_STATE(fdir::ResultTrust, fitted),
    BSP_CONTROL_STATE(fdir::ResultTrust, scale)};
constexpr bsp::ControlLayout kTrustLayout{kTrustFields, sizeof(fdir::ResultTrust), alignof(fdir::ResultTrust)};
static_assert(bsp::control_layout_ok(kTrustLayout), "every member of ResultTrust");

constexpr std::array kPriorFields{BSP_CONTROL_STATE(vision::PosePrior, t_s), BSP_CONTROL_STATE(vision::PosePrior, p_m),
                                  BSP_CONTROL_STATE(vision::PosePrior, q_mb),
                                  BSP_CONTROL_STATE(vision::PosePrior, sigma_p_m),
                                  BSP_CONTROL_STATE(vision::PosePrior, sigma_att_rad)};
constexpr bsp::ControlLayout kPriorLayout{kPriorFields, sizeof(vision::PosePrior), alignof(vision::PosePrior)};
static_assert(bsp::control_layout_ok(kPriorLayout), "every member of PosePrior");

constexpr std::array kConsistencyFields{BSP_CONTROL_STATE(vision::ConsistencyWork, norm),
                                        BSP_CONTROL_STATE(vision::ConsistencyWork, du),
                                        BSP_CONTROL_STATE(vision::ConsistencyWork, dv),
                                        BSP_CONTROL_STATE(vision::ConsistencyWork, sorted),
                                        BSP_CONTROL_STATE(vision::ConsistencyWork, in_fit)};
constexpr bsp::ControlLayout kConsistencyLayout{kConsistencyFields, sizeof(vision::ConsistencyWork),
                                                alignof(vision::ConsistencyWork)};
static_assert(bsp::control_layout_ok(kConsistencyLayout), "every member of ConsistencyWork");

constexpr std::array kCoordFields{
    BSP_CONTROL_HOST(CoordState, cfg),
    BSP_CONTROL_HOST(CoordState, set),
    BSP_CONTROL_HOST(CoordState, fine),
    BSP_CONTROL_HOST(CoordState, coarse_map),
    BSP_CONTROL_HOST(CoordState, table),
    BSP_CONTROL_HOST(CoordState, coarse_ws),
    BSP_CONTROL_HOST(CoordState, plan_scratch),
    BSP_CONTROL_NESTED(CoordState, bands, kBandJobLayout),
    BSP_CONTROL_STATE(CoordState, band_count),
    BSP_CONTROL_NESTED(CoordState, gather, kGatherLayout),
    BSP_CONTROL_NESTED(CoordState, nav, filter::kNavOutputLayout),
    BSP_CONTROL_STATE(CoordState, nav_count),
    BSP_CONTROL_STATE(CoordState, have_pending),
    BSP_CONTROL_NESTED(CoordState, pending, kNoticeLayout),
    BSP_CONTROL_STATE(CoordState, busy),
    BSP_CONTROL_STATE(CoordState, apply_job),
    BSP_CONTROL_NESTED(CoordState, frame, kNoticeLayout),
    BSP_CONTROL_STATE(CoordState, frame_start),
    BSP_CONTROL_STATE(CoordState, deadline),
    BSP_CONTROL_NESTED(CoordState, units, kUnitLayout),
    BSP_CONTROL_STATE(CoordState, unit_count),
    BSP_CONTROL_NESTED(CoordState, planned, kPlannedLayout),
    BSP_CONTROL_NESTED(CoordState, matches, kMatchLayout),
    BSP_CONTROL_STATE(CoordState, match_count),
    BSP_CONTROL_NESTED(CoordState, live, kLivenessLayout),
    BSP_CONTROL_STATE(CoordState, frames_planned),
    BSP_CONTROL_HOST(CoordState, relit),
    BSP_CONTROL_STATE(CoordState, band_done),
    BSP_CONTROL_STATE(CoordState, tiles),
    BSP_CONTROL_HOST(CoordState, list),
    BSP_CONTROL_NESTED(CoordState, prior, kPriorLayout),
    BSP_CONTROL_NESTED(CoordState, trust, kTrustLayout),
    BSP_CONTROL_NESTED(CoordState, cws, kConsistencyLayout),
    BSP_CONTROL_STATE(CoordState, failed),
    BSP_CONTROL_STATE(CoordState, order),
    BSP_CONTROL_STATE(CoordState, placed),
    BSP_CONTROL_STATE(CoordState, rate_div),
    BSP_CONTROL_STATE(CoordState, ready_s),
};
constexpr bsp::ControlLayout kCoordLayout{kCoordFields, sizeof(CoordState), alignof(CoordState)};
static_assert(bsp::control_layout_ok(kCoordLayout), "every member of CoordState, pointers and views as host state");

/** The parts of the coordinator's state check_coord() and the uses check (coord_state_bad's subject). */
enum class CoordPart : std::uint32_t {
  kRateDiv = 1,
  kBandCount = 2,
  kBandRows = 3,
  kUnitCount = 4,
  kMatchCount = 5,
  kTileList = 6,
  kLiveness = 7,
  kTrust = 8,
  kFrameSize = 9,
  kMatch = 10,
  kPrior = 11,
  kDeadline = 12,
  kReadyTime = 13,
};

void coord_repaired(CoordPart part, std::uint32_t index, std::uint32_t value) noexcept {
  trn::report(ev::kCoordStateBad, static_cast<std::uint32_t>(part), index, value);
}

// Counts and divisors as every use takes them: bounded, whatever an upset left there since the last
// check_coord() (an upset lands whenever the tile's time advances: at a send, a wait, a charge of work).
std::uint32_t rate_div_of(const CoordState& st) noexcept { return st.rate_div != 0U ? st.rate_div : 1U; }
std::uint32_t band_count_of(const CoordState& st) noexcept {
  return st.band_count < kMaxCoarseBands ? st.band_count : kMaxCoarseBands;
}
std::uint32_t unit_count_of(const CoordState& st) noexcept {
  return st.unit_count < st.cfg->vision_count ? st.unit_count : st.cfg->vision_count;
}
std::uint32_t match_count_of(const CoordState& st) noexcept {
  const auto cap = static_cast<std::uint32_t>(st.matches.size());
  return st.match_count < cap ? st.match_count : cap;
}

/** Idle poll period of the coordinator (results, notices and solutions are drained each time). */
constexpr k::Ticks kCoordIdleTicks = 2;

/** Ticks the coordinator waits for the vision tiles' relit bands before doing the rest itself. */
constexpr k::Ticks kRelightWaitTicks = 400;
/** The vision tiles kRelightWaitTicks is sized for (each relights 1/40 of the coarse layer). */
constexpr std::uint32_t kRelightSharers = 40U;


k::Ticks seconds_to_ticks(double s) noexcept {
  // The frame logic works in ticks.
  return static_cast<k::Ticks>(std::ceil(s * static_cast<double>(kTicksPerSecond)));
}

// ------------------------------------------------------------------ coordinator: set-up

void drain_nav(CoordState& st) noexcept;

/**
 * Grid cells the landmark selection searches between two drains of the
 * filter's solutions (~15 ms of this tile; 16 cells of 32 px).
 */
constexpr std::int32_t kSelectCellsPerStep = 16;

/** Set-up steps as kVisionSetUpFailed names them (its subject). */
enum class SetUpStep : std::uint32_t { kLists = 1, kMapProduct = 2, kCarves = 3, kSelection = 4, kRelight = 5 };

/** Says why the coordinator cannot start; @return false (for the caller's return). */
bool set_up_failed(SetUpStep step, std::uint32_t status) noexcept {
  trn::report(ev::kVisionSetUpFailed, static_cast<std::uint32_t>(step), 0U, status);
  return false;
}

/**
 * The landmark selection (~0.9 s of this tile) in steps, the filter's
 * solutions taken between them. In one block the filter's stream to this
 * tile filled, and the filter gave up ~45 packets at every start
 * (packet_gave_up, packet_settled in a fault-free flight).
 */
vision::Status select_in_steps(CoordState& st) noexcept {
  vision::SelectProgress progress{};
  for (std::uint32_t step = 0; step <= vision::kMaxLandmarks && !progress.done; ++step) {
    bsp::Work work{};
    const vision::Status s = vision::select_landmarks_step(st.fine.image, vision::ConstImageF32{}, st.fine.geo,
                                                           st.cfg->select, *st.table, progress, kSelectCellsPerStep,
                                                           work);
    bsp::consume(work);
    if (s != vision::Status::kOk) {
      return s;
    }
    k::checkin();
    drain_nav(st);
  }
  return progress.done ? vision::Status::kOk : vision::Status::kTooLarge;
}

/**
 * The ground's landmark table (landmark_product.hpp), if the map came with
 * one and it passes its checks, into st.table. A table that fails them is
 * reported (landmark_product_refused) and the caller selects on board.
 */
bool take_ground_table(CoordState& st) noexcept {
  std::size_t bytes = 0U;
  const std::uint8_t* block = ddr_find_sized(kLandmarkProductCarveName, bytes);
  if (block == nullptr) {
    return false;  // no table came with the map: selected on board, as designed
  }
  const ProductLayer layer{st.fine.image.width, st.fine.image.height, st.fine.geo};
  bsp::Work work{};
  const ProductCheck c =
      landmark_product_load(std::span<const std::uint8_t>(block, bytes), st.cfg->select, layer, *st.table, work);
  bsp::consume(work);
  k::checkin();
  if (c != ProductCheck::kOk) {  // the table is untouched: still the empty one coord_set_up() made
    trn::report(ev::kLandmarkProductRefused, 0U, static_cast<std::uint32_t>(c),
                 static_cast<std::uint32_t>(bytes));
    return false;
  }
  return true;
}

bool coord_set_up(CoordState& st, VisionCoordStats& stats) noexcept {
  const bsp::MapProductHeader* product = bsp::map_product_find();
  if (product == nullptr || vision::map_view(product, bsp::kMapLayerFine, st.fine) != vision::Status::kOk ||
      vision::map_view(product, bsp::kMapLayerCoarse, st.coarse_map) != vision::Status::kOk) {
    return set_up_failed(SetUpStep::kMapProduct, product == nullptr ? 1U : 2U);
  }
  // A restarted coordinator takes back the DDR its predecessor carved (the
  // products are rebuilt below): restarts never use up the shared region.
  st.table = reinterpret_cast<vision::LandmarkTable*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named(kLandmarkCarveName, sizeof(vision::LandmarkTable), alignof(vision::LandmarkTable)));
  st.coarse_ws = reinterpret_cast<vision::CoarseFrameWorkspace*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named(kCoarseWsCarveName, sizeof(vision::CoarseFrameWorkspace), alignof(vision::CoarseFrameWorkspace)));
  st.plan_scratch = reinterpret_cast<vision::PlanScratch*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named(kPlanScratchCarveName, sizeof(vision::PlanScratch), alignof(vision::PlanScratch)));
  // The band slots (CoarseBandSlots, ~16 MB): the vision tiles find them by name.
  const std::uint8_t* band_slots = ddr_carve_named(kCoarseBandCarveName, sizeof(CoarseBandSlots), alignof(CoarseBandSlots));
  const vision::ConstImageU8 orbital = st.coarse_map.image;
  std::uint8_t* relit =
      ddr_carve_named(kRelitCarveName, static_cast<std::size_t>(orbital.width) * static_cast<std::size_t>(orbital.height), 1U);
  if (st.table == nullptr || st.coarse_ws == nullptr || st.plan_scratch == nullptr || relit == nullptr ||
      band_slots == nullptr) {
    return set_up_failed(SetUpStep::kCarves, 0U);
  }
  ::new (st.table) vision::LandmarkTable{};
  ::new (st.coarse_ws) vision::CoarseFrameWorkspace{};
  for (std::size_t i = 0; i < 3U; ++i) {
    st.fine.descent_sun_m[i] = st.cfg->descent_sun_m[i];
    st.coarse_map.descent_sun_m[i] = st.cfg->descent_sun_m[i];
  }
  st.relit = vision::ImageU8{relit, orbital.width, orbital.height, orbital.width};
  if (take_ground_table(st)) {
    stats.landmarks_selected = st.table->count;
    stats.landmarks_from_ground = 1U;
    return true;
  }
  // The product's elevation is int16 counts, the selection's optional view is
  // metres as float: the selection runs on the image alone and each chosen
  // landmark's 3D position is then read from the product.
  const vision::Status selected = select_in_steps(st);
  if (selected != vision::Status::kOk) {
    return set_up_failed(SetUpStep::kSelection, static_cast<std::uint32_t>(selected));
  }
  bsp::Work work{};
  for (std::uint32_t i = 0; i < st.table->count; ++i) {
    vision::Landmark& lm = st.table->items[i];
    bsp::map_pixel_position(product, bsp::kMapLayerFine, static_cast<std::uint32_t>(lm.col_px),
                            static_cast<std::uint32_t>(lm.row_px), lm.p_m);
  }
  work.flops += 3ULL * st.table->count;
  bsp::consume(work);
  k::checkin();
  stats.landmarks_selected = st.table->count;
  stats.landmarks_from_ground = 0U;
  return true;
}

/**
 * The coarse stage searches the coarse layer as the descent sun lights it (the
 * orbital sun's shading would bias it by ~60 m). Relighting the whole layer is
 * ~2.5 G cycles: the vision tiles share it by bands (~90 ms each), and the
 * coordinator does any band not reported done within kRelightWaitTicks.
 */
bool relight_coarse(CoordState& st) noexcept {
  const std::uint32_t n = st.cfg->vision_count;
  const std::int32_t height = st.relit.height;
  std::uint32_t done = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    std::int32_t row0 = 0;
    std::int32_t rows = 0;
    band_rows(height, i, n, row0, rows);
    std::array<std::uint32_t, kRelightWords> w{};
    (void)fdir::msg::encode(kRelightMsg, RelightBand{row0, rows}, w);
    // Band i goes to vision tile i, or the next one the network reaches
    // (a tile out of the fault map refuses at once).
    st.band_done[i] = rows == 0;
    bool sent = st.band_done[i];
    k::checkin();
    for (std::uint32_t k = 0; k < n && !sent; ++k) {
      sent = udn::endpoint_send(st.tiles[(i + k) % n], kChanControl, w, kVisionSendTicks) == udn::FtError::kOk;
    }
    if (!sent) {
      if (!relight_band(st.coarse_map, st.cfg->descent_sun_m, st.relit, row0, rows)) {
        return false;
      }
      st.band_done[i] = true;
    }
    done += st.band_done[i] ? 1U : 0U;
  }
  // A band takes a tile about 90 ms when 40 share the layer, 40 / n times that when n do.
  const k::Ticks until = k::now_ticks() + kRelightWaitTicks * (n != 0U && n < kRelightSharers ? kRelightSharers / n : 1U);
  udn::FtMessage m{};
  while (done < n && k::now_ticks() < until) {
    drain_nav(st);
    while (udn::endpoint_receive(kChanResult, m) == udn::FtError::kOk) {
      RelightBand band{};
      if (!fdir::msg::decode(kRelightDoneMsg, std::span<const std::uint32_t>(m.data.data(), m.data_words), band)) {
        continue;
      }
      for (std::uint32_t i = 0; i < n; ++i) {
        std::int32_t row0 = 0;
        std::int32_t rows = 0;
        band_rows(height, i, n, row0, rows);
        if (!st.band_done[i] && band.row0 == row0) {
          st.band_done[i] = true;
          ++done;
        }
      }
    }
    k::checkin();
    k::sleep(1);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    std::int32_t row0 = 0;
    std::int32_t rows = 0;
    band_rows(height, i, n, row0, rows);
    k::checkin();
    if (!st.band_done[i] && !relight_band(st.coarse_map, st.cfg->descent_sun_m, st.relit, row0, rows)) {
      return false;
    }
  }
  st.coarse_map.image = st.relit.as_const();
  return true;
}

/** The tile list from DDR when a predecessor wrote it, else the configured one (written there). */
bool take_tile_list(CoordState& st) noexcept {
  st.list = reinterpret_cast<TileListRecord*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): carve bytes
      ddr_carve_named(kTileListCarveName, sizeof(TileListRecord), alignof(TileListRecord)));
  if (st.list == nullptr) {
    return false;
  }
  if (st.list->magic != kTileListMagic || st.list->count != st.cfg->vision_count) {
    st.list->tiles = st.cfg->vision_tiles;
    st.list->count = st.cfg->vision_count;
    st.list->magic = kTileListMagic;
  }
  st.tiles = st.list->tiles;
  return true;
}

// ------------------------------------------------------------------ coordinator: inputs

void drain_nav(CoordState& st) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < kDrainPerPass && udn::endpoint_receive(kChanNav, m) == udn::FtError::kOk; ++i) {
    if (fdir::msg::decode(kNavMsg, std::span<const std::uint32_t>(m.data.data(), m.data_words), st.nav[st.nav_count % kNavRing])) {
      ++st.nav_count;
    }
  }
}

/** Index of @p tile in the coordinator's tile list; cfg->vision_count when it is not there. */
std::uint32_t tile_index(const CoordState& st, bsp::TileId tile) noexcept {
  std::uint32_t i = 0;
  while (i < st.cfg->vision_count && st.tiles[i] != tile) {
    ++i;
  }
  return i;
}

/** The supervisor put a spare in the place of a tile whose matches stayed wrong: it gets the tile's share. */
void take_replacement(CoordState& st, VisionCoordStats& stats, bsp::TileId from, const fdir::Replaced& r) noexcept {
  const std::uint32_t i = tile_index(st, r.old_tile);
  const bsp::TileId spare = r.spare;
  if (from != udn::endpoint_role_tile(kSlotTrnSupervisor, st.cfg->health_tile) || i >= st.cfg->vision_count || spare >= bsp::kMaxTiles) {
    return;  // not from the supervisor, not ours, or no spare (the tile stays unused)
  }
  st.tiles[i] = spare;
  st.list->tiles[i] = spare;
  st.live.tile[i] = spare;
  st.live.misses[i] = 0U;
  fdir::result_trust_replace(st.trust, i, spare);
  ++stats.tiles_replaced;
}

/** What a handler of the coordinator's inputs acts on: the coordinator, its statistics, the message. */
struct Inbox {
  CoordState& st;
  VisionCoordStats& stats;
  const udn::FtMessage& m;
};

void take_replaced(Inbox& in, const fdir::Replaced& replaced) noexcept {
  take_replacement(in.st, in.stats, in.m.source, replaced);
}

void take_rate(Inbox& in, const VisionRate& r) noexcept {
  in.st.rate_div = r.div;
  in.stats.rate_div = r.div;
}

void take_frame(Inbox& in, const FrameNotice& notice) noexcept {
  CoordState& st = in.st;
  ++in.stats.frames_seen;
  if (notice.seq % rate_div_of(st) != 0U) {
    ++in.stats.frames_rate_skipped;  // half rate: the tiles left get twice the time per frame
    return;
  }
  if (st.have_pending) {
    ++in.stats.frames_skipped;  // a newer frame replaces one that never started
  }
  st.pending = notice;
  st.have_pending = true;
}

/** The kinds the coordinator takes on kChanControl; anything else there is dropped uncounted. */
constexpr std::array<fdir::msg::Handler<Inbox>, 3> kNoticeHandlers{{
    fdir::msg::on<kReplacedOnControl, &take_replaced, Inbox>(),
    fdir::msg::on<kVisionRateMsg, &take_rate, Inbox>(),
    fdir::msg::on<kFrameMsg, &take_frame, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kNoticeHandlers, kChanControl, role_bit(Role::kVisionCoordinator)),
              "the coordinator's control handlers are kinds declared for it on kChanControl");

void drain_notices(CoordState& st, VisionCoordStats& stats) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < kDrainPerPass && udn::endpoint_receive(kChanControl, m) == udn::FtError::kOk; ++i) {
    Inbox in{st, stats, m};
    (void)fdir::msg::dispatch(kNoticeHandlers, std::span<const std::uint32_t>(m.data.data(), m.data_words), in);
  }
}

void take_unit_result(Inbox& in, const UnitResult& r) noexcept {
  CoordState& st = in.st;
  const udn::FtMessage& m = in.m;
  const std::uint32_t unit = r.unit;
  const std::uint32_t n = r.m;
  if (!st.busy || r.frame != st.frame.seq || unit >= unit_count_of(st) || st.units[unit].answered ||
      st.units[unit].tile != m.source) {
    ++in.stats.results_late;
    return;
  }
  st.units[unit].answered = true;
  ++in.stats.units_answered;
  for (std::uint32_t i = 0; i < n && st.match_count < st.matches.size(); ++i) {
    const std::span<const std::uint32_t, kMatchWords> w(m.data.data() + kResultHeaderWords + static_cast<std::size_t>(i) * kMatchWords,
                                                        kMatchWords);
    st.matches[st.match_count] = fdir::msg::read(kMatchRecord, w);
    st.matches[st.match_count].tile = static_cast<std::uint16_t>(m.source);  // what the check holds it to
    ++st.match_count;
  }
}

/** A coarse band answered after its stage was gathered (its band computed here instead): late. */
void take_late_band(Inbox& in, const CoarseBandDone& /*d*/) noexcept { ++in.stats.results_late; }

/** The kinds the coordinator takes on kChanResult while it gathers a frame's units. */
constexpr std::array<fdir::msg::Handler<Inbox>, 2> kResultHandlers{{
    fdir::msg::on<kResultMsg, &take_unit_result, Inbox>(),
    fdir::msg::on<kCoarseBandDoneMsg, &take_late_band, Inbox>(),
}};
static_assert(fdir::msg::handlers_fit(kResultHandlers, kChanResult, role_bit(Role::kVisionCoordinator)),
              "the coordinator's result handlers are kinds declared for it on kChanResult");

/**
 * A result that changed after its tile computed it (its seal broken, or words no kind of the channel
 * holds): dropped and reported against the tile. Its unit, if the header still names one of this frame's
 * dealt to that tile, counts as answered (the tile did answer; liveness is not the question).
 */
void drop_unsealed(CoordState& st, VisionCoordStats& stats, const udn::FtMessage& m) noexcept {
  ++stats.results_unsealed;
  const std::uint32_t frame = m.data_words > 1U ? m.data[1] : 0U;
  const std::uint32_t unit = m.data_words > 2U ? m.data[2] : 0xFFFF'FFFFU;
  const std::uint32_t n = m.data_words > kResultHeaderWords ? (m.data_words - kResultHeaderWords) / kMatchWords : 0U;
  if (st.busy && frame == st.frame.seq && unit < unit_count_of(st) && !st.units[unit].answered &&
      st.units[unit].tile == m.source) {
    st.units[unit].answered = true;
    ++stats.units_answered;
  }
  trn::report(ev::kResultSealBroken, m.source, ev::kSealVisionResult, frame, n);
}

void take_result(CoordState& st, VisionCoordStats& stats, const udn::FtMessage& m) noexcept {
  Inbox in{st, stats, m};
  const std::span<const std::uint32_t> words(m.data.data(), m.data_words);
  // A unit's result is checked against the seal its tile took as it computed it, before anything of it is
  // read; a word 0 that is no kind of this channel is a result whose tag changed.
  const bool result = !words.empty() && words[0] == kResultMsg.info.tag;
  if ((result && !result_sealed(words)) || fdir::msg::dispatch(kResultHandlers, words, in) != fdir::msg::Dispatch::kTaken) {
    drop_unsealed(st, stats, m);
  }
}

void drain_results(CoordState& st, VisionCoordStats& stats) noexcept {
  udn::FtMessage m{};
  for (std::uint32_t i = 0; i < kDrainPerPass && udn::endpoint_receive(kChanResult, m) == udn::FtError::kOk; ++i) {
    take_result(st, stats, m);
  }
}

/**
 * The prior at @p t_s from the newest solution at least cfg.prior_lag_s older,
 * moved along its velocity. The lag makes the choice independent of when
 * solutions arrive (a simplex filter's come a job sooner than a voted one),
 * so the same solutions give the same prior.
 */
bool prior_at(const CoordState& st, double t_s, vision::PosePrior& out) noexcept {
  const std::uint32_t have = st.nav_count < kNavRing ? st.nav_count : kNavRing;
  const filter::NavOutput* best = nullptr;
  for (std::uint32_t i = 0; i < have; ++i) {
    const filter::NavOutput& o = st.nav[i];
    if (o.t_s <= t_s - st.set->s.prior_lag_s + 1e-9 && (best == nullptr || o.t_s > best->t_s)) {
      best = &o;
    }
  }
  if (best == nullptr || t_s - best->t_s > st.set->s.max_prior_age_s || (best->flags & filter::kNavFinite) == 0U) {
    return false;
  }
  // The filter said it was finite: a value that is not changed in this tile's RAM (the ring).
  bool finite = std::isfinite(best->t_s);
  for (std::size_t i = 0; i < 3U; ++i) {
    finite = finite && std::isfinite(best->p_m[i]) && std::isfinite(best->v_mps[i]) && best->var_diag[i] >= 0.0 &&
             best->var_diag[6U + i] >= 0.0 && std::isfinite(best->var_diag[i]) && std::isfinite(best->var_diag[6U + i]);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    finite = finite && std::isfinite(best->q_mb_wxyz[i]);
  }
  if (!finite) {
    coord_repaired(CoordPart::kPrior, static_cast<std::uint32_t>(best - st.nav.data()), best->flags);
    return false;
  }
  const double dt = t_s - best->t_s;
  out.t_s = t_s;
  for (std::size_t i = 0; i < 3U; ++i) {
    out.p_m[i] = best->p_m[i] + best->v_mps[i] * dt;
    out.sigma_p_m[i] = std::sqrt(best->var_diag[i]);
    out.sigma_att_rad[i] = std::sqrt(best->var_diag[6U + i]);
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    out.q_mb[i] = best->q_mb_wxyz[i];
  }
  return true;
}

// ------------------------------------------------------------------ coordinator: a frame

/** The coarse stage's correlation in one piece on this tile (by its configured method: the transform). */
vision::Status coarse_one_piece(CoordState& st, const vision::CoarsePrepared& prep, vision::MatchResult& out) noexcept {
  vision::CorrelatorBuffers buf = st.coarse_ws->coarse.corr.buffers();
  buf.transform = st.coarse_ws->coarse.transform.buffers();
  bsp::Work work{};
  const vision::Status s = vision::correlate(prep.tmpl, prep.window, st.set->s.coarse.coarse.quality, buf, out, work,
                                             vision::CorrelationTaps{}, st.set->s.coarse.coarse.method);
  bsp::consume(work);
  report_correlation_checks(out.check_failed, out.recomputes, out.first_check, kCoarseLandmark, st.frame.seq);
  return s;
}

/** Copies @p j's rows from @p slot into the gathered surface; true when the copy's digest is @p digest. */
bool gather_band(CoordState& st, const CoarseBandJob& j, const CoarseBandSlot& slot, std::uint64_t digest) noexcept {
  const std::int32_t sw = st.gather.surface.width;
  if (j.row0 < 0 || j.rows < 0 || j.row0 > st.gather.surface.height - j.rows ||
      static_cast<std::int64_t>(sw) * j.rows > kCoarseBandValues) {
    coord_repaired(CoordPart::kBandRows, static_cast<std::uint32_t>(&j - st.bands.data()),
                   static_cast<std::uint32_t>(j.rows));
    return false;  // rows no band has: the band is computed again here, from its rows as dealt
  }
  const auto values = static_cast<std::size_t>(sw) * static_cast<std::size_t>(j.rows);
  float* dst = st.gather.surface.row(j.row0);
  std::copy_n(slot.surface, values, dst);
  bsp::Work work{};
  work.mem_words += 2U * values;
  const bool same = vision::surface_digest(vision::ConstImageF32{dst, sw, j.rows, sw}, work) == digest;
  bsp::consume(work);
  return same;
}

/** A tile's answer for a band of this frame: its rows gathered when its checks passed and the copy matches. */
void take_band_done(CoordState& st, VisionCoordStats& stats, bsp::TileId from, const CoarseBandDone& d) noexcept {
  std::uint32_t j = 0;
  const std::uint32_t bands = band_count_of(st);
  while (j < bands && !(st.bands[j].row0 == d.row0 && st.bands[j].rows == d.rows && st.bands[j].tile == from &&
                                !st.bands[j].answered)) {
    ++j;
  }
  if (j == bands || d.frame != st.frame.seq) {
    ++stats.results_late;
    return;
  }
  CoarseBandJob& b = st.bands[j];
  b.answered = true;
  --st.gather.pending;
  const CoarseBandSlot* slot = coarse_band_slot(j);
  if (d.status != 0U || d.check_failed || slot == nullptr) {
    b.why = BandRedo::kFailed;
    return;
  }
  if (!gather_band(st, b, *slot, d.digest)) {
    b.why = BandRedo::kCopyWrong;
    return;
  }
  b.done = true;
  st.gather.digest += d.digest;
  st.gather.flat_windows += d.flat_windows;
  st.gather.recomputes += d.recomputes;
}

/** Cycles of @p rows rows of @p prep's surface computed spatially (a band's work) by the cost model. */
bsp::Cycles band_cycles(const vision::CoarsePrepared& prep, std::int32_t rows) noexcept {
  return bsp::cost_of(vision::ncc_surface_work(prep.tmpl.width, prep.tmpl.height, prep.surface_w, rows));
}

/** Cycles of @p prep's whole surface by the coordinator's configured method, by the cost model. */
bsp::Cycles one_piece_cycles(const CoordState& st, const vision::CoarsePrepared& prep) noexcept {
  if (st.set->s.coarse.coarse.method != vision::CorrelationMethod::kTransform) {
    return band_cycles(prep, prep.surface_h);
  }
  bsp::Work whole = vision::ncc_score_work(prep.surface_w, prep.surface_h);
  whole += vision::transform_dots_work(prep.tmpl.width, prep.tmpl.height, prep.window.width, prep.window.height);
  return bsp::cost_of(whole);
}

/** The vision tiles that answer and are trusted, as indices into the tile list; @return how many. */
std::uint32_t band_workers(const CoordState& st, std::array<std::uint32_t, kMaxVisionTiles>& working) noexcept {
  std::uint32_t n = 0;
  for (std::uint32_t i = 0; i < st.cfg->vision_count; ++i) {
    if (st.live.misses[i] < st.live.config.suspect_after_misses && fdir::result_trust_used(st.trust, i)) {
      working[n] = i;
      ++n;
    }
  }
  return n;
}

/**
 * Sends @p w to working tile @p first, or the next one the network takes it
 * for (a tile out of the fault map refuses at once). @return the working
 * index it went to; @p n_working when none took it.
 */
std::uint32_t send_band(const CoordState& st, const std::array<std::uint32_t, kMaxVisionTiles>& working,
                        std::uint32_t n_working, std::uint32_t first,
                        const std::array<std::uint32_t, kCoarseBandWords>& w) noexcept {
  for (std::uint32_t k = 0; k < n_working; ++k) {
    const std::uint32_t at = (first + k) % n_working;
    if (udn::endpoint_send(st.tiles[working[at]], kChanControl, w, kVisionSendTicks) == udn::FtError::kOk) {
      return at;
    }
  }
  return n_working;
}

/**
 * Deals the rows of @p prep's surface in bands over the vision tiles that
 * answer and are trusted (one band each, more when a slot cannot hold a
 * tile's share) and sends them. @return the bands a tile got at most;
 * 0 when nothing was dealt: no such tile, bands too many for the slots, or
 * so few tiles that their bands in turn cost more than the whole surface
 * on this tile (by the cost model: below about 8 tiles).
 */
std::uint32_t deal_coarse_bands(CoordState& st, VisionCoordStats& stats, const vision::CoarsePrepared& prep) noexcept {
  st.band_count = 0U;
  std::array<std::uint32_t, kMaxVisionTiles> working{};
  const std::uint32_t n_working = band_workers(st, working);
  const std::int32_t rows_max = coarse_band_rows_max(prep);
  const std::int32_t sh = prep.surface_h;
  if (n_working == 0U || rows_max < 1) {
    return 0U;
  }
  const auto need = static_cast<std::uint32_t>((sh + rows_max - 1) / rows_max);
  const std::uint32_t n = need > n_working ? need : n_working;
  // Too few tiles (their bands in turn would take longer than the whole here), or too many bands.
  const auto rows = static_cast<std::int32_t>((static_cast<std::uint32_t>(sh) + n - 1U) / n);
  const bsp::Cycles per_tile_cycles = band_cycles(prep, rows) * ((n + n_working - 1U) / n_working);
  if (n > kMaxCoarseBands || per_tile_cycles >= one_piece_cycles(st, prep)) {
    return 0U;
  }
  st.band_count = n;
  st.gather.pending = 0U;
  std::array<std::uint32_t, kMaxVisionTiles> dealt{};  // bands per working tile
  std::uint32_t per_tile = 1U;
  std::array<std::uint32_t, kCoarseBandWords> w{};
  for (std::uint32_t i = 0; i < n; ++i) {
    CoarseBandJob& b = st.bands[i];
    band_rows(sh, i, n, b.row0, b.rows);
    b = CoarseBandJob{b.row0, b.rows, st.tiles[working[i % n_working]], b.rows == 0, b.rows == 0, BandRedo::kNone};
    if (b.done) {
      continue;
    }
    (void)fdir::msg::encode(kCoarseBandMsg,
                            CoarseBand{st.frame.seq, b.row0, b.rows, prep.window.width, prep.window.height, prep.tx0,
                                       prep.ty0, prep.tmpl.width, prep.tmpl.height, i},
                            w);
    k::checkin();
    const std::uint32_t at = send_band(st, working, n_working, i % n_working, w);
    if (at == n_working) {
      b.answered = true;  // no tile took it: the coordinator computes it
      b.why = BandRedo::kNotSent;
      continue;
    }
    b.tile = st.tiles[working[at]];
    ++dealt[at];
    per_tile = dealt[at] > per_tile ? dealt[at] : per_tile;
    ++stats.coarse_bands_sent;
    ++st.gather.pending;
  }
  return per_tile;
}

/**
 * Ticks to wait for the bands: twice what @p per_tile bands of the largest
 * size cost a tile by the cost model, plus the network's and the tiles' idle
 * poll (about 36 ticks with 40 tiles).
 */
k::Ticks band_wait_ticks(const vision::CoarsePrepared& prep, std::int32_t rows, std::uint32_t per_tile) noexcept {
  constexpr k::Ticks kSlackTicks = 10;
  const bsp::Cycles band = band_cycles(prep, rows);
  const bsp::Cycles tick = bsp::tick_cycles();
  const auto ticks = static_cast<k::Ticks>(tick == 0U ? 0U : (band + tick - 1U) / tick);
  return k::Ticks{2U} * per_tile * ticks + kSlackTicks;
}

/** Each of the @p bands bands' rows are its rows as dealt (deal_coarse_bands); one that is not is computed again here. */
void check_band_rows(CoordState& st, std::int32_t surface_h, std::uint32_t bands) noexcept {
  for (std::uint32_t j = 0; j < bands; ++j) {
    std::int32_t row0 = 0;
    std::int32_t rows = 0;
    band_rows(surface_h, j, bands, row0, rows);
    if (st.bands[j].row0 != row0 || st.bands[j].rows != rows) {
      coord_repaired(CoordPart::kBandRows, j, static_cast<std::uint32_t>(st.bands[j].rows));
      st.bands[j].row0 = row0;
      st.bands[j].rows = rows;
      st.bands[j].done = false;  // gathered from rows it was not dealt
    }
  }
}

/**
 * The bands not gathered, computed here: band by band, or in one piece when
 * that costs less. @p settled: @p out is the stage's result already (the
 * surface correlated in one piece, or a band still wrong here: rejected).
 */
vision::Status redo_bands(CoordState& st, VisionCoordStats& stats, const vision::CoarsePrepared& prep,
                          vision::MatchResult& out, bool& settled) noexcept {
  settled = false;
  std::int32_t missing = 0;
  const std::uint32_t bands = band_count_of(st);
  check_band_rows(st, prep.surface_h, bands);
  for (std::uint32_t j = 0; j < bands; ++j) {
    CoarseBandJob& b = st.bands[j];
    if (b.done) {
      continue;
    }
    const BandRedo why = b.answered ? b.why : BandRedo::kNoAnswer;
    trn::report(ev::kCoarseBandRedone, b.tile, static_cast<std::uint32_t>(why),
                 static_cast<std::uint32_t>(b.row0), st.frame.seq);
    ++stats.coarse_bands_redone;
    missing += b.rows;
  }
  // Band by band (spatially), or the whole surface by the configured method (the transform)
  // when that costs less by the cost model: it gives the same surface.
  if (missing > 0 && one_piece_cycles(st, prep) < band_cycles(prep, missing)) {
    settled = true;
    ++stats.coarse_one_piece;
    return coarse_one_piece(st, prep, out);
  }
  CoarseBandSlot* own = coarse_band_slot(kCoordinatorBandSlot);
  for (std::uint32_t j = 0; j < bands && own != nullptr; ++j) {
    CoarseBandJob& b = st.bands[j];
    if (b.done) {
      continue;
    }
    vision::BandResult r{};
    bsp::Work work{};
    const vision::Status s = vision::correlate_band(prep.tmpl, prep.window, b.row0, b.rows, own->buffers(), r, work);
    bsp::consume(work);
    report_correlation_checks(r.check_failed, r.recomputes, r.first_check, kCoarseLandmark, st.frame.seq);
    if (s != vision::Status::kOk) {
      return s;
    }
    if (r.check_failed || !gather_band(st, b, *own, r.digest)) {
      out = vision::MatchResult{};
      out.check_failed = true;
      out.first_check = r.first_check != vision::CorrelationCheck::kNone ? r.first_check : vision::CorrelationCheck::kSurface;
      out.peak.reason = vision::Reject::kCheckFailed;  // nothing of a band still wrong is used
      settled = true;
      return vision::Status::kOk;
    }
    b.done = true;
    st.gather.digest += r.digest;
    st.gather.flat_windows += r.flat_windows;
    st.gather.recomputes += r.recomputes;
  }
  return own == nullptr ? vision::Status::kBadInput : vision::Status::kOk;
}

/**
 * The coarse stage's correlation spread over the vision tiles: each computes
 * and checks a band of the surface's rows in its slot, the coordinator copies
 * each band it is told is done into the surface and holds the copy to the
 * band's digest, computes itself what did not come back right in time
 * (kCoarseBandRedone), and searches the gathered surface (correlate_gathered():
 * its digest again, the peak's scores again). The match is the one-piece
 * correlation's bit for bit.
 */
vision::Status coarse_in_bands(CoordState& st, VisionCoordStats& stats, const vision::CoarsePrepared& prep,
                               vision::MatchResult& out) noexcept {
  vision::CorrelatorBuffers buf = st.coarse_ws->coarse.corr.buffers();
  st.gather = CoarseGather{vision::ImageF32{buf.surface, prep.surface_w, prep.surface_h, prep.surface_w}, 0U, 0, 0U, 0U};
  const std::uint32_t per_tile = deal_coarse_bands(st, stats, prep);
  if (per_tile == 0U) {
    ++stats.coarse_one_piece;
    return coarse_one_piece(st, prep, out);
  }
  std::int32_t largest = 0;
  for (std::uint32_t j = 0; j < band_count_of(st); ++j) {
    largest = st.bands[j].rows > largest ? st.bands[j].rows : largest;
  }
  const k::Ticks until = k::now_ticks() + band_wait_ticks(prep, largest, per_tile);
  udn::FtMessage m{};
  while (st.gather.pending > 0U && k::now_ticks() < until) {
    for (std::uint32_t i = 0; i < kDrainPerPass && udn::endpoint_receive(kChanResult, m) == udn::FtError::kOk; ++i) {
      CoarseBandDone d{};
      if (fdir::msg::decode(kCoarseBandDoneMsg, std::span<const std::uint32_t>(m.data.data(), m.data_words), d)) {
        take_band_done(st, stats, m.source, d);
      } else {
        take_result(st, stats, m);  // a unit's answer from an earlier frame: late
      }
    }
    drain_nav(st);
    k::checkin();
    if (st.gather.pending > 0U) {
      k::sleep(1);
    }
  }
  bool settled = false;
  const vision::Status s = redo_bands(st, stats, prep, out, settled);
  if (s != vision::Status::kOk || settled) {
    return s;
  }
  bsp::Work work{};
  const vision::Status g =
      vision::correlate_gathered(prep.tmpl, prep.window, st.set->s.coarse.coarse.quality, st.gather.surface.as_const(),
                                 st.gather.digest, st.gather.flat_windows, st.gather.recomputes, buf, out, work);
  bsp::consume(work);
  report_correlation_checks(out.check_failed, 0U, out.first_check, kCoarseLandmark, st.frame.seq);
  return g;
}

/** Runs the coarse stage when the prior is too uncertain; false when the frame cannot go on. */
bool coarse_if_needed(CoordState& st, VisionCoordStats& stats, const vision::ConstImageU8& image,
                      vision::PosePrior& prior) noexcept {
  const double sigma_h = std::sqrt(prior.sigma_p_m[0] * prior.sigma_p_m[0] + prior.sigma_p_m[1] * prior.sigma_p_m[1]);
  if (sigma_h <= st.set->s.coarse_above_sigma_m) {
    return true;
  }
  ++stats.coarse_runs;
  const bsp::Cycles start = bsp::now();
  bsp::Work work{};
  vision::CoarseFrameResult res{};
  vision::CoarseFrameStage stage{};
  vision::Status s = vision::coarse_frame_prepare(image, st.set->s.camera, prior, st.coarse_map, st.set->s.coarse,
                                                  *st.coarse_ws, stage, res, work);
  bsp::consume(work);
  if (s != vision::Status::kOk || !stage.search) {
    return false;
  }
  vision::MatchResult cm{};
  s = coarse_in_bands(st, stats, stage.prep, cm);
  if (s != vision::Status::kOk) {
    return false;
  }
  bsp::Work finish{};
  vision::coarse_frame_finish(st.set->s.camera, st.coarse_map, st.set->s.coarse, stage, cm, res, finish);
  bsp::consume(finish);
  const bsp::Cycles took = bsp::now() - start;
  stats.max_coarse_cycles = took > stats.max_coarse_cycles ? took : stats.max_coarse_cycles;
  if (!res.accepted) {
    return false;
  }
  ++stats.coarse_accepted;
  prior.p_m[0] += res.dp_m[0];
  prior.p_m[1] += res.dp_m[1];
  prior.sigma_p_m[0] = res.sigma_m;
  prior.sigma_p_m[1] = res.sigma_m;
  Match& m = st.matches[0];
  m = res.match;
  m.landmark = kCoarseLandmark;
  m.tile = static_cast<std::uint16_t>(bsp::current_tile());
  m.frame = st.frame.seq;
  m.t_s = st.frame.t_s;
  st.match_count = 1;
  return true;
}

/** Whether vision tile @p i gets work this frame (suspects only on their probe frames). */
bool tile_gets_work(const CoordState& st, std::uint32_t i) noexcept {
  return fdir::liveness_gets_work(st.live, i, st.frames_planned);
}

/** Packs @p wu (its landmarks set) as unit @p unit of the current frame, from @p prior. */
void pack_frame_unit(const CoordState& st, const vision::PosePrior& prior, std::uint32_t unit, WorkUnit& wu,
                     std::span<std::uint32_t> w) noexcept {
  wu.frame = st.frame.seq;
  wu.unit = unit;
  wu.t_s = st.frame.t_s;
  wu.ddr_offset = st.frame.ddr_offset;
  wu.width_px = st.frame.width_px;
  wu.height_px = st.frame.height_px;
  for (std::size_t i = 0; i < 3U; ++i) {
    wu.p_m[i] = prior.p_m[i];
  }
  for (std::size_t i = 0; i < 4U; ++i) {
    wu.q_mb_wxyz[i] = prior.q_mb[i];
  }
  (void)fdir::msg::encode(kUnitMsg, wu, w);
}

/** Spreads the planned landmarks over the working tiles (round robin) and sends the units. */
void distribute(CoordState& st, VisionCoordStats& stats, const vision::PosePrior& prior, std::uint32_t planned) {
  std::array<std::uint32_t, kMaxVisionTiles> working{};
  std::uint32_t n_working = 0;
  for (std::uint32_t i = 0; i < st.cfg->vision_count; ++i) {
    if (tile_gets_work(st, i)) {
      working[n_working] = i;
      ++n_working;
    }
  }
  st.unit_count = n_working;
  const std::uint32_t cap = n_working * kMaxLandmarksPerUnit;
  const std::uint32_t used = planned < cap ? planned : cap;
  std::array<std::uint32_t, kUnitHeaderWords + kMaxLandmarksPerUnit> w{};
  for (std::uint32_t u = 0; u < n_working; ++u) {
    Unit& unit = st.units[u];
    unit = Unit{st.tiles[working[u]], 0U, false, false};
    std::uint32_t n = 0;
    WorkUnit wu{};
    for (std::uint32_t j = u; j < used && n < kMaxLandmarksPerUnit; j += n_working) {
      const vision::PlannedLandmark& p = st.planned[j];
      wu.landmark[n] = p.landmark;
      wu.radius_px[n] = static_cast<std::uint16_t>(p.radius_px);
      ++n;
    }
    wu.n = n;
    unit.planned = n;
    if (n == 0U) {
      unit.answered = true;  // nothing to do: not waited for, not a miss
      continue;
    }
    pack_frame_unit(st, prior, u, wu, w);
    const udn::FtError e = udn::endpoint_send(unit.tile, kChanControl,
                                     std::span<const std::uint32_t>(w.data(), kUnitHeaderWords + n), kVisionSendTicks);
    if (e == udn::FtError::kOk) {
      unit.sent = true;
      ++stats.units_sent;
      stats.planned_total += n;
    } else {
      // Not sent (no route: the tile is out of the fault map, or the network
      // refused): it counts as a miss, so its share moves to the others.
      unit.sent = true;
      ++stats.units_send_failed;
    }
  }
}

/**
 * The settings in RAM against their seal (@p when: ev::kSettingsAtStart as a frame starts,
 * ev::kSettingsAtBatch before its batch leaves). Changed: built again from the image and reported
 * (tile_settings_bad, with the matches @p dropped because of it). @return true if they were intact.
 */
bool check_settings(CoordState& st, VisionCoordStats& stats, std::uint32_t when, std::uint32_t frame,
                    std::uint32_t dropped) noexcept {
  bsp::Work work{};
  const bool intact = settings_intact(*st.set, work);
  if (!intact) {
    settings_seal(*st.set, coord_settings_of(*st.cfg), work);
    ++stats.settings_rebuilt;
    trn::report(ev::kTileSettingsBad, frame, ev::kSettingsOfCoordinator, when, dropped);
  }
  bsp::consume(work);
  return intact;
}

void start_frame(CoordState& st, VisionCoordStats& stats) noexcept {
  (void)check_settings(st, stats, ev::kSettingsAtStart, st.pending.seq, 0U);
  st.frame = st.pending;
  st.have_pending = false;
  st.match_count = 0;
  st.unit_count = 0;
  vision::PosePrior prior{};
  if (st.frame.t_s < st.ready_s) {
    ++stats.frames_before_ready;  // see frames_before_ready
    return;
  }
  if (st.frame.width_px != st.set->s.camera.width_px || st.frame.height_px != st.set->s.camera.height_px) {
    // The I/O tile announces frames of the camera's size only (its message is checked on the way).
    coord_repaired(CoordPart::kFrameSize, st.frame.seq, st.frame.width_px);
    ++stats.frames_skipped;
    return;
  }
  const std::uint64_t bytes = static_cast<std::uint64_t>(st.frame.width_px) * st.frame.height_px;
  const std::uint8_t* pixels = ddr_at(st.frame.ddr_offset, bytes);
  if (st.frame.status != 0U || pixels == nullptr || !prior_at(st, st.frame.t_s, prior)) {
    ++stats.frames_skipped;
    return;
  }
  st.busy = true;
  st.frame_start = bsp::now();
  st.deadline = k::now_ticks() + seconds_to_ticks(st.set->s.deadline_s);
  const vision::ConstImageU8 image{pixels, static_cast<std::int32_t>(st.frame.width_px),
                                   static_cast<std::int32_t>(st.frame.height_px),
                                   static_cast<std::int32_t>(st.frame.width_px)};
  const std::uint32_t coarse_before = stats.coarse_runs;
  if (!coarse_if_needed(st, stats, image, prior)) {
    st.busy = false;
    ++stats.frames_skipped;
    return;
  }
  // The job that takes the batch, from the capture (in ticks, like the frame logic).
  st.prior = prior;
  const auto capture_job = static_cast<std::uint32_t>(
      std::floor(st.frame.t_s * static_cast<double>(kTicksPerSecond) / kFilterPeriodTicks + 1e-9));
  st.apply_job = capture_job + (stats.coarse_runs != coarse_before ? kCoarseApplyJobs : kFineApplyJobs);
  bsp::Work work{};
  std::uint32_t planned = 0;
  if (vision::plan_frame(*st.table, st.fine, st.set->s.camera, prior, st.set->s.plan, st.planned.data(),
                         static_cast<std::uint32_t>(st.planned.size()), planned, st.plan_scratch, work) !=
      vision::Status::kOk) {
    planned = 0;
  }
  bsp::consume(work);
  ++stats.frames_processed;
  distribute(st, stats, prior, planned);
  ++st.frames_planned;
}

/**
 * Orders the fine matches by landmark (then tile and pixel), then deals them
 * round the image's quadrants (deal_by_quadrant()): results come in whatever
 * order the network brings them, and the filter's result depends on the
 * order it applies them. The coarse match, when there is one, stays first.
 * Seeds 11 and 76 (docs/FILTER.md, "Fix and convergence"): dealt, the worst
 * output inside the coarse frame's batch went from 1.37 to 0.99 and from 1.36
 * to 0.54 of its 3-sigma.
 */
void order_matches(CoordState& st) noexcept {
  const std::uint32_t count = match_count_of(st);
  const std::uint32_t first = (count > 0U && st.matches[0].landmark == kCoarseLandmark) ? 1U : 0U;
  if (count <= first + 1U) {
    return;
  }
  const auto before = [](const Match& a, const Match& b) noexcept {
    if (a.landmark != b.landmark) {
      return a.landmark < b.landmark;
    }
    if (a.tile != b.tile) {
      return a.tile < b.tile;
    }
    return a.u_px != b.u_px ? a.u_px < b.u_px : a.v_px < b.v_px;
  };
  std::sort(st.matches.begin() + first, st.matches.begin() + count, before);
  // The scratch holds every place of the matches array, so the deal is never refused; were it,
  // the sorted order would stand (a valid order, only not dealt) and the deal's work is not charged.
  const bool dealt = deal_by_quadrant(std::span<Match>(st.matches.data(), count), first,
                                      st.set->s.camera.cx_px, st.set->s.camera.cy_px, st.order, st.placed);
  // About n log2 n (n <= 201: log2 n <= 8) compares, and as many moves of 25-word matches; the deal
  // tests each match's quadrant once per quadrant and moves each match once more.
  const std::uint64_t n = count;
  const std::uint64_t n_log_n = 8ULL * n;
  const std::uint64_t dealt_n = dealt ? n : 0U;
  bsp::consume(bsp::Work{4ULL * n_log_n + 8ULL * dealt_n, 0U, 8ULL * dealt_n, 0U, 25ULL * (n_log_n + dealt_n)});
}

void send_batch(CoordState& st, VisionCoordStats& stats) noexcept {
  const std::uint32_t count = match_count_of(st);
  if (count == 0U || st.cfg->filter_tile == bsp::kNoTile) {
    return;
  }
  const std::uint32_t parts = (count + kMatchesPerPart - 1U) / kMatchesPerPart;
  std::array<std::uint32_t, kMatchHeaderWords + kMatchesPerPart * kMatchWords> w{};
  for (std::uint32_t part = 0; part < parts; ++part) {
    const std::uint32_t first = part * kMatchesPerPart;
    const std::uint32_t left = count - first;
    const std::uint32_t n = left < kMatchesPerPart ? left : kMatchesPerPart;
    const std::size_t words = fdir::msg::encode(kMatchesMsg, MatchPart{st.frame.seq, part, parts, n, st.apply_job, 0U}, w);
    for (std::uint32_t i = 0; i < n; ++i) {
      (void)fdir::msg::encode(kMatchRecord, st.matches[first + i],
                              std::span<std::uint32_t>(w.data() + kMatchHeaderWords + static_cast<std::size_t>(i) * kMatchWords,
                                                       kMatchWords));
    }
    // Sealed as made: the filter checks the seal where it takes the matches.
    seal_result(std::span<std::uint32_t>(w.data(), words));
    // Each part as sent is a published result: where a corrupted batch is injected.
    (void)bsp::publish_filter(kCoordinatorBatchChannel, w.data(), words * sizeof(std::uint32_t));
    if (udn::endpoint_send(udn::endpoint_role_tile(kSlotFilter, st.cfg->filter_tile), kChanMatches,
                           std::span<const std::uint32_t>(w.data(), words), kVisionSendTicks) != udn::FtError::kOk) {
      ++stats.batch_send_failed;
    }
  }
}

/** Reports vision tile @p i to the tile-health supervisor: reset it, or replace it by a spare. */
void ask_supervisor(const CoordState& st, VisionCoordStats& stats, std::uint32_t i, fdir::TrustAction a) noexcept {
  if (st.cfg->health_tile == bsp::kNoTile || a == fdir::TrustAction::kNone) {
    return;
  }
  const bool replace = a == fdir::TrustAction::kReplace;
  std::array<std::uint32_t, fdir::kResultsBadWords> w{};
  const fdir::ResultsAction action = replace ? fdir::ResultsAction::kReplace : fdir::ResultsAction::kReset;
  (void)fdir::msg::encode(fdir::kResultsBadMsg,
                          fdir::ResultsBad{bsp::current_tile(), st.tiles[i], action, kSlotVisionPool, kChanControl}, w);
  if (udn::endpoint_send(udn::endpoint_role_tile(kSlotTrnSupervisor, st.cfg->health_tile), udn::kFtChanHealth, w,
                         kVisionSendTicks) == udn::FtError::kOk) {
    ++(replace ? stats.replacements_asked : stats.resets_asked);
  }
}

/**
 * Each tile's checked and failed matches of the frame, and the residuals of those that passed, to its
 * result trust; asks for resets and replacements. Keeps the largest bias of a trusted tile's window.
 */
void judge_tiles(CoordState& st, VisionCoordStats& stats, std::uint32_t first, const vision::ConsistencyResult& r) noexcept {
  std::array<std::uint16_t, kMaxVisionTiles> n_checked{};
  std::array<std::uint16_t, kMaxVisionTiles> n_failed{};
  std::array<fdir::RoundResiduals, kMaxVisionTiles> res{};
  const std::uint32_t count = match_count_of(st);
  for (std::uint32_t k = first; r.checked && k < count && k - first < st.failed.size(); ++k) {
    const std::uint32_t i = tile_index(st, st.matches[k].tile);
    if (i < st.cfg->vision_count) {
      const bool failed = st.failed[k - first];
      ++n_checked[i];
      n_failed[i] = static_cast<std::uint16_t>(n_failed[i] + (failed ? 1U : 0U));
      if (!failed) {
        fdir::result_trust_add_residual(st.trust, res[i], st.cws.du[k - first], st.cws.dv[k - first]);
        res[i].scale = r.scale_px;
      }
    }
  }
  for (std::uint32_t i = 0; i < st.cfg->vision_count; ++i) {
    ask_supervisor(st, stats, i, fdir::result_trust_round(st.trust, i, n_checked[i], n_failed[i], res[i]));
    if (fdir::result_trust_used(st.trust, i)) {
      stats.tile_bias_max_px = std::max(stats.tile_bias_max_px, fdir::result_trust_bias_px(st.trust, i));
    }
  }
  fdir::result_trust_close_round(st.trust);
  // The tally, then the window sums and one square root per tile.
  bsp::consume(bsp::Work{4ULL * kMaxVisionTiles * (count + 1U), 0U, 2ULL * count + 8ULL * kMaxVisionTiles * 3U,
                         kMaxVisionTiles, 0U});
}

/** Each fine match of the batch (from @p first) weighed by the frame's prior attitude (weighed_sigma_px()). */
void weigh_by_prior(CoordState& st, std::uint32_t first) noexcept {
  const double extra = prior_attitude_px(st.prior, st.set->s.sigma_px_per_prior_deg);
  const std::uint32_t count = match_count_of(st);
  if (extra > 0.0) {
    for (std::uint32_t k = first; k < count; ++k) {
      const double s = st.matches[k].sigma_px;
      st.matches[k].sigma_px = std::sqrt(s * s + extra * extra);
    }
  }
  bsp::consume(bsp::Work{0U, 0U, 12ULL + 3ULL * count, 1ULL + count, 0U});  // the norm once, a root per match
}

/**
 * Checks the frame's fine matches against the pose they fit together, judges
 * each tile by its share of failed matches, and leaves out of the batch the
 * matches of the tiles not trusted now (matches_unused) and the failed ones.
 */
void check_frame(CoordState& st, VisionCoordStats& stats) noexcept {
  const std::uint32_t count = match_count_of(st);
  const std::uint32_t first = (count > 0U && st.matches[0].landmark == kCoarseLandmark) ? 1U : 0U;
  bsp::Work work{};
  vision::ConsistencyResult r{};
  if (vision::check_match_consistency(st.set->s.camera, st.prior, st.matches.data() + first, count - first,
                                      st.set->s.consistency, st.failed.data(), st.cws, r, work) != vision::Status::kOk) {
    r.checked = false;
  }
  bsp::consume(work);
  if (r.checked) {
    ++stats.frames_checked;
    stats.matches_checked += count - first;
    stats.matches_failed += r.failed;
    stats.residual_scale_max_px = std::max(stats.residual_scale_max_px, r.scale_px);
  }
  judge_tiles(st, stats, first, r);
  std::uint32_t kept = first;
  for (std::uint32_t k = first; k < count; ++k) {
    if (!fdir::result_trust_used(st.trust, tile_index(st, st.matches[k].tile))) {
      ++stats.matches_unused;
    } else if (!(r.checked && k - first < st.failed.size() && st.failed[k - first])) {
      st.matches[kept] = st.matches[k];
      ++kept;
    }  // else failed (counted in matches_failed): a filter whose covariance is still wide could take it
  }
  st.match_count = kept;
  stats.tiles_untrusted = fdir::result_trust_untrusted(st.trust);
  weigh_by_prior(st, first);  // after the check, which judges the matches by their own sigmas
}

/** The frame's outcome for the vision supervisor: how many tiles can still take work. */
void send_status(const CoordState& st, VisionCoordStats& stats, std::uint32_t lost) noexcept {
  // Healthy: answered every unit of its last frame with work (no miss in a row: not isolated
  // either) and trusted.
  const std::uint32_t n = st.cfg->vision_count;
  std::uint32_t healthy = 0U;
  for (std::uint32_t i = 0; i < n && i < kMaxVisionTiles; ++i) {
    healthy += (st.live.misses[i] == 0U && fdir::result_trust_used(st.trust, i)) ? 1U : 0U;
  }
  stats.healthy_tiles = healthy;
  if (st.cfg->vision_supervisor_tile == bsp::kNoTile) {
    return;
  }
  std::array<std::uint32_t, kVisionStatusWords> w{};
  (void)fdir::msg::encode(kVisionStatusMsg, VisionStatus{st.frame.seq, stats.healthy_tiles, n, lost, st.rate_div}, w);
  // Sent right after the frame's batch, the status meets the batch's back-pressure: it waits for
  // the network as the batch's parts do (sent without waiting, three of five statuses were refused
  // in FDIR-SUP-13's flight and the half rate was judged met 6 s later). One still lost is a missing
  // verdict: the supervisor judges the next frame's.
  if (udn::endpoint_send(udn::endpoint_role_tile(kSlotVisionSupervisor, st.cfg->vision_supervisor_tile), kChanControl, w,
                         kVisionSendTicks) != udn::FtError::kOk) {
    ++stats.status_send_failed;
  }
}

/**
 * Leaves out of the frame each match holding a value no match can have (not finite: its
 * order would be no order, its weight no weight), and says so: an upset of this tile's RAM,
 * or of the vision tile's before it sent it.
 */
void drop_wrong_matches(CoordState& st) noexcept {
  const std::uint32_t count = match_count_of(st);
  if (count != st.match_count) {
    coord_repaired(CoordPart::kMatchCount, 0U, st.match_count);
  }
  std::uint32_t kept = 0U;
  for (std::uint32_t k = 0; k < count; ++k) {
    const Match& m = st.matches[k];
    bool finite = std::isfinite(m.u_px) && std::isfinite(m.v_px) && std::isfinite(m.sigma_px) && std::isfinite(m.t_s) &&
                  std::isfinite(m.quality);
    for (std::size_t i = 0; i < 3U; ++i) {
      finite = finite && std::isfinite(m.w_c[i]) && std::isfinite(m.p_m[i]);
    }
    if (!finite) {
      coord_repaired(CoordPart::kMatch, k, m.landmark);
      continue;
    }
    st.matches[kept] = st.matches[k];
    ++kept;
  }
  st.match_count = kept;  // at no emulated cost, like check_coord()
}

/** Closes the frame: misses counted per tile, the batch sent to the filter. */
void finish_frame(CoordState& st, VisionCoordStats& stats) noexcept {
  std::uint32_t lost = 0;
  for (std::uint32_t i = 0; i < st.cfg->vision_count; ++i) {
    const bsp::TileId t = st.tiles[i];
    for (std::uint32_t u = 0; u < unit_count_of(st); ++u) {
      if (st.units[u].tile != t || st.units[u].planned == 0U) {
        continue;
      }
      if (st.units[u].answered) {
        fdir::liveness_answered(st.live, i);
      } else {
        ++lost;
        fdir::liveness_missed(st.live, i);
      }
    }
  }
  stats.units_lost += lost;
  stats.suspect_tiles = fdir::liveness_isolated(st.live);
  // Settings changed during the frame: its matches were planned, checked or weighed with them.
  // The batch is not sent, and the tiles are not judged by it.
  if (!check_settings(st, stats, ev::kSettingsAtBatch, st.frame.seq, match_count_of(st))) {
    st.match_count = 0U;
  }
  drop_wrong_matches(st);
  const std::uint32_t count = match_count_of(st);
  const std::uint32_t fine = count - ((count > 0U && st.matches[0].landmark == kCoarseLandmark) ? 1U : 0U);
  stats.matches_total += fine;
  stats.last_frame_matches = fine;
  order_matches(st);
  check_frame(st, stats);
  send_batch(st, stats);
  trn::report(ev::kFrameDone, fdir::kUnknown, lost, st.frame.seq, fine);
  send_status(st, stats, lost);
  st.busy = false;
  stats.last_frame_cycles = bsp::now() - st.frame_start;
  if (stats.last_frame_cycles > stats.max_frame_cycles) {
    stats.max_frame_cycles = stats.last_frame_cycles;
  }
}

/** The lists the coordinator keeps per vision tile: as its tile list in DDR and its configuration hold them. */
void check_lists(CoordState& st) noexcept {
  const VisionCoordConfig& cfg = *st.cfg;
  const std::uint32_t n = cfg.vision_count;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (st.tiles[i] != st.list->tiles[i]) {
      coord_repaired(CoordPart::kTileList, i, st.tiles[i]);
      st.tiles[i] = st.list->tiles[i];
    }
    if (st.live.tile[i] != st.tiles[i]) {
      coord_repaired(CoordPart::kLiveness, i, st.live.tile[i]);
      st.live.tile[i] = st.tiles[i];
    }
    if (st.trust.tile[i] != st.tiles[i] || st.trust.state[i] > fdir::TrustState::kReplacing) {
      coord_repaired(CoordPart::kTrust, i, static_cast<std::uint32_t>(st.trust.state[i]));
      st.trust.tile[i] = st.tiles[i];
      // A state no worker has: suspect until its clean rounds make it trusted again.
      st.trust.state[i] = st.trust.state[i] > fdir::TrustState::kReplacing ? fdir::TrustState::kSuspect : st.trust.state[i];
    }
  }
  if (st.live.count != n || st.live.config.suspect_after_misses != cfg.liveness.suspect_after_misses ||
      st.live.config.probe_every != cfg.liveness.probe_every) {
    coord_repaired(CoordPart::kLiveness, n, st.live.count);
    st.live.count = n;
    st.live.config = cfg.liveness;
  }
  if (st.trust.count != n || st.trust.config.window != cfg.trust.window ||
      st.trust.config.min_failed != cfg.trust.min_failed || st.trust.config.reset_after != cfg.trust.reset_after ||
      st.trust.config.probation != cfg.trust.probation) {
    coord_repaired(CoordPart::kTrust, n, st.trust.count);
    st.trust.count = n;
    st.trust.config = cfg.trust;
  }
}

/**
 * The coordinator's state in its tile's RAM can take an upset: at each pass every count, index
 * and divisor it follows is checked against what a valid state holds, and one that is off is
 * reported (coord_state_bad) and reset. At no emulated cost, like the endpoint's and the
 * kernel's checks; each use takes its counts bounded as well (rate_div_of() and the others).
 */
void check_coord(CoordState& st) noexcept {
  if (st.rate_div == 0U || st.rate_div > kMaxRateDiv) {
    coord_repaired(CoordPart::kRateDiv, 0U, st.rate_div);
    st.rate_div = 1U;  // the full rate until the vision supervisor says otherwise again
  }
  if (st.band_count > kMaxCoarseBands) {
    coord_repaired(CoordPart::kBandCount, 0U, st.band_count);
    st.band_count = 0U;  // a later band's answer is late; the frame's stage computes its bands itself
  }
  if (st.unit_count > st.cfg->vision_count) {
    coord_repaired(CoordPart::kUnitCount, 0U, st.unit_count);
    st.unit_count = st.cfg->vision_count;
  }
  if (st.match_count > st.matches.size()) {
    coord_repaired(CoordPart::kMatchCount, 0U, st.match_count);
    st.match_count = 0U;  // the frame's matches are lost: which of them were its own is not known
  }
  check_lists(st);
  const k::Ticks now = k::now_ticks();
  if (st.busy && st.deadline > now + seconds_to_ticks(st.set->s.deadline_s)) {
    coord_repaired(CoordPart::kDeadline, 0U, static_cast<std::uint32_t>(st.deadline));
    st.deadline = now;  // the frame closes now with what came back
  }
  // In the frames' time, as vision_coord_main() sets it.
  const double now_s = static_cast<double>(bsp::now()) / static_cast<double>(bsp::tick_cycles()) *
                       (1.0 / static_cast<double>(kTicksPerSecond));
  if (!(st.ready_s <= now_s)) {  // also not a number
    coord_repaired(CoordPart::kReadyTime, 0U, static_cast<std::uint32_t>(now));
    st.ready_s = now_s;
  }
}

bool all_answered(const CoordState& st) noexcept {
  for (std::uint32_t u = 0; u < unit_count_of(st); ++u) {
    if (st.units[u].sent && !st.units[u].answered) {
      return false;
    }
  }
  return true;
}

}  // namespace

const bsp::ControlLayout& vision_coord_state_layout() noexcept { return kCoordLayout; }

CoordSettings coord_settings_of(const VisionCoordConfig& cfg) noexcept {
  CoordSettings s{};
  s.camera = cfg.camera;
  s.plan = cfg.plan;
  s.coarse = cfg.coarse;
  s.consistency = cfg.consistency;
  s.coarse_above_sigma_m = cfg.coarse_above_sigma_m;
  s.deadline_s = cfg.deadline_s;
  s.prior_lag_s = cfg.prior_lag_s;
  s.max_prior_age_s = cfg.max_prior_age_s;
  s.sigma_px_per_prior_deg = cfg.sigma_px_per_prior_deg;
  return s;
}

double prior_attitude_px(const vision::PosePrior& prior, double px_per_deg) noexcept {
  constexpr double kDegPerRad = 57.29577951308232;
  const double* sa = prior.sigma_att_rad;
  const double att_deg = std::sqrt(sa[0] * sa[0] + sa[1] * sa[1] + sa[2] * sa[2]) * kDegPerRad;
  return (px_per_deg > 0.0 && std::isfinite(att_deg)) ? px_per_deg * att_deg : 0.0;
}

double weighed_sigma_px(double sigma_px, const vision::PosePrior& prior, double px_per_deg) noexcept {
  const double extra = prior_attitude_px(prior, px_per_deg);
  return extra > 0.0 ? std::sqrt(sigma_px * sigma_px + extra * extra) : sigma_px;
}

void vision_coord_main(void* arg) noexcept {
  const bsp::TileId self = bsp::current_tile();
  const auto* cfg = static_cast<const VisionCoordConfig*>(arg);
  bsp::MemError err = bsp::MemError::kOk;
  auto* st = bsp::carve_control_array<CoordState>(bsp::Region{self}, 1, kVisionCoordCarve, &err, &kCoordLayout);
  // The counters' record after the state: the state keeps the place it had before they were a record.
  VisionCoordStats* const counters =
      err == bsp::MemError::kOk ? bsp::carve_record(bsp::Region{self}, kVisionCoordStatsRecord, &err) : nullptr;
  if (cfg == nullptr || cfg->vision_count > kMaxVisionTiles || counters == nullptr || !udn::endpoint_wait_ready(100)) {
    (void)set_up_failed(SetUpStep::kLists, cfg == nullptr ? 1U : 2U);
    return;
  }
  VisionCoordStats& stats = *counters;
  ::new (st) CoordState{};
  st->cfg = cfg;
  st->rate_div = 1U;
  stats.rate_div = 1U;
  if (!take_tile_list(*st) ||
      fdir::liveness_init(st->live, cfg->liveness, st->tiles.data(),
                          cfg->vision_count) != fdir::LivenessError::kOk ||
      fdir::result_trust_init(st->trust, cfg->trust, st->tiles.data(), cfg->vision_count) != fdir::TrustError::kOk) {
    (void)set_up_failed(SetUpStep::kLists, 3U);
    return;
  }
  // coord_set_up() says which of its steps failed; the relight, here.
  if (!coord_set_up(*st, stats)) {
    return;
  }
  if (!relight_coarse(*st)) {
    (void)set_up_failed(SetUpStep::kRelight, 0U);
    return;
  }
  // The settings frames use, last: every carve before keeps its place.
  st->set = bsp::carve_array<SettingsCopy<CoordSettings>>(bsp::Region{self}, 1, kCoordSettingsCarve, &err);
  if (st->set == nullptr) {
    (void)set_up_failed(SetUpStep::kCarves, 1U);
    return;
  }
  bsp::Work work{};
  settings_seal(*st->set, coord_settings_of(*cfg), work);
  bsp::consume(work);
  // Emulated seconds, as the frames' capture times (kTicksPerSecond, as seconds_to_ticks() takes it).
  st->ready_s = static_cast<double>(bsp::now()) / static_cast<double>(bsp::tick_cycles()) *
                (1.0 / static_cast<double>(kTicksPerSecond));
  stats.ready_ms = static_cast<std::uint32_t>(bsp::now() / bsp::tick_cycles());
  for (;;) {
    check_coord(*st);
    drain_nav(*st);
    drain_notices(*st, stats);
    drain_results(*st, stats);
    if (st->busy && (all_answered(*st) || k::now_ticks() >= st->deadline)) {
      finish_frame(*st, stats);
    }
    if (!st->busy && st->have_pending) {
      start_frame(*st, stats);
    }
    k::checkin();
    k::sleep(kCoordIdleTicks);
  }
}

}  // namespace trn::tasks
