/**
 * @file state_block_fuzz.cpp
 * @brief libFuzzer target for the filter's state block restore (trn::filter::read_state_block).
 *
 * Three input modes, chosen by the first byte:
 *  - raw: the rest of the input is the block, of whatever size;
 *  - patched: a valid block of a filter run for a few steps (the input chooses
 *    how many, and the times), then byte patches from the input; the CRC is
 *    recomputed unless the mode says not to, so the content checks are reached;
 *  - overlay: the input's bytes laid over a valid block from a chosen offset,
 *    the CRC recomputed.
 * Properties: a refused block leaves the target state exactly as it was; an
 * accepted block's state is within the documented ranges (flags 0/1, finite
 * numbers, unit quaternion, a valid history) and writing it back gives the
 * very same bytes (one state, one block).
 */
#include "tests/fuzz/fuzz_check.hpp"
#include "trn/filter/byte_io.hpp"
#include "trn/filter/state_block.hpp"

#include <cmath>
#include <cstring>

namespace {

using trn::filter::BlockError;
using trn::filter::FilterState;
using trn::filter::StateBlock;
using trn::filter::kStateBlockBytes;

// States of 18 KB are static: a fuzz iteration does not allocate them.
FilterState g_target;
FilterState g_before_probe;
StateBlock g_before;
StateBlock g_block;
StateBlock g_again;

/** A valid initialized state with @p steps history entries after its start. */
void make_state(FilterState& s, std::uint32_t steps, double t0_s, double dt_s) {
  trn::filter::clear_state(s);
  s.initialized = 1U;
  s.last_imu_ok = 1U;
  s.t_s = t0_s;
  s.x.p_m = trn::filter::Vec3(100.0, -20.0, 1500.0);
  s.x.v_mps = trn::filter::Vec3(1.0, 2.0, -3.0);
  s.p.setIdentity();
  trn::filter::history_start(s.hist, s.t_s, s.x);
  bsp::Work work{};
  for (std::uint32_t i = 0; i < steps; ++i) {
    s.t_s += dt_s;
    trn::filter::history_record(s.hist, s.t_s, dt_s, trn::filter::Vec3(0.01, 0.0, -0.02),
                                trn::filter::Quat::Identity(), s.x, work);
  }
  s.c.propagations = steps;
}

void fix_crc(StateBlock& b) {
  const std::uint32_t crc = trn::filter::crc32(b.data(), kStateBlockBytes - 4U);
  for (unsigned i = 0; i < 4U; ++i) {
    b[kStateBlockBytes - 4U + i] = static_cast<std::uint8_t>(crc >> (8U * i));
  }
}

void check(const std::uint8_t* block, std::uint32_t n) {
  // The target holds a valid state that a refused block must not change.
  fuzz::require(trn::filter::write_state_block(g_target, g_before) == BlockError::kOk, "write");
  const BlockError e = trn::filter::read_state_block(block, n, g_target);
  if (e != BlockError::kOk) {
    fuzz::require(trn::filter::write_state_block(g_target, g_again) == BlockError::kOk && g_again == g_before,
                  "a refused block leaves the state as it was");
    return;
  }
  const FilterState& s = g_target;
  fuzz::require(n == kStateBlockBytes, "accepted only at the block size");
  fuzz::require(s.initialized <= 1U && s.last_imu_ok <= 1U, "flags 0 or 1");
  fuzz::require(std::isfinite(s.t_s) && s.x.p_m.allFinite() && s.p.allFinite(), "finite");
  fuzz::require(std::abs(s.x.q_mb.squaredNorm() - 1.0) < 1e-9, "unit quaternion");
  fuzz::require(trn::filter::history_valid(s.hist, s.t_s, s.initialized != 0U), "valid history");
  fuzz::require(trn::filter::write_state_block(s, g_again) == BlockError::kOk, "write back");
  for (std::uint32_t i = 0; i < kStateBlockBytes; ++i) {
    if (g_again[i] != block[i]) {
      std::fprintf(stderr, "byte %u: read 0x%02x, written back 0x%02x\n", i, block[i], g_again[i]);
      fuzz::require(false, "one state, one block: same bytes back");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) {
    return 0;
  }
  fuzz::Reader r{data + 1, size - 1};
  const std::uint32_t mode = data[0] % 3U;
  make_state(g_target, r.take(1) % 40U, 0.5, 0.01);
  if (mode == 0U) {
    check(r.p, static_cast<std::uint32_t>(r.left));
    return 0;
  }
  const std::uint32_t steps = r.take(2) % (trn::filter::kHistoryLen + 40U);
  const double dt_s = 0.001 * static_cast<double>(1U + r.take(1));
  make_state(g_before_probe, steps, 10.0, dt_s);
  fuzz::require(trn::filter::write_state_block(g_before_probe, g_block) == BlockError::kOk, "write a valid block");
  const bool keep_crc = (data[0] & 0x80U) != 0U;
  if (mode == 1U) {
    const std::uint32_t patches = r.take(1) % 16U;
    for (std::uint32_t i = 0; i < patches && r.left >= 3U; ++i) {
      const std::uint32_t at = r.take(2) % kStateBlockBytes;
      g_block[at] = static_cast<std::uint8_t>(g_block[at] ^ r.take(1));
    }
  } else {
    const std::uint32_t at = r.take(2) % kStateBlockBytes;
    const std::size_t n = r.left < kStateBlockBytes - at ? r.left : kStateBlockBytes - at;
    std::memcpy(g_block.data() + at, r.p, n);
  }
  if (!keep_crc) {
    fix_crc(g_block);
  }
  check(g_block.data(), kStateBlockBytes);
  return 0;
}
