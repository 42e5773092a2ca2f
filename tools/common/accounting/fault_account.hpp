/**
 * @file fault_account.hpp
 * @brief The strict join of the flight's events to the injector's ground truth: per fault, who was
 *        accused of what and when, whether the service came back on its output stream; per run,
 *        wrong diagnoses, false alarms and healthy tiles disturbed (docs/FDIR.md, "The join").
 *
 * The host decides nothing for the flight code: a fault counts as detected
 * only through an event a flight layer wrote that accuses the fault's tile
 * with a class the fault's kind allows (tools/common/accounting/accusation.hpp), within that
 * kind's latency bound (kDetectBounds). Recovery is measured on the output
 * stream of the role the tile held (the filter's solutions, the I/O tile's
 * samples, the coordinator's frames, ...): a reboot alone recovers nothing,
 * and giving a mode up (TMR to simplex) is a degraded recovery, accepted.
 */
#pragma once

#include "bsp_tile64/faults/fault_injector.hpp"
#include "fdir/event_log.hpp"
#include "tools/common/accounting/accusation.hpp"
#include "tools/common/mission/run_folder.hpp"
#include "trn/tasks/tile_map.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace tools {

/** One kind's detection bound and why. */
struct DetectBound {
  bsp::FaultKind kind;
  double seconds;      ///< an accusation later than this after the injection is not its detection
  const char* reason;
};

/** The bound of every kind (docs/FDIR.md, "The join"). */
extern const std::array<DetectBound, static_cast<std::size_t>(bsp::FaultKind::kCount)> kDetectBounds;

/** The bound of @p kind, seconds. */
double detect_bound_s(bsp::FaultKind kind) noexcept;

/** Whether an accusation of class @p d detects a fault of kind @p kind (@p crashed: an upset modelled as a crash). */
bool class_detects(bsp::FaultKind kind, bool crashed, fdir::Diagnosis d) noexcept;

/** What the host saw of the roles' outputs during the flight (times in emulated seconds, ascending). */
struct ServiceStreams {
  std::span<const double> filter_outputs_s;  ///< each new navigation solution delivered
  std::span<const double> io_samples_s;      ///< each check at which the I/O role had forwarded more IMU samples
  std::span<const double> health_rounds_s;   ///< each check at which the tile-health supervisor had voted another self-test round
};

enum class Effect : std::uint8_t {
  kNotDelivered,  ///< never applied (armed and never hit, skipped, unsupported)
  kDetected,      ///< a right accusation within the bound
  kNotDetected,   ///< delivered, nothing accused it rightly (it may have had no effect: see kNoEffect)
  kNoEffect,      ///< delivered, not detected, and the run's delivered stream is the golden run's bit for bit
};
enum class DiagnosisVerdict : std::uint8_t { kNone, kRight, kWrong, kRightAndWrong };
enum class Recovery : std::uint8_t { kNone, kRecovered, kDegradedAccepted };

/** "not_delivered", "detected", "not_detected", "no_effect". */
const char* effect_name(Effect e) noexcept;
/** "none", "right", "wrong", "right_and_wrong". */
const char* verdict_name(DiagnosisVerdict v) noexcept;
/** "none", "recovered", "degraded_accepted". */
const char* recovery_name(Recovery r) noexcept;

/** What became of one injection. */
struct FaultOutcome {
  bool delivered = false;
  bool detected = false;
  bool recovered = false;           ///< service back (kRecovered)
  Effect effect = Effect::kNotDelivered;
  DiagnosisVerdict diagnosis = DiagnosisVerdict::kNone;
  Recovery recovery = Recovery::kNone;
  trn::tasks::Role role = trn::tasks::Role::kSpare;  ///< the role its tile held when it took effect
  double injected_s = 0.0;
  double detected_s = 0.0;          ///< time of the accusing event
  double recovered_s = 0.0;         ///< service back, or the mode given up
  double service_gap_s = -1.0;      ///< longest gap of the role's output stream from before the fault to its recovery (-1: no stream measured)
  fdir::EventId detected_by = fdir::EventId::kAssertFailed;
  bsp::TileId detector = bsp::kNoTile;
  const char* recovered_by = "";    ///< the event or stream that showed the service back
  std::uint32_t wrong_accusations = 0U;  ///< accusations of the wrong tile or class charged to it
  fdir::EventId first_wrong = fdir::EventId::kAssertFailed;
  bsp::TileId first_wrong_tile = bsp::kNoTile;
};

/** An accusation or an action the run's faults do not explain. */
struct Unexplained {
  std::size_t event = 0U;       ///< index into the events joined
  bsp::TileId tile = bsp::kNoTile;  ///< the tile accused or acted on
};

struct FaultAccount {
  std::uint64_t injected = 0U;       ///< delivered faults, planned and random
  std::uint64_t not_delivered = 0U;
  std::uint64_t detected = 0U;
  std::uint64_t recovered = 0U;
  std::uint64_t degraded_accepted = 0U;
  std::uint64_t misdiagnosed = 0U;   ///< faults with at least one wrong accusation charged to them
  double max_detection_latency_s = 0.0;
  double mean_detection_latency_s = 0.0;
  std::vector<FaultOutcome> outcomes;       ///< one per fault record, same order
  std::vector<Unexplained> false_alarms;    ///< accusations no delivered fault explains or is charged with
  std::vector<Unexplained> healthy_disturbed;  ///< resets, retirements, exclusions, outvotes, switches taken out, of tiles without a fault then
};

/**
 * Joins the flight events to the injector's records by the rules of docs/FDIR.md, "The join".
 * Each accusation credits at most one injection per tile it names.
 */
FaultAccount join_faults(std::span<const bsp::FaultRecord> records, std::span<const fdir::Event> events,
                         double clock_hz, const ServiceStreams& streams = {});

/** Marks every delivered fault not detected as without effect (the run's delivered stream is the golden run's). */
void mark_no_effect(FaultAccount& account);

/** Writes one line per injection (INJECT, or INFO if not delivered), then one per false alarm and healthy tile disturbed. */
void log_fault_outcomes(std::span<const bsp::FaultRecord> records, std::span<const fdir::Event> events,
                        const FaultAccount& account, double clock_hz, EventLog& log);

/** faults.csv's name of an upset's model ("flipped", "host_crash", "control_crash", "stack_crash"; "": none). */
const char* upset_model_name(bsp::UpsetModel m) noexcept;

/** faults.csv: one row per injection (docs/RUN_FOLDER.md or docs/FDIR.md lists the columns). */
std::string faults_csv(std::span<const bsp::FaultRecord> records, const FaultAccount& account);

}  // namespace tools
