/**
 * @file world_cache.cpp
 * @brief World products kept in a folder between runs, keyed by what builds them.
 */
#include "tools/common/mission/world_cache.hpp"

#include "tools/common/mission/huge_pages.hpp"
#include "tools/common/mission/image_id.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

namespace tools {

namespace {

namespace fs = std::filesystem;
namespace w = bsp::world;

/** Bumped whenever what a file holds, or how a product is built, changes. */
constexpr std::uint32_t kFormat = 1U;
constexpr std::array<char, 8> kTerrainMagic = {'T', 'R', 'N', 'T', 'E', 'R', 'R', '1'};

/** FNV-1a over the text of every parameter: the same key on every host and compiler. */
std::string hex_key(const std::string& text) {
  std::uint64_t h = 0xCBF2'9CE4'8422'2325ULL;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x0000'0100'0000'01B3ULL;
  }
  std::array<char, 17> b{};
  (void)std::snprintf(b.data(), b.size(), "%016llx", static_cast<unsigned long long>(h));
  return b.data();
}

/**
 * The build of this image (image_id.hpp: its ELF build ID): part of every key, so that an image
 * rebuilt with other world code never reads what an older build wrote. Runs of one build (a
 * campaign, or copies of the image elsewhere) share the cache.
 */
std::string image_stamp() { return own_image_identity(); }

std::string terrain_text(const w::TerrainConfig& c) {
  std::ostringstream o;
  o.precision(17);
  o << "image " << image_stamp() << " format " << kFormat << " cell " << sizeof(w::detail::Cell) << " seed " << c.seed << " size " << c.size_px
    << " mpp " << c.m_per_px << " relief " << c.relief_m << " wavelength " << c.base_wavelength_m << " octaves "
    << c.octaves << " craters " << c.crater_density_per_km2 << " " << c.crater_min_d_m << " " << c.crater_max_d_m
    << " " << c.crater_sfd_exponent << " boulders " << c.boulder_density_per_km2;
  return o.str();
}

/** Writes @p n bytes at @p data to @p path through a temporary name and a rename; false on failure. */
bool write_atomic(const fs::path& path, const void* head, std::size_t head_n, const void* data, std::size_t n) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  const fs::path tmp = path.string() + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(static_cast<const char*>(head), static_cast<std::streamsize>(head_n));
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(n));
    out.flush();
    if (!out) {
      fs::remove(tmp, ec);
      return false;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return false;
  }
  return true;
}

/** Removes the files in @p dir that another image build wrote (their stamp differs from @p keep's). */
void prune(const fs::path& dir, const std::string& stamp_tag) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(stamp_tag, 0) != 0 && name.find(".tmp") == std::string::npos) {
      fs::remove(e.path(), ec);
    }
  }
}

/** The file-name prefix of this image build's files. */
std::string stamp_tag() { return hex_key(image_stamp()).substr(0, 8) + "-"; }

/**
 * An exclusive lock on one product's key, held while it is looked up, built and written: runs that
 * start together (test shards, parallel flights) build a product once, and the others wait and read
 * it, instead of each building the same seconds of work. Without a lock file (a folder that cannot be
 * written) every run builds for itself, as without a cache.
 */
class KeyLock {
 public:
  explicit KeyLock(const fs::path& file) {
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    fd_ = ::open((file.string() + ".lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    while (fd_ >= 0 && ::flock(fd_, LOCK_EX) != 0) {
      if (errno != EINTR) {
        (void)::close(fd_);
        fd_ = -1;
      }
    }
  }
  ~KeyLock() {
    if (fd_ >= 0) {
      (void)::close(fd_);  // closing releases the lock
    }
  }
  KeyLock(const KeyLock&) = delete;
  KeyLock& operator=(const KeyLock&) = delete;
  KeyLock(KeyLock&&) = delete;
  KeyLock& operator=(KeyLock&&) = delete;

 private:
  int fd_ = -1;
};

/**
 * A cached file mapped read-only: its bytes are read straight from the page cache into the
 * world's storage. Reading it into a buffer first would zero and copy the 134 MB of a terrain
 * once more in every run; that was most of a short test flight's host time.
 */
class MappedFile {
 public:
  explicit MappedFile(const fs::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      return;
    }
    struct stat st{};
    if (::fstat(fd, &st) == 0 && st.st_size > 0) {
      void* p = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (p != MAP_FAILED) {
        data_ = static_cast<const std::byte*>(p);
        size_ = static_cast<std::size_t>(st.st_size);
        (void)::madvise(p, size_, MADV_SEQUENTIAL);
      }
    }
    (void)::close(fd);  // the mapping stays valid
  }
  ~MappedFile() {
    if (data_ != nullptr) {
      (void)::munmap(const_cast<std::byte*>(data_), size_);  // NOLINT(cppcoreguidelines-pro-type-const-cast): munmap takes void*
    }
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  MappedFile(MappedFile&&) = delete;
  MappedFile& operator=(MappedFile&&) = delete;

  /** The file's bytes; empty if it could not be opened or mapped (or is empty). */
  [[nodiscard]] std::span<const std::byte> bytes() const { return {data_, size_}; }

 private:
  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
};

struct TerrainHead {
  std::array<char, 8> magic;
  std::uint64_t cells;
};
static_assert(sizeof(TerrainHead) % alignof(bsp::world::detail::Cell) == 0, "the cells after the head are aligned");

}  // namespace

std::string WorldCache::terrain_key(const w::TerrainConfig& cfg) { return hex_key(terrain_text(cfg)); }

std::string WorldCache::map_key(const w::TerrainConfig& cfg, const w::MapConfig& m) {
  std::ostringstream o;
  o.precision(17);
  o << terrain_text(cfg) << " map version " << bsp::kMapProductVersion << " fine " << m.fine_m_per_px << " coarse "
    << m.coarse_m_per_px << " extent " << m.extent_m << " sun " << m.sun.azimuth_deg << " " << m.sun.elevation_deg
    << " dn " << m.dn_per_radiance;
  return hex_key(o.str());
}

bool WorldCache::terrain(const w::TerrainConfig& cfg, std::string& error) {
  prefer_huge_pages();  // before the grid, tile RAM and DDR are first touched
  const fs::path file = fs::path(dir_) / (stamp_tag() + "terrain-" + terrain_key(cfg) + ".bin");
  std::optional<KeyLock> lock;
  if (enabled()) {
    lock.emplace(file);
    const MappedFile in(file);
    const std::span<const std::byte> bytes = in.bytes();
    TerrainHead h{};
    const std::uint64_t want = std::uint64_t{cfg.size_px} * cfg.size_px;
    if (bytes.size() >= sizeof h) {
      std::memcpy(&h, bytes.data(), sizeof h);
    }
    if (h.magic == kTerrainMagic && h.cells == want && bytes.size() == sizeof h + want * sizeof(w::detail::Cell)) {
      // The cells follow the head at an 8-byte offset of a page-aligned mapping: aligned for Cell.
      const std::span<const w::detail::Cell> cells(
          reinterpret_cast<const w::detail::Cell*>(bytes.data() + sizeof h), want);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw file bytes
      if (w::terrain_restore(cfg, cells) == w::WorldError::kOk) {
        ++hits_;
        return true;
      }
    }
  }
  if (w::terrain_build(cfg) != w::WorldError::kOk) {
    error = "cannot build the terrain";
    return false;
  }
  if (enabled()) {
    ++misses_;
    const std::span<const w::detail::Cell> cells = w::terrain_cells();
    const TerrainHead h{kTerrainMagic, cells.size()};
    if (write_atomic(file, &h, sizeof h, cells.data(), cells.size_bytes())) {  // a cache that cannot be written is no cache
      prune(dir_, stamp_tag());
    }
  }
  return true;
}

const bsp::MapProductHeader* WorldCache::map(const w::TerrainConfig& cfg, const w::MapConfig& m, w::WorldError& err) {
  prefer_huge_pages();
  const fs::path file = fs::path(dir_) / (stamp_tag() + "map-" + map_key(cfg, m) + ".bin");
  std::optional<KeyLock> lock;
  if (enabled()) {
    lock.emplace(file);
    const MappedFile in(file);
    if (in.bytes().size() >= sizeof(bsp::MapProductHeader)) {
      const bsp::MapProductHeader* p = w::refmap_restore(in.bytes(), &err);
      if (p != nullptr) {
        ++hits_;
        return p;
      }
    }
  }
  const bsp::MapProductHeader* p = w::refmap_build(m, &err);
  if (p != nullptr && enabled()) {
    ++misses_;
    (void)write_atomic(file, p, 0U, p, p->total_bytes);
  }
  return p;
}

bool WorldCache::landmarks(const w::TerrainConfig& cfg, const w::MapConfig& m, const trn::vision::SelectParams& p,
                           trn::vision::LandmarkTable& table,
                           const std::function<bool(trn::vision::LandmarkTable&)>& select) {
  std::ostringstream o;
  o << map_key(cfg, m) << " landmarks " << sizeof(trn::vision::LandmarkTable) << " patch " << p.patch_px << " cell "
    << p.cell_px << " stride " << p.stride_px << " margin " << p.margin_px << " inset " << p.cell_inset_px << " sep "
    << p.min_separation_px << " corner " << p.min_corner << " sd " << p.min_stddev << " dense " << p.dense_cell_px
    << " " << p.dense_cell_inset_px;
  const fs::path file = fs::path(dir_) / (stamp_tag() + "landmarks-" + hex_key(o.str()) + ".bin");
  std::optional<KeyLock> lock;
  if (enabled()) {
    lock.emplace(file);
    std::error_code ec;
    std::ifstream in(file, std::ios::binary);
    if (fs::file_size(file, ec) == sizeof table && !ec && in &&
        in.read(reinterpret_cast<char*>(&table), sizeof table)) {  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw file bytes
      ++hits_;
      return true;
    }
  }
  if (!select(table)) {
    return false;
  }
  if (enabled()) {
    ++misses_;
    (void)write_atomic(file, &table, 0U, &table, sizeof table);
  }
  return true;
}

}  // namespace tools
