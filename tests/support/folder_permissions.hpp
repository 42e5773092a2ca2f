/**
 * @file folder_permissions.hpp
 * @brief Test helper: folder permission bits that hold for root too, so a test of an unwritable folder
 *        runs (and can fail) whoever runs it, CI's root included.
 *
 * Root writes through permission bits because it holds CAP_DAC_OVERRIDE (and CAP_DAC_READ_SEARCH). On
 * Linux the effective capabilities are per thread: the guard clears those two from the calling thread's
 * effective set and puts them back when it ends (they stay in the permitted set, so a thread may raise
 * them again). For a user without them it changes nothing. The raw capset system call is used, not
 * libcap: it acts on the calling thread alone, which is what a test wants.
 */
#pragma once

#include <linux/capability.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdint>

namespace test_support {

class PermissionBitsHold {
 public:
  PermissionBitsHold() {
    __user_cap_header_struct hdr{_LINUX_CAPABILITY_VERSION_3, 0};
    if (::syscall(SYS_capget, &hdr, saved_) != 0) {
      return;
    }
    __user_cap_data_struct lowered[2] = {saved_[0], saved_[1]};
    const std::uint32_t drop = (1U << CAP_DAC_OVERRIDE) | (1U << CAP_DAC_READ_SEARCH);  // both below 32
    lowered[0].effective &= ~drop;
    active_ = ::syscall(SYS_capset, &hdr, lowered) == 0;
  }
  ~PermissionBitsHold() {
    if (active_) {
      __user_cap_header_struct hdr{_LINUX_CAPABILITY_VERSION_3, 0};
      (void)::syscall(SYS_capset, &hdr, saved_);
    }
  }
  PermissionBitsHold(const PermissionBitsHold&) = delete;
  PermissionBitsHold& operator=(const PermissionBitsHold&) = delete;
  PermissionBitsHold(PermissionBitsHold&&) = delete;
  PermissionBitsHold& operator=(PermissionBitsHold&&) = delete;

  /** The capabilities were read and lowered (false: the system calls failed, nothing changed). */
  [[nodiscard]] bool active() const { return active_; }

 private:
  __user_cap_data_struct saved_[2]{};
  bool active_ = false;
};

}  // namespace test_support
