/**
 * @file trace_dump.cpp
 * @brief Trace dump files: the writer (the board's trace sink), the reader, the first difference and event names.
 */
#include "tools/common/mission/trace_dump.hpp"

#include "bsp_tile64/emu/udn_net.hpp"
#include "fdir/event_ids.hpp"
#include "kernel/sched.hpp"
#include "tools/common/accounting/event_tables.hpp"

#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

namespace tools {
namespace {

constexpr std::array<char, 8> kMagic{'T', 'R', 'N', 'T', 'R', 'A', 'C', 'E'};
constexpr std::uint32_t kVersion = 1U;
constexpr std::size_t kHeaderBytes = 16U;  // magic, version (u32), record size (u32)
constexpr std::size_t kBufferRecords = 4096U;

/** The writer the sink appends to (the board has one sink, so one writer at a time). */
TraceDumpWriter* g_writer = nullptr;

void put_le(unsigned char* p, std::uint64_t v, std::size_t bytes) {
  for (std::size_t i = 0; i < bytes; ++i) {
    p[i] = static_cast<unsigned char>(v >> (8U * i));
  }
}

std::uint64_t get_le(const unsigned char* p, std::size_t bytes) {
  std::uint64_t v = 0U;
  for (std::size_t i = 0; i < bytes; ++i) {
    v |= static_cast<std::uint64_t>(p[i]) << (8U * i);
  }
  return v;
}

void encode(const bsp::TraceEvent& ev, unsigned char* p) {
  put_le(p, ev.time, 8U);
  put_le(p + 8, ev.a, 8U);
  put_le(p + 16, ev.b, 8U);
  put_le(p + 24, ev.tile, 4U);
  put_le(p + 28, ev.kind, 2U);
  put_le(p + 30, 0U, 2U);
}

bsp::TraceEvent decode(const unsigned char* p) {
  return bsp::TraceEvent{get_le(p, 8U), static_cast<bsp::TileId>(get_le(p + 24, 4U)),
                         static_cast<std::uint16_t>(get_le(p + 28, 2U)), get_le(p + 8, 8U), get_le(p + 16, 8U)};
}

/** Writes all of @p n bytes; @return false on an error. */
bool write_all(int fd, const unsigned char* p, std::size_t n) {
  while (n > 0U) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) {
      continue;
    }
    if (w <= 0) {
      return false;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

const char* board_kind_name(std::uint16_t kind) {
  switch (kind) {
    case static_cast<std::uint16_t>(bsp::BoardEvent::kInit): return "init";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kPowerOn): return "power_on";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kPowerOff): return "power_off";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kBoot): return "boot";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kReset): return "reset";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kIrqTaken): return "irq_taken";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kIrqDropped): return "irq_dropped";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kWatchdogExpired): return "watchdog_expired";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kHang): return "hang";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kHalt): return "halt";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kEventLate): return "event_late";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kFault): return "fault";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kSdcApplied): return "sdc_applied";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kQueueFull): return "queue_full";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kBootFailed): return "boot_failed";
    case static_cast<std::uint16_t>(bsp::BoardEvent::kDeviceSelect): return "device_select";
    case static_cast<std::uint16_t>(bsp::UdnTrace::kLost): return "udn_lost";
    case static_cast<std::uint16_t>(bsp::UdnTrace::kBitFlip): return "udn_bit_flip";
    case static_cast<std::uint16_t>(bsp::UdnTrace::kSwitchFail): return "udn_switch_fail";
    case static_cast<std::uint16_t>(bsp::UdnTrace::kLinkFail): return "udn_link_fail";
    case static_cast<std::uint16_t>(bsp::UdnTrace::kResized): return "udn_resized";
    default: return nullptr;
  }
}

const char* kernel_kind_name(std::uint16_t kind) {
  switch (kind) {
    case static_cast<std::uint16_t>(k::TraceKind::kStart): return "start";
    case static_cast<std::uint16_t>(k::TraceKind::kSwitch): return "switch";
    case static_cast<std::uint16_t>(k::TraceKind::kRelease): return "release";
    case static_cast<std::uint16_t>(k::TraceKind::kBlock): return "block";
    case static_cast<std::uint16_t>(k::TraceKind::kDeadlineMiss): return "deadline_miss";
    case static_cast<std::uint16_t>(k::TraceKind::kOverrun): return "overrun";
    case static_cast<std::uint16_t>(k::TraceKind::kStackOverflow): return "stack_overflow";
    case static_cast<std::uint16_t>(k::TraceKind::kTaskExit): return "task_exit";
    case static_cast<std::uint16_t>(k::TraceKind::kWaitListCut): return "wait_list_cut";
    case static_cast<std::uint16_t>(k::TraceKind::kKernelStateBad): return "kernel_state_bad";
    default: return nullptr;
  }
}

const char* fdir_kind_name(std::uint16_t kind) {
  // fdir/event_log.cpp traces an event as the fdir base plus the id's low 12 bits.
  for (const std::span<const fdir::EventInfo> table : kEventTables) {
    for (const fdir::EventInfo& e : table) {
      if ((static_cast<std::uint16_t>(e.id) & 0x0FFFU) == (kind & 0x0FFFU)) {
        return e.name;
      }
    }
  }
  return nullptr;
}

}  // namespace

TraceDumpWriter::~TraceDumpWriter() {
  std::string ignored;
  (void)close(ignored);
}

bool TraceDumpWriter::open(const std::string& path, std::string& error) {
  if (fd_ >= 0 || g_writer != nullptr) {
    error = "a trace dump is already open";
    return false;
  }
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    error = "cannot create the trace dump " + path + ": " + std::strerror(errno);
    return false;
  }
  path_ = path;
  buf_.assign(kBufferRecords * kTraceRecordBytes, 0U);
  std::array<unsigned char, kHeaderBytes> header{};
  std::memcpy(header.data(), kMagic.data(), kMagic.size());
  put_le(header.data() + 8, kVersion, 4U);
  put_le(header.data() + 12, kTraceRecordBytes, 4U);
  if (!write_all(fd_, header.data(), header.size())) {
    error = "cannot write the trace dump " + path + ": " + std::strerror(errno);
    (void)::close(fd_);
    fd_ = -1;
    return false;
  }
  used_ = 0U;
  events_ = 0U;
  failed_ = false;
  g_writer = this;
  bsp::set_trace_sink(&TraceDumpWriter::sink);
  return true;
}

bool TraceDumpWriter::close(std::string& error) {
  if (fd_ < 0) {
    return true;
  }
  if (g_writer == this) {
    bsp::set_trace_sink(nullptr);
    g_writer = nullptr;
  }
  flush();
  const bool closed = ::close(fd_) == 0;
  fd_ = -1;
  if (failed_ || !closed) {
    error = "cannot write the trace dump " + path_ + " (disk full?)";
    return false;
  }
  return true;
}

void TraceDumpWriter::sink(const bsp::TraceEvent& ev) noexcept {
  if (g_writer != nullptr) {
    g_writer->append(ev);
  }
}

void TraceDumpWriter::append(const bsp::TraceEvent& ev) noexcept {
  if (used_ + kTraceRecordBytes > buf_.size()) {
    flush();
  }
  encode(ev, buf_.data() + used_);
  used_ += kTraceRecordBytes;
  ++events_;
}

void TraceDumpWriter::flush() noexcept {
  if (used_ > 0U && !failed_) {
    failed_ = !write_all(fd_, buf_.data(), used_);
  }
  used_ = 0U;
}

std::optional<TraceDump> read_trace_dump(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot open " + path;
    return std::nullopt;
  }
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0) {
    error = path + " is not a trace dump (trn_mission --trace-dump writes them)";
    return std::nullopt;
  }
  const std::uint64_t version = get_le(bytes.data() + 8, 4U);
  const std::uint64_t record = get_le(bytes.data() + 12, 4U);
  if (version != kVersion || record != kTraceRecordBytes) {
    error = path + ": trace dump version " + std::to_string(version) + " (this tool reads version " +
            std::to_string(kVersion) + ")";
    return std::nullopt;
  }
  const std::size_t body = bytes.size() - kHeaderBytes;
  if (body % kTraceRecordBytes != 0U) {
    error = path + " is truncated (a partial record at its end)";
    return std::nullopt;
  }
  TraceDump d;
  d.events.reserve(body / kTraceRecordBytes);
  for (std::size_t off = kHeaderBytes; off < bytes.size(); off += kTraceRecordBytes) {
    d.events.push_back(decode(bytes.data() + off));
  }
  d.hash = fold_trace(d.events);
  return d;
}

std::uint64_t fold_trace(const std::vector<bsp::TraceEvent>& events) {
  // The board's starting value is what its hash reads right after a reset with no event.
  std::uint64_t h = bsp::trace_initial_hash();
  for (const bsp::TraceEvent& ev : events) {
    h = bsp::trace_fold(h, ev);
  }
  return h;
}

std::optional<std::size_t> first_difference(const std::vector<bsp::TraceEvent>& a,
                                            const std::vector<bsp::TraceEvent>& b) {
  const std::size_t n = a.size() < b.size() ? a.size() : b.size();
  for (std::size_t i = 0; i < n; ++i) {
    const bsp::TraceEvent& x = a[i];
    const bsp::TraceEvent& y = b[i];
    if (x.time != y.time || x.tile != y.tile || x.kind != y.kind || x.a != y.a || x.b != y.b) {
      return i;
    }
  }
  if (a.size() != b.size()) {
    return n;
  }
  return std::nullopt;
}

std::string trace_kind_name(std::uint16_t kind) {
  const std::uint16_t layer = kind & 0xF000U;
  const char* name = nullptr;
  const char* prefix = "unknown";
  if (layer == 0x0000U) {
    prefix = "board";
    name = board_kind_name(kind);
  } else if (layer == bsp::kTraceKernelBase) {
    prefix = "kernel";
    name = kernel_kind_name(kind);
  } else if (layer == bsp::kTraceUdnBase) {
    prefix = "udn";
  } else if (layer == bsp::kTraceFdirBase) {
    prefix = "fdir";
    name = fdir_kind_name(kind);
  } else if (layer == bsp::kTraceTrnBase) {
    prefix = "trn";
  }
  if (name != nullptr) {
    return std::string(prefix) + "." + name;
  }
  std::array<char, 16> hex{};
  (void)std::snprintf(hex.data(), hex.size(), "0x%04X", static_cast<unsigned>(kind));
  return std::string(prefix) + "." + hex.data();
}

std::string format_trace_event(std::size_t index, const bsp::TraceEvent& ev, double clock_hz) {
  std::array<char, 320> line{};
  (void)std::snprintf(line.data(), line.size(),
                      "#%zu  t %" PRIu64 " cyc (%.6f s)  tile %u  %s (0x%04X)  a %" PRIu64 " (0x%" PRIX64 ")  b %" PRIu64
                      " (0x%" PRIX64 ")",
                      index, ev.time, static_cast<double>(ev.time) / clock_hz, static_cast<unsigned>(ev.tile),
                      trace_kind_name(ev.kind).c_str(), static_cast<unsigned>(ev.kind), ev.a, ev.a, ev.b, ev.b);
  return std::string(line.data());
}

}  // namespace tools
