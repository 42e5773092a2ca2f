/**
 * @file ft_sink.hpp
 * @brief The sink that turns the messaging layer's events into flight events.
 *
 * The image puts ft_event_sink() in every endpoint's configuration; the
 * messaging layer then reports corrections, forwards, damaged packets,
 * resends, give-ups, suspects and applied maps into the flight event log
 * without including it.
 */
#pragma once

#include "udn/ft_event.hpp"

namespace fdir {

/** The sink for udn::EndpointConfig::sink. */
udn::FtEventSink ft_event_sink() noexcept;

}  // namespace fdir
