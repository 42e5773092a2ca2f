/**
 * @file run_folder.cpp
 * @brief Run folder staging and atomic commit; summary.json, nav.csv, events.log, tile_map.csv and gnuplot plots.
 */
#include "tools/common/mission/run_folder.hpp"

#include "tools/common/gnuplot.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace tools {
namespace fs = std::filesystem;
namespace {

std::atomic<std::uint32_t> g_staging_serial{0U};

std::string errno_text(int e) { return std::strerror(e); }

/** True if @p dir is an empty folder or one of our run folders (has the marker). */
bool replaceable(const fs::path& dir, std::string& why) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    why = "exists and is not a folder";
    return false;
  }
  if (fs::exists(dir / kRunFolderMarker, ec) || fs::is_empty(dir, ec)) {
    return true;
  }
  why = std::string("exists and is not a run folder (not empty, no ") + kRunFolderMarker +
        " marker): refusing to replace it";
  return false;
}


/** Appends a number in %.Nf, or "nan"/"inf" for non-finite values, and very large ones in %e. */
void put_number(char*& p, const char* end, double v, int decimals) noexcept {
  const auto room = static_cast<std::size_t>(end - p);
  int n = 0;
  if (std::isnan(v)) {
    n = std::snprintf(p, room, "nan");
  } else if (std::isinf(v)) {
    n = std::snprintf(p, room, v > 0.0 ? "inf" : "-inf");
  } else if (std::fabs(v) >= 1e12) {
    n = std::snprintf(p, room, "%.6e", v);
  } else {
    n = std::snprintf(p, room, "%.*f", decimals, v);
  }
  if (n > 0) {
    p += std::min(static_cast<std::size_t>(n), room - 1U);
  }
}

constexpr std::size_t kNavLineBytes = 640U;  // 18 fields of at most 24 characters, with room to spare
constexpr std::size_t kNavBufferBytes = std::size_t{1} << 16U;

/** One nav.csv row into @p buf (no newline); returns its length. */
std::size_t nav_line(const NavRow& r, std::array<char, kNavLineBytes>& buf) noexcept {
  char* p = buf.data();
  const char* end = buf.data() + buf.size();
  const auto field = [&p, end](double v, int decimals, bool first = false) {
    if (!first && p + 1 < end) {
      *p++ = ',';
    }
    put_number(p, end, v, decimals);
  };
  field(r.t_s, 6, true);
  for (const double v : r.truth_p_m) {
    field(v, 3);
  }
  for (const double v : r.est_p_m) {
    field(v, 3);
  }
  for (const double v : r.truth_v_mps) {
    field(v, 4);
  }
  for (const double v : r.est_v_mps) {
    field(v, 4);
  }
  field(r.position_error_m(), 3);
  for (const double v : r.sigma3_p_m) {
    field(v, 3);
  }
  field(r.attitude_error_deg, 5);
  *p = '\0';
  return static_cast<std::size_t>(p - buf.data());
}

/** A CSV field with no separator, quote or line break in it. */
std::string csv_safe(const std::string& s) {
  std::string out = s;
  std::replace_if(
      out.begin(), out.end(), [](char c) { return c == ',' || c == '"' || c == '\n' || c == '\r'; }, '_');
  return out.empty() ? "-" : out;
}

// ------------------------------------------------------------------ plots

std::string position_error_script() {
  return "# Position error of the navigation filter and its 3-sigma bound over time, from nav.csv;\n"
         "# below it, each axis's error over the 3-sigma the filter reports with it (integrity).\n"
         "# Run in this folder: gnuplot position_error.gp\n" +
         gnuplot_png_terminal("1100,1000") +
         "set output 'position_error.png'\n"
         "set datafile separator comma\n"
         "set multiplot layout 2,1\n"
         "set title 'Position error of the navigation filter'\n"
         "set xlabel 'emulated time (s)'\n"
         "set ylabel 'position error (m)'\n"
         "set logscale y\n"
         "set grid\n"
         "set key top right\n"
         "plot 'nav.csv' using (column('t_s')):(column('pos_err_m')) with lines lw 2 lc rgb '#1f77b4' "
         "title '|estimate - truth|', \\\n"
         "     '' using (column('t_s')):(sqrt(column('sigma3_x_m')**2 + column('sigma3_y_m')**2 + "
         "column('sigma3_z_m')**2)) with lines lw 1.5 dt 2 lc rgb '#d62728' "
         "title '3-sigma bound (root sum of the per-axis 3-sigma)'\n"
         "set title 'Integrity: each axis error over its own reported 3-sigma (above 1: outside the bound)'\n"
         "set ylabel '|error| / 3-sigma'\n"
         "set yrange [0.001:*]\n"
         "plot 'nav.csv' using (column('t_s')):(abs(column('est_x_m') - column('truth_x_m')) / column('sigma3_x_m')) "
         "with lines lw 1 lc rgb '#1f77b4' title 'x', \\\n"
         "     '' using (column('t_s')):(abs(column('est_y_m') - column('truth_y_m')) / column('sigma3_y_m')) "
         "with lines lw 1 lc rgb '#2ca02c' title 'y', \\\n"
         "     '' using (column('t_s')):(abs(column('est_z_m') - column('truth_z_m')) / column('sigma3_z_m')) "
         "with lines lw 1 lc rgb '#9467bd' title 'z', \\\n"
         "     1.0 with lines lw 1.5 dt 2 lc rgb '#d62728' title '3-sigma', \\\n"
         "     5.0 / 3.0 with lines lw 1.5 dt 3 lc rgb '#000000' title '5-sigma'\n"
         "unset multiplot\n";
}

struct TileMapShape {
  std::uint32_t cols = 0U;
  std::uint32_t rows = 0U;
  std::vector<std::string> roles;  ///< in order of first appearance
};

/** Reads the grid size and the roles present from tile_map.csv (our own format: no quoting). */
bool read_tile_map(const std::string& path, TileMapShape& shape, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot open (write it with write_tile_map_csv before the plots): " + errno_text(errno);
    return false;
  }
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) {
      f.push_back(cell);
    }
    if (f.size() < 4U) {
      continue;
    }
    shape.cols = std::max(shape.cols, static_cast<std::uint32_t>(std::strtoul(f[1].c_str(), nullptr, 10)) + 1U);
    shape.rows = std::max(shape.rows, static_cast<std::uint32_t>(std::strtoul(f[2].c_str(), nullptr, 10)) + 1U);
    if (std::find(shape.roles.begin(), shape.roles.end(), f[3]) == shape.roles.end()) {
      shape.roles.push_back(f[3]);
    }
  }
  return true;
}

/** Power-state marks of the tile map: a point in each tile's top-left corner, with their legend entries. */
std::string power_marks_script() {
  struct Mark {
    const char* state;
    const char* style;
    const char* title;
  };
  constexpr std::array<Mark, 4> kMarks = {{
      {"active", "pt 7 ps 1.3 lc rgb '#d00000'", "power: active (executing)"},
      {"idle", "pt 6 ps 1.3 lw 2 lc rgb '#202020'", "power: idle (waiting)"},
      {"booting", "pt 9 ps 1.3 lc rgb '#e0a000'", "power: booting"},
      {"off", "pt 2 ps 1.1 lw 2 lc rgb '#707070'", "power: off (switch only)"},
  }};
  std::string s;
  for (const Mark& m : kMarks) {
    s += std::string(", \\\n     '' using (column('x') - 0.34):(pmark('") + m.state + "')) with points " + m.style +
         " notitle";
  }
  for (const Mark& m : kMarks) {
    s += std::string(", \\\n     keyentry with points ") + m.style + " title '" + m.title + "'";
  }
  return s;
}

std::string tile_map_script(const TileMapShape& shape) {
  std::array<char, 160> buf{};
  (void)std::snprintf(buf.data(), buf.size(), "set xrange [-0.5:%u.5]\nset yrange [%u.5:-0.5]\n",
                      shape.cols > 0U ? shape.cols - 1U : 0U, shape.rows > 0U ? shape.rows - 1U : 0U);
  std::string s = "# The tile grid: fill colour by role, mark by health, corner point by power state at the end,\n"
                  "# label: tile, role code, health, energy over the run; from tile_map.csv.\n"
                  "# Run in this folder: gnuplot tile_map.gp\n" +
                  gnuplot_png_terminal("1100,860") +
                  "set output 'tile_map.png'\n"
                  "set datafile separator comma\n"
                  "set title 'Tiles: role (fill), health (mark), power state at the end (corner), energy (J)'\n"
                  "set size ratio -1\n" +
                  std::string(buf.data()) +
                  "unset xtics\nunset ytics\nunset border\n"
                  "set key outside right top spacing 1.4 samplen 1.5\n"
                  "mark(code) = column('health_code') == code ? column('y') : NaN\n"
                  "pmark(state) = stringcolumn('power_state') eq state ? column('y') - 0.34 : NaN\n"
                  "health_line(d) = stringcolumn('health') eq 'ok' ? '' : \"\\n\" . stringcolumn('health')\n"
                  "label(d) = sprintf(\"%d\\n%s\", column('tile'), stringcolumn('code')) . health_line(0) . "
                  "sprintf(\"\\n%.2f J\", column('energy_j'))\n"
                  "plot 'tile_map.csv' using (column('x')):(column('y')):(0.47):(0.47):(column('role_rgb')) "
                  "with boxxy fs solid 0.9 border lc rgb '#404040' fc rgb variable notitle, \\\n"
                  "     '' using (column('x')):(mark(4)):(0.47):(0.47) with boxxy fs transparent solid 0.6 "
                  "noborder fc rgb '#ffffff' notitle, \\\n"
                  "     keyentry with boxes fs solid 0.9 border lc rgb '#404040' fc rgb '#e8e8e8' "
                  "title 'off (dimmed)', \\\n"
                  "     '' using (column('x')):(mark(2)) with points pt 2 ps 5 lw 3 lc rgb '#d00000' title 'failed', "
                  "\\\n"
                  "     '' using (column('x')):(mark(1)) with points pt 6 ps 5 lw 3 lc rgb '#e0a000' title 'suspect', "
                  "\\\n"
                  "     '' using (column('x')):(mark(3)) with points pt 6 ps 5 lw 3 lc rgb '#00a0c0' "
                  "title 'recovered', \\\n"
                  // A label's first line sits at its point: the 3- or 4-line block is raised to centre it.
                  "     '' using (column('x')):(column('y') - (stringcolumn('health') eq 'ok' ? 0.16 : 0.24)):(label(0)) "
                  "with labels font ',10' notitle" +
                  power_marks_script();
  for (const std::string& role : shape.roles) {
    std::array<char, 200> k{};
    (void)std::snprintf(k.data(), k.size(),
                        ", \\\n     keyentry with boxes fs solid 0.9 fc rgb '#%06x' title '%s'",
                        static_cast<unsigned>(tile_role_rgb(role)), role.c_str());
    s += k.data();
  }
  return s + "\n";
}

}  // namespace

bool write_text_file(const std::string& path, const std::string& text, std::string& error) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    error = path + ": cannot create: " + errno_text(errno);
    return false;
  }
  const bool wrote = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const int write_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) {
    error = path + ": cannot write: " + errno_text(wrote ? errno : write_errno);
    return false;
  }
  return true;
}

// ------------------------------------------------------------------ RunFolder

std::optional<RunFolder> RunFolder::open(const std::string& dir_in, std::string& error) {
  std::string dir = dir_in;
  while (dir.size() > 1U && dir.back() == '/') {
    dir.pop_back();
  }
  if (dir.empty() || dir == "/" || dir == "." || dir == "..") {
    error = "run folder '" + dir_in + "': not a usable folder name (give a new or previous run folder)";
    return std::nullopt;
  }
  const fs::path p(dir);
  const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent, ec)) {
    error = dir + ": cannot create the parent folder " + parent.string() + ": " +
            (ec ? ec.message() : std::string("exists and is not a folder"));
    return std::nullopt;
  }
  if (fs::exists(fs::symlink_status(p, ec))) {
    std::string why;
    if (fs::is_symlink(fs::symlink_status(p, ec))) {
      error = dir + ": is a symbolic link: refusing to replace it";
      return std::nullopt;
    }
    if (!replaceable(p, why)) {
      error = dir + ": " + why;
      return std::nullopt;
    }
  }
  // The effective permissions (AT_EACCESS), as the mkdir below meets them: access() would answer for the
  // real user, and for root with the permitted capabilities rather than the effective ones.
  if (::faccessat(AT_FDCWD, parent.c_str(), W_OK | X_OK, AT_EACCESS) != 0) {
    error = dir + ": the folder " + parent.string() + " is not writable: " + errno_text(errno);
    return std::nullopt;
  }
  const std::string staging = dir + ".partial-" + std::to_string(::getpid()) + "-" +
                              std::to_string(g_staging_serial.fetch_add(1U));
  if (::mkdir(staging.c_str(), 0755) != 0) {
    error = dir + ": cannot create the staging folder " + staging + ": " + errno_text(errno);
    return std::nullopt;
  }
  RunFolder rf(dir, staging);
  if (!write_text_file(rf.staging_path(kRunFolderMarker), "a trn_mission run folder\n", error)) {
    error = dir + ": " + error;
    return std::nullopt;  // rf's destructor removes the staging folder
  }
  return rf;
}

RunFolder::RunFolder(RunFolder&& other) noexcept
    : dir_(std::move(other.dir_)),
      staging_(std::move(other.staging_)),
      committed_(other.committed_),
      active_(other.active_) {
  other.active_ = false;
}

RunFolder& RunFolder::operator=(RunFolder&& other) noexcept {
  if (this != &other) {
    abandon();
    dir_ = std::move(other.dir_);
    staging_ = std::move(other.staging_);
    committed_ = other.committed_;
    active_ = other.active_;
    other.active_ = false;
  }
  return *this;
}

RunFolder::~RunFolder() { abandon(); }

std::string RunFolder::staging_path(const std::string& file) const { return staging_ + "/" + file; }

bool RunFolder::commit(std::string& error) {
  if (!active_) {
    error = dir_ + ": the run folder was already committed or abandoned";
    return false;
  }
  if (::rename(staging_.c_str(), dir_.c_str()) == 0) {
    committed_ = true;  // there was no folder, or an empty one
    active_ = false;
    return true;
  }
  if (errno != ENOTEMPTY && errno != EEXIST) {
    error = dir_ + ": cannot move the run folder into place: " + errno_text(errno);
    return false;
  }
  std::string why;
  if (!replaceable(fs::path(dir_), why)) {
    error = dir_ + ": " + why;
    return false;
  }
  // Swap the two folders in one step; the old run then sits at the staging path.
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS) {
      error = dir_ + ": cannot replace the previous run folder: " + errno_text(errno);
      return false;
    }
    // A file system without RENAME_EXCHANGE: move the old folder aside first
    // (DIR is briefly absent, never partial).
    const std::string old = staging_ + ".old";
    if (::rename(dir_.c_str(), old.c_str()) != 0) {
      error = dir_ + ": cannot move the previous run folder aside: " + errno_text(errno);
      return false;
    }
    if (::rename(staging_.c_str(), dir_.c_str()) != 0) {
      error = dir_ + ": cannot move the run folder into place: " + errno_text(errno);
      (void)::rename(old.c_str(), dir_.c_str());
      return false;
    }
    std::error_code ec;
    fs::remove_all(old, ec);
    committed_ = true;
    active_ = false;
    return true;
  }
  committed_ = true;
  active_ = false;
  std::error_code ec;
  fs::remove_all(staging_, ec);  // the previous run
  return true;
}

void RunFolder::abandon() noexcept {
  if (!active_) {
    return;
  }
  active_ = false;
  std::error_code ec;
  (void)fs::remove_all(staging_, ec);
}

// ------------------------------------------------------------------ summary.json

std::string trace_hash_hex(std::uint64_t hash) {
  std::array<char, 20> buf{};
  (void)std::snprintf(buf.data(), buf.size(), "%016llx", static_cast<unsigned long long>(hash));
  return buf.data();
}

bool summary_json(const Summary& s, std::string& json, std::string& error) {
  nlohmann::ordered_json j;
  const auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  j["scenario"] = s.scenario;
  j["chip"] = s.chip;
  j["fault_plan"] = s.fault_plan;
  j["seed"] = s.seed;
  j["emulated_s"] = num(s.emulated_s);
  j["host_s"] = num(s.host_s);
  j["realtime_factor"] = num(s.realtime_factor);
  j["final_position_error_m"] = num(s.final_position_error_m);
  j["max_position_error_after_convergence_m"] = num(s.max_position_error_after_convergence_m);
  j["final_velocity_error_mps"] = num(s.final_velocity_error_mps);
  j["final_attitude_error_deg"] = num(s.final_attitude_error_deg);
  j["frames"] = s.frames;
  j["matches_per_frame_mean"] = num(s.matches_per_frame_mean);
  j["deadline_misses"] = s.deadline_misses;
  j["heap_allocs_after_init"] = s.heap_allocs_after_init;
  j["faults_injected"] = s.faults_injected;
  j["faults_detected"] = s.faults_detected;
  j["faults_recovered"] = s.faults_recovered;
  j["trace_hash"] = s.trace_hash;
  for (const auto& [key, value] : s.extra) {
    if (key.empty() || j.contains(key)) {
      error = "summary.json: extra key '" + key + "' is empty or repeats a key";
      return false;
    }
    j[key] = num(value);
  }
  for (const auto& [name, figures] : s.objects) {
    if (name.empty() || j.contains(name)) {
      error = "summary.json: object '" + name + "' is empty or repeats a key";
      return false;
    }
    nlohmann::ordered_json o = nlohmann::ordered_json::object();
    for (const auto& [key, value] : figures) {
      if (key.empty() || o.contains(key)) {
        error = "summary.json: key '";
        error.append(key).append("' of '").append(name).append("' is empty or repeated");
        return false;
      }
      o[key] = num(value);
    }
    j[name] = o;
  }
  // Invalid UTF-8 (a scenario name read from a file) is replaced, not thrown.
  json = j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  return true;
}

bool write_summary_json(const std::string& path, const Summary& s, std::string& error) {
  std::string json;
  return summary_json(s, json, error) && write_text_file(path, json, error);
}

// ------------------------------------------------------------------ nav.csv

double NavRow::position_error_m() const noexcept {
  const double dx = est_p_m[0] - truth_p_m[0];
  const double dy = est_p_m[1] - truth_p_m[1];
  const double dz = est_p_m[2] - truth_p_m[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

NavCsv::~NavCsv() {
  std::string ignored;
  (void)close(ignored);
}

bool NavCsv::open(const std::string& path, std::string& error) {
  if (f_ != nullptr) {
    error = path + ": nav.csv writer already open on " + path_;
    return false;
  }
  f_ = std::fopen(path.c_str(), "wb");
  if (f_ == nullptr) {
    error = path + ": cannot create: " + errno_text(errno);
    return false;
  }
  // Our own buffer, taken now: stdio would otherwise allocate it at the first write (under the sealed heap).
  buffer_ = std::make_unique<char[]>(kNavBufferBytes);
  if (std::setvbuf(f_, buffer_.get(), _IOFBF, kNavBufferBytes) != 0) {
    error = path + ": cannot set the write buffer";
    (void)std::fclose(f_);
    f_ = nullptr;
    return false;
  }
  path_ = path;
  rows_ = 0U;
  failed_ = std::fputs(kHeader, f_) < 0 || std::fputc('\n', f_) == EOF;
  if (failed_) {
    error = path + ": cannot write: " + errno_text(errno);
    return false;
  }
  return true;
}

bool NavCsv::write(const NavRow& row) noexcept {
  if (f_ == nullptr || failed_) {
    return false;
  }
  std::array<char, kNavLineBytes> line{};
  const std::size_t n = nav_line(row, line);
  line[n] = '\n';
  if (std::fwrite(line.data(), 1, n + 1U, f_) != n + 1U) {
    failed_ = true;
    return false;
  }
  ++rows_;
  return true;
}

bool NavCsv::close(std::string& error) {
  if (f_ == nullptr) {
    return true;
  }
  const bool flushed = std::fflush(f_) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  buffer_.reset();  // after fclose: stdio no longer uses it
  if (failed_ || !flushed || !closed) {
    error = path_ + ": cannot write: " + errno_text(flushed ? errno : flush_errno);
    return false;
  }
  return true;
}

std::string NavCsv::format_row(const NavRow& row) {
  std::array<char, kNavLineBytes> line{};
  const std::size_t n = nav_line(row, line);
  return {line.data(), n};
}

// ------------------------------------------------------------------ events.log

const char* event_category_name(EventCategory c) noexcept {
  switch (c) {
    case EventCategory::kInject:
      return "INJECT";
    case EventCategory::kDetect:
      return "DETECT";
    case EventCategory::kIsolate:
      return "ISOLATE";
    case EventCategory::kRecover:
      return "RECOVER";
    case EventCategory::kInfo:
      return "INFO";
  }
  return "?";
}

EventLog::EventLog(std::size_t capacity) : events_(capacity) {}

bool EventLog::add(double t_s, EventCategory category, bsp::TileId tile, std::string_view text) noexcept {
  if (count_ >= events_.size() || !std::isfinite(t_s)) {
    ++dropped_;
    return false;
  }
  Event& e = events_[count_];
  e.t_s = t_s;
  e.category = category;
  e.tile = tile;
  e.seq = static_cast<std::uint32_t>(count_);
  const std::size_t n = std::min(text.size(), kEventTextBytes - 1U);
  for (std::size_t i = 0; i < n; ++i) {
    const char c = text[i];
    e.text[i] = (c == '\n' || c == '\r') ? ' ' : c;
  }
  e.text[n] = '\0';
  ++count_;
  return true;
}

bool EventLog::addf(double t_s, EventCategory category, bsp::TileId tile, const char* fmt, ...) noexcept {
  std::array<char, kEventTextBytes> buf{};
  std::va_list ap;
  va_start(ap, fmt);
  const int n = std::vsnprintf(buf.data(), buf.size(), fmt, ap);
  va_end(ap);
  if (n < 0) {
    ++dropped_;
    return false;
  }
  return add(t_s, category, tile, std::string_view(buf.data()));
}

std::size_t EventLog::count(EventCategory c) const noexcept {
  return static_cast<std::size_t>(std::count_if(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(count_),
                                                [c](const Event& e) { return e.category == c; }));
}

std::vector<Event> EventLog::sorted() const {
  std::vector<Event> out(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(count_));
  std::sort(out.begin(), out.end(),
            [](const Event& a, const Event& b) { return a.t_s < b.t_s || (a.t_s == b.t_s && a.seq < b.seq); });
  return out;
}

std::string EventLog::format_line(const Event& e) {
  std::array<char, 64> head{};
  if (e.tile == bsp::kNoTile) {
    (void)std::snprintf(head.data(), head.size(), "%12.6f  %-7s  tile  -  ", e.t_s, event_category_name(e.category));
  } else {
    (void)std::snprintf(head.data(), head.size(), "%12.6f  %-7s  tile %2u  ", e.t_s,
                        event_category_name(e.category), static_cast<unsigned>(e.tile));
  }
  return std::string(head.data()) + e.text.data();
}

bool EventLog::write(const std::string& path, std::string& error) const {
  std::string text = "# emulated_s  category  tile  what (sorted by time)\n";
  for (const Event& e : sorted()) {
    text += format_line(e) + "\n";
  }
  if (dropped_ > 0U) {
    text += "# " + std::to_string(dropped_) + " events dropped (log full, or a time that is not finite)\n";
  }
  return write_text_file(path, text, error);
}

// ------------------------------------------------------------------ tile map and plots

bool write_tile_map_csv(const std::string& path, std::uint32_t cols, std::uint32_t rows,
                        const std::vector<TileInfo>& tiles, std::string& error) {
  if (cols == 0U || rows == 0U || tiles.size() > static_cast<std::size_t>(cols) * rows) {
    error = path + ": " + std::to_string(tiles.size()) + " tiles do not fit a " + std::to_string(cols) + "x" +
            std::to_string(rows) + " grid";
    return false;
  }
  std::string text =
      "tile,x,y,role,code,health,role_rgb,health_code,faults_injected,faults_detected,faults_recovered,resets,"
      "deadline_misses,energy_j,power_state\n";
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const TileInfo& t = tiles[i];
    const std::array<char, 3> code = tile_role_code(t.role);
    std::string code_s = csv_safe(code.data());
    std::array<char, 160> nums{};
    (void)std::snprintf(nums.data(), nums.size(), ",%u,%u,%u,%u,%u,%u,%u,", tile_role_rgb(t.role),
                        tile_health_code(t.health), t.faults_injected, t.faults_detected, t.faults_recovered,
                        t.resets, t.deadline_misses);
    std::array<char, 48> energy{};
    char* p = energy.data();
    put_number(p, energy.data() + energy.size(), t.energy_j, 6);
    text += std::to_string(i) + "," + std::to_string(i % cols) + "," + std::to_string(i / cols) + "," +
            csv_safe(t.role) + "," + code_s + "," + csv_safe(t.health) + nums.data() + energy.data() + "," +
            csv_safe(t.power) + "\n";
  }
  return write_text_file(path, text, error);
}

bool write_plots(const std::string& folder, std::string& error, std::string& note) {
  note.clear();
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    error = folder + ": no such folder for the plots";
    return false;
  }
  for (const char* data : {"nav.csv", "tile_map.csv"}) {
    if (!fs::exists(folder + "/" + data, ec)) {
      error = folder + "/" + data + ": missing (write it before the plots)";
      return false;
    }
  }
  TileMapShape shape;
  if (!read_tile_map(folder + "/tile_map.csv", shape, error) ||
      !write_text_file(folder + "/position_error.gp", position_error_script(), error) ||
      !write_text_file(folder + "/tile_map.gp", tile_map_script(shape), error)) {
    return false;
  }
  const std::string gnuplot = find_on_path("gnuplot");
  if (gnuplot.empty()) {
    note = "gnuplot is not installed: the plot scripts are in " + folder +
           " (position_error.gp, tile_map.gp; run them there with gnuplot)";
    return true;
  }
  for (const char* script : {"position_error.gp", "tile_map.gp"}) {
    const std::string e = run_gnuplot(gnuplot, folder, script);
    if (!e.empty()) {
      // A plot that fails leaves the run's data intact: say so, do not fail the run.
      note += (note.empty() ? "" : "; ") + e;
    }
  }
  return true;
}

bool write_plots(const std::string& folder, std::string& error) {
  std::string note;
  const bool ok = write_plots(folder, error, note);
  if (ok && !note.empty()) {
    std::fprintf(stderr, "plots: %s\n", note.c_str());
  }
  return ok;
}

}  // namespace tools
