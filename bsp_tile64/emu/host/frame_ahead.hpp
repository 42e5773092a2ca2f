/**
 * @file frame_ahead.hpp
 * @brief A second host thread that renders the camera's next frame while the board runs.
 *
 * Host-side infrastructure (not a hardware model). A capture's image is a pure
 * function of its capture time, the camera's read-noise state before it and
 * the shaded terrain, all fixed before the frame is due: captures come on a
 * fixed schedule (device_bus.cpp), whatever the flight software does. So while
 * the emulator runs the second before a capture, this thread renders that
 * frame into a staging buffer from a copy of the noise state; the capture then
 * copies it into the camera's DDR ring and takes the noise state after it.
 * Same bytes, same noise state, same trace: nothing the board does waits on
 * the host thread's timing except the host itself, which waits at the capture
 * if the frame is not finished (CameraDeviceAhead.* tests compare both ways).
 *
 * One worker per process. Nothing here allocates after start(), which a host
 * front end calls before it seals the heap.
 */
#pragma once

#include "bsp_tile64/emu/devices/camera.hpp"
#include "bsp_tile64/emu/rng.hpp"

#include <cstddef>
#include <cstdint>

namespace bsp::frame_ahead {

/**
 * Starts the worker with a staging buffer of @p frame_bytes (allocates; call
 * before the heap is sealed). A second call with a size that fits keeps the
 * running worker. @return false if the thread cannot be started.
 */
bool start(std::size_t frame_bytes);

/** Waits for any render in progress, drops it, and ends the worker. */
void stop() noexcept;

/** Whether a worker is running. */
[[nodiscard]] bool running() noexcept;

/**
 * Asks for the frame @p cam will capture as number @p seq at @p t_s, its read
 * noise drawn from @p noise onwards. Waits for a render in progress first; a
 * no-op without a worker or when the frame is larger than the staging buffer.
 */
void request(const CameraDevice& cam, std::uint32_t seq, double t_s, const Rng& noise) noexcept;

/**
 * If the last request was @p cam's frame @p seq at @p t_s (exactly): waits for
 * it, copies its pixels into @p out, and gives its error and the noise state
 * after it. @return false (nothing written) if there is no such request.
 */
bool take(const CameraDevice& cam, std::uint32_t seq, double t_s, std::uint8_t* out, CameraError* error,
          Rng* noise_after) noexcept;

/** Waits for any render in progress and drops every request (a camera going away or being re-initialised). */
void forget() noexcept;

/** Frames taken from the worker and frames rendered at the capture instead, since start(). */
struct Stats {
  std::uint64_t taken;
  std::uint64_t missed;
};
[[nodiscard]] Stats stats() noexcept;

}  // namespace bsp::frame_ahead
