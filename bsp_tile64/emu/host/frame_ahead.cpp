/**
 * @file frame_ahead.cpp
 * @brief The next-frame render worker: one job slot, a mutex and a condition variable.
 */
#include "bsp_tile64/emu/host/frame_ahead.hpp"

#include <condition_variable>
#include <cstring>
#include <memory>
#include <mutex>
#include <pthread.h>

namespace bsp::frame_ahead {
namespace {

enum class Job : std::uint8_t { kNone, kQueued, kRendering, kDone };

struct Worker {
  std::mutex m;
  std::condition_variable cv;
  pthread_t thread{};
  bool started = false;  ///< thread is a running worker, to be joined
  std::unique_ptr<std::uint8_t[]> staging;
  std::size_t capacity = 0;
  bool quit = false;
  Job job = Job::kNone;
  // The request (written under m while no render is in progress).
  const CameraDevice* cam = nullptr;
  std::uint32_t seq = 0;
  double t_s = 0.0;
  Rng noise{0, StreamId::kSensor, kCameraStreamIndex};
  CameraError error = CameraError::kOk;
  Stats stats{0, 0};

  Worker() = default;
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;
  Worker(Worker&&) = delete;
  Worker& operator=(Worker&&) = delete;
  ~Worker() {  // at exit: a joinable thread must not be destroyed
    {
      const std::lock_guard<std::mutex> lock(m);
      quit = true;
      cv.notify_all();
    }
    if (started) {
      (void)pthread_join(thread, nullptr);
    }
  }
};

Worker& worker() {
  static Worker w;
  return w;
}

void* run(void* arg) {
  auto* w = static_cast<Worker*>(arg);
  std::unique_lock<std::mutex> lock(w->m);
  for (;;) {
    w->cv.wait(lock, [w] { return w->quit || w->job == Job::kQueued; });
    if (w->quit) {
      return nullptr;
    }
    w->job = Job::kRendering;
    const CameraDevice* cam = w->cam;
    const double t_s = w->t_s;
    Rng noise = w->noise;
    lock.unlock();
    // The render reads the camera's fixed settings, the truth and the shaded terrain, and writes
    // only the staging buffer and this thread's own line buffers.
    const CameraError e = cam->render_at(t_s, w->staging.get(), &noise);
    lock.lock();
    w->noise = noise;
    w->error = e;
    w->job = Job::kDone;
    w->cv.notify_all();
  }
}

/** Waits (holding @p lock) until no render is in progress. */
void settle(Worker& w, std::unique_lock<std::mutex>& lock) {
  w.cv.wait(lock, [&w] { return w.job != Job::kRendering; });
}

}  // namespace

bool start(std::size_t frame_bytes) {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  if (w.started && frame_bytes <= w.capacity) {
    return true;
  }
  lock.unlock();
  stop();
  lock.lock();
  w.staging = std::make_unique<std::uint8_t[]>(frame_bytes);
  w.capacity = frame_bytes;
  w.quit = false;
  w.job = Job::kNone;
  w.stats = Stats{0, 0};
  if (pthread_create(&w.thread, nullptr, &run, &w) != 0) {  // checked: no exception to catch here
    w.staging.reset();
    w.capacity = 0;
    return false;
  }
  w.started = true;
  return true;
}

void stop() noexcept {
  Worker& w = worker();
  {
    std::unique_lock<std::mutex> lock(w.m);
    if (!w.started) {
      return;
    }
    w.quit = true;
    w.cv.notify_all();
  }
  (void)pthread_join(w.thread, nullptr);
  std::unique_lock<std::mutex> lock(w.m);
  w.started = false;
  w.job = Job::kNone;
  w.cam = nullptr;
}

bool running() noexcept {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  return w.started && !w.quit;
}

void request(const CameraDevice& cam, std::uint32_t seq, double t_s, const Rng& noise) noexcept {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  if (!w.started || w.quit) {
    return;
  }
  settle(w, lock);
  const CameraConfig& c = cam.config();
  if (std::size_t{c.width_px} * c.height_px > w.capacity) {
    w.job = Job::kNone;
    return;
  }
  w.cam = &cam;
  w.seq = seq;
  w.t_s = t_s;
  w.noise = noise;
  w.job = Job::kQueued;
  w.cv.notify_all();
}

bool take(const CameraDevice& cam, std::uint32_t seq, double t_s, std::uint8_t* out, CameraError* error,
          Rng* noise_after) noexcept {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  if (!w.started || w.quit) {
    return false;
  }
  // Exact comparison on purpose: the worker's frame is the capture's only if its time is the same double.
  const bool match = w.job != Job::kNone && w.cam == &cam && w.seq == seq && w.t_s == t_s;
  if (!match || out == nullptr || error == nullptr || noise_after == nullptr) {
    settle(w, lock);
    w.job = Job::kNone;
    ++w.stats.missed;
    return false;
  }
  w.cv.wait(lock, [&w] { return w.job == Job::kDone; });
  const CameraConfig& c = cam.config();
  std::memcpy(out, w.staging.get(), std::size_t{c.width_px} * c.height_px);
  *error = w.error;
  *noise_after = w.noise;
  w.job = Job::kNone;
  ++w.stats.taken;
  return true;
}

void forget() noexcept {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  settle(w, lock);
  w.job = Job::kNone;
  w.cam = nullptr;
}

Stats stats() noexcept {
  Worker& w = worker();
  std::unique_lock<std::mutex> lock(w.m);
  return w.stats;
}

}  // namespace bsp::frame_ahead
