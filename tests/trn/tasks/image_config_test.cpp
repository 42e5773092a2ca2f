/**
 * @file image_config_test.cpp
 * @brief The image's one configuration step: checked, all or nothing, and what the role tables point to.
 */
#include "trn/tasks/tile_map.hpp"

#include "build_info.hpp"
#include "tools/common/mission/fdir_params_doc.hpp"
#include "trn/tasks/fdir_params.hpp"

#include <gtest/gtest.h>

#include <bit>

#include <fstream>
#include <string>

namespace {

using trn::tasks::configure_image;
using trn::tasks::ImageConfig;
using trn::tasks::ImageError;
using trn::tasks::image_config;

ImageConfig mission_like() {
  ImageConfig c{};
  c.endpoint.health_tile = trn::tasks::kSupervisorTile;
  c.io.filter_tile = trn::tasks::kFilterTile;
  c.io.coordinator_tile = trn::tasks::kCoordinatorTile;
  c.filter.coordinator_tile = trn::tasks::kCoordinatorTile;
  c.coord.filter_tile = trn::tasks::kFilterTile;
  trn::tasks::tile_map_vision_tiles(trn::tasks::kTile64Deployment, c.coord, 0);
  c.vision.coordinator_tile = trn::tasks::kCoordinatorTile;
  return c;
}

TEST(ImageConfig, AcceptedConfigurationIsWhatTheRoleTablesPointTo) {
  ImageConfig c = mission_like();
  c.filter.matches_per_job = 7;
  ASSERT_EQ(configure_image(c), ImageError::kOk);
  EXPECT_EQ(image_config().filter.matches_per_job, 7U);
  EXPECT_EQ(image_config().coord.vision_count, 40U);
  // Every role's task gets its part of the one configuration.
  EXPECT_EQ(trn::tasks::kFilterRole[2].arg, &image_config().filter);
  EXPECT_EQ(trn::tasks::kIoRole[2].arg, &image_config().io);
  EXPECT_EQ(trn::tasks::kCoordinatorRole[2].arg, &image_config().coord);
  EXPECT_EQ(trn::tasks::kVisionRole[2].arg, &image_config().vision);
  EXPECT_EQ(trn::tasks::kSupervisorRole[2].arg, &image_config().tile_health);
  EXPECT_EQ(trn::tasks::kSupervisorRole[3].arg, &image_config().net_health);
  EXPECT_EQ(trn::tasks::kCommTask.arg, &image_config().endpoint);
  // Every role tile runs the health agent second, configured once.
  for (const k::TaskTable t : {k::TaskTable(trn::tasks::kFilterRole), k::TaskTable(trn::tasks::kIoRole),
                               k::TaskTable(trn::tasks::kCoordinatorRole), k::TaskTable(trn::tasks::kVisionRole),
                               k::TaskTable(trn::tasks::kSupervisorRole)}) {
    EXPECT_EQ(t[1].arg, &image_config().agent);
  }
}

TEST(ImageConfig, RefusedConfigurationChangesNothing) {
  ImageConfig good = mission_like();
  good.filter.matches_per_job = 9;
  ASSERT_EQ(configure_image(good), ImageError::kOk);

  ImageConfig c = mission_like();
  c.io.filter_tile = 64;  // off the 8x8 chip
  EXPECT_EQ(configure_image(c), ImageError::kBadTile);
  c = mission_like();
  c.endpoint.health_tile = 200;
  EXPECT_EQ(configure_image(c), ImageError::kBadTile);
  c = mission_like();
  c.coord.vision_count = trn::tasks::kMaxVisionTiles + 1U;
  EXPECT_EQ(configure_image(c), ImageError::kBadVisionList);
  c = mission_like();
  c.coord.vision_tiles[3] = bsp::kNoTile;
  EXPECT_EQ(configure_image(c), ImageError::kBadVisionList);
  c = mission_like();
  c.net_health.votes_to_fail = 1;  // one vote is never enough
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.filter.matches_per_job = 0;
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.coord.deadline_s = 0.0;
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.agent.health_tile = 64;
  EXPECT_EQ(configure_image(c), ImageError::kBadTile);
  c = mission_like();
  c.endpoint.roles.tile[trn::tasks::kSlotFilter] = 99;  // the directory names a tile off the chip
  EXPECT_EQ(configure_image(c), ImageError::kBadTile);
  c = mission_like();
  c.agent.watchdog_ticks = fdir::kAgentPeriodTicks;  // shorter than two kicks: it would expire between them
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.agent.watcher_tile = 64;
  EXPECT_EQ(configure_image(c), ImageError::kBadTile);
  c = mission_like();
  c.agent.health_tile = trn::tasks::kSupervisorTile;
  c.agent.watcher_tile = trn::tasks::kSupervisorTile;  // a tile cannot watch itself
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.agent.watcher_tile = trn::tasks::kIoTile;
  c.agent.watcher_timeout_ticks = c.agent.watchdog_ticks;  // it would reset a tile its own watchdog is resetting
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.tile_health.max_resets = 0;
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.tile_health.disagreements_to_fail = 0;
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);
  c = mission_like();
  c.tile_health.self_test_wait_ticks = c.tile_health.self_test_ticks;  // a round would overlap the next
  EXPECT_EQ(configure_image(c), ImageError::kBadConfig);

  EXPECT_EQ(image_config().filter.matches_per_job, 9U) << "the last accepted configuration stands";
  EXPECT_EQ(image_config().io.filter_tile, trn::tasks::kFilterTile);
}

// FDIR-TR-01, FDIR-TR-06: the image's transit plan on its own tile map (every tile powered) tests
// every subject, and every tested one can be voted failed: two transits with no end in common.
TEST(ImageConfig, TransitPlanOnTheTileMapVotesOnEverySubject) {
  std::uint64_t powered = 0;
  std::uint64_t spares = 0;
  for (std::uint32_t t = 0; t < trn::tasks::kMapTiles; ++t) {
    const bool spare = trn::tasks::kTileRoles[t] == trn::tasks::Role::kSpare;
    (spare ? spares : powered) |= std::uint64_t{1} << t;
  }
  udn::FaultMap map{};
  ASSERT_EQ(udn::fault_map_init(map, 8U, 8U), udn::RouteError::kOk);
  fdir::TransitPlan plan{};
  std::uint64_t subjects = 0;
  ASSERT_EQ(trn::tasks::tile_map_transits(trn::tasks::kTile64Deployment, map, powered, spares, 2U, plan, subjects), fdir::TransitError::kOk);
  EXPECT_EQ(plan.untested, std::uint64_t{1} << 7U) << "the vision supervisor's corner tile alone (fdir/transit_test.cpp)";
  EXPECT_NE(plan.tested, 0U);
  EXPECT_EQ(plan.tested & ~subjects, 0U);
  for (std::uint32_t i = 0; i < plan.count; ++i) {
    EXPECT_NE(plan.t[i].prober, trn::tasks::kCoordinatorTile) << "the coordinator does not ping";
    EXPECT_NE(plan.t[i].prober, trn::tasks::kFilterTile) << "the filter does not ping";
    EXPECT_NE(plan.t[i].target, trn::tasks::kFilterTile) << "the filter does not answer";
  }
  for (bsp::TileId x = 0; x < 64U; ++x) {
    if ((plan.tested & (std::uint64_t{1} << x)) == 0U) {
      continue;
    }
    bool pair = false;
    for (std::uint32_t i = 0; i < plan.count; ++i) {
      for (std::uint32_t j = 0; j < plan.count; ++j) {
        const fdir::Transit& a = plan.t[i];
        const fdir::Transit& b = plan.t[j];
        const std::uint64_t x_bit = std::uint64_t{1} << x;
        const std::uint64_t a_ends = (std::uint64_t{1} << a.prober) | (std::uint64_t{1} << a.target);
        const std::uint64_t b_ends = (std::uint64_t{1} << b.prober) | (std::uint64_t{1} << b.target);
        pair = pair || ((a.path & x_bit) != 0U && (b.path & x_bit) != 0U && (a_ends & b_ends) == 0U);
      }
    }
    EXPECT_TRUE(pair) << "subject " << x;
  }
  // Every subject's failed switch is named from the transits it loses (all that cross it).
  for (bsp::TileId x = 0; x < 64U; ++x) {
    std::uint64_t lost = 0;
    for (std::uint32_t i = 0; i < plan.count; ++i) {
      lost |= (plan.t[i].path >> x & 1U) != 0U ? std::uint64_t{1} << i : 0U;
    }
    if ((plan.tested & (std::uint64_t{1} << x)) != 0U) {
      EXPECT_EQ(fdir::transit_verdict(plan, lost, subjects, 0U), x) << "subject " << x;
    }
  }
  // The untested corner tile 7 is an end tile: transits end there (answered by its software) or
  // cross it, all by the link from tile 15 (its other neighbour, 6, takes none). All of them lost and
  // a neighbour's probe finding it silent too name it (a hung core loses the same ones: net_health
  // tells the two apart by time); without that report the shared link alone could lose them all,
  // and any of them heard names nothing.
  std::uint64_t on7 = 0;
  for (std::uint32_t i = 0; i < plan.count; ++i) {
    on7 |= (plan.t[i].path >> 7U & 1U) != 0U && plan.t[i].prober != 7U ? std::uint64_t{1} << i : 0U;
  }
  ASSERT_GE(std::popcount(on7), 2);
  const std::uint64_t reported7 = std::uint64_t{1} << 7U;
  std::uint64_t out = 0;
  EXPECT_EQ(fdir::end_tile_verdict(plan, on7, plan.untested, 0U, 0U, reported7, out), 7U);
  EXPECT_EQ(out, on7);
  EXPECT_EQ(fdir::end_tile_verdict(plan, on7, plan.untested, 0U, 0U, 0U, out), bsp::kNoTile) << "one link under them all";
  const std::uint64_t one = on7 & (~on7 + 1U);  // the lowest of them
  EXPECT_EQ(fdir::end_tile_verdict(plan, on7 & ~one, plan.untested, 0U, 0U, reported7, out), bsp::kNoTile) << "one heard";
  EXPECT_EQ(fdir::end_tile_verdict(plan, on7, 0U, 0U, 0U, reported7, out), bsp::kNoTile) << "not a candidate";
  EXPECT_EQ(fdir::end_tile_verdict(plan, on7, plan.untested, reported7, 0U, reported7, out), bsp::kNoTile)
      << "already failed";
}

// The deployment declared once: every tile a role's configuration names is filled from the wiring
// table with its role's boot tile, and checked from the same table.
TEST(Deployment, WiringFillsEveryTileARoleNamesWithThatRolesBootTile) {
  ImageConfig c{};
  trn::tasks::wire_image(c, trn::tasks::kTile64Deployment);
  for (const trn::tasks::Wire& w : trn::tasks::kWiring) {
    EXPECT_EQ(w.get(c), trn::tasks::boot_tile(w.to, w.index)) << w.field;
    EXPECT_NE(w.get(c), bsp::kNoTile) << w.field << ": every wired role is placed";
  }
  EXPECT_EQ(c.io.filter_tile, 18U);
  EXPECT_EQ(c.agent.watcher_tile, trn::tasks::kIoTile) << "the I/O tile watches the supervisor";
  EXPECT_EQ(c.agent.watcher_slot, trn::tasks::kSlotIo) << "and the watching moves with the I/O role";
  // The I/O role's one spare is the devices' second attachment, kept for it, and the TRN supervisor's
  // is its standby; no other slot has one.
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    const bsp::TileId kept = slot == trn::tasks::kSlotIo                ? trn::tasks::kIoBackupTile
                             : slot == trn::tasks::kSlotTrnSupervisor ? trn::tasks::kSupervisorStandbyTile
                                                                        : bsp::kNoTile;
    EXPECT_EQ(c.tile_health.slot_spare[slot], kept) << "slot " << slot;
  }
  EXPECT_EQ(trn::tasks::kIoBackupTile, 8U);
  EXPECT_EQ(trn::tasks::kTileRoles[trn::tasks::kIoBackupTile], trn::tasks::Role::kSpare) << "off until the role moves";
  EXPECT_EQ(trn::tasks::kSupervisorStandbyTile, 16U);
  EXPECT_EQ(trn::tasks::kTileRoles[trn::tasks::kSupervisorStandbyTile], trn::tasks::Role::kSpare);
  // The supervisor is a role the directory names: its reports, the watching and its standby follow it.
  EXPECT_EQ(c.agent.standby, trn::tasks::kSupervisorStandbyTile);
  EXPECT_EQ(c.agent.supervisor_slot, trn::tasks::kSlotTrnSupervisor);
  EXPECT_EQ(c.endpoint.report_slot, trn::tasks::kSlotTrnSupervisor);
  EXPECT_EQ(c.tile_health.own_slot, trn::tasks::kSlotTrnSupervisor);
  EXPECT_EQ(c.filter.replica_tiles, trn::tasks::kReplicaTiles);
  EXPECT_EQ(c.sup.replica_tiles, trn::tasks::kReplicaTiles);
  for (std::uint32_t slot = 0; slot < udn::kRoleSlots; ++slot) {
    EXPECT_EQ(c.endpoint.roles.tile[slot], trn::tasks::slot_boot_tile(trn::tasks::kTile64Deployment, slot)) << "slot " << slot;
  }
  trn::tasks::tile_map_vision_tiles(trn::tasks::kTile64Deployment, c.coord, 0);
  EXPECT_EQ(configure_image(c), ImageError::kOk);
}

TEST(Deployment, EveryWiredTileOffTheChipIsRefused) {
  for (const trn::tasks::Wire& w : trn::tasks::kWiring) {
    ImageConfig c{};
    trn::tasks::wire_image(c, trn::tasks::kTile64Deployment);
    trn::tasks::tile_map_vision_tiles(trn::tasks::kTile64Deployment, c.coord, 0);
    w.set(c) = 64U;
    EXPECT_EQ(configure_image(c), ImageError::kBadTile) << w.field;
  }
}

TEST(Deployment, PlacementsRolesAndSlotsAgree) {
  using trn::tasks::Role;
  for (const trn::tasks::Placement& p : trn::tasks::kPlacements) {
    EXPECT_EQ(trn::tasks::kTileRoles[p.tile], p.role);
    if (p.slot != trn::tasks::kNoSlot) {
      EXPECT_EQ(trn::tasks::slot_role(p.slot), p.role);
      EXPECT_EQ(trn::tasks::slot_boot_tile(trn::tasks::kTile64Deployment, p.slot), p.tile);
    }
  }
  EXPECT_EQ(trn::tasks::slot_boot_tile(trn::tasks::kTile64Deployment, trn::tasks::kNoSlot), bsp::kNoTile);
  EXPECT_EQ(trn::tasks::slot_role(trn::tasks::kNoSlot), Role::kSpare);
  EXPECT_EQ(trn::tasks::slot_role(trn::tasks::kSlotVisionPool), Role::kVision);
  // The coordinator, the filter, its replicas, the two application supervisors and the I/O role (to
  // its backup only) move; the TRN supervisor is moved by its watcher (to its standby), not by itself.
  EXPECT_EQ(trn::tasks::movable_slots(), (1U << trn::tasks::kSlotCoordinator) | (1U << trn::tasks::kSlotFilter) |
                                             (1U << trn::tasks::kSlotIo) |
                                             (7U << trn::tasks::kSlotReplica0) |
                                             (1U << trn::tasks::kSlotFilterSupervisor) |
                                             (1U << trn::tasks::kSlotVisionSupervisor));
  EXPECT_STREQ(trn::tasks::role_name(Role::kFilterReplica), "filter_replica");
  EXPECT_EQ(trn::tasks::role_code(Role::kVision), 'v');
  EXPECT_TRUE(trn::tasks::role_table(Role::kSpare).empty());
  EXPECT_EQ(trn::tasks::role_table(Role::kIo).data(), trn::tasks::kIoRole);
}

// The same roles deployed on Maestro's 7x7 grid: its own tiles, 35 vision tiles, three free spares, and
// every tile the configuration names on its grid.
ImageConfig wired();

TEST(Deployment, MaestroDeploysTheSameRolesOnItsSevenBySevenGrid) {
  using trn::tasks::Role;
  const trn::tasks::Deployment& m = trn::tasks::kMaestroDeployment;
  EXPECT_EQ(trn::tasks::find_deployment("maestro"), &m);
  EXPECT_EQ(trn::tasks::find_deployment("tile64"), &trn::tasks::kTile64Deployment);
  EXPECT_EQ(trn::tasks::find_deployment("tile65"), nullptr);
  EXPECT_EQ(trn::tasks::find_deployment(nullptr), nullptr);
  EXPECT_EQ(m.tiles(), 49U);
  EXPECT_EQ(trn::tasks::count_role(m, Role::kVision), 35U);
  EXPECT_EQ(trn::tasks::count_role(m, Role::kSpare), 5U) << "three free, the I/O role's backup and the standby";
  EXPECT_EQ(trn::tasks::tile_role(m, 49U), Role::kSpare) << "off the chip";
  EXPECT_EQ(trn::tasks::tile_role(m, 48U), Role::kVision);
  EXPECT_EQ(trn::tasks::movable_slots(m), trn::tasks::movable_slots()) << "the same roles move on both chips";
  ImageConfig c{};
  trn::tasks::wire_image(c, m);
  trn::tasks::tile_map_vision_tiles(m, c.coord, 0);
  EXPECT_EQ(c.deployment, &m);
  for (const trn::tasks::Wire& w : trn::tasks::kWiring) {
    EXPECT_EQ(w.get(c), trn::tasks::boot_tile(m, w.to, w.index)) << w.field;
    EXPECT_LT(w.get(c), 49U) << w.field;
  }
  EXPECT_EQ(c.io.filter_tile, 9U);
  EXPECT_EQ(c.agent.standby, 13U);
  EXPECT_EQ(c.tile_health.slot_spare[trn::tasks::kSlotIo], 7U);
  EXPECT_EQ(c.coord.vision_count, 35U);
  EXPECT_EQ(c.coord.vision_tiles[0], 14U);
  EXPECT_EQ(c.coord.vision_tiles[34], 48U);
  ASSERT_EQ(configure_image(c), ImageError::kOk);
  EXPECT_EQ(trn::tasks::slot_role(trn::tasks::kSlotFilter), Role::kFilter);
  // A tile of the TILE64's grid beyond Maestro's is off this chip.
  ImageConfig off = c;
  off.io.filter_tile = 49U;
  const char* what = nullptr;
  EXPECT_EQ(configure_image(off, &what), ImageError::kBadTile);
  EXPECT_STREQ(what, "io.filter_tile");
  ImageConfig vision = c;
  vision.coord.vision_tiles[3] = 60U;
  EXPECT_EQ(configure_image(vision), ImageError::kBadVisionList);
  // A deployment that is not one of the image's is refused.
  ImageConfig unknown = c;
  static constexpr trn::tasks::Deployment kOther = trn::tasks::kMaestroDeployment;
  unknown.deployment = &kOther;
  EXPECT_EQ(configure_image(unknown, &what), ImageError::kBadTile);
  EXPECT_STREQ(what, "deployment");
  // The image goes back to the TILE64 for the tests after this one.
  ASSERT_EQ(configure_image(wired()), ImageError::kOk);
}

// Every FDIR threshold in one table: each field's default is in its range, a value out of it is
// refused with the field's name, and docs/FDIR.md's table is the declaration's.
ImageConfig wired() {
  ImageConfig c{};
  trn::tasks::wire_image(c, trn::tasks::kTile64Deployment);
  trn::tasks::tile_map_vision_tiles(trn::tasks::kTile64Deployment, c.coord, 0);
  return c;
}

TEST(FdirParams, EveryDefaultIsInItsRange) {
  const ImageConfig c = wired();
  EXPECT_EQ(trn::tasks::fdir_param_out_of_range(c), nullptr);
  const char* what = "x";
  EXPECT_EQ(configure_image(c, &what), ImageError::kOk);
  EXPECT_EQ(what, nullptr);
}

TEST(FdirParams, AFieldOutOfItsRangeIsRefusedByName) {
  std::size_t fields = 0U;
  for (const trn::tasks::FdirParam& p : trn::tasks::kFdirParams) {
    if (p.get == nullptr) {
      EXPECT_EQ(p.set, nullptr) << p.name;
      EXPECT_EQ(p.min, p.value) << p.name;
      continue;
    }
    ++fields;
    for (const std::uint64_t bad : {std::uint64_t{p.min} - 1U, std::uint64_t{p.max} + 1U}) {
      if (bad > 0xFFFF'FFFFU) {
        continue;  // min 0: nothing below
      }
      ImageConfig c = wired();
      p.set(c) = static_cast<std::uint32_t>(bad);
      EXPECT_EQ(p.get(c), bad) << p.name << ": the row reads the field it writes";
      const char* what = nullptr;
      EXPECT_EQ(configure_image(c, &what), ImageError::kBadConfig) << p.name << " = " << bad;
      EXPECT_STREQ(what, p.name);
    }
  }
  EXPECT_GE(fields, 28U);
}

TEST(FdirParams, ATieBetweenParametersIsRefusedByName) {
  ImageConfig c = wired();
  c.tile_health.self_test_wait_ticks = c.tile_health.self_test_ticks;
  const char* what = nullptr;
  EXPECT_EQ(configure_image(c, &what), ImageError::kBadConfig);
  EXPECT_STREQ(what, "tile_health.self_test_wait_ticks");
  c = wired();
  c.io.filter_tile = 70U;
  EXPECT_EQ(configure_image(c, &what), ImageError::kBadTile);
  EXPECT_STREQ(what, "io.filter_tile");
}

TEST(FdirParams, TheTableInFdirMdIsTheDeclaration) {
  std::ifstream f(std::string(build_info::kRepoRoot) + "/docs/FDIR.md");
  ASSERT_TRUE(f) << "docs/FDIR.md";
  std::string line;
  std::string doc;
  bool in = false;
  while (std::getline(f, line)) {
    if (line == "## Parameters") {
      in = true;
    } else if (in && line.rfind("## ", 0) == 0) {
      break;
    } else if (in && line.rfind("| `", 0) == 0) {
      doc += line + "\n";
    }
  }
  const std::string want = tools::fdir_params_markdown();
  EXPECT_EQ(doc, want) << "docs/FDIR.md, \"Parameters\", should hold these rows (make docs-params writes them):\n"
                       << want;
}

}  // namespace
