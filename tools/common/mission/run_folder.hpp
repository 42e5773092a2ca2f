/**
 * @file run_folder.hpp
 * @brief The run folder and its files: complete or absent; summary.json, nav.csv, events.log, tile map and plots.
 *
 * A run writes every file into a staging folder next to the destination
 * (DIR.partial-PID) and commits it at the end by an atomic rename, so DIR is
 * either the previous complete run, the new complete run, or absent; never a
 * mix. Errors are messages for the image to print with exit status 2.
 *
 * NavCsv::write() and EventLog::add() allocate nothing (their buffers are
 * taken when they are opened or constructed): the image calls them during the
 * run with the heap sealed. Everything else runs before the seal or after it
 * is lifted.
 */
#pragma once

#include "bsp_tile64/api/port.hpp"
#include "tools/common/mission/tile_view.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tools {

/** Name of the marker file that tells a run folder from any other folder (an existing DIR is replaced only if it has one, or is empty). */
inline constexpr const char* kRunFolderMarker = ".trn_run";

class RunFolder {
 public:
  /**
   * Prepares a run folder at @p dir: creates the missing parent folders,
   * refuses a @p dir that exists and is neither empty nor a run folder, and
   * creates the staging folder. @return nullopt with the reason in @p error.
   */
  static std::optional<RunFolder> open(const std::string& dir, std::string& error);

  RunFolder(RunFolder&& other) noexcept;
  RunFolder& operator=(RunFolder&& other) noexcept;
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;
  /** Abandons the staging folder unless committed. */
  ~RunFolder();

  /** Where to write @p file (a plain name) until commit. */
  std::string staging_path(const std::string& file) const;
  /** The staging folder. */
  const std::string& staging_dir() const { return staging_; }
  /** The destination folder. */
  const std::string& dir() const { return dir_; }
  bool committed() const { return committed_; }

  /**
   * Replaces @p dir with the staging folder atomically (an existing run folder
   * is swapped out, then removed). @return false with the reason; the staging
   * folder is then kept for abandon() or the destructor.
   */
  bool commit(std::string& error);

  /** Removes the staging folder and everything in it (no-op after commit). */
  void abandon() noexcept;

 private:
  RunFolder(std::string dir, std::string staging) : dir_(std::move(dir)), staging_(std::move(staging)) {}

  std::string dir_;
  std::string staging_;
  bool committed_ = false;
  bool active_ = true;  ///< false once moved from, committed or abandoned
};

/** The figures of one run, written as summary.json. */
struct Summary {
  std::string scenario;
  std::string chip;        ///< the chip flown (Scenario::chip)
  std::string fault_plan;  ///< name of the plan ("" for none)
  std::uint64_t seed = 0U;
  double emulated_s = 0.0;
  double host_s = 0.0;
  double realtime_factor = 0.0;  ///< emulated seconds per host second
  double final_position_error_m = 0.0;
  double max_position_error_after_convergence_m = 0.0;
  double final_velocity_error_mps = 0.0;
  double final_attitude_error_deg = 0.0;
  std::uint64_t frames = 0U;
  double matches_per_frame_mean = 0.0;
  std::uint64_t deadline_misses = 0U;
  std::uint64_t heap_allocs_after_init = 0U;
  std::uint64_t faults_injected = 0U;
  std::uint64_t faults_detected = 0U;
  std::uint64_t faults_recovered = 0U;
  std::string trace_hash;  ///< hex, see trace_hash_hex()
  /** Further figures, written after the fixed keys in this order; a name must not repeat a fixed key. */
  std::vector<std::pair<std::string, double>> extra;
  /**
   * Named groups of figures (energy_j_by_phase: phase -> J), each written after
   * the extras as a JSON object of numbers, in this order; a group's name must
   * not repeat a key, nor a name inside a group another of the same group.
   */
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>> objects;
};

/** Writes @p text to @p path in one go; the error names the file. */
bool write_text_file(const std::string& path, const std::string& text, std::string& error);

/** 16 lower-case hex digits. */
std::string trace_hash_hex(std::uint64_t hash);

/** The summary as a JSON object (non-finite numbers as null); error if an extra key repeats a key. */
bool summary_json(const Summary& s, std::string& json, std::string& error);

/** Writes summary_json() to @p path. */
bool write_summary_json(const std::string& path, const Summary& s, std::string& error);

/** One row of nav.csv; the position error norm is computed from truth and estimate. */
struct NavRow {
  double t_s = 0.0;
  std::array<double, 3> truth_p_m{};
  std::array<double, 3> est_p_m{};
  std::array<double, 3> truth_v_mps{};
  std::array<double, 3> est_v_mps{};
  std::array<double, 3> sigma3_p_m{};  ///< 3-sigma of the position estimate per axis
  double attitude_error_deg = 0.0;
  [[nodiscard]] double position_error_m() const noexcept;
};

/** nav.csv: a header line, then one line per NavRow. */
class NavCsv {
 public:
  static constexpr const char* kHeader =
      "t_s,truth_x_m,truth_y_m,truth_z_m,est_x_m,est_y_m,est_z_m,truth_vx_mps,truth_vy_mps,truth_vz_mps,"
      "est_vx_mps,est_vy_mps,est_vz_mps,pos_err_m,sigma3_x_m,sigma3_y_m,sigma3_z_m,att_err_deg";

  NavCsv() = default;
  NavCsv(const NavCsv&) = delete;
  NavCsv& operator=(const NavCsv&) = delete;
  NavCsv(NavCsv&&) = delete;
  NavCsv& operator=(NavCsv&&) = delete;
  ~NavCsv();

  /** Creates the file and writes the header; takes the write buffer (before the heap seal). */
  bool open(const std::string& path, std::string& error);
  /** Appends a row; allocates nothing. False after a write error or when not open (close() reports it). */
  bool write(const NavRow& row) noexcept;
  /** Flushes and closes; @return false with the reason if any write failed. */
  bool close(std::string& error);
  [[nodiscard]] std::size_t rows() const noexcept { return rows_; }
  /** The text of one row (no newline), as write() puts it. */
  static std::string format_row(const NavRow& row);

 private:
  std::FILE* f_ = nullptr;
  std::unique_ptr<char[]> buffer_;
  std::string path_;
  std::size_t rows_ = 0U;
  bool failed_ = false;
};

enum class EventCategory : std::uint8_t { kInject, kDetect, kIsolate, kRecover, kInfo };

/** "INJECT", "DETECT", "ISOLATE", "RECOVER", "INFO". */
const char* event_category_name(EventCategory c) noexcept;

/** Longest text of one event, bytes (longer texts are cut). */
inline constexpr std::size_t kEventTextBytes = 256U;

struct Event {
  double t_s;  ///< emulated time
  EventCategory category;
  bsp::TileId tile;    ///< source tile (bsp::kNoTile: the host or the whole chip)
  std::uint32_t seq;   ///< order of arrival: keeps equal times in order
  std::array<char, kEventTextBytes> text;  ///< NUL-terminated, one line
};

/**
 * events.log: every injection, detection and recovery with its emulated time.
 * Entries may arrive out of order; write() sorts them by time (equal times in
 * arrival order). Line: "<t_s, 6 decimals> <CATEGORY> tile <id or -> <text>".
 */
class EventLog {
 public:
  /** Takes room for @p capacity events now, so add() never allocates. */
  explicit EventLog(std::size_t capacity = 4096U);

  /** Adds one event; newlines in the text become spaces. False (and counted) when full or t_s is not finite. */
  bool add(double t_s, EventCategory category, bsp::TileId tile, std::string_view text) noexcept;
  /** printf-style add. */
  bool addf(double t_s, EventCategory category, bsp::TileId tile, const char* fmt, ...) noexcept
      __attribute__((format(printf, 5, 6)));

  /**
   * Room for @p extra more events (allocates: after the flight only, e.g. for
   * the injections' lines, which are never dropped however full the flight
   * left the log).
   */
  void grow(std::size_t extra) { events_.resize(count_ + extra > events_.size() ? count_ + extra : events_.size()); }

  [[nodiscard]] std::size_t size() const noexcept { return count_; }
  [[nodiscard]] std::size_t dropped() const noexcept { return dropped_; }
  [[nodiscard]] std::size_t count(EventCategory c) const noexcept;
  /** The events in time order. */
  [[nodiscard]] std::vector<Event> sorted() const;
  /** One line of the log for @p e (no newline). */
  static std::string format_line(const Event& e);
  /** Writes the sorted log; a last comment line says how many events were dropped, if any. */
  bool write(const std::string& path, std::string& error) const;

 private:
  std::vector<Event> events_;
  std::size_t count_ = 0U;
  std::size_t dropped_ = 0U;
};

/**
 * tile_map.csv: tile,x,y,role,code,health,role_rgb,health_code, the counters of
 * each TileInfo, then energy_j and power_state (the tile-map plot reads it).
 */
bool write_tile_map_csv(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                        const std::vector<TileInfo>& tiles, std::string& error);

/**
 * Writes position_error.gp (from nav.csv) and tile_map.gp (from tile_map.csv)
 * into @p folder and, if gnuplot is on the PATH, runs them there (no terminal,
 * stdin from /dev/null, output in plots.log, killed after 60 s) to make
 * position_error.png and tile_map.png. Without gnuplot the scripts stay and
 * @p note says so: not an error; a gnuplot that fails or times out is also
 * only a note (the run's data stay whole). @return false with the reason if
 * nav.csv or tile_map.csv is missing or a script cannot be written.
 */
bool write_plots(const std::string& folder, std::string& error, std::string& note);

/** Same; the note (if any) goes to stderr. */
bool write_plots(const std::string& folder, std::string& error);

}  // namespace tools
