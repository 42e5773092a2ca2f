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
 */
#include "bsp_tile64/devices/camera.hpp"

#include "bsp_tile64/memory.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

// The lane helpers below take and return 32-byte vectors; they are all always inlined into the
// AVX2 entry point, so no call crosses the ABI boundary that -Wpsabi warns about.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace bsp {
namespace {

using Cell = world::detail::Cell;

// ---------------------------------------------------------------- float lanes

using V4f [[gnu::vector_size(16)]] = float;
using V4i [[gnu::vector_size(16)]] = std::int32_t;
using V8f [[gnu::vector_size(32)]] = float;
using V8i [[gnu::vector_size(32)]] = std::int32_t;

template <std::uint32_t N>
struct LaneTypes;
template <>
struct LaneTypes<4> {
  using F = V4f;
  using I = V4i;
};
template <>
struct LaneTypes<8> {
  using F = V8f;
  using I = V8i;
};
template <std::uint32_t N>
using VecF = typename LaneTypes<N>::F;
template <std::uint32_t N>
using VecI = typename LaneTypes<N>::I;

constexpr std::uint32_t kMaxLanes = 8;

// Everything that handles lanes is always inlined: inside the AVX2 entry point it is compiled for
// AVX2, and no call passes 32-byte vectors across a function boundary.
#define BSP_LANE [[gnu::always_inline]] inline  // NOLINT(cppcoreguidelines-macro-usage): one spelling for all of them

template <std::uint32_t N>
BSP_LANE VecF<N> splat(float x) noexcept {
  return x - VecF<N>{};  // x - 0 is x in every lane, -0 included
}
template <std::uint32_t N>
BSP_LANE VecF<N> iota() noexcept {
  VecF<N> v{};
  for (std::uint32_t k = 0; k < N; ++k) {
    v[k] = static_cast<float>(k);
  }
  return v;
}
template <class F>
BSP_LANE F vmin(const F& a, const F& b) noexcept {
  return a < b ? a : b;
}
template <class F>
BSP_LANE F vmax(const F& a, const F& b) noexcept {
  return a > b ? a : b;
}
template <std::uint32_t N>
BSP_LANE VecF<N> vabs(const VecF<N>& a) noexcept {
  return std::bit_cast<VecF<N>>(std::bit_cast<VecI<N>>(a) & 0x7FFFFFFF);
}
template <std::uint32_t N>
BSP_LANE VecF<N> to_float(const VecI<N>& a) noexcept {
  return __builtin_convertvector(a, VecF<N>);
}
/** Truncation towards zero (the lanes it is used on are >= 0: floor). */
template <std::uint32_t N>
BSP_LANE VecI<N> to_int(const VecF<N>& a) noexcept {
  return __builtin_convertvector(a, VecI<N>);
}
BSP_LANE V4f low_half(const V8f& v) noexcept { return __builtin_shufflevector(v, v, 0, 1, 2, 3); }
BSP_LANE V4f high_half(const V8f& v) noexcept { return __builtin_shufflevector(v, v, 4, 5, 6, 7); }
BSP_LANE V8f join(V4f lo, V4f hi) noexcept { return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7); }

/** The heights and shades of the four cells of a bilinear patch, one patch per lane. */
template <std::uint32_t N>
struct Corners {
  VecF<N> a, b, c, d;      ///< heights at (ix, iy), (ix+1, iy), (ix, iy+1), (ix+1, iy+1)
  VecF<N> sa, sb, sc, sd;  ///< shades at the same cells
};

#if defined(__SSE2__)
static_assert(offsetof(Cell, height_m) == 0 && offsetof(Cell, shade) == 4, "gather reads cells as float pairs");

BSP_LANE V4f load_pair(const Cell* p) noexcept {
  V4f r;
  std::memcpy(&r, p, sizeof r);  // cells ix and ix+1: [h, shade bits, h, shade bits]
  return r;
}
/** [x0, x2, y0, y2] and [x1, x3, y1, y3]. */
BSP_LANE V4f even(V4f x, V4f y) noexcept { return _mm_shuffle_ps(x, y, 0x88); }
BSP_LANE V4f odd(V4f x, V4f y) noexcept { return _mm_shuffle_ps(x, y, 0xDD); }
BSP_LANE V4f shade_of(V4f bits) noexcept {
  return to_float<4>(std::bit_cast<V4i>(bits) & 0xFFFF);  // x86 is little-endian: the shade is the low half
}

/** Reads the patches of four lanes at cell indices @p idx: two 16-byte loads per lane, then a transpose. */
BSP_LANE Corners<4> gather4(const Cell* cells, const std::int32_t* idx, std::size_t n) noexcept {
  const V4f r0a = load_pair(cells + idx[0]);
  const V4f r0b = load_pair(cells + idx[1]);
  const V4f r0c = load_pair(cells + idx[2]);
  const V4f r0d = load_pair(cells + idx[3]);
  const V4f r1a = load_pair(cells + idx[0] + n);
  const V4f r1b = load_pair(cells + idx[1] + n);
  const V4f r1c = load_pair(cells + idx[2] + n);
  const V4f r1d = load_pair(cells + idx[3] + n);
  const V4f h0ab = even(r0a, r0b);
  const V4f h0cd = even(r0c, r0d);
  const V4f h1ab = even(r1a, r1b);
  const V4f h1cd = even(r1c, r1d);
  const V4f s0ab = odd(r0a, r0b);
  const V4f s0cd = odd(r0c, r0d);
  const V4f s1ab = odd(r1a, r1b);
  const V4f s1cd = odd(r1c, r1d);
  return Corners<4>{even(h0ab, h0cd),           odd(h0ab, h0cd),           even(h1ab, h1cd),
                    odd(h1ab, h1cd),            shade_of(even(s0ab, s0cd)), shade_of(odd(s0ab, s0cd)),
                    shade_of(even(s1ab, s1cd)), shade_of(odd(s1ab, s1cd))};
}

/** Bit k set where lane k is true. */
BSP_LANE std::uint32_t lane_bits4(V4i m) noexcept {
  return static_cast<std::uint32_t>(_mm_movemask_ps(std::bit_cast<__m128>(m)));
}

/** Four lanes (0..255) as four bytes, lane 0 first. */
BSP_LANE std::uint32_t pack_bytes4(V4i v) noexcept {
  const __m128i w = _mm_packs_epi32(std::bit_cast<__m128i>(v), std::bit_cast<__m128i>(v));
  return static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(w, w)));
}
#else
BSP_LANE Corners<4> gather4(const Cell* cells, const std::int32_t* idx, std::size_t n) noexcept {
  Corners<4> c{};
  for (std::uint32_t k = 0; k < 4U; ++k) {
    const Cell* p = cells + idx[k];
    c.a[k] = p[0].height_m;
    c.b[k] = p[1].height_m;
    c.c[k] = p[n].height_m;
    c.d[k] = p[n + 1U].height_m;
    c.sa[k] = static_cast<float>(p[0].shade);
    c.sb[k] = static_cast<float>(p[1].shade);
    c.sc[k] = static_cast<float>(p[n].shade);
    c.sd[k] = static_cast<float>(p[n + 1U].shade);
  }
  return c;
}

BSP_LANE std::uint32_t lane_bits4(V4i m) noexcept {
  std::uint32_t bits = 0;
  for (std::uint32_t k = 0; k < 4U; ++k) {
    bits |= m[k] != 0 ? 1U << k : 0U;
  }
  return bits;
}

BSP_LANE std::uint32_t pack_bytes4(V4i v) noexcept {
  std::uint32_t out = 0;
  for (std::uint32_t k = 0; k < 4U; ++k) {
    out |= static_cast<std::uint32_t>(v[k]) << (8U * k);
  }
  return out;
}
#endif

template <std::uint32_t N>
BSP_LANE Corners<N> gather(const Cell* cells, const std::int32_t* idx, std::size_t n) noexcept {
  if constexpr (N == 4U) {
    return gather4(cells, idx, n);
  } else {
    const Corners<4> lo = gather4(cells, idx, n);
    const Corners<4> hi = gather4(cells, idx + 4, n);
    return Corners<8>{join(lo.a, hi.a),   join(lo.b, hi.b),   join(lo.c, hi.c),   join(lo.d, hi.d),
                      join(lo.sa, hi.sa), join(lo.sb, hi.sb), join(lo.sc, hi.sc), join(lo.sd, hi.sd)};
  }
}

template <std::uint32_t N>
BSP_LANE std::uint32_t lane_bits(const VecI<N>& m) noexcept {
  if constexpr (N == 4U) {
    return lane_bits4(m);
  } else {
    const V8f f = std::bit_cast<V8f>(m);
    return lane_bits4(std::bit_cast<V4i>(low_half(f))) | (lane_bits4(std::bit_cast<V4i>(high_half(f))) << 4U);
  }
}

/** Lanes (0..255) as bytes into @p out, lane 0 first. */
template <std::uint32_t N>
BSP_LANE void store_bytes(const VecI<N>& v, std::uint8_t* out) noexcept {
  if constexpr (N == 4U) {
    const std::uint32_t b = pack_bytes4(v);
    std::memcpy(out, &b, sizeof b);
  } else {
    const V8f f = std::bit_cast<V8f>(v);
    const std::uint32_t lo = pack_bytes4(std::bit_cast<V4i>(low_half(f)));
    const std::uint32_t hi = pack_bytes4(std::bit_cast<V4i>(high_half(f)));
    std::memcpy(out, &lo, sizeof lo);
    std::memcpy(out + 4, &hi, sizeof hi);
  }
}

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

/** Scratch for the blur pass (static: no frame-sized stack or heap buffer). */
std::uint8_t g_blur_scratch[std::size_t{kMaxCameraPx} * kMaxCameraPx];
/** Hits (depth, metres) of the two lines before, by parity of the line; <= 0 where there is none. */
alignas(32) float g_hist[2][kLineCap];
alignas(32) float g_t[kLineCap];             ///< the current line's hits
alignas(32) float g_shade[kLineCap];         ///< and their shades (0..65535)
alignas(32) std::int32_t g_noise[kLineCap];  ///< Irwin-Hall sums of the current line's noise draws
std::uint32_t g_list[kLineCap];              ///< pixels of the line still to solve
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

/** The frame's constants as lanes, and the ray directions of one line: d(p) = b + p dp. */
template <std::uint32_t N>
struct LineLanes {
  const Cell* cells;
  std::uint32_t n;
  VecF<N> nf, lim, last;
  VecF<N> ox, oy, oz;
  VecF<N> bx, by, bz;
  VecF<N> px, py, pz;
};

template <std::uint32_t N>
BSP_LANE LineLanes<N> line_lanes(const Frame& f, std::uint32_t q) noexcept {
  const auto fq = static_cast<double>(q);
  return LineLanes<N>{f.cells,
                      f.n,
                      splat<N>(f.nf),
                      splat<N>(f.lim),
                      splat<N>(f.last),
                      splat<N>(static_cast<float>(f.ox)),
                      splat<N>(static_cast<float>(f.oy)),
                      splat<N>(static_cast<float>(f.oz)),
                      splat<N>(static_cast<float>(f.bx + fq * f.dqx)),
                      splat<N>(static_cast<float>(f.by + fq * f.dqy)),
                      splat<N>(static_cast<float>(f.bz + fq * f.dqz)),
                      splat<N>(static_cast<float>(f.dpx)),
                      splat<N>(static_cast<float>(f.dpy)),
                      splat<N>(static_cast<float>(f.dpz))};
}

template <std::uint32_t N>
struct Dirs {
  VecF<N> dx, dy, dz;
};

template <std::uint32_t N>
BSP_LANE Dirs<N> dirs(const LineLanes<N>& l, const VecF<N>& p) noexcept {
  return Dirs<N>{l.bx + p * l.px, l.by + p * l.py, l.bz + p * l.pz};
}

// ---------------------------------------------------------------- the tap

/** Result of a tap, per lane. */
template <std::uint32_t N>
struct Tap {
  VecF<N> t;      ///< depth of the hit (metres)
  VecF<N> shade;  ///< shade there (0..65535)
  VecI<N> ok;     ///< all ones where the ray converged inside the cell it read
};

/**
 * One tap per lane: the cell under the ray at depth @p t, then on its
 * bilinear patch h = a + ab fx + ac fy + e fx fy a Newton step on
 * f(t) = z(t) - h(t) and a chord step with the same slope (no further memory
 * access). The slope is capped at a quarter of dz so a grazing ray cannot be
 * thrown far. Converged where the chord step is under kTolM (the error after
 * it is far smaller) and the hit is inside the cell; the shade is read at the
 * hit from the same four cells. @p kPrefetch also prefetches the cells
 * @p pf_off (index offset) further on.
 */
template <std::uint32_t N, bool kPrefetch>
BSP_LANE Tap<N> tap(const LineLanes<N>& l, const Dirs<N>& d, const VecF<N>& t, const VecF<N>& pf_off) noexcept {
  using F = VecF<N>;
  const F zero = splat<N>(0.0F);
  const F gx = l.ox + t * d.dx;
  const F gy = l.oy + t * d.dy;
  const F ixf = to_float<N>(to_int<N>(vmin(vmax(gx, zero), l.lim)));
  const F iyf = to_float<N>(to_int<N>(vmin(vmax(gy, zero), l.lim)));
  const F idxf = iyf * l.nf + ixf;  // exact: below 2^24
  alignas(32) std::int32_t idx[N];
  const VecI<N> iv = to_int<N>(idxf);
  std::memcpy(idx, &iv, sizeof idx);
  if constexpr (kPrefetch) {
    alignas(32) std::int32_t pf[N];
    const VecI<N> pv = to_int<N>(vmin(vmax(idxf + pf_off, zero), l.last));
    std::memcpy(pf, &pv, sizeof pf);
    for (std::uint32_t k = 0; k < N; ++k) {
      __builtin_prefetch(l.cells + pf[k], 0, 2);
      __builtin_prefetch(l.cells + pf[k] + l.n, 0, 2);
    }
  }
  const Corners<N> c = gather<N>(l.cells, idx, l.n);
  const F ab = c.b - c.a;
  const F ac = c.c - c.a;
  const F e = (c.d - c.c) - ab;
  // Newton step.
  F fx = gx - ixf;
  F fy = gy - iyf;
  F h = c.a + ab * fx + (ac + e * fx) * fy;
  const F slope = vmin(d.dz - ((ab + e * fy) * d.dx + (ac + e * fx) * d.dy), splat<N>(0.25F) * d.dz);
  const F inv_slope = splat<N>(1.0F) / slope;
  const F t1 = t - ((l.oz + t * d.dz) - h) * inv_slope;
  // Chord step.
  fx = (l.ox + t1 * d.dx) - ixf;
  fy = (l.oy + t1 * d.dy) - iyf;
  h = c.a + ab * fx + (ac + e * fx) * fy;
  const F step = ((l.oz + t1 * d.dz) - h) * inv_slope;
  const F t2 = t1 - step;
  fx = (l.ox + t2 * d.dx) - ixf;
  fy = (l.oy + t2 * d.dy) - iyf;
  const F half = splat<N>(0.5F);
  const F reach = splat<N>(0.5F + kEdgeCells);
  const VecI<N> ok = (vabs<N>(step) < splat<N>(kTolM)) & (vabs<N>(fx - half) <= reach) &
                     (vabs<N>(fy - half) <= reach) & (t2 > zero);
  // Converged lanes are within kEdgeCells of the cell: no clamp needed for the shade.
  const F top = c.sa + (c.sb - c.sa) * fx;
  const F bot = c.sc + (c.sd - c.sc) * fx;
  return Tap<N>{t2, top + (bot - top) * fy, ok};
}

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

// ---------------------------------------------------------------- one line of a strip

/** Sum of the four 16-bit fields of one 64-bit draw (Irwin-Hall: about normal, mean 131070). */
BSP_LANE std::int32_t irwin_hall_sum(std::uint64_t x) noexcept {
  constexpr std::uint64_t kLow16 = 0x0000FFFF0000FFFFULL;
  const std::uint64_t pairs = (x & kLow16) + ((x >> 16U) & kLow16);
  return static_cast<std::int32_t>((pairs & 0xFFFFFFFFULL) + (pairs >> 32U));
}

/** What the lines of a frame share. */
struct LineJob {
  const Frame* f;
  const RenderOptions* opt;
  Rng* noise;  ///< null: no read noise
  std::uint8_t* out;
};

/**
 * Pass 1: pixels [p0, p1) of a line from their guesses, one tap each; lists the pixels that did not
 * converge. @p kPrefetch: also prefetch the cells of the line kPrefetchLines on, @p pf_off cells further.
 */
template <std::uint32_t N, bool kPrefetch>
BSP_LANE std::uint32_t first_taps(const LineLanes<N>& l, const float* prev1, const float* prev2, std::uint32_t p0,
                                  std::uint32_t p1, float pf_off) noexcept {
  using F = VecF<N>;
  const F zero = splat<N>(0.0F);
  const F off = splat<N>(pf_off);
  constexpr std::uint32_t kAll = (1U << N) - 1U;
  std::uint32_t n_list = 0;
  for (std::uint32_t p = p0; p < p1; p += N) {
    const Dirs<N> d = dirs<N>(l, splat<N>(static_cast<float>(p)) + iota<N>());
    F t1;
    F t2;
    std::memcpy(&t1, prev1 + p, sizeof t1);
    std::memcpy(&t2, prev2 + p, sizeof t2);
    // Linear extrapolation from the two lines before; the line before alone, or the datum plane, where missing.
    F t = ((t1 > zero) & (t2 > zero)) ? (t1 + t1) - t2 : t1;
    if (lane_bits<N>(t1 > zero) != kAll) {
      t = t1 > zero ? t : l.oz / -d.dz;
    }
    t = vmax(t, zero);  // a ray looking up gets any finite guess: its tap fails
    const Tap<N> r = tap<N, kPrefetch>(l, d, t, off);
    std::memcpy(g_t + p, &r.t, sizeof r.t);
    std::memcpy(g_shade + p, &r.shade, sizeof r.shade);
    const std::uint32_t ok = lane_bits<N>(r.ok);
    if (ok != kAll) {
      for (std::uint32_t k = 0; k < N; ++k) {
        g_list[n_list] = p + k;
        n_list += ((ok >> k) & 1U) ^ 1U;
      }
    }
  }
  while (n_list > 0U && g_list[n_list - 1U] >= p1) {
    --n_list;  // lanes past the line's end
  }
  return n_list;
}

/** Pass 2: one more tap for the @p n_list listed pixels, N at a time; returns the count still unsettled. */
template <std::uint32_t N>
BSP_LANE std::uint32_t second_taps(const LineLanes<N>& l, std::uint32_t n_list) noexcept {
  using F = VecF<N>;
  const F zero = splat<N>(0.0F);
  std::uint32_t n_left = 0;
  for (std::uint32_t k = 0; k < n_list; k += N) {
    std::uint32_t ps[N];
    F pf{};
    F t{};
    for (std::uint32_t j = 0; j < N; ++j) {
      ps[j] = g_list[std::min(k + j, n_list - 1U)];  // a partial group repeats its last pixel
      pf[j] = static_cast<float>(ps[j]);
      t[j] = g_t[ps[j]];
    }
    const Tap<N> r = tap<N, false>(l, dirs<N>(l, pf), vmax(t, zero), zero);
    for (std::uint32_t j = 0; j < N && k + j < n_list; ++j) {
      g_t[ps[j]] = r.t[j];
      g_shade[ps[j]] = r.shade[j];
      g_list[n_left] = ps[j];
      n_left += r.ok[j] != 0 ? 0U : 1U;
    }
  }
  return n_left;
}

/** Pass 4: DN = exposure * radiance + read noise, clamped, for pixels [p0, p1) of line q; the hits become history. */
template <std::uint32_t N>
BSP_LANE void expose(const LineJob& job, std::uint32_t q, std::uint32_t p0, std::uint32_t p1, float* hist) noexcept {
  using F = VecF<N>;
  const Frame& f = *job.f;
  const RenderOptions& opt = *job.opt;
  const bool noisy = job.noise != nullptr && opt.read_noise_dn > 0.0;
  if (noisy) {
    Rng rng = *job.noise;  // a local copy: the state stays in registers
    for (std::uint32_t p = p0; p < p1; ++p) {
      g_noise[p] = irwin_hall_sum(rng.next());
    }
    *job.noise = rng;
  }
  constexpr double kMean = 2.0 * 65535.0;
  constexpr double kInvSigma = 1.7320508075688772 / 65536.0;  // sigma of the sum: 65536 / sqrt(3)
  const F gain = splat<N>(static_cast<float>(opt.exposure_dn / 65535.0));
  const F noise_gain = splat<N>(noisy ? static_cast<float>(opt.read_noise_dn * kInvSigma) : 0.0F);
  const F mean = splat<N>(static_cast<float>(kMean));
  const F zero = splat<N>(0.0F);
  const F top = splat<N>(255.0F);
  const std::size_t base = std::size_t{q} * f.q_stride;
  for (std::uint32_t p = p0; p < p1; p += N) {
    F t;
    F shade;
    VecI<N> sum{};
    std::memcpy(&t, g_t + p, sizeof t);
    std::memcpy(&shade, g_shade + p, sizeof shade);
    if (noisy) {
      std::memcpy(&sum, g_noise + p, sizeof sum);
    }
    const F signal = t > zero ? gain * shade : zero;
    const F dn = signal + (to_float<N>(sum) - mean) * noise_gain + splat<N>(0.5F);
    alignas(32) std::uint8_t bytes[N];
    store_bytes<N>(to_int<N>(vmin(vmax(dn, zero), top)), bytes);
    const F depth = t > zero ? t : splat<N>(-1.0F);
    const std::uint32_t n = std::min(N, p1 - p);  // the line's last group may be partial
    if (f.p_stride == 1U && n == N) {
      std::memcpy(job.out + base + p, bytes, sizeof bytes);
      std::memcpy(hist + p, &t, sizeof t);
      if (opt.depth_m != nullptr) {
        std::memcpy(opt.depth_m + base + p, &depth, sizeof depth);
      }
    } else {
      for (std::uint32_t k = 0; k < n; ++k) {
        const std::size_t at = base + (p + k) * f.p_stride;
        job.out[at] = bytes[k];
        hist[p + k] = t[k];
        if (opt.depth_m != nullptr) {
          opt.depth_m[at] = depth[k];
        }
      }
    }
  }
}

/** @p x rounded to whole cells (|x| is far below 2^31). */
std::int32_t to_cells(double x) noexcept { return static_cast<std::int32_t>(x + (x < 0.0 ? -0.5 : 0.5)); }

/** Pixels [p0, p1) of line @p q. */
template <std::uint32_t N>
BSP_LANE void render_line(const LineJob& job, std::uint32_t q, std::uint32_t p0, std::uint32_t p1) noexcept {
  const Frame& f = *job.f;
  const LineLanes<N> l = line_lanes<N>(f, q);
  const float* prev1 = g_hist[(q + 1U) & 1U];
  float* prev2 = g_hist[q & 1U];  // becomes this line's hits
  // Lines kPrefetchLines on land about kPrefetchLines * t * dq further on: one cell offset per line.
  const float t_mid = prev1[(p0 + p1) / 2U];
  std::uint32_t n_list = 0;
  if (f.prefetch && t_mid > 0.0F) {
    const double dx = kPrefetchLines * static_cast<double>(t_mid) * f.dqx;
    const double dy = kPrefetchLines * static_cast<double>(t_mid) * f.dqy;
    const auto off = static_cast<float>(static_cast<double>(to_cells(dy)) * static_cast<double>(f.n) +
                                        static_cast<double>(to_cells(dx)));
    n_list = first_taps<N, true>(l, prev1, prev2, p0, p1, off);
  } else {
    n_list = first_taps<N, false>(l, prev1, prev2, p0, p1, 0.0F);
  }
  const std::uint32_t n_left = n_list > 0U ? second_taps<N>(l, n_list) : 0U;
  for (std::uint32_t k = 0; k < n_left; ++k) {
    // From the previous pixel's hit if it has one (the list is in order), else from the last tap.
    const std::uint32_t p = g_list[k];
    const float start = p > p0 && g_t[p - 1U] > 0.0F ? g_t[p - 1U] : g_t[p];
    robust(f, p, q, start);
  }
  expose<N>(job, q, p0, p1, prev2);
}

/** The whole frame, strip by strip, N lanes at a time. */
template <std::uint32_t N>
BSP_LANE void render_strips(const LineJob& job) noexcept {
  const Frame& f = *job.f;
  for (std::uint32_t p0 = 0; p0 < f.length; p0 += kStripPx) {
    const std::uint32_t p1 = std::min(p0 + kStripPx, f.length);
    for (std::uint32_t q = 0; q < f.lines; ++q) {
      render_line<N>(job, q, p0, p1);
    }
  }
}

void render_strips_4(const LineJob& job) noexcept { render_strips<4>(job); }

#if defined(__x86_64__) || defined(__i386__)
[[gnu::target("avx2")]] void render_strips_8(const LineJob& job) noexcept { render_strips<8>(job); }

std::uint32_t host_lanes() noexcept { return __builtin_cpu_supports("avx2") ? 8U : 4U; }
#else
void render_strips_8(const LineJob& job) noexcept { render_strips<8>(job); }

std::uint32_t host_lanes() noexcept { return 4U; }
#endif

/** Vertical 1-2-1 sums of one row of the blur (edges replicate), 0..1020. */
std::uint16_t g_blur_col[kMaxCameraPx];

/**
 * 3x3 binomial blur from @p src into @p dst (edges replicate), separably:
 * the vertical 1-2-1 sums of a row, then the horizontal 1-2-1 of those, /16 rounded.
 */
void blur3(const std::uint8_t* src, std::uint8_t* dst, std::uint32_t w, std::uint32_t h) noexcept {
  for (std::uint32_t y = 0; y < h; ++y) {
    const std::uint8_t* up = src + std::size_t{y > 0U ? y - 1U : 0U} * w;
    const std::uint8_t* mid = src + std::size_t{y} * w;
    const std::uint8_t* dn = src + std::size_t{y + 1U < h ? y + 1U : y} * w;
    for (std::uint32_t x = 0; x < w; ++x) {
      g_blur_col[x] = static_cast<std::uint16_t>(up[x] + 2U * mid[x] + dn[x]);
    }
    const std::uint16_t* c = g_blur_col;
    std::uint8_t* out = dst + std::size_t{y} * w;
    out[0] = static_cast<std::uint8_t>((3U * c[0] + c[1] + 8U) / 16U);
    for (std::uint32_t x = 1; x + 1U < w; ++x) {
      out[x] = static_cast<std::uint8_t>((c[x - 1U] + 2U * c[x] + c[x + 1U] + 8U) / 16U);
    }
    out[w - 1U] = static_cast<std::uint8_t>((c[w - 2U] + 3U * c[w - 1U] + 8U) / 16U);
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

#undef BSP_LANE

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
  const LineJob job{&f, &opt, noise, opt.blur ? g_blur_scratch : out};
  for (float* hist : g_hist) {
    std::fill_n(hist, kLineCap, -1.0F);
  }
  if (detail::render_lanes() == 8U) {
    render_strips_8(job);
  } else {
    render_strips_4(job);
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
