/**
 * @file trace_dump.hpp
 * @brief The board trace written to a file event by event, read back, named and compared:
 *        where two runs that should be the same bits first part.
 *
 * A trace hash says whether two runs differ; a dump says where. The writer
 * installs itself as the board's trace sink (bsp::set_trace_sink) and appends
 * every event to a file through a buffer taken when it opens, so it allocates
 * nothing while the heap is sealed. The file is a header ("TRNTRACE", the
 * format version, the record size) and then one fixed 32-byte little-endian
 * record per event: time (cycles), a, b (u64), tile (u32), kind (u16), 0 (u16).
 * Folding the records with bsp::trace_fold gives the run's trace hash back, so
 * a dump can be checked against the summary it came with.
 */
#pragma once

#include "bsp_tile64/emu/trace.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tools {

/** Bytes of one event record in a dump. */
inline constexpr std::size_t kTraceRecordBytes = 32U;

/** Appends every board trace event to a file (one writer at a time: the board has one sink). */
class TraceDumpWriter {
 public:
  TraceDumpWriter() = default;
  TraceDumpWriter(const TraceDumpWriter&) = delete;
  TraceDumpWriter& operator=(const TraceDumpWriter&) = delete;
  TraceDumpWriter(TraceDumpWriter&&) = delete;  ///< the board's sink points at this object
  TraceDumpWriter& operator=(TraceDumpWriter&&) = delete;
  /** Closes the file if still open (without reporting a write error: call close() to see it). */
  ~TraceDumpWriter();

  /**
   * Creates @p path, writes the header and installs the trace sink. Every event
   * recorded from now on goes to the file. @return false with the reason in @p error.
   */
  bool open(const std::string& path, std::string& error);

  /** Removes the sink, writes what is buffered and closes. @return false with the reason in @p error. */
  bool close(std::string& error);

  /** Events written so far. */
  std::uint64_t events() const { return events_; }

 private:
  static void sink(const bsp::TraceEvent& ev) noexcept;
  void append(const bsp::TraceEvent& ev) noexcept;
  void flush() noexcept;

  int fd_ = -1;
  std::vector<unsigned char> buf_;
  std::size_t used_ = 0U;
  std::uint64_t events_ = 0U;
  bool failed_ = false;  ///< a write failed: the dump is incomplete
  std::string path_;
};

/** A dump read back. */
struct TraceDump {
  std::vector<bsp::TraceEvent> events;
  std::uint64_t hash = 0U;  ///< the events folded as the board folds them: the run's trace hash
};

/** Reads a dump; @return nullopt with the reason in @p error (not a dump, truncated, wrong version). */
std::optional<TraceDump> read_trace_dump(const std::string& path, std::string& error);

/** The board's hash of @p events, from the start of a run. */
std::uint64_t fold_trace(const std::vector<bsp::TraceEvent>& events);

/** Index of the first event where @p a and @p b differ (or where the shorter ends); nullopt if identical. */
std::optional<std::size_t> first_difference(const std::vector<bsp::TraceEvent>& a,
                                            const std::vector<bsp::TraceEvent>& b);

/** The name of a trace kind, with its layer: "board.init", "kernel.switch", "fdir.frame_done", "trn.0x4003". */
std::string trace_kind_name(std::uint16_t kind);

/** One event as a line: index, time in cycles and seconds, tile, kind (name and hex), a and b (decimal and hex). */
std::string format_trace_event(std::size_t index, const bsp::TraceEvent& ev, double clock_hz);

}  // namespace tools
