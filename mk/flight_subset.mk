# @file flight_subset.mk
# @brief `make test FLIGHTS=subset`: every unit suite, and of the suites that fly the mission image
#        (whole descents, seconds of host time each), the flights named here.
#
# CI's sanitizer stage (.ci/run: Clang with AddressSanitizer and UndefinedBehaviorSanitizer) runs
# this: an instrumented flight costs three to five times the release one, and the release stage
# has flown every flight already. The subset is chosen so that every fault path of the flight
# software runs instrumented at least once: one flight per mechanism, the one that drives it
# furthest (a reset and a move to a spare rather than a reset alone), plus the host front ends'
# input parsing and the second host thread that renders frames ahead.
#
#   flight                                                  what it drives
#   SameInputsGiveTheSameTraceHash...                       packet ECC, a vision crash and hang, the
#                                                           frame-ahead host thread, the run folder
#   DemoPlanCountsComeFromFlightEvents                      the demonstration plan: every default mechanism
#   BadInputsExit2AndWriteNothing                           the scenario and fault-plan parsers' errors
#   ATraceDumpFolds...                                      the trace dump and trn_trace
#   ACrashedFilterResumesFromItsCheckpoint                  checkpoints in DDR, resume after a crash
#   AFilterHungFourTimesMovesToASpareWithItsState           watchdog resets, a role moved to a spare
#   EveryRoleIsRestartedAfterAHangOrACrash                  the supervisor's own watchdog, the coordinator
#   TmrOfTheFilterOutvotesExcludesAndReseedsFaultyReplicas  the vote, exclusion, re-seeding
#   ASwitchToTmrAndBackDeliversTheSimplexStream             the live switch both ways: the deepest task stacks
#   AHungVoterIsResetThenMovedAndNoOutputIsLost             the voter's failover from DDR
#   NoMajorityAgainAndAgainEscalatesToTheTrnSupervisor      the supervisor tree's escalation
#   IdleReplicasAreSwitchedOffAndWokenBeforeTheTerminalPhase  power policy, parking and waking tiles
#   AVisionTileWithWrongMatchesIsSuspectResetAndReplaced    result trust: suspect, reset, replace
#   WrongOrMissingCoarseBandsAreComputedAgain...            the coarse stage dealt in bands, recomputed
#   ACorruptedUpdateProductInTheFilterIsCorrected...        ABFT of the Kalman update
#   AnUpsetOrAWrongDigestOnEveryRoleIsOutvotedAndRecovered  self-tests, the scrubbed pattern, upsets
#   UpsetsInTheFiltersSettingsAreFoundAndBuiltAgain...      the settings CRC and rebuild
#   TheSimplexFiltersCorruptedStateIsRefused...             the state check and the way back
#   ATileWhoseSwitchFailedIsRetiredAndItsRoleMoves          neighbour probes, the fault map, detours
#   TheIoTilesSwitchIsNamedByTransits...                    transit probes, the cut-off watcher
#   ControlUpsets.EveryEmulatedMember...                    upsets of control structs' own state, flipped
#                                                           for real: the bounds the flight code keeps
#
# Of the campaign runner's suite: a campaign in parallel with its resume, replay and shards merged,
# a crashed and a hung image, shrinking, and the bad-input and script tests (no flight): the host
# code the sanitizers look at. The seed sweep and the stamp check fly the same code again.

SUBSET_FLIGHTS := SameInputsGiveTheSameTraceHashAndAFullRunFolderOnOneHostThreadOrTwo \
  DemoPlanCountsComeFromFlightEvents BadInputsExit2AndWriteNothing \
  ATraceDumpFoldsToTheSummarysHashAndTrnTraceNamesTheFirstDifference \
  ACrashedFilterResumesFromItsCheckpoint AFilterHungFourTimesMovesToASpareWithItsState \
  EveryRoleIsRestartedAfterAHangOrACrash TmrOfTheFilterOutvotesExcludesAndReseedsFaultyReplicas \
  ASwitchToTmrAndBackDeliversTheSimplexStream AHungVoterIsResetThenMovedAndNoOutputIsLost \
  NoMajorityAgainAndAgainEscalatesToTheTrnSupervisor IdleReplicasAreSwitchedOffAndWokenBeforeTheTerminalPhase \
  AVisionTileWithWrongMatchesIsSuspectResetAndReplaced \
  WrongOrMissingCoarseBandsAreComputedAgainAndTheOutputUnchanged \
  ACorruptedUpdateProductInTheFilterIsCorrectedAndTheOutputUnchanged \
  AnUpsetOrAWrongDigestOnEveryRoleIsOutvotedAndRecovered \
  UpsetsInTheFiltersSettingsAreFoundAndBuiltAgainWithoutARestart \
  TheSimplexFiltersCorruptedStateIsRefusedAndItGoesBackToItsCheckpoint \
  ATileWhoseSwitchFailedIsRetiredAndItsRoleMoves \
  TheIoTilesSwitchIsNamedByTransitsAndItsCutOffWatcherResetsNobody
SUBSET_CAMPAIGN := RunsInParallelResumesReplaysARunAndMergesItsShards ACrashedOrHungImageIsTheRunsOutcome \
  ShrinkFindsTheOneGuiltyFaultAmongMany BadInputIsRefusedWithExitStatusTwo TheRunsForAMarginArePrinted \
  TheSlurmScriptIsAnArrayOfShards

space := $(subst ,, )
subset_filter = $(subst $(space),:,$(addprefix $(1).,$(2)))
SUBSET_TEST_FILTERS := tools_trn_mission_tests=$(call subset_filter,TrnMissionBinary,$(SUBSET_FLIGHTS)):ControlUpsets.EveryEmulatedMemberOfTheDeclaredControlStructsSurvivesAnUpset \
  tools_trn_campaign_tests=$(call subset_filter,TrnCampaignBinary,$(SUBSET_CAMPAIGN))

FLIGHTS ?= all
ifeq ($(filter $(FLIGHTS),all subset),)
$(error FLIGHTS must be all or subset (got '$(FLIGHTS)'))
endif
TEST_FILTERS_ARG := $(if $(filter subset,$(FLIGHTS)),$(SUBSET_TEST_FILTERS))
