/**
 * @file ft_sink.cpp
 * @brief Messaging events to flight events.
 */
#include "fdir/ft_sink.hpp"

#include "fdir/event_log.hpp"

namespace fdir {
namespace {

std::uint32_t tile_or_unknown(bsp::TileId t) noexcept { return t == bsp::kNoTile ? kUnknown : t; }

void on_ft_event(void* /*ctx*/, bsp::TileId /*tile*/, const udn::FtEvent& e) noexcept {
  const std::uint32_t peer = tile_or_unknown(e.peer);
  switch (e.cause) {
    case udn::FtCause::kCorrected: report(EventId::kPacketCorrected, peer, e.channel, e.seq); break;
    case udn::FtCause::kForwarded: report(EventId::kPacketForwarded, peer, e.seq, e.channel); break;
    case udn::FtCause::kDamaged: report(EventId::kPacketDamaged, peer, e.channel, e.seq); break;
    case udn::FtCause::kResentNack: report(EventId::kPacketResent, peer, 0U, e.channel, e.seq); break;
    case udn::FtCause::kResentTimeout: report(EventId::kPacketResent, peer, 1U, e.channel, e.seq); break;
    case udn::FtCause::kResentBusy: break;  // flow control: the messaging layer counts it and never emits it
    case udn::FtCause::kRetriesExhausted: report(EventId::kPacketGaveUp, peer, e.word, e.channel, e.seq); break;
    case udn::FtCause::kUnreachable: report(EventId::kRouteUnreachable, peer, e.word, e.channel, e.seq); break;
    case udn::FtCause::kSettled: report(EventId::kPacketSettled, peer, e.word, e.channel, e.seq); break;
    case udn::FtCause::kForwardUnreachable: report(EventId::kForwardUnreachable, peer, 0U); break;
    case udn::FtCause::kSuspectNeighbour: report(EventId::kNeighbourSuspect, peer, 0U); break;
    case udn::FtCause::kMapApplied: report(EventId::kMapApplied, e.word, peer); break;
    case udn::FtCause::kMapPushed: report(EventId::kMapPushed, peer, 0U, e.word); break;
    case udn::FtCause::kTransitLost: report(EventId::kTransitLost, peer, 0U); break;
    case udn::FtCause::kTransitBack: report(EventId::kTransitBack, peer, 0U); break;
    case udn::FtCause::kStateRepaired: report(EventId::kEndpointStateBad, e.channel, e.peer, e.word); break;
  }
}

}  // namespace

udn::FtEventSink ft_event_sink() noexcept { return udn::FtEventSink{&on_ft_event, nullptr}; }

}  // namespace fdir
