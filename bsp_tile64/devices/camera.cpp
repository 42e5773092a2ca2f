/**
 * @file camera.cpp
 * @brief Pinhole projection, height-field ray casting and the DDR frame ring.
 */
#include "bsp_tile64/devices/camera.hpp"

#include "bsp_tile64/memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace bsp {
namespace {

/** Side of the pixel blocks rendered together: their ground footprint stays in cache. */
constexpr std::uint32_t kBlockPx = 16;
constexpr std::uint32_t kMaxNodes = kMaxCameraPx / kBlockPx + 1U;

/** Scratch for the blur pass (static: no frame-sized stack or heap buffer). */
std::uint8_t g_blur_scratch[std::size_t{kMaxCameraPx} * kMaxCameraPx];
/** Ray parameters of the hits at block corners: the first guesses of the pixels between them. */
double g_node_t[std::size_t{kMaxNodes} * kMaxNodes];

/** The grid as the ray caster sees it, in grid units (samples). */
struct GridView {
  const world::detail::Cell* cells;
  std::uint32_t n;
  double max_g;      ///< n - 1
  double inv_mpp;
  double centre_px;
};

GridView grid_view() noexcept {
  const world::TerrainConfig& c = world::terrain_config();
  GridView g{};
  g.cells = world::detail::cell_data();
  g.n = c.size_px;
  g.max_g = static_cast<double>(c.size_px - 1U);
  g.inv_mpp = 1.0 / c.m_per_px;
  g.centre_px = 0.5 * g.max_g;
  return g;
}

/** One ray: origin and direction with x, y in grid units and z in metres. */
struct Ray {
  double ox, oy, oz;
  double dx, dy, dz;
};

/** Bilinear weights of one grid position, for reading several members of the same four cells. */
struct Tap {
  const world::detail::Cell* p;
  double fx;
  double fy;
};

[[gnu::always_inline]] inline Tap tap(const GridView& g, double gx, double gy) noexcept {
  const auto ix = std::min(static_cast<std::uint32_t>(gx), g.n - 2U);
  const auto iy = std::min(static_cast<std::uint32_t>(gy), g.n - 2U);
  return {g.cells + std::size_t{iy} * g.n + ix, gx - static_cast<double>(ix), gy - static_cast<double>(iy)};
}

template <class T>
[[gnu::always_inline]] inline double read(const Tap& t, std::uint32_t n, T world::detail::Cell::*field) noexcept {
  const double a = static_cast<double>(t.p[0].*field);
  const double b = static_cast<double>(t.p[1].*field);
  const double top = a + (static_cast<double>(t.p[n].*field) - a) * t.fy;
  const double bot = b + (static_cast<double>(t.p[n + 1U].*field) - b) * t.fy;
  return top + (bot - top) * t.fx;
}

/** A ray's hit: its parameter (negative: missed the grid) and the pre-shaded radiance there (0..65535). */
struct Hit {
  double t;
  double shade;
};

/**
 * Terrain hit by fixed-point iteration t = (h(p(t)) - oz) / dz from @p t_guess.
 * Converged when the height changes by less than 10 cm between iterations (the
 * first compares with the height the guess implies); the
 * shade is read from the cells of the last height lookup (within 10 cm of the
 * hit; 10 cm is under 0.1 px at the lowest altitude), which saves a second bilinear lookup per pixel.
 */
[[gnu::always_inline]] inline Hit intersect(const GridView& g, const Ray& r, double t_guess) noexcept {
  constexpr int kMaxIter = 8;
  constexpr double kTolM = 0.1;
  const double inv_dz = 1.0 / r.dz;
  double t = t_guess;
  double h_prev = r.oz + t_guess * r.dz;  // the height the guess assumes: a good guess converges at once
  Hit hit{-1.0, 0.0};
  for (int i = 0; i < kMaxIter; ++i) {
    const double gx = r.ox + t * r.dx;
    const double gy = r.oy + t * r.dy;
    if (!(gx >= 0.0 && gy >= 0.0 && gx <= g.max_g && gy <= g.max_g)) {
      return Hit{-1.0, 0.0};
    }
    const Tap at = tap(g, gx, gy);
    const double h = read(at, g.n, &world::detail::Cell::height_m);
    t = (h - r.oz) * inv_dz;
    if (std::fabs(h - h_prev) < kTolM || i + 1 == kMaxIter) {
      hit = Hit{t, read(at, g.n, &world::detail::Cell::shade)};
      break;
    }
    h_prev = h;
  }
  return hit;
}

/** Approximately standard normal from one 64-bit draw: the sum of four 16-bit uniforms (Irwin-Hall). */
double fast_normal(Rng& rng) noexcept {
  const std::uint64_t x = rng.next();
  const double sum = static_cast<double>((x & 0xFFFFU) + ((x >> 16U) & 0xFFFFU) + ((x >> 32U) & 0xFFFFU) +
                                         (x >> 48U));
  constexpr double kMean = 2.0 * 65535.0;
  constexpr double kInvSigma = 1.7320508075688772 / 65536.0;  // sigma of the sum: 65536 / sqrt(3)
  return (sum - kMean) * kInvSigma;
}

struct RowJob {
  const GridView* g;
  Eigen::Vector3d d00;  ///< map-frame ray direction of pixel (0, 0) (camera z component 1)
  Eigen::Vector3d du;   ///< change of the direction per column
  Eigen::Vector3d dv;   ///< change of the direction per row
  Eigen::Vector3d origin_m;
  std::uint32_t width_px;
  const RenderOptions* opt;
  Rng* noise;
};

Ray ray_from(const RowJob& job, const Eigen::Vector3d& d) noexcept {
  const GridView& g = *job.g;
  return Ray{job.origin_m.x() * g.inv_mpp + g.centre_px, job.origin_m.y() * g.inv_mpp + g.centre_px,
             job.origin_m.z(), d.x() * g.inv_mpp, d.y() * g.inv_mpp, d.z()};
}

/**
 * Hits of the rays through the block corners (u, v multiples of kBlockPx),
 * each iterated from the datum plane; -1 where the ray misses.
 */
void node_hits(const RowJob& job, std::uint32_t nu, std::uint32_t nv) noexcept {
  for (std::uint32_t j = 0; j < nv; ++j) {
    double t_prev = -1.0;
    for (std::uint32_t i = 0; i < nu; ++i) {
      const Eigen::Vector3d d = job.d00 + static_cast<double>(i * kBlockPx) * job.du +
                                static_cast<double>(j * kBlockPx) * job.dv;
      double t = -1.0;
      if (d.z() < -1e-9) {
        const Ray ray = ray_from(job, d);
        t = intersect(*job.g, ray, t_prev > 0.0 ? t_prev : -ray.oz / ray.dz).t;
      }
      g_node_t[std::size_t{j} * kMaxNodes + i] = t;
      t_prev = t;
    }
  }
}

/** First guess of the hit of pixel (u, v): bilinear in the corner hits, the datum plane if one missed. */
double guess_t(std::uint32_t u, std::uint32_t v, const Ray& ray) noexcept {
  const std::uint32_t i = u / kBlockPx;
  const std::uint32_t j = v / kBlockPx;
  const double* n = g_node_t + std::size_t{j} * kMaxNodes + i;
  if (n[0] <= 0.0 || n[1] <= 0.0 || n[kMaxNodes] <= 0.0 || n[kMaxNodes + 1U] <= 0.0) {
    return -ray.oz / ray.dz;
  }
  const double fu = static_cast<double>(u - i * kBlockPx) * (1.0 / kBlockPx);
  const double fv = static_cast<double>(v - j * kBlockPx) * (1.0 / kBlockPx);
  const double top = n[0] + (n[1] - n[0]) * fu;
  const double bot = n[kMaxNodes] + (n[kMaxNodes + 1U] - n[kMaxNodes]) * fu;
  return top + (bot - top) * fv;
}

/**
 * Renders the block of pixels [u0, u1) x [v0, v1). Pixels start from the
 * corner-hit guess, not from their neighbour, so their memory accesses are
 * independent and overlap.
 */
void render_block(const RowJob& job, std::uint32_t u0, std::uint32_t u1, std::uint32_t v0, std::uint32_t v1,
                  std::uint8_t* out) noexcept {
  const GridView& g = *job.g;
  Ray ray = ray_from(job, job.d00);
  const bool noisy = job.noise != nullptr && job.opt->read_noise_dn > 0.0;
  const double gain = job.opt->exposure_dn * (1.0 / 65535.0);
  for (std::uint32_t v = v0; v < v1; ++v) {
    const Eigen::Vector3d d_row = job.d00 + static_cast<double>(v) * job.dv;
    for (std::uint32_t u = u0; u < u1; ++u) {
      const Eigen::Vector3d d = d_row + static_cast<double>(u) * job.du;
      double dn = 0.0;
      if (d.z() < -1e-9) {
        ray.dx = d.x() * g.inv_mpp;
        ray.dy = d.y() * g.inv_mpp;
        ray.dz = d.z();
        const Hit hit = intersect(g, ray, guess_t(u, v, ray));
        if (hit.t > 0.0) {
          dn = gain * hit.shade;
        }
      }
      if (noisy) {
        dn += job.opt->read_noise_dn * fast_normal(*job.noise);
      }
      out[std::size_t{v} * job.width_px + u] = static_cast<std::uint8_t>(std::clamp(dn + 0.5, 0.0, 255.0));
    }
  }
}

/** Horizontal 1-2-1 sum of one row at column @p x (edges replicate). */
std::uint32_t h121(const std::uint8_t* row, std::uint32_t x, std::uint32_t w) noexcept {
  const std::uint32_t xl = x > 0U ? x - 1U : 0U;
  const std::uint32_t xr = x + 1U < w ? x + 1U : x;
  return std::uint32_t{row[xl]} + 2U * row[x] + row[xr];
}

/** 3x3 binomial blur from @p src into @p dst (edges replicate). */
void blur3(const std::uint8_t* src, std::uint8_t* dst, std::uint32_t w, std::uint32_t h) noexcept {
  for (std::uint32_t y = 0; y < h; ++y) {
    const std::size_t y_up = y > 0U ? y - 1U : 0U;
    const std::size_t y_dn = y + 1U < h ? y + 1U : y;
    const std::uint8_t* up = src + y_up * w;
    const std::uint8_t* mid = src + std::size_t{y} * w;
    const std::uint8_t* dn = src + y_dn * w;
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::uint32_t acc = h121(up, x, w) + 2U * h121(mid, x, w) + h121(dn, x, w);
      dst[std::size_t{y} * w + x] = static_cast<std::uint8_t>((acc + 8U) / 16U);
    }
  }
}

}  // namespace

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
  const GridView g = grid_view();
  const Eigen::Matrix3d r_mc = camera_to_map(model, pose);
  const RowJob job{&g,
                   r_mc * Eigen::Vector3d(-model.cx_px / model.fx_px, -model.cy_px / model.fy_px, 1.0),
                   r_mc.col(0) / model.fx_px,
                   r_mc.col(1) / model.fy_px,
                   pose.r_m,
                   model.width_px,
                   &opt,
                   noise};
  std::uint8_t* target = opt.blur ? g_blur_scratch : out;
  node_hits(job, (model.width_px + kBlockPx - 1U) / kBlockPx + 1U, (model.height_px + kBlockPx - 1U) / kBlockPx + 1U);
  for (std::uint32_t v0 = 0; v0 < model.height_px; v0 += kBlockPx) {
    const std::uint32_t v1 = std::min(v0 + kBlockPx, model.height_px);
    for (std::uint32_t u0 = 0; u0 < model.width_px; u0 += kBlockPx) {
      render_block(job, u0, std::min(u0 + kBlockPx, model.width_px), v0, v1, target);
    }
  }
  if (opt.blur) {
    blur3(g_blur_scratch, out, model.width_px, model.height_px);
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

FrameInfo CameraDevice::capture(double t_s) noexcept {
  FrameInfo f{nullptr, seq_, seq_ % kCameraFrameBuffers, t_s, CameraError::kNotReady};
  if (ring_ == nullptr || truth_ == nullptr) {
    return f;
  }
  std::uint8_t* buf = ring_ + std::size_t{f.buffer} * cfg_.width_px * cfg_.height_px;
  const world::TruthState s = truth_->at(t_s);
  const CameraPose pose{s.r_m, s.q_mb};
  const RenderOptions opt{cfg_.exposure_dn, cfg_.read_noise_dn, cfg_.blur};
  f.error = render(model_, pose, opt, buf, &rng_);
  if (f.error == CameraError::kOk) {
    f.pixels = buf;
    ++seq_;
  }
  return f;
}

}  // namespace bsp
