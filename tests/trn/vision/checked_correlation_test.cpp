/**
 * @file checked_correlation_test.cpp
 * @brief The checked correlation (correlator.hpp): the dot-product checksum is exact, every single
 *        corrupted dot product and a corrupted surface are found and computed again to the clean match
 *        bit for bit, and a persistent corruption rejects the match (FDIR-CC-01..04), by the spatial
 *        and by the transform dot products alike; a surface computed in bands and gathered is the
 *        same surface and match, and each band and the gatherer check what they hold (FDIR-CC-05..07).
 */
#include "trn/vision/correlator.hpp"
#include "trn/vision/integral.hpp"
#include "trn/vision/ncc.hpp"

#include "tests/trn/vision/synth.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace {

namespace tv = trn::vision;
using vision_test::Image;

constexpr std::int32_t kTmpl = 9;
constexpr std::int32_t kWin = 19;
constexpr std::int32_t kSurf = kWin - kTmpl + 1;  // 11 x 11 = 121 dot products
constexpr std::int32_t kTrueX = 4;                // the template's place in the window
constexpr std::int32_t kTrueY = 6;
constexpr std::uint32_t kTestChannelDot = 10U;
constexpr std::uint32_t kTestChannelSurface = 9U;

/**
 * The test's corruption: flips bit @c bit of publication number @c index on @c channel (counted
 * from the first of the correlation), or of every @c period -th publication from it when
 * @c period is not 0 (a corruption that comes back in every recomputation).
 */
struct Corruption {
  std::uint32_t channel = 0U;
  std::int64_t index = -1;
  std::int64_t period = 0;
  std::uint32_t bit = 0U;
  std::int64_t calls = 0;
  std::int64_t flips = 0;
};
Corruption g_corruption;

bool corrupt(std::uint32_t channel, void* data, std::size_t bytes) noexcept {
  Corruption& c = g_corruption;
  if (channel != c.channel) {
    return false;
  }
  const std::int64_t k = c.calls++;
  const bool hit = c.period == 0 ? k == c.index : (k >= c.index && (k - c.index) % c.period == 0);
  if (!hit || bytes * 8U <= c.bit) {
    return false;
  }
  auto* p = static_cast<std::uint8_t*>(data);
  p[c.bit / 8U] = static_cast<std::uint8_t>(p[c.bit / 8U] ^ (1U << (c.bit % 8U)));
  ++c.flips;
  return true;
}

/** A template cut from a textured window at (kTrueX, kTrueY), and the workspace. */
struct Scene {
  Image window = vision_test::smooth_texture(kWin, kWin, 1, 7U);
  Image tmpl{kTmpl, kTmpl};
  tv::CorrelatorWorkspace<32> ws{};
  tv::TransformWorkspace<32> tws{};

  Scene() {
    for (std::int32_t y = 0; y < kTmpl; ++y)
      for (std::int32_t x = 0; x < kTmpl; ++x) tmpl.at(x, y) = window.at(kTrueX + x, kTrueY + y);
  }
  tv::Status run(tv::MatchResult& out, const tv::CorrelationTaps& taps, bsp::Work& work,
                 tv::CorrelationMethod method = tv::CorrelationMethod::kSpatial) {
    tv::CorrelatorBuffers buf = ws.buffers();
    buf.transform = tws.buffers();
    return tv::correlate(tmpl.view(), window.view(), tv::QualityParams{}, buf, out, work, taps, method);
  }
};

tv::CorrelationTaps test_taps(std::uint32_t channel, std::int64_t index, std::uint32_t bit, std::int64_t period = 0) {
  g_corruption = Corruption{channel, index, period, bit, 0, 0};
  return tv::CorrelationTaps{&corrupt, kTestChannelDot, kTestChannelSurface};
}

constexpr tv::CorrelationMethod kMethods[] = {tv::CorrelationMethod::kSpatial, tv::CorrelationMethod::kTransform};

const char* name_of(tv::CorrelationMethod m) { return m == tv::CorrelationMethod::kSpatial ? "spatial" : "transform"; }

std::vector<float> copy_surface(const tv::MatchResult& r) {
  std::vector<float> v;
  for (std::int32_t y = 0; y < r.surface.height; ++y)
    for (std::int32_t x = 0; x < r.surface.width; ++x) v.push_back(r.surface.at(x, y));
  return v;
}

/** The match and surface of @p b are bit for bit those of @p a. */
void expect_same_match(const tv::MatchResult& a, const std::vector<float>& sa, const tv::MatchResult& b,
                       const char* what) {
  EXPECT_EQ(b.peak.ix, a.peak.ix) << what;
  EXPECT_EQ(b.peak.iy, a.peak.iy) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(b.x_px), std::bit_cast<std::uint64_t>(a.x_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(b.y_px), std::bit_cast<std::uint64_t>(a.y_px)) << what;
  EXPECT_EQ(std::bit_cast<std::uint32_t>(b.peak.score), std::bit_cast<std::uint32_t>(a.peak.score)) << what;
  EXPECT_EQ(std::bit_cast<std::uint32_t>(b.peak.second), std::bit_cast<std::uint32_t>(a.peak.second)) << what;
  EXPECT_EQ(b.reason(), a.reason()) << what;
  const std::vector<float> sb = copy_surface(b);
  ASSERT_EQ(sb.size(), sa.size());
  EXPECT_EQ(std::memcmp(sb.data(), sa.data(), sa.size() * sizeof(float)), 0) << what;
}

// FDIR-CC-01: the checksum identity is exact: sum over offsets of the dot products equals the
// template against the window's box sums, and every score computed alone equals the surface's bit
// for bit (random windows with flat patches, whose dot products enter by their exact value).
TEST(CheckedCorrelation, TheChecksumIsExactAndEveryScoreAloneEqualsTheSurface) {
  // Window widths give surfaces 1 to 40 wide: below, at and above the 16 offsets the surface
  // computes at once (a row's last pass moved left to end on its last offset), against each
  // score computed alone, offset by offset.
  for (const std::int32_t ww : {7, 12, 22, 23, 31, 46}) {
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
      Image win = vision_test::random_image(ww, 17, seed);
      for (std::int32_t y = 0; y < 8; ++y)
        for (std::int32_t x = 0; x < std::min(9, ww); ++x) win.at(x, y) = 77U;  // flat windows at the top left
      const Image t = vision_test::random_image(7, 5, seed + 100U);
      static tv::FixedIntegral<64, 32> ii;
      bsp::Work work;
      ASSERT_EQ(ii.build(win.view(), work), tv::Status::kOk);
      tv::TemplateStats stats;
      ASSERT_EQ(tv::template_stats(t.view(), stats, work), tv::Status::kOk);
      const std::int32_t sw = ww - 7 + 1;
      const std::int32_t sh = 17 - 5 + 1;
      std::vector<float> surf(static_cast<std::size_t>(sw * sh));
      std::int32_t flat = 0;
      tv::NccCheck check;
      ASSERT_EQ(tv::ncc_surface(t.view(), stats, win.view(), ii.ref(), tv::ImageF32{surf.data(), sw, sh, sw},
                                tv::ImageU8{}, flat, work, &check),
                tv::Status::kOk);
      EXPECT_GT(flat, 0) << "seed " << seed;
      std::int64_t naive = 0;
      for (std::int32_t oy = 0; oy < sh; ++oy)
        for (std::int32_t ox = 0; ox < sw; ++ox)
          for (std::int32_t y = 0; y < 5; ++y)
            for (std::int32_t x = 0; x < 7; ++x) naive += std::int64_t{t.at(x, y)} * win.at(ox + x, oy + y);
      EXPECT_EQ(check.dot_sum, naive) << "seed " << seed << " width " << ww;
      EXPECT_EQ(tv::ncc_dot_checksum(t.view(), ii.ref(), sw, sh, work), naive) << "seed " << seed;
      const tv::ConstImageF32 s{surf.data(), sw, sh, sw};
      EXPECT_EQ(tv::surface_digest(s, work), check.surface_sum);
      for (std::int32_t oy = 0; oy < sh; ++oy)
        for (std::int32_t ox = 0; ox < sw; ++ox)
          ASSERT_EQ(std::bit_cast<std::uint32_t>(tv::ncc_score_at(t.view(), stats, win.view(), ii.ref(), ox, oy, work)),
                    std::bit_cast<std::uint32_t>(s.at(ox, oy)))
              << "seed " << seed << " width " << ww << " offset " << ox << "," << oy;
    }
  }
}

// FDIR-CC-01: a clean correlation passes with no recomputation, and publishing changes nothing.
TEST(CheckedCorrelation, ACleanSurfacePassesWithNoRecomputation) {
  Scene sc;
  tv::MatchResult quiet;
  bsp::Work w0;
  ASSERT_EQ(sc.run(quiet, tv::CorrelationTaps{nullptr, 0U, 0U}, w0), tv::Status::kOk);
  const std::vector<float> s0 = copy_surface(quiet);
  tv::MatchResult r;
  bsp::Work w1;
  ASSERT_EQ(sc.run(r, test_taps(0U, -1, 0U), w1), tv::Status::kOk);
  EXPECT_TRUE(r.accepted());
  EXPECT_EQ(r.peak.ix, kTrueX);
  EXPECT_EQ(r.peak.iy, kTrueY);
  EXPECT_EQ(r.recomputes, 0U);
  EXPECT_FALSE(r.check_failed);
  EXPECT_EQ(r.first_check, tv::CorrelationCheck::kNone);
  EXPECT_EQ(g_corruption.flips, 0);
  expect_same_match(quiet, s0, r, "published");
  EXPECT_EQ(w1.int_macs, w0.int_macs);
}

// FDIR-CC-02: every single dot product of the surface, corrupted in turn (a low and a high bit), is
// found by the checksum; the surface computed again gives the clean match bit for bit. On the transform
// path the dot products are published before use just the same, so the same corruptions are caught.
TEST(CheckedCorrelation, EveryCorruptedDotProductIsFoundAndTheMatchIsTheCleanOne) {
  Scene sc;
  tv::MatchResult clean;
  bsp::Work w;
  ASSERT_EQ(sc.run(clean, tv::CorrelationTaps{nullptr, 0U, 0U}, w), tv::Status::kOk);
  ASSERT_TRUE(clean.accepted());
  const std::vector<float> s0 = copy_surface(clean);
  for (const tv::CorrelationMethod method : kMethods) {
    for (const std::uint32_t bit : {0U, 21U}) {
      for (std::int64_t k = 0; k < std::int64_t{kSurf} * kSurf; ++k) {
        tv::MatchResult r;
        ASSERT_EQ(sc.run(r, test_taps(kTestChannelDot, k, bit), w, method), tv::Status::kOk);
        ASSERT_EQ(g_corruption.flips, 1) << name_of(method) << " dot " << k;
        EXPECT_EQ(r.recomputes, 1U) << name_of(method) << " dot " << k << " bit " << bit;
        EXPECT_EQ(r.first_check, tv::CorrelationCheck::kDotSum) << name_of(method) << " dot " << k;
        EXPECT_FALSE(r.check_failed);
        expect_same_match(clean, s0, r, name_of(method));
      }
    }
  }
}

// FDIR-CC-03: a corrupted surface value (the peak lowered below a neighbour, or a far value raised
// above the peak) is found after the peak search and the surface computed again.
TEST(CheckedCorrelation, ACorruptedSurfaceValueIsFoundAndTheMatchIsTheCleanOne) {
  Scene sc;
  tv::MatchResult clean;
  bsp::Work w;
  ASSERT_EQ(sc.run(clean, tv::CorrelationTaps{nullptr, 0U, 0U}, w), tv::Status::kOk);
  const std::vector<float> s0 = copy_surface(clean);
  const auto at = [](std::int32_t x, std::int32_t y) { return static_cast<std::uint32_t>(y * kSurf + x); };
  // Bit 31: the sign (the peak becomes -score); bit 30 of a value below 1: it becomes huge.
  const std::uint32_t peak_sign = 32U * at(kTrueX, kTrueY) + 31U;
  const std::uint32_t far_exponent = 32U * at(0, 0) + 30U;
  for (const std::uint32_t bit : {peak_sign, far_exponent}) {
    tv::MatchResult r;
    ASSERT_EQ(sc.run(r, test_taps(kTestChannelSurface, 0, bit), w), tv::Status::kOk);
    ASSERT_EQ(g_corruption.flips, 1);
    EXPECT_EQ(r.recomputes, 1U) << "bit " << bit;
    EXPECT_EQ(r.first_check, tv::CorrelationCheck::kSurface);
    expect_same_match(clean, s0, r, "surface");
  }
}

// FDIR-CC-04: a corruption that comes back in every computation (the same dot product, the same
// surface value) is still wrong after kCorrelationMaxRecompute: the match is rejected, not sent.
TEST(CheckedCorrelation, APersistentCorruptionRejectsTheMatch) {
  Scene sc;
  bsp::Work w;
  const std::int64_t dots = std::int64_t{kSurf} * kSurf;
  for (const tv::CorrelationMethod method : kMethods) {
    for (const std::uint32_t channel : {kTestChannelDot, kTestChannelSurface}) {
      tv::MatchResult r;
      // Dot product 5 of each computation, or value 0 of each surface (one publication per computation).
      const bool dot = channel == kTestChannelDot;
      ASSERT_EQ(sc.run(r, test_taps(channel, dot ? 5 : 0, 27U, dot ? dots : 1), w, method), tv::Status::kOk);
      EXPECT_EQ(g_corruption.flips, std::int64_t{tv::kCorrelationMaxRecompute} + 1)
          << name_of(method) << " channel " << channel;
      EXPECT_TRUE(r.check_failed) << name_of(method);
      EXPECT_EQ(r.recomputes, tv::kCorrelationMaxRecompute);
      EXPECT_EQ(r.reason(), tv::Reject::kCheckFailed);
      EXPECT_FALSE(r.accepted());
    }
  }
}

// FDIR-CC-01: the transform path gives the spatial match, surface and recomputation count bit for bit,
// publishes as many dot products (one per non-flat offset), and needs its buffers.
TEST(CheckedCorrelation, TheTransformPathGivesTheSpatialMatchBitForBit) {
  Scene sc;
  tv::MatchResult spatial;
  bsp::Work ws;
  ASSERT_EQ(sc.run(spatial, test_taps(0U, -1, 0U), ws), tv::Status::kOk);
  const std::vector<float> s0 = copy_surface(spatial);
  g_corruption = Corruption{kTestChannelDot, -1, 0, 0U, 0, 0};
  tv::MatchResult transform;
  bsp::Work wt;
  ASSERT_EQ(sc.run(transform, tv::CorrelationTaps{&corrupt, kTestChannelDot, kTestChannelSurface}, wt,
                   tv::CorrelationMethod::kTransform),
            tv::Status::kOk);
  EXPECT_EQ(g_corruption.calls, std::int64_t{kSurf} * kSurf) << "one publication per dot product";
  EXPECT_TRUE(transform.accepted());
  EXPECT_EQ(transform.recomputes, 0U);
  EXPECT_EQ(transform.flat_windows, spatial.flat_windows);
  expect_same_match(spatial, s0, transform, "transform");
  EXPECT_NE(wt.int_macs, ws.int_macs) << "the transform path counts its own work";
  tv::MatchResult r;
  tv::CorrelatorBuffers no_planes = sc.ws.buffers();
  EXPECT_EQ(tv::correlate(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, no_planes, r, wt,
                          tv::CorrelationTaps{}, tv::CorrelationMethod::kTransform),
            tv::Status::kBadInput);
  static tv::TransformWorkspace<16> small;
  no_planes.transform = small.buffers();
  EXPECT_EQ(tv::correlate(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, no_planes, r, wt,
                          tv::CorrelationTaps{}, tv::CorrelationMethod::kTransform),
            tv::Status::kTooLarge);
}

// The checks' cost: the checksum (one integral lookup per template pixel), the digest (one add per
// position) and nine scores, against the surface's positions times template pixels.
TEST(CheckedCorrelation, TheChecksCostAFewPercentOfTheSurface) {
  Scene sc;
  bsp::Work plain;
  const std::int64_t n = std::int64_t{kTmpl} * kTmpl;
  const bsp::Work surface = tv::ncc_surface_work(kTmpl, kTmpl, kSurf, kSurf);
  tv::MatchResult r;
  ASSERT_EQ(sc.run(r, tv::CorrelationTaps{nullptr, 0U, 0U}, plain), tv::Status::kOk);
  // Minus the template's statistics (n) and the integral image (one square per window pixel).
  const std::uint64_t checks = plain.int_macs - surface.int_macs - static_cast<std::uint64_t>(n) -
                               static_cast<std::uint64_t>(kWin) * static_cast<std::uint64_t>(kWin);
  EXPECT_EQ(checks, static_cast<std::uint64_t>(n) + 9U * static_cast<std::uint64_t>(n + 3));
  EXPECT_LT(static_cast<double>(checks), 0.1 * static_cast<double>(surface.int_macs));
}


namespace band_test {

/** Band buffers for the Scene's surface (every row at most). */
struct BandSpace {
  std::vector<std::uint32_t> sum = std::vector<std::uint32_t>((kWin + 1) * (kWin + 1));
  std::vector<std::uint64_t> sum_sq = std::vector<std::uint64_t>((kWin + 1) * (kWin + 1));
  std::vector<float> surface = std::vector<float>(kSurf * kSurf);
  std::vector<std::uint8_t> flags = std::vector<std::uint8_t>(kSurf * kSurf);
  tv::BandBuffers buffers() {
    return tv::BandBuffers{sum.data(), sum_sq.data(), static_cast<std::int64_t>(sum.size()), surface.data(),
                           flags.data(), static_cast<std::int64_t>(surface.size())};
  }
};

/** The Scene's surface in bands of @p rows (the last shorter), gathered into @p out; the bands' digest, flats and recomputations. */
void gather_bands(Scene& sc, std::int32_t rows, std::vector<float>& out, std::uint64_t& digest, std::int32_t& flats,
                  std::uint32_t& recomputes, const tv::CorrelationTaps& taps) {
  out.assign(kSurf * kSurf, 0.0F);
  digest = 0U;
  flats = 0;
  recomputes = 0U;
  BandSpace b;
  bsp::Work w;
  for (std::int32_t row0 = 0; row0 < kSurf; row0 += rows) {
    const std::int32_t n = row0 + rows <= kSurf ? rows : kSurf - row0;
    tv::BandResult r;
    ASSERT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), row0, n, b.buffers(), r, w, taps), tv::Status::kOk);
    ASSERT_FALSE(r.check_failed) << "band at " << row0;
    EXPECT_EQ(r.width, kSurf);
    EXPECT_EQ(r.rows, n);
    std::memcpy(out.data() + static_cast<std::size_t>(row0) * kSurf, b.surface.data(), sizeof(float) * static_cast<std::size_t>(kSurf * n));
    digest += r.digest;
    flats += r.flat_windows;
    recomputes += r.recomputes;
  }
}

}  // namespace band_test

// FDIR-CC-05: a surface computed in bands (any band height) and gathered gives correlate()'s
// surface and match bit for bit; the bands' digests sum to the whole surface's.
TEST(CheckedCorrelation, BandsGatheredGiveTheWholeSurfaceAndMatchBitForBit) {
  Scene sc;
  tv::MatchResult clean;
  bsp::Work w;
  ASSERT_EQ(sc.run(clean, tv::CorrelationTaps{nullptr, 0U, 0U}, w), tv::Status::kOk);
  ASSERT_TRUE(clean.accepted());
  const std::vector<float> s0 = copy_surface(clean);
  for (const std::int32_t rows : {1, 2, 3, 5, kSurf}) {
    std::vector<float> surface;
    std::uint64_t digest = 0U;
    std::int32_t flats = 0;
    std::uint32_t recomputes = 0U;
    band_test::gather_bands(sc, rows, surface, digest, flats, recomputes, tv::CorrelationTaps{nullptr, 0U, 0U});
    EXPECT_EQ(std::memcmp(surface.data(), s0.data(), s0.size() * sizeof(float)), 0) << "bands of " << rows;
    const tv::ConstImageF32 gathered{surface.data(), kSurf, kSurf, kSurf};
    EXPECT_EQ(digest, tv::surface_digest(gathered, w));
    tv::MatchResult g;
    ASSERT_EQ(tv::correlate_gathered(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, gathered, digest, flats,
                                     recomputes, sc.ws.buffers(), g, w),
              tv::Status::kOk);
    EXPECT_FALSE(g.check_failed);
    EXPECT_EQ(g.flat_windows, clean.flat_windows);
    expect_same_match(clean, s0, g, "gathered");
  }
}

// FDIR-CC-06: a band checks itself as a surface does: a corrupted dot product or surface value
// is computed again to the clean band; a persistent one says the band failed.
TEST(CheckedCorrelation, ABandFindsItsOwnCorruptionAndSaysWhenItStaysWrong) {
  Scene sc;
  band_test::BandSpace b;
  bsp::Work w;
  tv::BandResult clean;
  ASSERT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 3, 4, b.buffers(), clean, w,
                               tv::CorrelationTaps{nullptr, 0U, 0U}),
            tv::Status::kOk);
  const std::vector<float> s0(b.surface.begin(), b.surface.begin() + 4 * kSurf);
  for (const std::uint32_t channel : {kTestChannelDot, kTestChannelSurface}) {
    tv::BandResult r;
    ASSERT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 3, 4, b.buffers(), r, w,
                                 test_taps(channel, channel == kTestChannelDot ? 2 : 0, 30U)),
              tv::Status::kOk);
    ASSERT_EQ(g_corruption.flips, 1);
    EXPECT_EQ(r.recomputes, 1U) << "channel " << channel;
    EXPECT_EQ(r.first_check, channel == kTestChannelDot ? tv::CorrelationCheck::kDotSum : tv::CorrelationCheck::kSurface);
    EXPECT_FALSE(r.check_failed);
    EXPECT_EQ(r.digest, clean.digest);
    EXPECT_EQ(std::memcmp(b.surface.data(), s0.data(), s0.size() * sizeof(float)), 0);
    const bool dot = channel == kTestChannelDot;
    ASSERT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 3, 4, b.buffers(), r, w,
                                 test_taps(channel, dot ? 2 : 0, 30U, dot ? 4 * kSurf : 1)),
              tv::Status::kOk);
    EXPECT_TRUE(r.check_failed) << "channel " << channel;
    EXPECT_EQ(r.recomputes, tv::kCorrelationMaxRecompute);
  }
}

// FDIR-CC-07: the gatherer finds a value changed after its band was checked (the digests
// disagree) and a wrong score at the peak (the digests agree but the score computed again
// does not): either rejects the match.
TEST(CheckedCorrelation, TheGathererRejectsAChangedSurfaceAndAWrongPeak) {
  Scene sc;
  std::vector<float> surface;
  std::uint64_t digest = 0U;
  std::int32_t flats = 0;
  std::uint32_t recomputes = 0U;
  band_test::gather_bands(sc, 4, surface, digest, flats, recomputes, tv::CorrelationTaps{nullptr, 0U, 0U});
  bsp::Work w;
  const tv::ConstImageF32 gathered{surface.data(), kSurf, kSurf, kSurf};
  const std::size_t peak = static_cast<std::size_t>(kTrueY) * kSurf + kTrueX;
  const float was = surface[peak];
  surface[peak] = -was;  // changed on its way: the digest says so
  tv::MatchResult g;
  ASSERT_EQ(tv::correlate_gathered(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, gathered, digest, flats,
                                   recomputes, sc.ws.buffers(), g, w),
            tv::Status::kOk);
  EXPECT_TRUE(g.check_failed);
  EXPECT_EQ(g.first_check, tv::CorrelationCheck::kSurface);
  EXPECT_EQ(g.reason(), tv::Reject::kCheckFailed);
  // A neighbour of the peak wrong from the start (its band's digest includes it): found by the peak's scores again.
  surface[peak] = was;
  const float right = surface[peak + 1];
  surface[peak + 1] = right * 0.5F;
  const std::uint64_t wrong_digest = tv::surface_digest(gathered, w);
  ASSERT_EQ(tv::correlate_gathered(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, gathered, wrong_digest,
                                   flats, recomputes, sc.ws.buffers(), g, w),
            tv::Status::kOk);
  EXPECT_TRUE(g.check_failed);
  EXPECT_EQ(g.first_check, tv::CorrelationCheck::kPeakScore);
  EXPECT_FALSE(g.accepted());
}

TEST(CheckedCorrelation, BandArgumentsOutsideTheSurfaceOrBuffersAreRefused) {
  Scene sc;
  band_test::BandSpace b;
  bsp::Work w;
  tv::BandResult r;
  EXPECT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), -1, 2, b.buffers(), r, w), tv::Status::kBadInput);
  EXPECT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), kSurf - 1, 2, b.buffers(), r, w), tv::Status::kBadInput);
  EXPECT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 0, 0, b.buffers(), r, w), tv::Status::kBadInput);
  tv::BandBuffers small = b.buffers();
  small.surface_values = kSurf * 2;
  EXPECT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 0, 3, small, r, w), tv::Status::kTooLarge);
  small = b.buffers();
  small.integral_entries = 10;
  EXPECT_EQ(tv::correlate_band(sc.tmpl.view(), sc.window.view(), 0, 3, small, r, w), tv::Status::kTooLarge);
  EXPECT_EQ(tv::correlate_band(sc.window.view(), sc.tmpl.view(), 0, 1, b.buffers(), r, w), tv::Status::kBadInput);
  tv::MatchResult g;
  const tv::ConstImageF32 wrong{b.surface.data(), kSurf - 1, kSurf, kSurf};
  EXPECT_EQ(tv::correlate_gathered(sc.tmpl.view(), sc.window.view(), tv::QualityParams{}, wrong, 0U, 0, 0U,
                                   sc.ws.buffers(), g, w),
            tv::Status::kBadInput);
}

}  // namespace
