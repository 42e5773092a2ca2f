/**
 * @file io_task.cpp
 * @brief I/O tile driver: device FIFO to UDN.
 */
#include "trn/tasks/io/io_task.hpp"

#include "bsp_tile64/api/device_io.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/supervisor.hpp"
#include "kernel/kernel.hpp"
#include "trn/events.hpp"
#include "trn/tasks/io/imu_ring.hpp"
#include "trn/tasks/messages.hpp"
#include "udn/endpoint.hpp"

#include <array>

namespace trn::tasks {
namespace {

/** The task's own state, in its tile's RAM (carve kIoStateCarve): given by the device interrupt, taken by the loop. */
struct IoState {
  k::Semaphore device_ready{0, 1000};
};
/** What an upset of it does (bsp::ControlLayout): the semaphore is emulated state, its wait list checked by the kernel. */
constexpr std::array kIoStateFields{BSP_CONTROL_NESTED(IoState, device_ready, k::SemaphoreLayout::kLayout)};
constexpr bsp::ControlLayout kIoStateLayout{kIoStateFields, sizeof(IoState), alignof(IoState)};
static_assert(bsp::control_layout_ok(kIoStateLayout), "every member of IoState");

/** In the I/O tile's RAM, set at its task's start (before the interrupt hook is installed). */
IoState* g_io = nullptr;
/** The task's counters, in its tile's RAM (kIoTaskStatsRecord); carved at task start. */
IoTaskStats* g_stats = nullptr;

void device_isr(bsp::TileId /*tile*/) noexcept { (void)g_io->device_ready.give_from_isr(); }

/** Samples forwarded per wake-up at most (the FIFO depth). */
constexpr std::uint32_t kMaxPerWake = bsp::kImuFifoDepth;
/** A sample that cannot be sent within this many ticks is counted and dropped. */
constexpr std::uint32_t kSendTicks = kControlSendTicks;

void forward_frames(const IoTaskConfig& cfg) noexcept {
  bsp::FrameRecord f{};
  for (std::uint32_t n = 0; n < bsp::kFrameFifoDepth && bsp::frame_read(&f); ++n) {
    if (cfg.coordinator_tile == bsp::kNoTile) {
      continue;
    }
    const auto* base = reinterpret_cast<const std::uint8_t*>(  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): DDR bytes
        bsp::region_span(bsp::Region{bsp::Region::kDdr}).data());
    FrameNotice notice{f.seq, f.width_px, f.height_px, f.status, f.t_s,
                       static_cast<std::uint64_t>(f.pixels - base)};
    std::array<std::uint32_t, kFrameNoticeWords> w{};
    (void)fdir::msg::encode(kFrameMsg, notice, w);
    const bsp::TileId coord = udn::endpoint_role_tile(kSlotCoordinator, cfg.coordinator_tile);
    if (udn::endpoint_send(coord, kChanControl, w, kNoticeTicks) == udn::FtError::kOk) {
      ++g_stats->frames_forwarded;
    } else {
      ++g_stats->frame_send_failures;
    }
  }
}

/** A command for the filter, in its IMU stream after the last sample read (@p last_imu): it takes it at a defined job. */
void command_filter(const IoTaskConfig& cfg, std::uint32_t seq, std::uint32_t code, std::uint32_t arg,
                    std::uint32_t last_imu) noexcept {
  std::array<std::uint32_t, kCommandWords> w{};
  (void)fdir::msg::encode(kCommandMsg, Command{seq, code, arg, last_imu}, w);
  const bsp::TileId filter = udn::endpoint_role_tile(kSlotFilter, cfg.filter_tile);
  if (udn::endpoint_send(filter, kChanImu, w, kSendTicks) != udn::FtError::kOk) {
    ++g_stats->send_failures;
  }
}

/** A policy telecommand for the TRN supervisor (codes from kCmdFirstPolicy). */
void policy_to_supervisor(const IoTaskConfig& cfg, std::uint32_t code) noexcept {
  const fdir::Constraint constraint = code <= kCmdReliabilityHigh ? fdir::Constraint::kReliability : fdir::Constraint::kPower;
  const std::uint32_t level = (code - kCmdFirstPolicy) % 2U;  // normal / full 0, high / save 1
  std::array<std::uint32_t, fdir::kSupMsgWords> w{};
  (void)fdir::msg::encode(kPolicyOnControl,
                          fdir::SupMessage{static_cast<std::uint8_t>(constraint), static_cast<std::uint8_t>(level),
                                           fdir::kFromGround},
                          w);
  if (cfg.trn_supervisor_tile != bsp::kNoTile &&
      udn::endpoint_send(udn::endpoint_role_tile(kSlotTrnSupervisor, cfg.trn_supervisor_tile), kChanControl, w, kSendTicks) ==
          udn::FtError::kOk) {
    ++g_stats->policies;
  } else {
    ++g_stats->send_failures;
  }
}

/** A ground command of the filter's mode, as the filter supervisor's policy (it sends no command of its own for it). */
void tell_filter_supervisor(const IoTaskConfig& cfg, std::uint32_t code) noexcept {
  if (cfg.filter_supervisor_tile == bsp::kNoTile || (code != kCmdFilterTmr && code != kCmdFilterSimplex)) {
    return;
  }
  const std::uint32_t level = code == kCmdFilterTmr ? fdir::kReliabilityHigh : fdir::kReliabilityNormal;
  std::array<std::uint32_t, fdir::kSupMsgWords> w{};
  (void)fdir::msg::encode(kPolicyOnControl,
                          fdir::SupMessage{static_cast<std::uint8_t>(fdir::Constraint::kReliability),
                                           static_cast<std::uint8_t>(level), fdir::kFromGround},
                          w);
  if (udn::endpoint_send(udn::endpoint_role_tile(kSlotFilterSupervisor, cfg.filter_supervisor_tile), kChanControl, w,
                         kSendTicks) != udn::FtError::kOk) {
    ++g_stats->send_failures;
  }
}

/** Telecommands: the filter's into its stream, policies to the TRN supervisor; then the supervisors' commands. */
void forward_commands(const IoTaskConfig& cfg, std::uint32_t last_imu) noexcept {
  bsp::Telecommand c{};
  for (std::uint32_t n = 0; n < bsp::kCommandFifoDepth && bsp::command_read(&c); ++n) {
    if (c.code >= kCmdFirstPolicy && c.code <= kCmdPowerSave) {
      policy_to_supervisor(cfg, c.code);
    } else {
      command_filter(cfg, c.seq, c.code, c.arg, last_imu);
      tell_filter_supervisor(cfg, c.code);
    }
  }
  udn::FtMessage m{};
  for (std::uint32_t n = 0; n < 4U && udn::endpoint_receive(kChanControl, m) == udn::FtError::kOk; ++n) {
    SupCommand sc{};
    if (fdir::msg::decode(kSupCommandMsg, std::span<const std::uint32_t>(m.data.data(), m.data_words), sc)) {
      ++g_stats->sup_commands;
      command_filter(cfg, kSupCommandSeq | g_stats->sup_commands, sc.code, sc.node, last_imu);
    }
  }
}

}  // namespace

const bsp::ControlLayout& io_state_layout() noexcept { return kIoStateLayout; }

void io_task_main(void* arg) noexcept {
  const auto* cfg = static_cast<const IoTaskConfig*>(arg);
  bsp::MemError err = bsp::MemError::kOk;
  const bsp::Region ram{bsp::current_tile()};
  g_stats = bsp::carve_record(ram, kIoTaskStatsRecord, &err);
  // The state after the counters: they keep the place they had before it lived in tile RAM.
  g_io = g_stats != nullptr ? bsp::carve_record(ram, bsp::RamRecord<IoState>{kIoStateCarve, &kIoStateLayout}, &err)
                            : nullptr;
  if (cfg == nullptr || g_io == nullptr || k::set_isr(bsp::Irq::kDevice, &device_isr) != k::Status::kOk) {
    return;  // the tile's health monitor sees a task that never runs
  }
  // The cross-strap: the devices deliver to this tile from now on (a no-op where they already do:
  // the prime at boot, or a tile restarted in place). Started where no device is wired, it has
  // nothing to drive: the task ends, and its tile's health monitor sees one that never runs.
  const bsp::DeviceSelect sel = bsp::devices_select();
  if (sel.result == bsp::SelectResult::kNotWired) {
    return;
  }
  if (sel.from != bsp::kNoTile) {
    trn::report(ev::kIoDevicesTaken, sel.from, sel.imu_stranded, sel.frames_stranded, sel.commands_stranded);
  }
  std::array<std::uint32_t, kImuWords> words{};
  // Every sample is also recorded in DDR, for a filter that restarts to replay what it missed.
  ImuRing* const ring = imu_ring();
  std::uint32_t last_imu = kNoImuYet;
  for (;;) {  // the driver loop: one pass per device interrupt
    // The IMU interrupts every 10 ms in flight; the timeout keeps the check-ins going before and after.
    (void)g_io->device_ready.take(k::Timeout{kIdleCheckinTicks});
    k::checkin();
    bsp::ImuSample s{};
    for (std::uint32_t n = 0; n < kMaxPerWake && bsp::imu_read(&s); ++n) {
      if (ring != nullptr) {
        imu_ring_put(*ring, s);
      }
      last_imu = s.seq;
      (void)fdir::msg::encode(kImuMsg, s, words);
      const bsp::TileId filter = udn::endpoint_role_tile(kSlotFilter, cfg->filter_tile);
      if (udn::endpoint_send(filter, kChanImu, words, kSendTicks) == udn::FtError::kOk) {
        ++g_stats->imu_forwarded;
      } else {
        ++g_stats->send_failures;
      }
    }
    forward_frames(*cfg);
    forward_commands(*cfg, last_imu);
  }
}

}  // namespace trn::tasks
