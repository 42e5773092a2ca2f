/**
 * @file camera.cpp
 * @brief Pinhole projection, height-field ray casting and the DDR frame ring.
 *
 * The renderer walks the image in strips 64 pixels wide, line by line (a
 * line is a row, or a column when columns cross fewer grid rows), several
 * rays at a time in float lanes (8 where the host has AVX2, else 4: the same
 * operations lane by lane, so the same bits). Each ray starts from a guess
 * extrapolated from the hits of the two pixels before it in its strip, reads
 * the four cells under the guess once and solves for the hit on the bilinear
 * patch of that cell (a Newton step and a chord step, no further memory
 * access). Most rays end there; the rest take one more such tap, and the rare
 * ray that still has not settled (a Newton cycle between two cells of a steep
 * slope) is bracketed and bisected in double precision.
 *
 * The lane code (detail/camera_lanes.hpp) is compiled once per lane width,
 * each copy for its own target, so no function ever passes or returns a
 * vector wider than its target's registers, at any optimisation level.
 */
#include "bsp_tile64/emu/devices/camera.hpp"

#include "bsp_tile64/emu/host/frame_ahead.hpp"
#include "bsp_tile64/api/memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace bsp {
namespace {

using Cell = world::detail::Cell;

/** The widest lane group (the 8-lane renderer); line buffers leave room for one past the end. */
constexpr std::uint32_t kMaxLanes = 8;

// ---------------------------------------------------------------- frame set-up

/** Width of the strips the image is rendered in: their ground footprint stays in cache and in the TLB. */
constexpr std::uint32_t kStripPx = 64;
static_assert(kStripPx % kMaxLanes == 0, "strips hold whole lane groups");
/** Per-line scratch: a line plus the lanes of a last, partial group. */
constexpr std::uint32_t kLineCap = kMaxCameraPx + kMaxLanes;
/** Lines ahead whose cells are prefetched (about 2 us of work at 64-pixel strips). */
constexpr double kPrefetchLines = 2.0;
/** Line spacing on the ground (cells) above which lines stop sharing cache lines and prefetching pays. */
constexpr double kPrefetchMinSpacing = 0.7;
/** A ray has converged when its last step is under this (metres of depth; float noise is ~0.5 mm)... */
constexpr float kTolM = 5e-3F;
/** ...and its hit lies within the cell it read, up to this (cells). */
constexpr float kEdgeCells = 1e-3F;

// The line buffers are per host thread: the next frame may be rendered on a second host thread
// (host/frame_ahead.hpp) while the board runs, and each render needs its own.
/** Hits (depth, metres) of the two lines before, by parity of the line; <= 0 where there is none. */
alignas(32) thread_local float g_hist[2][kLineCap];
alignas(32) thread_local float g_t[kLineCap];             ///< the current line's hits
alignas(32) thread_local float g_shade[kLineCap];         ///< and their shades (0..65535)
alignas(32) thread_local std::int32_t g_noise[kLineCap];  ///< Irwin-Hall sums of the current line's noise draws
thread_local std::uint32_t g_list[kLineCap];              ///< pixels of the line still to solve
/** Lane width in use: 0 until the first render picks it; tests may cap it. */
std::uint32_t g_lanes = 0;

/**
 * Everything the ray caster needs about one frame. Grid units for x and y
 * (the cell index space of the terrain), metres for z. The image is walked as
 * lines (its rows, or its columns when those cross fewer grid rows per pixel:
 * fewer cache lines and pages per line); pixel p of line q casts the ray
 * b + p dp + q dq from the camera, whose parameter is the depth (camera z) in metres.
 */
struct Frame {
  const Cell* cells;
  std::uint32_t n;  ///< samples per side
  float nf;         ///< n
  float lim;        ///< n - 2: the largest cell index
  float last;       ///< n (n - 1) - 2: the largest index whose row below exists
  double ox, oy, oz;
  double bx, by, bz;
  double dpx, dpy, dpz;
  double dqx, dqy, dqz;
  std::uint32_t length;  ///< pixels per line
  std::uint32_t lines;
  std::size_t p_stride;  ///< output offset of the next pixel of a line (1 or the image width)
  std::size_t q_stride;  ///< output offset of the next line
  bool prefetch;         ///< lines far apart on the ground: prefetch the cells of the lines ahead
};

// ---------------------------------------------------------------- the robust path

/** The ray's height above the bilinear terrain at @p t and the shade there; inside false off the grid. */
struct Probe {
  double f;
  double shade;
  bool inside;
};

struct RayD {
  double ox, oy, oz;
  double dx, dy, dz;
};

Probe probe(const Frame& f, const RayD& r, double t) noexcept {
  const double gx = r.ox + t * r.dx;
  const double gy = r.oy + t * r.dy;
  const auto max_g = static_cast<double>(f.n - 1U);
  if (!(gx >= 0.0 && gy >= 0.0 && gx <= max_g && gy <= max_g)) {
    return Probe{0.0, 0.0, false};
  }
  const auto ix = std::min(static_cast<std::uint32_t>(gx), f.n - 2U);
  const auto iy = std::min(static_cast<std::uint32_t>(gy), f.n - 2U);
  const double fx = gx - static_cast<double>(ix);
  const double fy = gy - static_cast<double>(iy);
  const Cell* p = f.cells + std::size_t{iy} * f.n + ix;
  const auto lerp2 = [fx, fy](double a, double b, double c, double d) {
    const double top = a + (b - a) * fx;
    const double bot = c + (d - c) * fx;
    return top + (bot - top) * fy;
  };
  const double h = lerp2(p[0].height_m, p[1].height_m, p[f.n].height_m, p[f.n + 1U].height_m);
  const double s = lerp2(p[0].shade, p[1].shade, p[f.n].shade, p[f.n + 1U].shade);
  return Probe{(r.oz + t * r.dz) - h, s, true};
}

/**
 * Hit of pixel p of line q for the rare pixel whose taps did not settle: from
 * @p t_start (the datum plane if <= 0), march along the ray in steps of at
 * most a quarter cell (and 1 m of depth) towards the sign change of the ray's
 * height above the terrain, then bisect the bracket. Writes g_t[p] and
 * g_shade[p]; depth -1 if the ray leaves the grid first.
 */
void robust(const Frame& f, std::uint32_t p, std::uint32_t q, float t_start) noexcept {
  constexpr int kMaxMarch = 4096;
  constexpr int kBisections = 40;
  const auto fp = static_cast<double>(p);
  const auto fq = static_cast<double>(q);
  const RayD r{f.ox, f.oy, f.oz, f.bx + fp * f.dpx + fq * f.dqx, f.by + fp * f.dpy + fq * f.dqy,
               f.bz + fp * f.dpz + fq * f.dqz};
  g_t[p] = -1.0F;
  g_shade[p] = 0.0F;
  if (!(r.dz < -1e-9)) {
    return;  // looks up
  }
  const double dt = std::min(1.0, 0.25 / std::max(std::max(std::fabs(r.dx), std::fabs(r.dy)), 1e-9));
  double ta = t_start > 0.0F ? static_cast<double>(t_start) : -r.oz / r.dz;
  Probe pa = probe(f, r, ta);
  if (!pa.inside) {
    ta = -r.oz / r.dz;
    pa = probe(f, r, ta);
  }
  const double dir = pa.f > 0.0 ? 1.0 : -1.0;  // above the terrain: the hit is further on
  double tb = ta;
  Probe pb = pa;
  bool bracketed = false;
  for (int i = 0; i < kMaxMarch && pb.inside && tb > 0.0 && !bracketed; ++i) {
    ta = tb;
    pa = pb;
    tb = ta + dir * dt;
    pb = probe(f, r, tb);
    bracketed = pb.inside && tb > 0.0 && (pb.f > 0.0) != (pa.f > 0.0);
  }
  if (!bracketed) {
    return;
  }
  double above = pa.f > 0.0 ? ta : tb;
  double below = pa.f > 0.0 ? tb : ta;
  for (int i = 0; i < kBisections; ++i) {
    const double mid = 0.5 * (above + below);
    if (probe(f, r, mid).f > 0.0) {
      above = mid;
    } else {
      below = mid;
    }
  }
  const double t = 0.5 * (above + below);
  g_t[p] = static_cast<float>(t);
  g_shade[p] = static_cast<float>(probe(f, r, t).shade);
}

/** What the lines of a frame share. */
struct LineJob {
  const Frame* f;
  const RenderOptions* opt;
  Rng* noise;  ///< null: no read noise
  std::uint8_t* out;
};

/** @p x rounded to whole cells (|x| is far below 2^31). */
std::int32_t to_cells(double x) noexcept { return static_cast<std::int32_t>(x + (x < 0.0 ? -0.5 : 0.5)); }

// ---------------------------------------------------------------- the lane code, once per width

// Every function of a copy is always inlined and compiled for that copy's target; a call between
// them in an unoptimised build then passes its vectors in registers that both sides have.
// NOLINTBEGIN(cppcoreguidelines-macro-usage): the one spelling the two copies differ by
#define BSP_LANE [[gnu::always_inline]] inline
namespace lanes4 {
#include "bsp_tile64/emu/devices/detail/camera_lanes.hpp"
}  // namespace lanes4
#undef BSP_LANE

#if defined(__x86_64__) || defined(__i386__)
#define BSP_LANE [[gnu::always_inline, gnu::target("avx2")]] inline
#else
#define BSP_LANE [[gnu::always_inline]] inline
#endif
namespace lanes8 {
#include "bsp_tile64/emu/devices/detail/camera_lanes.hpp"
}  // namespace lanes8
#undef BSP_LANE
// NOLINTEND(cppcoreguidelines-macro-usage)

void render_strips_4(const LineJob& job) noexcept { lanes4::render_strips<4>(job); }

#if defined(__x86_64__) || defined(__i386__)
[[gnu::target("avx2")]] void render_strips_8(const LineJob& job) noexcept { lanes8::render_strips<8>(job); }

std::uint32_t host_lanes() noexcept { return __builtin_cpu_supports("avx2") ? 8U : 4U; }
#else
void render_strips_8(const LineJob& job) noexcept { lanes8::render_strips<8>(job); }

std::uint32_t host_lanes() noexcept { return 4U; }
#endif

/** Vertical 1-2-1 sums of one row of the blur (edges replicate), 0..1020. */
thread_local std::uint16_t g_blur_col[kMaxCameraPx];
/** The blurred image's rows y - 1 and y as they were before the blur, by parity of y. */
thread_local std::uint8_t g_blur_rows[2][kMaxCameraPx];

/**
 * 3x3 binomial blur of @p img in place (edges replicate), separably: the
 * vertical 1-2-1 sums of a row, then the horizontal 1-2-1 of those, /16
 * rounded. Row y is kept before it is overwritten, for row y + 1's sums.
 */
void blur3(std::uint8_t* img, std::uint32_t w, std::uint32_t h) noexcept {
  for (std::uint32_t y = 0; y < h; ++y) {
    std::uint8_t* row = img + std::size_t{y} * w;
    std::memcpy(g_blur_rows[y & 1U], row, w);
    const std::uint8_t* mid = g_blur_rows[y & 1U];
    const std::uint8_t* up = y > 0U ? g_blur_rows[(y - 1U) & 1U] : mid;
    const std::uint8_t* dn = y + 1U < h ? row + w : mid;  // row y + 1 is not blurred yet
    for (std::uint32_t x = 0; x < w; ++x) {
      g_blur_col[x] = static_cast<std::uint16_t>(up[x] + 2U * mid[x] + dn[x]);
    }
    const std::uint16_t* c = g_blur_col;
    row[0] = static_cast<std::uint8_t>((3U * c[0] + c[1] + 8U) / 16U);
    for (std::uint32_t x = 1; x + 1U < w; ++x) {
      row[x] = static_cast<std::uint8_t>((c[x - 1U] + 2U * c[x] + c[x + 1U] + 8U) / 16U);
    }
    row[w - 1U] = static_cast<std::uint8_t>((c[w - 2U] + 3U * c[w - 1U] + 8U) / 16U);
  }
}

Frame make_frame(const CameraModel& model, const CameraPose& pose, const Eigen::Matrix3d& r_mc) noexcept {
  const world::TerrainConfig& c = world::terrain_config();
  const double inv_mpp = 1.0 / c.m_per_px;
  const double centre = 0.5 * static_cast<double>(c.size_px - 1U);
  const Eigen::Vector3d d00 = r_mc * Eigen::Vector3d(-model.cx_px / model.fx_px, -model.cy_px / model.fy_px, 1.0);
  Eigen::Vector3d du = r_mc.col(0) / model.fx_px;
  Eigen::Vector3d dv = r_mc.col(1) / model.fy_px;
  du.head<2>() *= inv_mpp;
  dv.head<2>() *= inv_mpp;
  const auto nf = static_cast<float>(c.size_px);
  Frame f{};
  f.cells = world::detail::cell_data();
  f.n = c.size_px;
  f.nf = nf;
  f.lim = nf - 2.0F;
  f.last = static_cast<float>(std::size_t{c.size_px} * (c.size_px - 1U) - 2U);
  f.ox = pose.r_m.x() * inv_mpp + centre;
  f.oy = pose.r_m.y() * inv_mpp + centre;
  f.oz = pose.r_m.z();
  f.bx = d00.x() * inv_mpp;
  f.by = d00.y() * inv_mpp;
  f.bz = d00.z();
  // Lines along the image axis whose pixels step across fewer grid rows.
  const bool rows = std::fabs(du.y()) <= std::fabs(dv.y());
  const Eigen::Vector3d& dp = rows ? du : dv;
  const Eigen::Vector3d& dq = rows ? dv : du;
  f.dpx = dp.x();
  f.dpy = dp.y();
  f.dpz = dp.z();
  f.dqx = dq.x();
  f.dqy = dq.y();
  f.dqz = dq.z();
  f.length = rows ? model.width_px : model.height_px;
  f.lines = rows ? model.height_px : model.width_px;
  f.p_stride = rows ? 1U : model.width_px;
  f.q_stride = rows ? model.width_px : 1U;
  // Spacing of the lines on the ground under the camera, in cells.
  f.prefetch = std::fabs(pose.r_m.z()) * dq.head<2>().norm() > kPrefetchMinSpacing;
  return f;
}

}  // namespace

namespace detail {
std::uint32_t render_lanes() noexcept {
  if (g_lanes == 0U) {
    g_lanes = host_lanes();
  }
  return g_lanes;
}

void cap_render_lanes(std::uint32_t lanes) noexcept { g_lanes = lanes == 4U ? 4U : host_lanes(); }
}  // namespace detail

Eigen::Matrix3d camera_to_map(const CameraModel& model, const CameraPose& pose) noexcept {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> r_bc(model.r_bc);
  return pose.q_mb.toRotationMatrix() * r_bc;
}

PixelPoint project(const CameraModel& model, const CameraPose& pose, const Eigen::Vector3d& p_m) noexcept {
  const Eigen::Vector3d p_c = camera_to_map(model, pose).transpose() * (p_m - pose.r_m);
  PixelPoint out{0.0, 0.0, p_c.z() > 0.0};
  if (out.in_front) {
    out.u_px = model.cx_px + model.fx_px * p_c.x() / p_c.z();
    out.v_px = model.cy_px + model.fy_px * p_c.y() / p_c.z();
  }
  return out;
}

CameraError render(const CameraModel& model, const CameraPose& pose, const RenderOptions& opt,
                   std::uint8_t* out, Rng* noise) noexcept {
  if (!world::terrain_ready() || !world::terrain_shaded()) {
    return CameraError::kNotReady;
  }
  if (out == nullptr || model.width_px < 2U || model.height_px < 2U || model.width_px > kMaxCameraPx ||
      model.height_px > kMaxCameraPx || model.fx_px <= 0.0 || model.fy_px <= 0.0) {
    return CameraError::kBadConfig;
  }
  const Frame f = make_frame(model, pose, camera_to_map(model, pose));
  const LineJob job{&f, &opt, noise, out};
  for (float* hist : g_hist) {
    std::fill_n(hist, kLineCap, -1.0F);
  }
  if (detail::render_lanes() == 8U) {
    render_strips_8(job);
  } else {
    render_strips_4(job);
  }
  if (opt.blur) {
    blur3(out, model.width_px, model.height_px);
  }
  return CameraError::kOk;
}

CameraError CameraDevice::init(const world::Trajectory* truth, const CameraConfig& cfg, std::uint64_t seed) noexcept {
  if (truth == nullptr || !world::terrain_ready()) {
    return CameraError::kNoTruth;
  }
  const bool ok = cfg.width_px >= 16U && cfg.width_px <= kMaxCameraPx && cfg.height_px >= 16U &&
                  cfg.height_px <= kMaxCameraPx && cfg.fov_deg >= 10.0 && cfg.fov_deg <= 120.0 &&
                  cfg.rate_hz >= 1.0 && cfg.rate_hz <= 2.0 && cfg.exposure_dn >= 1.0 &&
                  cfg.exposure_dn <= 10000.0 && cfg.read_noise_dn >= 0.0 && cfg.read_noise_dn <= 50.0;
  if (!ok) {
    return CameraError::kBadConfig;
  }
  frame_ahead::forget();  // no render ahead may read the terrain while it is shaded again
  (void)detail::render_lanes();  // chosen here, before any second thread renders
  if (world::terrain_shade(cfg.sun) != world::WorldError::kOk) {
    return CameraError::kNotReady;
  }
  const std::size_t frame_bytes = std::size_t{cfg.width_px} * cfg.height_px;
  const Carve c = carve(Region{Region::kDdr}, frame_bytes * kCameraFrameBuffers, 64, "camera_frames");
  if (c.error != MemError::kOk) {
    return CameraError::kNoMemory;
  }
  ring_ = reinterpret_cast<std::uint8_t*>(c.ptr);  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast): raw DDR bytes
  truth_ = truth;
  cfg_ = cfg;
  model_ = make_camera(cfg.width_px, cfg.height_px, cfg.fov_deg);
  seq_ = 0;
  rng_ = Rng(seed, StreamId::kSensor, kCameraStreamIndex);
  return CameraError::kOk;
}

CameraDevice::~CameraDevice() { frame_ahead::forget(); }

CameraError CameraDevice::render_at(double t_s, std::uint8_t* out, Rng* noise) const noexcept {
  if (truth_ == nullptr) {
    return CameraError::kNotReady;
  }
  const world::TruthState s = truth_->at(t_s);
  const CameraPose pose{s.r_m, s.q_mb};
  const RenderOptions opt{cfg_.exposure_dn, cfg_.read_noise_dn, cfg_.blur};
  return render(model_, pose, opt, out, noise);
}

FrameInfo CameraDevice::capture(double t_s) noexcept {
  FrameInfo f{nullptr, seq_, seq_ % kCameraFrameBuffers, t_s, CameraError::kNotReady};
  if (ring_ == nullptr || truth_ == nullptr) {
    return f;
  }
  std::uint8_t* buf = ring_ + std::size_t{f.buffer} * cfg_.width_px * cfg_.height_px;
  if (!frame_ahead::take(*this, seq_, t_s, buf, &f.error, &rng_)) {
    f.error = render_at(t_s, buf, &rng_);
  }
  if (f.error == CameraError::kOk) {
    f.pixels = buf;
    ++seq_;
  }
  return f;
}

void CameraDevice::prepare(double t_next_s) const noexcept {
  if (ring_ != nullptr && truth_ != nullptr) {
    frame_ahead::request(*this, seq_, t_next_s, rng_);
  }
}

}  // namespace bsp
