/**
 * @file gnuplot.cpp
 * @brief Finding gnuplot on the PATH, the PNG terminal line, and one bounded, detached run of a script.
 */
#include "tools/common/gnuplot.hpp"

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace tools {

namespace {

constexpr const char* kTerminalLine =
    "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) { set terminal pngcairo size %s noenhanced } "
    "else { set terminal png size %s noenhanced }\n";

std::string errno_text(int e) { return std::strerror(e); }

}  // namespace

std::string gnuplot_png_terminal(const char* size) {
  std::array<char, 256> buf{};
  (void)std::snprintf(buf.data(), buf.size(), kTerminalLine, size, size);
  return buf.data();
}

std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) {
    return {};
  }
  std::stringstream ss(path);
  for (std::string dir; std::getline(ss, dir, ':');) {
    std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
  }
  return {};
}

std::string run_gnuplot(const std::string& gnuplot, const std::string& folder, const std::string& script,
                        const std::vector<std::string>& args) {
  // The argument vector is built before the fork: the child may not allocate.
  std::vector<char*> argv;
  argv.reserve(args.size() + 3U);
  std::string name = "gnuplot";
  std::vector<std::string> owned(args);
  std::string script_arg = script;
  argv.push_back(name.data());
  for (std::string& a : owned) {
    argv.push_back(a.data());
  }
  argv.push_back(script_arg.data());
  argv.push_back(nullptr);

  const std::string log = folder + "/plots.log";
  const int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (log_fd < 0 || null_fd < 0) {
    std::string e = "cannot open " + (log_fd < 0 ? log : std::string("/dev/null")) + ": " + errno_text(errno);
    (void)(log_fd >= 0 && ::close(log_fd) == 0);
    (void)(null_fd >= 0 && ::close(null_fd) == 0);
    return e;
  }
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    if (::chdir(folder.c_str()) != 0 || ::dup2(null_fd, STDIN_FILENO) < 0 || ::dup2(log_fd, STDOUT_FILENO) < 0 ||
        ::dup2(log_fd, STDERR_FILENO) < 0) {
      ::_exit(126);
    }
    (void)::setsid();
    ::execv(gnuplot.c_str(), argv.data());
    ::_exit(127);
  }
  const int fork_errno = errno;
  (void)::close(log_fd);
  (void)::close(null_fd);
  if (pid < 0) {
    return "cannot start gnuplot: " + errno_text(fork_errno);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kGnuplotTimeoutS);
  int status = 0;
  for (;;) {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) {
      break;
    }
    if (w < 0 && errno != EINTR) {
      return "lost track of gnuplot: " + errno_text(errno);
    }
    if (std::chrono::steady_clock::now() > deadline) {
      (void)::kill(pid, SIGKILL);
      (void)::waitpid(pid, &status, 0);
      return "gnuplot " + script + " did not finish in " + std::to_string(kGnuplotTimeoutS) + " s and was stopped";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    return {};
  }
  return "gnuplot " + script + " failed (" +
         (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                            : "signal " + std::to_string(WTERMSIG(status))) +
         "; see plots.log)";
}

}  // namespace tools
