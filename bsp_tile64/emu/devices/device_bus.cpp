/**
 * @file device_bus.cpp
 * @brief Device FIFOs on the I/O tile and the events that fill them.
 */
#include "bsp_tile64/emu/devices/device_bus.hpp"

#include "bsp_tile64/emu/board.hpp"
#include "bsp_tile64/emu/trace.hpp"

#include <array>
#include <cmath>

namespace bsp {
namespace {

template <class T, std::uint32_t N>
struct Fifo {
  std::array<T, N> items{};
  std::uint32_t head = 0;
  std::uint32_t count = 0;
  bool push(const T& v) noexcept {
    if (count == N) {
      return false;
    }
    items[(head + count) % N] = v;
    ++count;
    return true;
  }
  bool pop(T* out) noexcept {
    if (count == 0U || out == nullptr) {
      return false;
    }
    *out = items[head];
    head = (head + 1U) % N;
    --count;
    return true;
  }
};

/** One end of the cross-strap: a tile and its FIFOs. */
struct Attachment {
  TileId tile = kNoTile;
  Fifo<ImuSample, kImuFifoDepth> imu;
  Fifo<FrameRecord, kFrameFifoDepth> frames;
  Fifo<Telecommand, kCommandFifoDepth> commands;
};

struct Bus {
  DeviceBusConfig cfg{};
  bool attached = false;
  std::array<Attachment, 2> end{};  ///< prime, backup
  std::uint32_t selected = 0;       ///< the attachment the devices deliver to
  std::uint32_t next_command = 0;
  DeviceStats stats{};
  std::uint32_t next_imu_seq = 0;
  std::uint32_t next_frame = 0;
  FrameRecord pending{};  ///< captured, waiting for its readout delay
  bool render_due = false;      ///< a capture happened; its image is rendered at the next barrier
  std::uint32_t render_frame = 0;
};

Bus g_bus;

Attachment& sel() noexcept { return g_bus.end[g_bus.selected]; }

/** The tile the next delivery's interrupt goes to. */
TileId sel_tile() noexcept { return sel().tile; }

/**
 * A delivery whose event was scheduled before a select (on the tile selected
 * then) went to the new attachment: its interrupt goes there too, at the
 * next barrier like any effect across tiles.
 */
void follow_select(TileId event_tile, Cycles cycle) noexcept {
  if (event_tile != sel_tile()) {
    (void)schedule_event(cycle, sel_tile(), Irq::kDevice, nullptr, 0U);
  }
}

/** The calling tile's attachment (from the host: the selected one); nullptr if it has none. */
Attachment* mine() noexcept {
  const TileId t = current_tile();
  if (t == kNoTile) {
    return &sel();
  }
  for (Attachment& a : g_bus.end) {
    if (a.tile == t) {
      return &a;
    }
  }
  return nullptr;
}

Cycles cycle_at(double t_s) noexcept {
  return static_cast<Cycles>(std::llround(t_s * static_cast<double>(board_config().profile.clock_hz)));
}

Cycles imu_cycle(std::uint32_t seq) noexcept {
  // Exact integer: the sample of interval seq ends at (seq + 1) / 100 s.
  return (static_cast<Cycles>(seq) + 1U) * (board_config().profile.clock_hz / kImuRateHz);
}

double frame_time(std::uint32_t n) noexcept {
  return g_bus.cfg.first_frame_s + static_cast<double>(n) / g_bus.cfg.camera->config().rate_hz;
}

void on_imu(TileId tile, Cycles cycle, std::uint64_t seq) noexcept {
  const ImuSample s = g_bus.cfg.imu->sample(static_cast<std::uint32_t>(seq));
  if (sel().imu.push(s)) {
    ++g_bus.stats.imu_delivered;
  } else {
    ++g_bus.stats.imu_dropped;
  }
  follow_select(tile, cycle);
  g_bus.next_imu_seq = static_cast<std::uint32_t>(seq) + 1U;
  const double next_t = static_cast<double>(g_bus.next_imu_seq + 1U) / kImuRateHz;
  if (next_t <= g_bus.cfg.last_time_s) {
    (void)schedule_event(imu_cycle(g_bus.next_imu_seq), sel_tile(), Irq::kDevice, &on_imu,
                         g_bus.next_imu_seq);
  }
}

/**
 * Renders the captured frame into the camera's DDR ring. It runs at the
 * barrier after the capture, on the host, not inside the capture event: an
 * event runs on the I/O tile's current stack, and the renderer's frames
 * (~2.5 KB, ~23 KB in sanitizer builds) are the camera's, not the tile's.
 * The image depends only on the capture time, so when it is rendered does
 * not change a bit of it.
 */
void render_pending() noexcept {
  if (!g_bus.render_due) {
    return;
  }
  g_bus.render_due = false;
  const double t = frame_time(g_bus.render_frame);
  const FrameInfo f = g_bus.cfg.camera->capture(t);
  const CameraModel& m = g_bus.cfg.camera->model();
  g_bus.pending = FrameRecord{f.pixels, f.seq, m.width_px, m.height_px,
                              f.error == CameraError::kOk ? 0U : 1U, f.t_s};
  const double next_t = frame_time(g_bus.render_frame + 1U);
  if (next_t <= g_bus.cfg.last_time_s) {
    g_bus.cfg.camera->prepare(next_t);  // the next image is fixed already: a host may render it meanwhile
  }
}

void on_barrier(Cycles /*barrier*/) noexcept { render_pending(); }

void on_frame_ready(TileId tile, Cycles cycle, std::uint64_t /*arg*/) noexcept {
  render_pending();  // a readout shorter than a quantum comes before the barrier
  if (sel().frames.push(g_bus.pending)) {
    ++g_bus.stats.frames_delivered;
  } else {
    ++g_bus.stats.frames_dropped;
  }
  follow_select(tile, cycle);
}

void on_capture(TileId /*tile*/, Cycles /*cycle*/, std::uint64_t n) noexcept {
  const double t = frame_time(static_cast<std::uint32_t>(n));
  g_bus.render_due = true;
  g_bus.render_frame = static_cast<std::uint32_t>(n);
  // The readout delay is shorter than the frame period, so at most one frame is pending.
  (void)schedule_event(cycle_at(t + g_bus.cfg.frame_readout_s), sel_tile(), Irq::kDevice, &on_frame_ready,
                       0);
  const double next_t = frame_time(static_cast<std::uint32_t>(n) + 1U);
  if (next_t <= g_bus.cfg.last_time_s) {
    (void)schedule_event(cycle_at(next_t), sel_tile(), Irq::kCount, &on_capture, n + 1U);
  }
}

void on_command(TileId tile, Cycles cycle, std::uint64_t arg) noexcept {
  const Telecommand c{g_bus.next_command++, static_cast<std::uint32_t>(arg >> 32U), static_cast<std::uint32_t>(arg)};
  if (sel().commands.push(c)) {
    ++g_bus.stats.commands_delivered;
  } else {
    ++g_bus.stats.commands_dropped;
  }
  follow_select(tile, cycle);
}

}  // namespace

DeviceBusError attach_devices(const DeviceBusConfig& cfg) noexcept {
  const TileId tiles = board_config().profile.tiles();
  if (cfg.io_tile >= tiles || (cfg.backup_tile != kNoTile && (cfg.backup_tile >= tiles || cfg.backup_tile == cfg.io_tile)) ||
      cfg.frame_readout_s < 0.0 ||
      (cfg.camera != nullptr && cfg.frame_readout_s >= 1.0 / cfg.camera->config().rate_hz)) {
    return DeviceBusError::kBadConfig;
  }
  g_bus = Bus{};
  g_bus.cfg = cfg;
  g_bus.attached = true;
  g_bus.end[0].tile = cfg.io_tile;
  g_bus.end[1].tile = cfg.backup_tile;
  if (cfg.imu != nullptr &&
      schedule_event(imu_cycle(0), cfg.io_tile, Irq::kDevice, &on_imu, 0) != BoardError::kOk) {
    return DeviceBusError::kScheduleFailed;
  }
  if (cfg.camera != nullptr &&
      (add_barrier_hook(&on_barrier) != BoardError::kOk ||
       schedule_event(cycle_at(cfg.first_frame_s), cfg.io_tile, Irq::kCount, &on_capture, 0) != BoardError::kOk)) {
    return DeviceBusError::kScheduleFailed;
  }
  if (cfg.camera != nullptr && cfg.first_frame_s <= cfg.last_time_s) {
    cfg.camera->prepare(cfg.first_frame_s);
  }
  return DeviceBusError::kOk;
}

bool imu_read(ImuSample* out) noexcept {
  Attachment* a = mine();
  return a != nullptr && a->imu.pop(out);
}

bool frame_read(FrameRecord* out) noexcept {
  Attachment* a = mine();
  return a != nullptr && a->frames.pop(out);
}

bool command_read(Telecommand* out) noexcept {
  Attachment* a = mine();
  return a != nullptr && a->commands.pop(out);
}

DeviceSelect devices_select() noexcept {
  DeviceSelect d{SelectResult::kNoBus, kNoTile, 0U, 0U, 0U};
  if (!g_bus.attached) {
    return d;
  }
  const TileId t = current_tile();
  std::uint32_t want = g_bus.end.size();
  for (std::uint32_t i = 0; i < g_bus.end.size(); ++i) {
    want = (g_bus.end[i].tile == t && t != kNoTile) ? i : want;
  }
  if (want == g_bus.end.size()) {
    d.result = SelectResult::kNotWired;
    return d;
  }
  d.result = SelectResult::kSelected;
  if (want == g_bus.selected) {
    return d;
  }
  // What waits in the attachment left behind is lost with it: counted, and emptied.
  Attachment& old = sel();
  d.from = old.tile;
  d.imu_stranded = old.imu.count;
  d.frames_stranded = old.frames.count;
  d.commands_stranded = old.commands.count;
  old.imu = {};
  old.frames = {};
  old.commands = {};
  g_bus.selected = want;
  ++g_bus.stats.selects;
  g_bus.stats.imu_stranded += d.imu_stranded;
  g_bus.stats.frames_stranded += d.frames_stranded;
  g_bus.stats.commands_stranded += d.commands_stranded;
  trace_record(tile_time(t), t, static_cast<std::uint16_t>(BoardEvent::kDeviceSelect), d.from, d.imu_stranded);
  return d;
}

DeviceBusError schedule_command(double t_s, std::uint32_t code, std::uint32_t arg) noexcept {
  if (!g_bus.attached || !(t_s >= 0.0)) {
    return DeviceBusError::kBadConfig;
  }
  const std::uint64_t word = (static_cast<std::uint64_t>(code) << 32U) | arg;
  return schedule_event(cycle_at(t_s), sel_tile(), Irq::kDevice, &on_command, word) == BoardError::kOk
             ? DeviceBusError::kOk
             : DeviceBusError::kScheduleFailed;
}

DeviceStats device_stats() noexcept { return g_bus.stats; }

TileId io_tile() noexcept { return g_bus.attached ? sel_tile() : kNoTile; }

}  // namespace bsp
