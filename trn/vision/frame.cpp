/**
 * @file frame.cpp
 * @brief Map views of the reference-map product, map elevation lookups and template relighting (see frame.hpp).
 *
 * The rest of frame.hpp lives in frame_plan.cpp (plan_frame), frame_match.cpp
 * (match_landmark) and frame_coarse.cpp (coarse_frame); their shared geometry
 * is in frame_window.* and pose_geometry.*.
 */
#include "trn/vision/frame.hpp"

#include "trn/vision/frame_window.hpp"

#include <cmath>

namespace trn::vision {

Status map_view(const bsp::MapProductHeader* product, std::uint32_t layer, MapView& out) noexcept {
  out = MapView{};
  if (product == nullptr || product->magic != bsp::kMapProductMagic || layer >= bsp::kMapLayers ||
      layer >= product->layer_count) {
    return Status::kBadInput;
  }
  const bsp::MapLayerHeader& h = product->layers[layer];
  if (h.width_px == 0U || h.height_px == 0U || h.width_px > 65536U || h.height_px > 65536U ||
      !(h.m_per_px > 0.0)) {
    return Status::kBadInput;
  }
  const auto w = static_cast<std::int32_t>(h.width_px);
  out.image = ConstImageU8{bsp::map_image(product, layer), w, static_cast<std::int32_t>(h.height_px), w};
  out.elevation = bsp::map_elevation(product, layer);
  out.elevation_scale_m = h.elevation_scale_m;
  out.geo = MapGeometry{h.m_per_px, h.origin_x_m, h.origin_y_m};
  if (std::isfinite(product->sun_azimuth_deg) && std::isfinite(product->sun_elevation_deg)) {
    sun_direction(product->sun_azimuth_deg, product->sun_elevation_deg, out.sun_m);
  }
  return Status::kOk;
}

void sun_direction(double azimuth_deg, double elevation_deg, double out[3]) noexcept {
  constexpr double kRad = 3.14159265358979323846 / 180.0;
  const double az = azimuth_deg * kRad;
  const double el = elevation_deg * kRad;
  out[0] = std::sin(az) * std::cos(el);
  out[1] = std::cos(az) * std::cos(el);
  out[2] = std::sin(el);
}

Status relight_region(const MapView& map, std::int32_t col0, std::int32_t row0, const double sun_m[3], ImageU8 out,
                     bsp::Work& work) noexcept {
  const double* sm = map.sun_m;
  const bool suns = sun_m != nullptr && (sun_m[0] != 0.0 || sun_m[1] != 0.0 || sun_m[2] != 0.0) &&
                    (sm[0] != 0.0 || sm[1] != 0.0 || sm[2] != 0.0);
  if (!detail::map_ok(map) || !suns || !out.valid() || col0 < 0 || row0 < 0 || out.width > map.image.width - col0 ||
      out.height > map.image.height - row0) {
    return Status::kBadInput;
  }
  const std::int64_t w = map.image.width;
  const std::int32_t last_col = map.image.width - 1;
  const std::int32_t last_row = map.image.height - 1;
  // Slopes from elevation counts: metres per count over metres per pixel.
  const double k = map.elevation_scale_m / map.geo.m_per_px;
  for (std::int32_t j = 0; j < out.height; ++j) {
    const std::int32_t r = row0 + j;
    const std::int32_t rn = r > 0 ? r - 1 : r;  // north neighbour
    const std::int32_t rs = r < last_row ? r + 1 : r;
    const std::uint8_t* src = map.image.row(r);
    std::uint8_t* dst = out.row(j);
    for (std::int32_t i = 0; i < out.width; ++i) {
      const std::int32_t c = col0 + i;
      const std::int32_t cw = c > 0 ? c - 1 : c;
      const std::int32_t ce = c < last_col ? c + 1 : c;
      // Differences over two pixels inside the layer, one at its edges.
      const double kx = ce - cw == 2 ? 0.5 * k : k;
      const double ky = rs - rn == 2 ? 0.5 * k : k;
      const double gx = kx * (map.elevation[r * w + ce] - map.elevation[r * w + cw]);
      const double gy = ky * (map.elevation[rn * w + c] - map.elevation[rs * w + c]);
      // Normal (-gx, -gy, 1) unnormalised: the ratio of two cosines needs no normalisation;
      // the floor 0.1 applies to the normalised map cosine (square root only when it binds).
      const double lit_map = -gx * sm[0] - gy * sm[1] + sm[2];
      const double lit_new = -gx * sun_m[0] - gy * sun_m[1] + sun_m[2];
      const double n2 = gx * gx + gy * gy + 1.0;
      const double den = (lit_map > 0.0 && lit_map * lit_map > 0.01 * n2) ? lit_map : 0.1 * std::sqrt(n2);
      const double ratio = (lit_new > 0.0 ? lit_new : 0.0) / den;
      const double v = src[c] * ratio + 0.5;
      dst[i] = static_cast<std::uint8_t>(v < 255.0 ? v : 255.0);  // v >= 0.5: truncation rounds
    }
  }
  const auto px = static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height);
  work.flops += px * 24U;
  work.fdivs += px;  // the ratio; the rare floored pixel's square root is not counted
  work.int_ops += px * 10U;
  work.mem_words += px * 3U;
  return Status::kOk;
}

double map_elevation_m(const MapView& map, double col, double row) noexcept {
  const double cmax = static_cast<double>(map.image.width - 1);
  const double rmax = static_cast<double>(map.image.height - 1);
  const double c = col < 0.0 ? 0.0 : (col > cmax ? cmax : col);
  const double r = row < 0.0 ? 0.0 : (row > rmax ? rmax : row);
  const auto c0 = static_cast<std::int32_t>(c);  // c >= 0: truncation is floor
  const auto r0 = static_cast<std::int32_t>(r);
  const std::int32_t c1 = c0 + 1 < map.image.width ? c0 + 1 : c0;
  const std::int32_t r1 = r0 + 1 < map.image.height ? r0 + 1 : r0;
  const double fc = c - c0;
  const double fr = r - r0;
  const std::int64_t w = map.image.width;
  const double e00 = map.elevation[r0 * w + c0];
  const double e01 = map.elevation[r0 * w + c1];
  const double e10 = map.elevation[r1 * w + c0];
  const double e11 = map.elevation[r1 * w + c1];
  const double top = e00 + fc * (e01 - e00);
  const double bot = e10 + fc * (e11 - e10);
  return (top + fr * (bot - top)) * map.elevation_scale_m;
}

}  // namespace trn::vision
