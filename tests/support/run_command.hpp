/**
 * @file run_command.hpp
 * @brief Test helper: runs a shell command and returns its exit status and everything it printed.
 */
#pragma once

#include <cstdio>
#include <string>
#include <utility>

#include <sys/wait.h>

namespace test_support {

/**
 * Runs @p cmd through the shell (add " 2>&1" to capture its errors too) and returns (exit status,
 * its standard output); the status is -1 if it could not be started or did not exit normally.
 */
inline std::pair<int, std::string> run_command(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr) {
    return {-1, out};
  }
  char buf[4096];
  for (std::size_t n = 0; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) {
    out.append(buf, n);
  }
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace test_support
