/**
 * @file endpoint_messages_test.cpp
 * @brief The endpoint's message layouts (udn/endpoint_messages.cpp): each packs and unpacks to
 *        itself, and a message with a field out of its documented range is refused untouched.
 */
#include "udn/endpoint.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

namespace {

using Words = std::span<const std::uint32_t>;

TEST(EndpointMessages, SuspectAndTransitRoundTrip) {
  std::array<std::uint32_t, udn::kSuspectWords> s{};
  udn::pack_suspect(udn::SuspectReport{3U, 4U}, s);
  udn::SuspectReport sr{};
  ASSERT_TRUE(udn::unpack_suspect(s, sr));
  EXPECT_EQ(sr.reporter, 3U);
  EXPECT_EQ(sr.suspect, 4U);
  std::array<std::uint32_t, udn::kTransitWords> t{};
  udn::pack_transit(udn::TransitReport{5U, 40U, true}, t);
  udn::TransitReport tr{};
  ASSERT_TRUE(udn::unpack_transit(t, tr));
  EXPECT_EQ(tr.prober, 5U);
  EXPECT_EQ(tr.target, 40U);
  EXPECT_TRUE(tr.lost);
}

TEST(EndpointMessages, SuspectOfAnOffGridOrSameTileIsRefusedUntouched) {
  const udn::SuspectReport before{7U, 8U};
  for (const auto& w : {std::array<std::uint32_t, 3>{udn::kMsgSuspect, 3U, udn::kRouteMaxTiles},
                        std::array<std::uint32_t, 3>{udn::kMsgSuspect, udn::kRouteMaxTiles + 3U, 4U},
                        std::array<std::uint32_t, 3>{udn::kMsgSuspect, 4U, 4U}}) {
    udn::SuspectReport r = before;
    EXPECT_FALSE(udn::unpack_suspect(w, r));
    EXPECT_EQ(r.reporter, before.reporter);
    EXPECT_EQ(r.suspect, before.suspect);
  }
  udn::SuspectReport r{};
  EXPECT_FALSE(udn::unpack_suspect(Words(std::array<std::uint32_t, 2>{udn::kMsgSuspect, 3U}), r));
}

TEST(EndpointMessages, TransitWithAFlagOtherThanZeroOrOneIsRefused) {
  udn::TransitReport r{};
  EXPECT_FALSE(udn::unpack_transit(std::array<std::uint32_t, 4>{udn::kMsgTransit, 3U, 4U, 2U}, r));
}

TEST(EndpointMessages, RoleMoveAndParkedRoundTripAndRefuseOutOfRange) {
  std::array<std::uint32_t, udn::kRoleMoveWords> m{};
  udn::pack_role_move(udn::RoleMove{2U, 17U, 3U}, m);
  udn::RoleMove rm{};
  ASSERT_TRUE(udn::unpack_role_move(m, rm));
  EXPECT_EQ(rm.slot, 2U);
  EXPECT_EQ(rm.tile, 17U);
  EXPECT_EQ(rm.version, 3U);
  // A move to no tile, of an unknown slot, or to the boot version: refused.
  EXPECT_FALSE(udn::unpack_role_move(std::array<std::uint32_t, 4>{udn::kMsgRoleMove, 2U, bsp::kNoTile, 3U}, rm));
  EXPECT_FALSE(udn::unpack_role_move(std::array<std::uint32_t, 4>{udn::kMsgRoleMove, udn::kRoleSlots, 1U, 3U}, rm));
  EXPECT_FALSE(udn::unpack_role_move(std::array<std::uint32_t, 4>{udn::kMsgRoleMove, 2U, 1U, 0U}, rm));
  EXPECT_EQ(rm.tile, 17U);
  std::array<std::uint32_t, udn::kParkedWords> p{};
  udn::pack_parked(udn::ParkedSet{0x8000'0000'0000'0001ULL, 9U}, p);
  udn::ParkedSet ps{};
  ASSERT_TRUE(udn::unpack_parked(p, ps));
  EXPECT_EQ(ps.tiles, 0x8000'0000'0000'0001ULL);
  EXPECT_EQ(ps.serial, 9U);
}

TEST(EndpointMessages, FaultMapRoundTrips) {
  udn::FaultMap map{};
  ASSERT_EQ(udn::fault_map_init(map, 8U, 8U), udn::RouteError::kOk);
  ASSERT_EQ(udn::fault_map_fail_tile(map, 44U), udn::RouteError::kOk);
  map.failed_links[3] = 0x5U;
  map.no_forward = 1ULL << 63U;
  std::array<std::uint32_t, udn::kFaultMapWords> w{};
  udn::pack_fault_map(map, w);
  udn::FaultMap back{};
  ASSERT_TRUE(udn::unpack_fault_map(w, back));
  EXPECT_EQ(back.version, map.version);
  EXPECT_EQ(back.failed_tiles, map.failed_tiles);
  EXPECT_EQ(back.no_forward, map.no_forward);
  EXPECT_EQ(back.failed_links, map.failed_links);
}

TEST(EndpointMessages, FaultMapNamingTilesOffItsGridIsRefusedUntouched) {
  udn::FaultMap map{};
  ASSERT_EQ(udn::fault_map_init(map, 4U, 4U), udn::RouteError::kOk);
  std::array<std::uint32_t, udn::kFaultMapWords> w{};
  udn::pack_fault_map(map, w);
  const udn::FaultMap before = map;
  auto failed = w;
  failed[4] = 1U << 20U;  // tile 20 of a 16-tile grid
  auto forward = w;
  forward[7] = 1U;  // tile 32
  auto link = w;
  link[8 + 5] = 0x1U;  // tile 20's east link
  auto dirs = w;
  dirs[8] = 0x10U;  // tile 0: a fifth direction
  for (const auto& bad : {failed, forward, link, dirs}) {
    EXPECT_FALSE(udn::unpack_fault_map(bad, map));
    EXPECT_EQ(map.cols, before.cols);
    EXPECT_EQ(map.failed_tiles, before.failed_tiles);
  }
}

}  // namespace
