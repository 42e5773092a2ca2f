/**
 * @file camera.hpp
 * @brief The camera device model: pinhole projection and rendering of the terrain (truth) into DDR frames.
 *
 * Geometry follows camera_model.hpp: p_C = R_MC^T (p_M - r_M) with
 * R_MC = R_MB * r_bc, u = cx + fx x/z, v = cy + fy y/z. The camera centre is
 * the body origin (no lever arm). Rendering casts one ray per pixel centre,
 * intersects it with the bilinear height field (Newton steps on the patch of
 * the cell under a guess extrapolated from the hits of two neighbouring
 * pixels; converged to millimetres), and samples there the radiance
 * pre-shaded under the descent sun (world::terrain_shade()).
 * DN = exposure_dn * radiance + read noise (approximately Gaussian, from one
 * 64-bit draw of StreamId::kSensor per pixel), optional 3x3 blur, clamped to 0..255.
 * Rays that miss the terrain grid (or look up) give DN 0.
 */
#pragma once

#include "bsp_tile64/api/camera_model.hpp"
#include "bsp_tile64/emu/rng.hpp"
#include "bsp_tile64/world/terrain.hpp"
#include "bsp_tile64/world/trajectory.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace bsp {

/** Largest frame side the static scratch supports, pixels. */
inline constexpr std::uint32_t kMaxCameraPx = 2048;
/** Frame buffers carved in DDR (a ring: the driver captures into one while flight code reads the other). */
inline constexpr std::uint32_t kCameraFrameBuffers = 2;
/** Stream index of the camera within StreamId::kSensor. */
inline constexpr std::uint64_t kCameraStreamIndex = 2;

enum class CameraError : std::uint8_t { kOk, kBadConfig, kNotReady, kNoMemory, kNoTruth };

struct CameraConfig {
  std::uint32_t width_px = 1024;     ///< 16..kMaxCameraPx
  std::uint32_t height_px = 1024;    ///< 16..kMaxCameraPx
  double fov_deg = 90.0;             ///< horizontal field of view, 10..120
  double rate_hz = 1.0;              ///< capture rate, 1..2 (the driver schedules captures)
  double exposure_dn = 600.0;        ///< DN for radiance 1.0, 1..10000
  double read_noise_dn = 2.0;        ///< 1-sigma noise, DN, 0..50
  bool blur = false;                 ///< 3x3 binomial blur (defocus, motion)
  world::SunAngle sun{135.0, 35.0};  ///< descent sun
};

/** Camera pose: centre and body attitude (camera axes follow r_bc of the model). */
struct CameraPose {
  Eigen::Vector3d r_m;
  Eigen::Quaterniond q_mb;
};

/** Result of a projection. */
struct PixelPoint {
  double u_px;
  double v_px;
  bool in_front;  ///< z_C > 0
};

/** Rotation camera -> map of @p pose under mounting @p model.r_bc. */
Eigen::Matrix3d camera_to_map(const CameraModel& model, const CameraPose& pose) noexcept;

/** Projects the map point @p p_m into pixel coordinates (pinhole, no distortion). */
PixelPoint project(const CameraModel& model, const CameraPose& pose, const Eigen::Vector3d& p_m) noexcept;

/** Rendering options of one frame. */
struct RenderOptions {
  double exposure_dn = 600.0;
  double read_noise_dn = 0.0;
  bool blur = false;
  /** Optional width * height floats: depth (camera z, metres) of each pixel's terrain hit, -1 where it misses. */
  float* depth_m = nullptr;
};

/**
 * Renders the terrain seen from @p pose into @p out (width * height bytes).
 * @param noise stream for read noise; may be null when read_noise_dn is 0.
 * @return kNotReady unless the terrain is built and shaded; kBadConfig for a size over kMaxCameraPx.
 */
CameraError render(const CameraModel& model, const CameraPose& pose, const RenderOptions& opt,
                   std::uint8_t* out, Rng* noise) noexcept;

namespace detail {
/** Float lanes the renderer runs: 8 on a host with AVX2, else 4 (the frames are the same bits either way). */
std::uint32_t render_lanes() noexcept;
/** 4 forces the 4-lane renderer; any other value restores the host's choice (tests compare the two). */
void cap_render_lanes(std::uint32_t lanes) noexcept;
}  // namespace detail

/** A captured frame as the device reports it. */
struct FrameInfo {
  const std::uint8_t* pixels;  ///< in DDR; valid until the ring comes round again
  std::uint32_t seq;           ///< capture counter from 0
  std::uint32_t buffer;        ///< ring index
  double t_s;                  ///< capture (mid-exposure) time, emulated seconds
  CameraError error;
};

class CameraDevice {
 public:
  /**
   * Validates @p cfg, shades the terrain under the descent sun, carves the
   * frame ring in DDR ("camera_frames"). Call once per run (the carve is not returned).
   * @return kNoTruth if @p truth is null or the terrain is not built; kNoMemory if the carve fails.
   */
  CameraError init(const world::Trajectory* truth, const CameraConfig& cfg, std::uint64_t seed) noexcept;

  CameraDevice() = default;
  CameraDevice(const CameraDevice&) = delete;
  CameraDevice& operator=(const CameraDevice&) = delete;
  CameraDevice(CameraDevice&&) = delete;
  CameraDevice& operator=(CameraDevice&&) = delete;
  /** Drops any frame rendered ahead (host/frame_ahead.hpp): it may be this camera's. */
  ~CameraDevice();

  /**
   * Renders the truth pose at @p t_s into the next ring buffer: copied from
   * the frame rendered ahead if prepare() asked for this one, else rendered now
   * (the same bytes and noise state either way).
   */
  FrameInfo capture(double t_s) noexcept;

  /**
   * Announces the next capture's time: a host front end that started the
   * render worker (host/frame_ahead.hpp) has that frame rendered meanwhile.
   */
  void prepare(double t_next_s) const noexcept;

  /**
   * The frame of the truth pose at @p t_s with read noise drawn from @p noise
   * (advanced past it) into @p out (width * height bytes): what capture() puts
   * in the ring. Reads only the camera's settings, the truth and the terrain.
   */
  CameraError render_at(double t_s, std::uint8_t* out, Rng* noise) const noexcept;

  const CameraModel& model() const noexcept { return model_; }
  const CameraConfig& config() const noexcept { return cfg_; }

 private:
  const world::Trajectory* truth_ = nullptr;
  CameraConfig cfg_{};
  CameraModel model_{};
  std::uint8_t* ring_ = nullptr;
  std::uint32_t seq_ = 0;
  Rng rng_{0, StreamId::kSensor, kCameraStreamIndex};
};

}  // namespace bsp
