/**
 * @file control_upset_test.cpp
 * @brief Upsets of the emulated state in control data, field by field, in a flight: the image
 *        survives every one (the sanitizer build too) and the flight ends (issue 54 item 6); the
 *        roles' records and the state moved into tile RAM likewise (issue 55 item 4).
 *
 * Each control struct with a declared layout (bsp::ControlLayout) names the members an upset
 * flips for real; the flight code must then bound what it indexes or loops by with them. The
 * sweep aims one upset at the first byte of every emulated member (in nested structs and arrays
 * of them, of the first element), a live bit each (a bool's bit 0), on the tiles that carve the
 * struct, spread over a short flight. `make control-sweep` flies the larger sweep: the first and
 * the last byte of every member, of the first and the last element, one flight per carve group.
 */
#include "build_dirs.hpp"
#include "build_info.hpp"
#include "bsp_tile64/api/memory.hpp"
#include "fdir/net_health.hpp"
#include "fdir/tile_health.hpp"
#include "kernel/detail/tcb.hpp"
#include "trn/tasks/vision/vision_worker.hpp"
#include "udn/endpoint.hpp"
#include "trn/tasks/filter/filter_task.hpp"
#include "trn/tasks/filter/filter_tmr.hpp"
#include "trn/tasks/io/io_task.hpp"
#include "trn/tasks/supervisors/supervisors.hpp"
#include "trn/tasks/vision/vision_coord.hpp"
#include "trn/tasks/vision/vision_worker.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

std::string image() { return std::string(build_info::kBinDir) + "/trn_mission"; }

int run(const std::string& cmd) {
  const int status = std::system((cmd + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/** One byte of emulated state and the bits of it that are live. */
struct Byte {
  std::size_t offset;
  std::uint8_t live;
};

/**
 * The bytes of @p l to upset, from @p base: the first byte of every emulated member (with
 * @p full, its last byte too), of the first element of a nested array (with @p full, the last too).
 */
void member_bytes(const bsp::ControlLayout& l, std::size_t base, bool full, std::vector<Byte>& out) {
  for (const bsp::ControlField& f : l.fields) {
    if (f.inner != nullptr) {
      const std::size_t n = f.bytes / f.inner->bytes;
      member_bytes(*f.inner, base + f.offset, full, out);
      if (full && n > 1U) {
        member_bytes(*f.inner, base + f.offset + (n - 1U) * f.inner->bytes, full, out);
      }
      continue;
    }
    if (f.live_bits == 0U) {
      continue;
    }
    out.push_back(Byte{base + f.offset, f.live_bits});
    if (full && f.bytes > 1U) {
      out.push_back(Byte{base + f.offset + f.bytes - 1U, f.live_bits});
    }
  }
}

struct Sweep {
  const char* carve;
  const char* role;
  std::uint32_t instances;  ///< instances of the role to spread the upsets over (0: the role has one)
  const bsp::ControlLayout* layout;
  std::uint32_t part = 0U;   ///< with parts > 1: the bytes i with i % parts == part only (a plan holds 256 faults)
  std::uint32_t parts = 1U;
};

/** Appends one seu per byte of @p s to @p plan, at times from @p t0_s to @p t1_s; returns how many. */
std::size_t add_upsets(const Sweep& s, bool full, double t0_s, double t1_s, std::ostringstream& plan) {
  std::vector<Byte> all;
  member_bytes(*s.layout, 0U, full, all);
  std::vector<Byte> bytes;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (i % s.parts == s.part) {
      bytes.push_back(all[i]);
    }
  }
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    // A live bit of the byte, another for each byte: the high bits of an index's low byte push it
    // off its array, a high byte's make it huge.
    std::uint32_t bit = static_cast<std::uint32_t>((i * 5U + 7U) % 8U);
    for (std::uint32_t k = 0; k < 8U && ((bytes[i].live >> bit) & 1U) == 0U; ++k) {
      bit = (bit + 1U) % 8U;
    }
    std::array<char, 256> line{};
    std::snprintf(line.data(), line.size(), "[[fault]]\nt_s = %.4f\nkind = \"seu\"\nrole = \"%s\"\n",
                  t0_s + (t1_s - t0_s) * static_cast<double>(i) / static_cast<double>(bytes.size()), s.role);
    plan << line.data();
    if (s.instances > 0U) {
      plan << "instance = " << (i % s.instances) << "\n";
    }
    plan << "carve = \"" << s.carve << "\"\noffset = " << bytes[i].offset << "\nbit = " << bit << "\n";
  }
  return bytes.size();
}

/** The rows of faults.csv whose last column (the upset's model) is @p model. */
std::size_t rows_with_model(const std::string& csv, const std::string& model) {
  std::size_t n = 0U;
  std::istringstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    n += line.size() > model.size() && line.compare(line.size() - model.size() - 1U, std::string::npos, "," + model) == 0
             ? 1U
             : 0U;
  }
  return n;
}

class ControlUpsets : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(image())) << image() << " is not built (make test builds it)";
    dir_ = fs::temp_directory_path() / ("control_upset_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /** Flies @p sweeps for @p duration_s; expects the image to exit normally, every delivered upset flipped. */
  void fly(const std::vector<Sweep>& sweeps, bool full, double duration_s, const std::string& name) {
    std::ostringstream plan;
    plan << "name = \"" << name << "\"\n";
    std::size_t planned = 0U;
    for (const Sweep& s : sweeps) {
      planned += add_upsets(s, full, 0.3, duration_s - 0.2, plan);
    }
    ASSERT_LE(planned, 256U) << "one plan holds 256 faults";
    const fs::path plan_path = dir_ / (name + ".toml");
    std::ofstream(plan_path) << plan.str();
    const fs::path out = dir_ / name;
    const std::string cmd = image() + " --world-cache " + std::string(build_info::kBinDir) +
                            "/test-world-cache --quiet --no-plots --duration " + std::to_string(duration_s) +
                            " --faults " + plan_path.string() + " --out " + out.string();
    ASSERT_EQ(run(cmd), 0) << "the image did not survive the upsets: " << cmd;
    const nlohmann::json s = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_DOUBLE_EQ(s["emulated_s"].get<double>(), duration_s) << "the flight ended";
    const std::string csv = read_text(out / "faults.csv");
    const std::size_t flipped = rows_with_model(csv, "flipped");
    // A tile that restarts (a check that found a corrupt value asks for it) has no such carve for
    // a moment: the upsets planned then are not delivered. Most are.
    EXPECT_GE(flipped * 4U, planned * 3U) << planned << " planned\n" << csv;
    EXPECT_EQ(rows_with_model(csv, "host_crash"), 0U) << "only emulated bits were aimed at";
    EXPECT_EQ(rows_with_model(csv, "control_crash"), 0U) << "every carve swept has a layout";
    std::printf("%s: %zu upsets planned, %zu flipped\n", name.c_str(), planned, flipped);
  }

  fs::path dir_;
};

const Sweep kTileHealth{fdir::kTileHealthCarve, "trn_supervisor", 0U, &fdir::tile_health_state_layout()};
const Sweep kNetHealth{fdir::kNetHealthCarve, "trn_supervisor", 0U, &fdir::net_health_state_layout()};
const Sweep kVisionWorker{trn::tasks::kVisionWorkerCarve, "vision", 40U, &trn::tasks::vision_worker_state_layout()};
const Sweep kVisionCoord{trn::tasks::kVisionCoordCarve, "vision_coordinator", 0U, &trn::tasks::vision_coord_state_layout()};
const Sweep kEndpointVision{udn::kEndpointCarve, "vision", 40U, &udn::endpoint_state_layout()};
const Sweep kEndpointSupervisor{udn::kEndpointCarve, "trn_supervisor", 0U, &udn::endpoint_state_layout()};
const Sweep kKernelVision{"kernel state", "vision", 40U, &k::detail::kKernelStateLayout};
const Sweep kKernelSupervisor{"kernel state", "trn_supervisor", 0U, &k::detail::kKernelStateLayout};

namespace tt = trn::tasks;
const Sweep kSupNodeTrn{tt::kSupNodeCarve, "trn_supervisor", 0U, &tt::sup_node_state_layout()};
const Sweep kSupTrn{tt::kSupTrnCarve, "trn_supervisor", 0U, &tt::sup_trn_state_layout()};
const Sweep kSupFilter{tt::kSupFilterCarve, "filter_supervisor", 0U, &tt::sup_filter_state_layout()};
const Sweep kSupNodeVision{tt::kSupNodeCarve, "vision_supervisor", 0U, &tt::sup_node_state_layout()};
const Sweep kReplica{tt::kReplicaCarve, "filter_replica", 3U, &tt::replica_state_layout()};
const Sweep kFilterTask{tt::kFilterTaskCarve, "filter", 0U, &tt::filter_task_layout()};
const Sweep kFilterOutput{tt::kFilterOutputRecord.name, "filter", 0U, tt::kFilterOutputRecord.layout};
const Sweep kFilterStats{tt::kFilterTaskStatsRecord.name, "filter", 0U, tt::kFilterTaskStatsRecord.layout};
const Sweep kCoordStats{tt::kVisionCoordStatsRecord.name, "vision_coordinator", 0U, tt::kVisionCoordStatsRecord.layout};
const Sweep kWorkerStats{tt::kVisionWorkerStatsRecord.name, "vision", 40U, tt::kVisionWorkerStatsRecord.layout};
const Sweep kIoStats{tt::kIoTaskStatsRecord.name, "io", 0U, tt::kIoTaskStatsRecord.layout};
const Sweep kIoState{tt::kIoStateCarve, "io", 0U, &tt::io_state_layout()};
const Sweep kSupStats{tt::kSupervisorStatsRecord.name, "trn_supervisor", 0U, tt::kSupervisorStatsRecord.layout};

// Issue 54 item 6: an upset of any emulated member of the converted control structs is made for
// real, the image survives it (no out-of-bounds index, no undefined behaviour under the
// sanitizers) and the flight ends. With CONTROL_SWEEP_FULL set (make control-sweep), the larger
// sweep: both ends of every member and of every nested array, one longer flight per carve.
TEST_F(ControlUpsets, EveryEmulatedMemberOfTheDeclaredControlStructsSurvivesAnUpset) {
  if (std::getenv("CONTROL_SWEEP_FULL") != nullptr) {
    fly({kTileHealth}, true, 6.0, "tile_health");
    fly({kNetHealth, kVisionWorker}, true, 6.0, "net_health_vision");
    fly({kVisionCoord}, true, 6.0, "vision_coord");
  } else {
    fly({kTileHealth, kNetHealth, kVisionWorker}, false, 3.0, "members");
    fly({kVisionCoord}, false, 4.0, "vision_coord");
  }
}

// The messaging endpoint (every tile's) and the kernel state: an upset of any of their emulated
// members is flipped for real and the flight code bounds every index, count and length it takes
// from them (udn::FtRepair, k::TraceKind::kKernelStateBad). With CONTROL_SWEEP_FULL, both ends of
// every member, on the supervisor's tile as well as the vision tiles.
TEST_F(ControlUpsets, EveryEmulatedMemberOfTheEndpointAndTheKernelSurvivesAnUpset) {
  if (std::getenv("CONTROL_SWEEP_FULL") != nullptr) {
    for (std::uint32_t part = 0; part < 2U; ++part) {
      Sweep vision = kEndpointVision;
      Sweep supervisor = kEndpointSupervisor;
      vision.part = supervisor.part = part;
      vision.parts = supervisor.parts = 2U;
      fly({vision}, true, 6.0, "endpoint_vision_" + std::to_string(part));
      fly({supervisor}, true, 6.0, "endpoint_supervisor_" + std::to_string(part));
    }
    fly({kKernelVision, kKernelSupervisor}, true, 6.0, "kernel");
  } else {
    fly({kEndpointVision, kKernelSupervisor}, false, 2.0, "endpoint_kernel");
  }
}

// Issue 55 item 4: the roles' records and the supervisors', replicas', filter's and I/O task's
// state, now in tile RAM with declared layouts, are flipped for real and the image survives every
// upset of them. A plan aims at a role by name: the TRN and the vision supervisor's nodes (the same
// NodeState as the filter supervisor's) and the filter supervisor's own state (sup_filter) are swept.
TEST_F(ControlUpsets, EveryEmulatedMemberOfTheRecordsAndStateMovedIntoTileRamSurvivesAnUpset) {
  if (std::getenv("CONTROL_SWEEP_FULL") != nullptr) {
    fly({kSupNodeTrn, kSupTrn, kReplica, kSupFilter, kSupNodeVision}, true, 6.0, "supervisors_replicas");
    fly({kFilterTask, kIoState}, true, 6.0, "filter_io");
    fly({kFilterStats, kFilterOutput, kCoordStats, kWorkerStats, kIoStats, kSupStats}, true, 6.0, "records");
  } else {
    fly({kSupNodeTrn, kSupTrn, kReplica, kSupFilter, kSupNodeVision, kFilterStats, kCoordStats, kWorkerStats,
         kIoStats, kSupStats},
        false, 2.0, "records_state");
    fly({kFilterTask, kFilterOutput, kIoState}, false, 2.0, "filter_io");
  }
}

}  // namespace
