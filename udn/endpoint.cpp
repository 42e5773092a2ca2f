/**
 * @file endpoint.cpp
 * @brief Per-tile fault-tolerant messaging endpoint, its fault map and its service task.
 */
#include "udn/endpoint.hpp"

#include "bsp_tile64/api/memory.hpp"
#include "kernel/kernel.hpp"
#include "udn/ft_probe.hpp"

#include <array>
#include <new>

namespace udn {
namespace {

/** Suspect reports waiting to be sent. */
constexpr std::uint32_t kPendingReports = 4U;

/** One transit probe of this tile: a straight ping to a distant tile across switches nobody else probes. */
struct TransitProbe {
  bsp::TileId target;
  std::uint32_t nonce;   ///< of the outstanding ping (0: none)
  std::uint32_t misses;  ///< rounds in a row without its PONG
  bool lost;             ///< reported lost, not back yet
  bool report_owed;      ///< the change of `lost` is still to be sent
};
/** A neighbour's map version not heard yet. */
constexpr std::uint32_t kVersionUnknown = 0xFFFF'FFFFU;

/** Everything of a tile's endpoint, carved in its RAM. */
struct Endpoint {
  FtNode node;
  FaultMap map;  ///< the tile's copy; the routes are built from it
  const EndpointConfig* cfg;
  FtProbe probe;
  bool probing;
  std::array<std::uint32_t, bsp::kUdnDirs> pushed;  ///< map version last sent to each neighbour
  std::array<std::uint32_t, bsp::kUdnDirs> behind;  ///< probe rounds in a row the neighbour's version was older
  std::array<bsp::TileId, kPendingReports> pending;
  std::uint32_t pending_count;
  std::uint8_t local_links;  ///< links leaving this tile towards neighbours its probe found silent (bit per UdnDir)
  std::array<TransitProbe, kMaxTransitTargets> transit;
  std::uint32_t transit_count;
  RoleDirectory roles;  ///< the tile's copy of the role directory
  std::uint64_t parked;         ///< tiles the power policy switched off (not probed, no transit to them)
  std::uint32_t parked_serial;  ///< serial of that set
  bsp::TileId twin;             ///< the second way of the reports (route_twin_via), once twin_known
  bool twin_known;              ///< false: to be found again (the routes changed)
  k::Semaphore wake{0U, 1U};    ///< given by the tile's UDN interrupt: the service sleeps on it
  k::EventFlags arrived{};      ///< bit c: a message was delivered on channel c (endpoint_wait)
};

/*
 * What an upset of an endpoint does (bsp::ControlLayout): it is the tile's own
 * state (node, map, probe, reports, transits, directory) but for its
 * configuration's address and the node's and the probe's host members. Every
 * index and count in it is checked at each entry (check_endpoint, and the
 * node's own checks): a value no valid state holds resets its part, counted
 * and reported (FtCause::kStateRepaired).
 */
constexpr std::array kTransitProbeFields{BSP_CONTROL_STATE(TransitProbe, target), BSP_CONTROL_STATE(TransitProbe, nonce),
                                         BSP_CONTROL_STATE(TransitProbe, misses), BSP_CONTROL_STATE(TransitProbe, lost),
                                         BSP_CONTROL_STATE(TransitProbe, report_owed)};
constexpr bsp::ControlLayout kTransitProbeLayout{kTransitProbeFields, sizeof(TransitProbe), alignof(TransitProbe)};
static_assert(bsp::control_layout_ok(kTransitProbeLayout), "every member of TransitProbe");

constexpr std::array kProbeConfigFields{BSP_CONTROL_STATE(ProbeConfig, miss_threshold)};
constexpr bsp::ControlLayout kProbeConfigLayout{kProbeConfigFields, sizeof(ProbeConfig), alignof(ProbeConfig)};
static_assert(bsp::control_layout_ok(kProbeConfigLayout), "every member of ProbeConfig");

constexpr std::array kProbeFields{
    BSP_CONTROL_NESTED(FtProbe, config, kProbeConfigLayout), BSP_CONTROL_HOST(FtProbe, hook),
    BSP_CONTROL_HOST(FtProbe, hook_ctx),                     BSP_CONTROL_STATE(FtProbe, neighbour),
    BSP_CONTROL_STATE(FtProbe, misses),                      BSP_CONTROL_STATE(FtProbe, nonce),
    BSP_CONTROL_STATE(FtProbe, reported),                    BSP_CONTROL_STATE(FtProbe, round),
};
constexpr bsp::ControlLayout kProbeLayout{kProbeFields, sizeof(FtProbe), alignof(FtProbe)};
static_assert(bsp::control_layout_ok(kProbeLayout), "every member of FtProbe");

constexpr std::array kRoleDirectoryFields{BSP_CONTROL_STATE(RoleDirectory, tile), BSP_CONTROL_STATE(RoleDirectory, version)};
constexpr bsp::ControlLayout kRoleDirectoryLayout{kRoleDirectoryFields, sizeof(RoleDirectory), alignof(RoleDirectory)};
static_assert(bsp::control_layout_ok(kRoleDirectoryLayout), "every member of RoleDirectory");

constexpr std::array kEndpointFields{
    BSP_CONTROL_NESTED(Endpoint, node, kFtNodeLayout),
    BSP_CONTROL_NESTED(Endpoint, map, kFaultMapLayout),
    BSP_CONTROL_HOST(Endpoint, cfg),
    BSP_CONTROL_NESTED(Endpoint, probe, kProbeLayout),
    BSP_CONTROL_STATE(Endpoint, probing),
    BSP_CONTROL_STATE(Endpoint, pushed),
    BSP_CONTROL_STATE(Endpoint, behind),
    BSP_CONTROL_STATE(Endpoint, pending),
    BSP_CONTROL_STATE(Endpoint, pending_count),
    BSP_CONTROL_STATE(Endpoint, local_links),
    BSP_CONTROL_NESTED(Endpoint, transit, kTransitProbeLayout),
    BSP_CONTROL_STATE(Endpoint, transit_count),
    BSP_CONTROL_NESTED(Endpoint, roles, kRoleDirectoryLayout),
    BSP_CONTROL_STATE(Endpoint, parked),
    BSP_CONTROL_STATE(Endpoint, parked_serial),
    BSP_CONTROL_STATE(Endpoint, twin),
    BSP_CONTROL_STATE(Endpoint, twin_known),
    BSP_CONTROL_NESTED(Endpoint, wake, k::SemaphoreLayout::kLayout),
    BSP_CONTROL_NESTED(Endpoint, arrived, k::EventFlagsLayout::kLayout),
};
constexpr bsp::ControlLayout kEndpointLayout{kEndpointFields, sizeof(Endpoint), alignof(Endpoint)};
static_assert(bsp::control_layout_ok(kEndpointLayout), "every member of Endpoint");

/** Per-tile pointer to the carve (a tile's base register); reset with the tile by its service start. */
std::array<Endpoint*, bsp::kMaxTiles> g_ep{};

/** Runs a node operation with interrupts masked (no preemption inside the node). */
class IrqGuard {
 public:
  IrqGuard() noexcept : was_(bsp::mask_irqs(true)) {}
  ~IrqGuard() { (void)bsp::mask_irqs(was_); }
  IrqGuard(const IrqGuard&) = delete;
  IrqGuard& operator=(const IrqGuard&) = delete;
  IrqGuard(IrqGuard&&) = delete;
  IrqGuard& operator=(IrqGuard&&) = delete;

 private:
  bool was_;
};

std::uint32_t tick32() noexcept { return static_cast<std::uint32_t>(k::now_ticks()); }

Endpoint* current() noexcept {
  const bsp::TileId t = bsp::current_tile();
  return t < bsp::kMaxTiles ? g_ep[t] : nullptr;
}

/**
 * Builds the node's routes from @p map plus this tile's own observations: a
 * link to a neighbour that stopped answering is avoided here at once, so the
 * tile's report (and its traffic) goes around it before the vote. Caller holds the guard.
 */
bool build_routes(Endpoint& ep, const FaultMap& map) noexcept {
  FaultMap local = map;
  const bsp::TileId self = ep.node.self;
  if (self < kRouteMaxTiles) {
    local.failed_links[self] = static_cast<std::uint8_t>(local.failed_links[self] | ep.local_links);
  }
  bsp::Work work{};
  const bool ok = ft_set_fault_map(ep.node, local, work) == FtError::kOk;
  ep.node.map_version = map.version;  // probes carry the published version, not the local additions
  ep.twin_known = false;
  bsp::consume(work);
  return ok;
}

/**
 * The intermediate the reports to @p to also go through, as copies: a second
 * way that shares no switch and no link with their route, so one failed
 * switch or link on either way cannot keep a report from the health tile
 * (one on the route did: the tiles behind the coordinator's failed east link
 * could not report it, and those behind a failed spare switch could not
 * report that). Found once per route table, when there is a report to send.
 */
bsp::TileId report_twin(Endpoint& ep, bsp::TileId to) noexcept {
  if (!ep.twin_known) {
    FaultMap local = ep.map;
    const bsp::TileId self = ep.node.self;
    if (self < kRouteMaxTiles) {
      local.failed_links[self] = static_cast<std::uint8_t>(local.failed_links[self] | ep.local_links);
    }
    const RoutePath path = route_path(local, ep.node.routes, to);
    bsp::Work work{};
    ep.twin = path.tiles == 0U ? bsp::kNoTile
                               : route_twin_via(local, self, to, path.tiles, path.links, ep.parked, work);
    ep.twin_known = true;
    bsp::consume(work);
  }
  return ep.twin;
}

/** Probe hook (inside the guarded section): avoids the silent neighbour here; the report is sent after. */
void on_suspect(void* ctx, bsp::TileId /*reporter*/, bsp::TileId suspect) noexcept {
  auto* ep = static_cast<Endpoint*>(ctx);
  for (std::size_t d = 0; d < ep->probe.neighbour.size(); ++d) {
    if (ep->probe.neighbour[d] == suspect) {
      ep->local_links = static_cast<std::uint8_t>(ep->local_links | (1U << d));
    }
  }
  (void)build_routes(*ep, ep->map);
  if (ep->pending_count < kPendingReports) {
    ep->pending[ep->pending_count] = suspect;
    ++ep->pending_count;
  }
}

/** True if the link leaving @p t towards neighbour @p nb is marked failed in @p map. */
bool link_failed(const FaultMap& map, bsp::TileId t, std::size_t dir) noexcept {
  return t < kRouteMaxTiles && ((static_cast<std::uint32_t>(map.failed_links[t]) >> dir) & 1U) != 0U;
}

/** Stops probing neighbours that are off by design, failed, or behind a failed link (nothing answers). */
void prune_probe(Endpoint& ep) noexcept {
  const std::uint64_t skip = ep.cfg->not_probed | ep.map.failed_tiles | ep.parked;
  for (std::size_t d = 0; d < ep.probe.neighbour.size(); ++d) {
    bsp::TileId& n = ep.probe.neighbour[d];
    if (n != bsp::kNoTile && (((skip >> n) & 1ULL) != 0ULL || link_failed(ep.map, ep.node.self, d))) {
      n = bsp::kNoTile;
    }
  }
}

/** Rebuilds the routes from @p map if it is newer; reports it. Caller holds the guard. */
bool install(Endpoint& ep, const FaultMap& map, bsp::TileId from) noexcept {
  if (map.version <= ep.map.version || map.cols != ep.map.cols || map.rows != ep.map.rows) {
    return false;
  }
  if (!build_routes(ep, map)) {
    return false;
  }
  ep.map = map;
  if (ep.probing) {
    prune_probe(ep);
  }
  ft_event_emit(ep.node.sink, ep.node.self, FtEvent{tick32(), FtCause::kMapApplied, 0U, 0U, from, map.version});
  return true;
}

/** The map the tile starts from: the configuration's, or an all-clear one of the network's grid. @return false if none. */
bool take_boot_map(Endpoint& ep) noexcept {
  ep.map = ep.cfg->boot_map;
  const std::uint32_t cols = bsp::udn_grid_cols();
  return ep.map.cols != 0U || (cols != 0U && fault_map_init(ep.map, cols, bsp::udn_grid_rows()) == RouteError::kOk);
}

/** The transit probes of tile @p self from the configuration, none outstanding. */
void plan_transits(Endpoint& ep, bsp::TileId self) noexcept {
  const EndpointConfig& cfg = *ep.cfg;
  const std::uint64_t targets = cfg.transit_targets[self];
  // One transit per tick of the probe period, after the tick of the neighbour pings.
  const std::uint32_t room = cfg.probe_period_ticks > 1U ? cfg.probe_period_ticks - 1U : 0U;
  const std::uint32_t most = room < kMaxTransitTargets ? room : kMaxTransitTargets;
  ep.transit_count = 0U;
  for (std::uint32_t t = 0; t < kRouteMaxTiles && ep.transit_count < most; ++t) {
    if (((targets >> t) & 1ULL) != 0ULL && t != self) {
      ep.transit[ep.transit_count] = TransitProbe{static_cast<bsp::TileId>(t), 0U, 0U, false, false};
      ++ep.transit_count;
    }
  }
}

bool open(Endpoint*& out, bsp::TileId self, const EndpointConfig& cfg) noexcept {
  bsp::MemError err = bsp::MemError::kOk;
  auto* ep = bsp::carve_control_array<Endpoint>(bsp::Region{self}, 1, kEndpointCarve, &err, &kEndpointLayout);
  if (err != bsp::MemError::kOk || ep == nullptr) {
    return false;
  }
  ::new (ep) Endpoint{};
  ep->cfg = &cfg;
  ep->roles = cfg.roles;
  if (!take_boot_map(*ep)) {
    return false;  // no boot map and no network to draw an all-clear one from
  }
  if (ft_init(ep->node, self, ep->map, ft_task_port(), cfg.ft) != FtError::kOk) {
    return false;
  }
  ft_set_event_sink(ep->node, cfg.sink);
  // Each boot is a new incarnation of the node: its peers restart its streams.
  ft_set_epoch(ep->node, bsp::boot_count());
  ep->node.peer_map_version.fill(kVersionUnknown);
  ep->pushed.fill(kVersionUnknown);
  ep->probing = cfg.health_tile != bsp::kNoTile &&
                ft_probe_init(ep->probe, ep->node, ProbeConfig{cfg.probe_miss_threshold}, &on_suspect, ep) ==
                    ProbeError::kOk;
  if (ep->probing) {
    prune_probe(*ep);
    plan_transits(*ep, self);
  }
  out = ep;
  return true;
}

/**
 * The node's tile, the map and the routes built from it. A map whose grid is
 * not the boot map's is taken again from the boot map (its version behind
 * every published one, so the next map, pushed by a neighbour whose probes
 * hear the old version, is applied); the routes are rebuilt from the map when
 * the tile, the map or their own grid was upset. Caller holds the guard.
 */
void check_ground(Endpoint& ep, bsp::TileId self) noexcept {
  bool rebuild = false;
  if (ep.node.self != self) {
    ft_report_repair(ep.node, FtRepair::kSelf, self, ep.node.self);
    ep.node.self = self;
    rebuild = true;
  }
  const FaultMap& boot = ep.cfg->boot_map;
  const std::uint32_t cols = boot.cols != 0U ? boot.cols : bsp::udn_grid_cols();
  const std::uint32_t rows = boot.cols != 0U ? boot.rows : bsp::udn_grid_rows();
  if (!fault_map_valid(ep.map) || ep.map.cols != cols || ep.map.rows != rows) {
    ft_report_repair(ep.node, FtRepair::kMap, 0U, (ep.map.cols << 16U) | (ep.map.rows & 0xFFFFU));
    rebuild = take_boot_map(ep);
  }
  if (!rebuild && !ft_routes_ok(ep.node)) {
    ft_report_repair(ep.node, FtRepair::kRoutes, ep.node.routes.self, ep.node.routes.tiles);
    rebuild = true;
  }
  if (rebuild) {
    (void)build_routes(ep, ep.map);
  }
}

/** The reports to send, the transit probes and the neighbour probe. Caller holds the guard. */
void check_probes(Endpoint& ep, bsp::TileId self) noexcept {
  if (ep.pending_count > kPendingReports) {
    ft_report_repair(ep.node, FtRepair::kPending, 0U, ep.pending_count);
    ep.pending_count = 0U;
  }
  bool transits_ok = ep.transit_count <= kMaxTransitTargets;
  for (std::uint32_t i = 0; i < kMaxTransitTargets && transits_ok; ++i) {
    transits_ok = i >= ep.transit_count || ep.transit[i].target < kRouteMaxTiles;
  }
  if (!transits_ok) {
    ft_report_repair(ep.node, FtRepair::kTransit, ep.transit_count, 0U);
    plan_transits(ep, self);
  }
  const EndpointConfig& cfg = *ep.cfg;
  bool probe_ok = ep.probing == (cfg.health_tile != bsp::kNoTile && cfg.probe_miss_threshold != 0U);
  probe_ok = probe_ok && (!ep.probing || ep.probe.config.miss_threshold == cfg.probe_miss_threshold);
  for (std::size_t d = 0; d < ep.probe.neighbour.size() && ep.probing; ++d) {
    const bsp::TileId n = ep.probe.neighbour[d];
    probe_ok = probe_ok && (n == bsp::kNoTile || n < ep.node.routes.tiles);
  }
  if (!probe_ok) {
    ft_report_repair(ep.node, FtRepair::kProbe, ep.probing ? 1U : 0U, ep.probe.config.miss_threshold);
    ep.probing = cfg.health_tile != bsp::kNoTile &&
                 ft_probe_init(ep.probe, ep.node, ProbeConfig{cfg.probe_miss_threshold}, &on_suspect, &ep) ==
                     ProbeError::kOk;
    if (ep.probing) {
      prune_probe(ep);
    }
  }
}

/**
 * The endpoint lives in its tile's RAM and can take an upset: at each entry,
 * before any of its indices or counts is followed, a value no valid state
 * holds resets its part (counted in the node, reported as kStateRepaired);
 * the node checks its own at each of its operations. Caller holds the guard.
 */
void check_endpoint(Endpoint& ep, bsp::TileId self) noexcept {
  check_ground(ep, self);
  check_probes(ep, self);
}

/**
 * Scores transit @p i's last ping and pings its target again, straight (one
 * X-then-Y leg each way, so the round trip crosses exactly the planned
 * switches). Each transit has its own tick in the probe period, offset by the
 * tile, so a tile's pings and its targets' answers are spread over the period
 * instead of leaving in one burst. A transit crossing a switch the map says
 * failed is left alone. Caller holds the guard.
 */
void transit_probe(Endpoint& ep, std::uint32_t i) noexcept {
  TransitProbe& p = ep.transit[i];
  const bsp::TileId self = ep.node.self;
  if (((ep.parked >> p.target) & 1ULL) != 0ULL) {
    return;  // switched off by the power policy: nothing answers there
  }
  const std::uint64_t round_trip = path_tiles(ep.map, self, p.target) | path_tiles(ep.map, p.target, self);
  if ((round_trip & ep.map.failed_tiles) != 0ULL) {
    return;  // crosses a switch the map says failed: it can tell nothing more
  }
  const std::uint32_t threshold = ep.cfg->probe_miss_threshold == 0U ? 1U : ep.cfg->probe_miss_threshold;
  if (p.nonce != 0U) {
    const bool answered = ep.node.pong_nonce[p.target] == p.nonce;
    p.misses = answered ? 0U : p.misses + 1U;
    if (answered == p.lost && (answered || p.misses >= threshold)) {  // back, or silent long enough
      p.lost = !answered;
      p.report_owed = true;
      ft_event_emit(ep.node.sink, ep.node.self,
                    FtEvent{tick32(), p.lost ? FtCause::kTransitLost : FtCause::kTransitBack, 0U, 0U, p.target, 0U});
    }
  }
  // Nonce: the tick in the high bits, the probe's index above the four directions, never 0.
  const std::uint32_t nonce = (tick32() << 4U) | (4U + i) | 0x8000'0000U;
  const bool sent = ft_send_control(ep.node, p.target, FtKind::kPing, 0U, nonce, false) == FtError::kOk;
  p.nonce = sent ? nonce : 0U;  // a refused ping is not a miss of the target
}

/** Sends a waiting item without blocking; @return false if the network or window refused (retry next tick). */
bool send_now(Endpoint& ep, bsp::TileId to, std::uint32_t channel, std::span<const std::uint32_t> w,
              bsp::TileId twin = bsp::kNoTile) noexcept {
  FtError e = FtError::kOk;
  {
    const IrqGuard guard;
    e = ft_send(ep.node, to, channel, w, tick32(), twin);
  }
  return e != FtError::kWindowFull && e != FtError::kNetFull;  // sent, or no route: nothing more to do
}

/** Queues again every suspicion and lost transit that still holds (see kReReportRounds). */
void report_again(Endpoint& ep) noexcept {
  for (std::size_t d = 0; d < ep.probe.neighbour.size(); ++d) {
    const bsp::TileId nb = ep.probe.neighbour[d];
    if (nb >= kRouteMaxTiles || !ep.probe.reported[d]) {
      continue;
    }
    bool queued = false;
    for (std::uint32_t i = 0; i < ep.pending_count; ++i) {
      queued = queued || ep.pending[i] == nb;
    }
    if (!queued && ep.pending_count < kPendingReports) {
      ep.pending[ep.pending_count] = nb;
      ++ep.pending_count;
    }
  }
  for (std::uint32_t i = 0; i < ep.transit_count; ++i) {
    TransitProbe& t = ep.transit[i];
    t.report_owed = t.report_owed || t.lost;
  }
}

/** Where reports go: the report slot's tile in the directory, or health_tile. */
bsp::TileId report_target(const Endpoint& ep) noexcept {
  const std::uint32_t slot = ep.cfg->report_slot;
  if (ep.cfg->health_tile == bsp::kNoTile || slot >= kRoleSlots || ep.roles.tile[slot] >= kRouteMaxTiles) {
    return ep.cfg->health_tile;
  }
  return ep.roles.tile[slot];
}

bool owes_transit_report(const Endpoint& ep) noexcept {
  bool owed = false;
  for (std::uint32_t i = 0; i < ep.transit_count; ++i) {
    owed = owed || ep.transit[i].report_owed;
  }
  return owed;
}

void send_reports(Endpoint& ep) noexcept {
  const bsp::TileId to = report_target(ep);
  if (to == bsp::kNoTile || (ep.pending_count == 0U && !owes_transit_report(ep))) {
    return;
  }
  const bsp::TileId twin = report_twin(ep, to);
  while (ep.pending_count > 0U && to != bsp::kNoTile) {
    std::array<std::uint32_t, kSuspectWords> w{};
    pack_suspect(SuspectReport{ep.node.self, ep.pending[ep.pending_count - 1U]}, w);
    if (!send_now(ep, to, kFtChanFdir, w, twin)) {
      return;
    }
    --ep.pending_count;
  }
  for (std::uint32_t i = 0; i < ep.transit_count && to != bsp::kNoTile; ++i) {
    TransitProbe& p = ep.transit[i];
    if (!p.report_owed) {
      continue;
    }
    std::array<std::uint32_t, kTransitWords> w{};
    pack_transit(TransitReport{ep.node.self, p.target, p.lost}, w);
    if (!send_now(ep, to, kFtChanFdir, w, twin)) {
      return;
    }
    p.report_owed = false;
  }
}

/** Catch-up: a neighbour whose probes carry an older map version is sent ours, once per version. */
void push_to_stale(Endpoint& ep) noexcept {
  std::array<std::uint32_t, kFaultMapWords> w{};
  bool packed = false;
  for (std::size_t d = 0; d < ep.probe.neighbour.size(); ++d) {
    const bsp::TileId nb = ep.probe.neighbour[d];
    if (nb >= kRouteMaxTiles) {  // kNoTile included
      continue;
    }
    const std::uint32_t theirs = ep.node.peer_map_version[nb];
    const bool older = theirs != kVersionUnknown && theirs < ep.map.version;
    ep.behind[d] = older ? ep.behind[d] + 1U : 0U;
    // Behind for two rounds: not a neighbour that is being sent the same map by the health tile right now.
    if (ep.behind[d] < 2U || ep.pushed[d] == ep.map.version) {
      continue;
    }
    if (!packed) {
      pack_fault_map(ep.map, w);
      packed = true;
    }
    if (!send_now(ep, nb, kFtChanMap, w)) {
      return;
    }
    ep.pushed[d] = ep.map.version;
    ft_event_emit(ep.node.sink, ep.node.self, FtEvent{tick32(), FtCause::kMapPushed, 0U, 0U, nb, ep.map.version});
  }
}

/** @p roles with every entry off the chip (an upset one) read as unused. */
RoleDirectory on_chip(const RoleDirectory& roles) noexcept {
  RoleDirectory r = roles;
  for (bsp::TileId& t : r.tile) {
    t = t < kRouteMaxTiles ? t : bsp::kNoTile;
  }
  return r;
}

bool move_role(Endpoint& ep, std::uint32_t slot, bsp::TileId tile, std::uint32_t version) noexcept {
  if (slot >= kRoleSlots || version <= ep.roles.version[slot]) {
    return false;  // unknown slot, or an older move arriving late
  }
  ep.roles.tile[slot] = tile;
  ep.roles.version[slot] = version;
  if (ep.cfg != nullptr && slot == ep.cfg->report_slot) {
    ep.twin_known = false;  // the reports' way is to the role's new tile
  }
  return true;
}

/**
 * A new parked set. Tiles that left it are neighbours to probe again: the
 * probe starts afresh over the grid (misses cleared) and is pruned anew; a
 * link this tile avoided towards a tile that was parked is used again.
 * Caller holds the guard.
 */
bool set_parked(Endpoint& ep, std::uint64_t parked, std::uint32_t serial) noexcept {
  if (serial <= ep.parked_serial) {
    return false;
  }
  const std::uint64_t woken = ep.parked & ~parked;
  ep.parked = parked;
  ep.parked_serial = serial;
  ep.twin_known = false;  // a parked tile forwards nothing
  if (!ep.probing) {
    return true;
  }
  if (woken != 0ULL) {
    const FtProbe before = ep.probe;
    (void)ft_probe_init(ep.probe, ep.node, ProbeConfig{ep.cfg->probe_miss_threshold}, before.hook, before.hook_ctx);
    for (std::size_t d = 0; d < ep.probe.neighbour.size(); ++d) {
      const bsp::TileId n = ep.probe.neighbour[d];
      if (n < kRouteMaxTiles && ((woken >> n) & 1ULL) != 0ULL) {
        ep.local_links = static_cast<std::uint8_t>(ep.local_links & ~(1U << d));
      }
    }
    (void)build_routes(ep, ep.map);
  }
  prune_probe(ep);
  for (std::uint32_t i = 0; i < ep.transit_count; ++i) {
    TransitProbe& t = ep.transit[i];
    if (((parked >> t.target) & 1ULL) != 0ULL) {
      t.nonce = 0U;  // not pinged while parked: no miss, no report
      t.misses = 0U;
    }
  }
  return true;
}

/** Takes the fault maps and role moves waiting on kFtChanMap (a bounded number per tick). Caller holds the guard. */
void take_maps(Endpoint& ep) noexcept {
  FtMessage m{};
  for (std::uint32_t i = 0; i < kFtRxDepth && ft_receive(ep.node, kFtChanMap, m) == FtError::kOk; ++i) {
    const std::span<const std::uint32_t> w(m.data.data(), m.data_words);
    FaultMap map{};
    RoleMove move{};
    ParkedSet parked{};
    if (unpack_role_move(w, move)) {
      (void)move_role(ep, move.slot, move.tile, move.version);
    } else if (unpack_parked(w, parked)) {
      (void)set_parked(ep, parked.tiles, parked.serial);
    } else if (unpack_fault_map(w, map)) {
      (void)install(ep, map, m.source);
    }
  }
}

/** The UDN interrupt: a packet arrived (or a refused send may go): the service looks again. */
void on_udn_irq(bsp::TileId tile) noexcept {
  Endpoint* ep = tile < bsp::kMaxTiles ? g_ep[tile] : nullptr;
  if (ep != nullptr && ep->wake.count() == 0U) {
    (void)ep->wake.give_from_isr();
  }
}

/** Transit i's tick in the period (1 .. transit_count), after the neighbour pings, offset by the tile; 0: none. */
std::uint32_t transit_slot(std::uint32_t tick, std::uint32_t period, bsp::TileId self) noexcept {
  return (tick + period - (self % period)) % period;
}

/** Ticks from @p tick to the next tick with a probe or a transit (1 .. period), or kCommMaxSleepTicks. */
std::uint32_t ticks_to_probe(const Endpoint& ep, std::uint32_t tick, std::uint32_t period, bsp::TileId self) noexcept {
  if (!ep.probing) {
    return kCommMaxSleepTicks;
  }
  for (std::uint32_t d = 1U; d < period && d < kCommMaxSleepTicks; ++d) {
    const std::uint32_t slot = transit_slot(tick + d, period, self);
    if ((tick + d) % period == 0U || (slot >= 1U && slot <= ep.transit_count)) {
      return d;
    }
  }
  return period < kCommMaxSleepTicks ? period : kCommMaxSleepTicks;
}

}  // namespace

void endpoint_task_main(void* arg) noexcept {
  const bsp::TileId self = bsp::current_tile();
  const auto* cfg = static_cast<const EndpointConfig*>(arg);
  if (self >= bsp::kMaxTiles) {
    return;
  }
  g_ep[self] = nullptr;  // a restart carves afresh: the old state is gone with the region
  Endpoint* opened = nullptr;
  if (cfg == nullptr || !open(opened, self, *cfg) || k::set_isr(bsp::Irq::kUdn, &on_udn_irq) != k::Status::kOk) {
    return;
  }
  g_ep[self] = opened;
  Endpoint& ep = *opened;
  const std::uint32_t period = cfg->probe_period_ticks == 0U ? 1U : cfg->probe_period_ticks;
  const k::Ticks start = k::now_ticks();
  k::Ticks last = ~k::Ticks{0};
  // Event-driven: a pass at each tick with a probe or a transit, at each arrival, and every tick while the
  // node has packets in flight or owes an answer; asleep otherwise (a tickless tile sleeps with it).
  for (;;) {
    const k::Ticks now = k::now_ticks();
    const auto tick = static_cast<std::uint32_t>(now - start);
    const bool new_tick = now != last;
    last = now;
    const bool probe_now = ep.probing && new_tick && tick % period == 0U;
    std::uint32_t handled = 0U;
    std::uint8_t ready = 0U;
    {
      const IrqGuard guard;
      check_endpoint(ep, self);
      if (probe_now) {
        (void)ft_probe_round(ep.probe, ep.node, tick32());
        if (ep.probe.round % kReReportRounds == 0U) {
          report_again(ep);
        }
      }
      const std::uint32_t slot = transit_slot(tick, period, self);
      if (ep.probing && new_tick && slot >= 1U && slot <= ep.transit_count) {
        transit_probe(ep, slot - 1U);
      }
      handled = ft_poll(ep.node, tick32(), cfg->packets_per_tick);
      take_maps(ep);
      ready = ep.node.rx_ready;
    }
    if (ready != 0U) {
      ep.arrived.set(ready);  // the tile's receivers waiting in endpoint_wait
    }
    send_reports(ep);
    if (probe_now) {
      push_to_stale(ep);
    }
    k::checkin();
    const bool busy = ft_busy(ep.node) || handled >= cfg->packets_per_tick || ep.pending_count != 0U ||
                      owes_transit_report(ep);
    const std::uint32_t sleep = busy ? 1U : ticks_to_probe(ep, tick, period, self);
    (void)ep.wake.take(k::Timeout{sleep});
  }
}

bool endpoint_ready() noexcept { return current() != nullptr; }

bool endpoint_cut_off(bsp::TileId besides) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr || !ep->probing) {
    return false;
  }
  const IrqGuard guard;
  check_endpoint(*ep, bsp::current_tile());
  std::uint32_t probed = 0U;
  std::uint32_t silent = 0U;
  for (std::size_t d = 0; d < ep->probe.neighbour.size(); ++d) {
    if (ep->probe.neighbour[d] < kRouteMaxTiles && ep->probe.neighbour[d] != besides) {
      ++probed;
      silent += ep->probe.reported[d] ? 1U : 0U;
    }
  }
  for (std::uint32_t i = 0; i < ep->transit_count; ++i) {
    const TransitProbe& t = ep->transit[i];
    if (((ep->parked >> t.target) & 1ULL) == 0ULL && t.target != besides) {
      ++probed;
      silent += t.lost ? 1U : 0U;
    }
  }
  return probed > 0U && silent == probed;
}

Heard endpoint_hears(bsp::TileId tile) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr || !ep->probing || tile >= kRouteMaxTiles) {
    return Heard::kNotProbed;
  }
  const IrqGuard guard;
  for (std::size_t d = 0; d < ep->probe.neighbour.size(); ++d) {
    if (ep->probe.neighbour[d] == tile) {
      // One ping lost in a row can be the network's; a tile that stopped misses every round.
      return ep->probe.misses[d] > 1U || ep->probe.reported[d] ? Heard::kSilent : Heard::kAnswers;
    }
  }
  return Heard::kNotProbed;
}

bool endpoint_wait_ready(std::uint32_t max_ticks) noexcept {
  for (std::uint32_t i = 0; i <= max_ticks; ++i) {
    if (endpoint_ready()) {
      return true;
    }
    k::sleep(1);
  }
  return false;
}

FtError endpoint_send(bsp::TileId dest, std::uint32_t channel, std::span<const std::uint32_t> words,
                      std::uint32_t max_ticks) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr) {
    return FtError::kBadArgs;
  }
  FtError e = FtError::kBadArgs;
  for (std::uint32_t i = 0; i <= max_ticks; ++i) {
    {
      const IrqGuard guard;
      check_endpoint(*ep, bsp::current_tile());
      e = ft_send(ep->node, dest, channel, words, tick32());
    }
    if ((e != FtError::kWindowFull && e != FtError::kNetFull) || i == max_ticks) {
      return e;
    }
    k::sleep(1);
  }
  return e;
}

FtError endpoint_receive(std::uint32_t channel, FtMessage& out) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr || channel == kFtChanMap) {
    return FtError::kBadArgs;  // maps belong to the endpoint itself
  }
  const IrqGuard guard;
  check_endpoint(*ep, bsp::current_tile());
  return ft_receive(ep->node, channel, out);
}

bool endpoint_wait(std::uint32_t channel, std::uint32_t max_ticks) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr || channel >= kFtAllChannels || channel == kFtChanMap) {
    return false;
  }
  const std::uint32_t bit = 1U << channel;
  {
    const IrqGuard guard;
    if ((ep->node.rx_ready & bit) != 0U) {
      return true;
    }
  }
  std::uint32_t got = 0U;
  (void)ep->arrived.wait(bit, k::WaitMode::kAny, true, k::Timeout{max_ticks}, &got);
  return true;
}

FtError endpoint_install_map(const FaultMap& map) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr) {
    return FtError::kBadArgs;
  }
  const IrqGuard guard;
  check_endpoint(*ep, bsp::current_tile());
  (void)install(*ep, map, ep->node.self);
  return FtError::kOk;
}

bsp::TileId endpoint_role_tile(std::uint32_t slot, bsp::TileId fallback) noexcept {
  const Endpoint* ep = current();
  if (ep == nullptr || slot >= kRoleSlots) {
    return fallback;
  }
  const IrqGuard guard;
  const bsp::TileId t = ep->roles.tile[slot];
  return t >= kRouteMaxTiles ? fallback : t;  // kNoTile, or an upset entry off the chip: not used
}

bool endpoint_move_role(std::uint32_t slot, bsp::TileId tile, std::uint32_t version) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr) {
    return false;
  }
  const IrqGuard guard;
  return move_role(*ep, slot, tile, version);
}

bool endpoint_set_parked(std::uint64_t parked, std::uint32_t serial) noexcept {
  Endpoint* ep = current();
  if (ep == nullptr) {
    return false;
  }
  const IrqGuard guard;
  check_endpoint(*ep, bsp::current_tile());
  return set_parked(*ep, parked, serial);
}

RoleDirectory endpoint_roles() noexcept {
  const Endpoint* ep = current();
  if (ep == nullptr) {
    return RoleDirectory{};
  }
  const IrqGuard guard;
  return on_chip(ep->roles);
}

RoleDirectory endpoint_roles_of(bsp::TileId tile) noexcept {
  return (tile < bsp::kMaxTiles && g_ep[tile] != nullptr) ? on_chip(g_ep[tile]->roles) : RoleDirectory{};
}

FaultMap endpoint_fault_map() noexcept {
  const Endpoint* ep = current();
  return ep != nullptr ? ep->map : FaultMap{};
}

const bsp::ControlLayout& endpoint_state_layout() noexcept { return kEndpointLayout; }

const FtNode* endpoint_node(bsp::TileId tile) noexcept {
  return (tile < bsp::kMaxTiles && g_ep[tile] != nullptr) ? &g_ep[tile]->node : nullptr;
}

std::uint32_t endpoint_map_version(bsp::TileId tile) noexcept {
  return (tile < bsp::kMaxTiles && g_ep[tile] != nullptr) ? g_ep[tile]->map.version : 0U;
}

}  // namespace udn
