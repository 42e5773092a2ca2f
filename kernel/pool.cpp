/**
 * @file pool.cpp
 * @brief Fixed-block pool.
 */
#include "kernel/pool.hpp"

#include "bsp_tile64/api/port.hpp"

namespace k {

PoolBase::PoolBase(std::byte* blocks, std::uint16_t* links, std::uint8_t* used, std::uint32_t block_bytes,
                   std::uint32_t capacity) noexcept
    : blocks_(blocks), links_(links), used_(used), block_bytes_(block_bytes), capacity_(capacity),
      free_(capacity), head_(0) {
  for (std::uint32_t i = 0; i < capacity; ++i) {
    links_[i] = (i + 1U < capacity) ? static_cast<std::uint16_t>(i + 1U) : kEnd;
    used_[i] = 0;
  }
}

Status PoolBase::allocate(void** out) noexcept {
  if (out == nullptr) {
    return Status::kBadArg;
  }
  const bool m = bsp::mask_irqs(true);
  Status s = Status::kOk;
  if (head_ == kEnd) {
    *out = nullptr;
    s = Status::kExhausted;
  } else {
    const std::uint16_t i = head_;
    head_ = links_[i];
    used_[i] = 1;
    --free_;
    *out = blocks_ + static_cast<std::size_t>(i) * block_bytes_;
  }
  (void)bsp::mask_irqs(m);
  return s;
}

Status PoolBase::release(void* block) noexcept {
  const auto* p = static_cast<const std::byte*>(block);
  if (p < blocks_ || p >= blocks_ + static_cast<std::size_t>(capacity_) * block_bytes_) {
    return Status::kBadArg;
  }
  const auto off = static_cast<std::size_t>(p - blocks_);
  if (off % block_bytes_ != 0U) {
    return Status::kBadArg;
  }
  const auto i = static_cast<std::uint16_t>(off / block_bytes_);
  const bool m = bsp::mask_irqs(true);
  Status s = Status::kOk;
  if (used_[i] == 0U) {
    s = Status::kBadArg;  // double release
  } else {
    used_[i] = 0;
    links_[i] = head_;
    head_ = i;
    ++free_;
  }
  (void)bsp::mask_irqs(m);
  return s;
}

}  // namespace k
