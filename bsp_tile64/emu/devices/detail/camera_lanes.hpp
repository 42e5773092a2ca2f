/**
 * @file camera_lanes.hpp
 * @brief The camera renderer's float-lane code: the tap, the passes over a line, a frame in strips.
 *
 * Not a header for anyone else: camera.cpp includes it twice, inside a namespace per lane
 * width, with BSP_LANE defined as always_inline plus that width's target (none for 4 lanes,
 * AVX2 for 8). So every function that takes or returns a 32-byte vector is compiled for a
 * target that has 32-byte registers, inlined or not: at -O0, where helpers stay calls, no call
 * passes a wide vector to code built without AVX (an ABI mismatch that corrupts the vector),
 * and Clang has no -Wpsabi to report. Hence, too: no std:: function here takes or returns a
 * vector (std::bit_cast is an out-of-line call in an unoptimised build and has no target);
 * lane_cast uses the builtin. It includes nothing and needs, from the file that includes it:
 * Cell, Frame, LineJob, the g_ line buffers, the k constants, robust() and to_cells().
 */
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

/** The bits of @p v as a @p To of the same size. */
template <class To, class From>
BSP_LANE To lane_cast(const From& v) noexcept {
  static_assert(sizeof(To) == sizeof(From), "a lane cast keeps every bit");
  return __builtin_bit_cast(To, v);
}

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
  return lane_cast<VecF<N>>(lane_cast<VecI<N>>(a) & 0x7FFFFFFF);
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
/** Two halves as one 8-lane vector (a template: only the 8-lane copy instantiates it, for its target). */
template <std::uint32_t N>
BSP_LANE VecF<N> join(V4f lo, V4f hi) noexcept {
  static_assert(N == 8U, "two halves make 8 lanes");
  return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
}

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
  return to_float<4>(lane_cast<V4i>(bits) & 0xFFFF);  // x86 is little-endian: the shade is the low half
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
  return static_cast<std::uint32_t>(_mm_movemask_ps(lane_cast<__m128>(m)));
}

/** Four lanes (0..255) as four bytes, lane 0 first. */
BSP_LANE std::uint32_t pack_bytes4(V4i v) noexcept {
  const __m128i w = _mm_packs_epi32(lane_cast<__m128i>(v), lane_cast<__m128i>(v));
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
    return Corners<N>{join<N>(lo.a, hi.a),   join<N>(lo.b, hi.b),   join<N>(lo.c, hi.c),
                      join<N>(lo.d, hi.d),   join<N>(lo.sa, hi.sa), join<N>(lo.sb, hi.sb),
                      join<N>(lo.sc, hi.sc), join<N>(lo.sd, hi.sd)};
  }
}

template <std::uint32_t N>
BSP_LANE std::uint32_t lane_bits(const VecI<N>& m) noexcept {
  if constexpr (N == 4U) {
    return lane_bits4(m);
  } else {
    const V8f f = lane_cast<V8f>(m);
    return lane_bits4(lane_cast<V4i>(low_half(f))) | (lane_bits4(lane_cast<V4i>(high_half(f))) << 4U);
  }
}

/** Lanes (0..255) as bytes into @p out, lane 0 first. */
template <std::uint32_t N>
BSP_LANE void store_bytes(const VecI<N>& v, std::uint8_t* out) noexcept {
  if constexpr (N == 4U) {
    const std::uint32_t b = pack_bytes4(v);
    std::memcpy(out, &b, sizeof b);
  } else {
    const V8f f = lane_cast<V8f>(v);
    const std::uint32_t lo = pack_bytes4(lane_cast<V4i>(low_half(f)));
    const std::uint32_t hi = pack_bytes4(lane_cast<V4i>(high_half(f)));
    std::memcpy(out, &lo, sizeof lo);
    std::memcpy(out + 4, &hi, sizeof hi);
  }
}

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

// ---------------------------------------------------------------- one line of a strip

/** Sum of the four 16-bit fields of one 64-bit draw (Irwin-Hall: about normal, mean 131070). */
BSP_LANE std::int32_t irwin_hall_sum(std::uint64_t x) noexcept {
  constexpr std::uint64_t kLow16 = 0x0000FFFF0000FFFFULL;
  const std::uint64_t pairs = (x & kLow16) + ((x >> 16U) & kLow16);
  return static_cast<std::int32_t>((pairs & 0xFFFFFFFFULL) + (pairs >> 32U));
}

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
    std::uint32_t ps[N]{};
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

