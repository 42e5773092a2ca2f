# @file Makefile
# @brief Top-level build: layer libraries, host images, tests, gates and benchmarks.
#
# Layers (dependencies point down only): bsp_tile64 <- kernel <- udn <- fdir <- trn.
# Each layer is a static library built from every .cpp under its folder.
# Programs: every folder tools/<name>/ holding a main.cpp is a host program;
# tools/common/ is a host library shared by them.
# Tests: tests/<dir>/*.cpp link into one GoogleTest binary per folder.
# Benchmarks: tests/bench/*.cpp, one Google Benchmark binary per file.
#
# Options: BUILD=release|debug, SAN=address,undefined (sanitizer build), FLIGHTS=all|subset (make test),
#          CXX=clang++ (the Clang build, beside the GCC one: objects under build/obj/clang-<variant>,
#          programs under build/clang/ for release, build/clang-<variant>/ otherwise).

.DEFAULT_GOAL := all
SHELL := /bin/bash
# Every core by default; a -j on the command line wins (make -j1 for one at a time).
MAKEFLAGS += -j$(shell nproc 2>/dev/null || echo 2)
# `make clean all` must not build while it cleans.
ifneq ($(filter clean,$(MAKECMDGOALS)),)
.NOTPARALLEL:
endif

BUILD ?= release
SAN ?=
# GCC unless the command line names another compiler (make CXX=clang++ ...).
CXX := g++
# The compiler family picks the flags one compiler lacks and the variant's folders.
CXX_FAMILY := $(if $(findstring clang,$(shell $(CXX) --version 2>/dev/null | head -n 1)),clang,gcc)

ifeq ($(filter $(BUILD),release debug cov),)
$(error BUILD must be release, debug or cov (got '$(BUILD)'))
endif

comma := ,
# A Clang variant is named clang-<variant> so that both compilers' builds live side by side.
VARIANT := $(if $(filter clang,$(CXX_FAMILY)),clang-)$(BUILD)$(if $(SAN),-san-$(subst $(comma),-,$(SAN)))
OBJ := build/obj/$(VARIANT)
# The default variant puts its programs straight under build/ (build/trn_mission), the Clang
# release build under build/clang/ (build/clang/trn_mission).
BIN := $(if $(filter release,$(VARIANT)),build,$(if $(filter clang-release,$(VARIANT)),build/clang,build/$(VARIANT)))
# Generated files hold the compiler's name and output (build_info.hpp, host_memory.ld): one folder per family.
GEN := build/gen$(if $(filter clang,$(CXX_FAMILY)),-clang)

LAYERS := bsp_tile64 kernel udn fdir trn
# Link order: highest layer first so the linker resolves downwards.
LINK_LAYERS := trn fdir udn kernel bsp_tile64

# ---------------------------------------------------------------- flags
WARN := -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion \
        -Wcast-align -Wnon-virtual-dtor -Woverloaded-virtual -Wformat=2 \
        -Wimplicit-fallthrough -Wundef -Wmissing-declarations -Werror
# -ffp-contract=off everywhere: a fused multiply-add would change results
# between builds and break bit-identical replay.
# EIGEN_RUNTIME_NO_MALLOC everywhere: Eigen's allocation check is an inline function whose body
# depends on the macro, so a macro set in some translation units only gives two definitions of one
# function, and the linker keeps either (the Clang sanitizer build kept the one without the check).
# The check does nothing until a test calls Eigen::internal::set_is_malloc_allowed(false).
COMMON := -std=c++20 -I. -isystem /usr/include/eigen3 -DEIGEN_RUNTIME_NO_MALLOC -ffp-contract=off -MMD -MP
OPT_release := -O2 -g
OPT_debug := -O0 -g3 -D_GLIBCXX_ASSERTIONS
OPT_cov := -O0 -g --coverage
OPT := $(OPT_$(BUILD))
# Sanitizer builds drop -Wmaybe-uninitialized only: GCC 12's flow analysis of
# instrumented code reports false positives inside libstdc++ (std::regex's
# std::function state). The normal build keeps it as an error.
# (Clang has no -Wmaybe-uninitialized; its -Wsometimes-uninitialized stays an error in every build.)
SANFLAGS := $(if $(SAN),-fsanitize=$(SAN) -fno-omit-frame-pointer -fno-sanitize-recover=all \
            $(if $(filter gcc,$(CXX_FAMILY)),-Wno-maybe-uninitialized))
HOST_CXXFLAGS := $(COMMON) $(WARN) $(OPT) $(SANFLAGS)
FLIGHT_CXXFLAGS := $(HOST_CXXFLAGS) -fno-exceptions -fno-rtti -fstack-usage
LDFLAGS := $(OPT) $(SANFLAGS) -Wl,-T,$(GEN)/host_memory.ld
LDLIBS := -lpthread

# ---------------------------------------------------------------- sources
src_of = $(shell find $(1) -name '*.cpp' -not -path '*/fixtures/*' 2>/dev/null | LC_ALL=C sort)
obj_of = $(patsubst %.cpp,$(OBJ)/%.o,$(1))

$(foreach l,$(LAYERS),$(eval SRC_$(l) := $(call src_of,$(l))))
$(foreach l,$(LAYERS),$(eval OBJ_$(l) := $(call obj_of,$(SRC_$(l)))))
$(foreach l,$(LAYERS),$(eval LIB_$(l) := $(if $(OBJ_$(l)),$(OBJ)/lib/lib$(l).a)))
FLIGHT_LIBS := $(foreach l,$(LINK_LAYERS),$(LIB_$(l)))

TOOLS_COMMON_SRC := $(call src_of,tools/common)
TOOLS_COMMON_LIB := $(if $(TOOLS_COMMON_SRC),$(OBJ)/lib/libtools.a)
PROGRAMS := $(sort $(patsubst tools/%/main.cpp,%,$(wildcard tools/*/main.cpp)))
$(foreach p,$(PROGRAMS),$(eval SRC_prog_$(p) := $(call src_of,tools/$(p))))

# A test binary per folder of tests/ that holds .cpp files directly:
# tests/trn/vision/*.cpp -> build/tests/trn_vision_tests.
TEST_DIRS := $(sort $(patsubst tests/%/,%,$(dir $(filter-out tests/support/% tests/bench/% tests/fixtures/% tests/fuzz/%,$(call src_of,tests)))))
test_name = $(subst /,_,$(1))
$(foreach d,$(TEST_DIRS),$(eval SRC_test_$(d) := $(wildcard tests/$(d)/*.cpp)))
TEST_SUPPORT_SRC := $(call src_of,tests/support)
TEST_BINS := $(foreach d,$(TEST_DIRS),$(BIN)/tests/$(call test_name,$(d))_tests)
BENCH_SRC := $(call src_of,tests/bench)
BENCH_BINS := $(patsubst tests/bench/%.cpp,$(BIN)/bench/%,$(BENCH_SRC))

ALL_SRC := $(foreach l,$(LAYERS),$(SRC_$(l))) $(TOOLS_COMMON_SRC) \
           $(foreach p,$(PROGRAMS),$(SRC_prog_$(p))) \
           $(foreach d,$(TEST_DIRS),$(SRC_test_$(d))) $(TEST_SUPPORT_SRC) $(BENCH_SRC)
FLIGHT_SRC := $(foreach l,$(LAYERS),$(SRC_$(l)))

# Per-file flags: flight layers get the flight flags, everything else host flags.
is_flight = $(filter $(addsuffix /%,$(LAYERS)),$(1))
flags_for = $(if $(call is_flight,$(1)),$(FLIGHT_CXXFLAGS),$(HOST_CXXFLAGS)) $(EXTRA_CXXFLAGS_$(1))

# ---------------------------------------------------------------- help
.PHONY: help
help: ## List the targets and options
	@echo "Targets:"
	@grep -hE '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed -E 's/^([a-z-]+):.*## (.*)/  \1\t\2/' | expand -t 14
	@echo "Options: BUILD=release|debug  SAN=address,undefined  CXX=clang++  FLIGHTS=all|subset (for test)  ARGS='...' (for run)"

# ---------------------------------------------------------------- deps
.PHONY: deps
deps: ## Install missing Debian packages (compiler, Eigen, GoogleTest, gates...)
	@tools/build/deps.sh base
	@mkdir -p $(dir $(DEPS_OK)) && touch $(DEPS_OK)

# Whatever is built (make, make all, a single program), the packages come first:
# every compile waits for this stamp, made once by installing what is missing
# (or stopping with one line that names make deps when that cannot be done).
DEPS_OK := build/gen/deps.ok
$(DEPS_OK): tools/build/deps.sh
	@tools/build/deps.sh base
	@mkdir -p $(@D) && touch $@

# ---------------------------------------------------------------- build rules
$(GEN)/host_memory.ld: linker/host_memory.ld.S linker/memory_config.h | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CXX) -E -P -x c -undef -I. $< -o $@

$(OBJ)/%.o: %.cpp | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CXX) $(call flags_for,$<) -c $< -o $@

$(foreach l,$(LAYERS),$(eval $(OBJ)/lib/lib$(l).a: $(OBJ_$(l)) ; @mkdir -p $$(@D) && rm -f $$@ && ar rcs $$@ $$^))
$(OBJ)/lib/libtools.a: $(call obj_of,$(TOOLS_COMMON_SRC))
	@mkdir -p $(@D) && rm -f $@ && ar rcs $@ $^
$(OBJ)/lib/libtestsupport.a: $(call obj_of,$(TEST_SUPPORT_SRC))
	@mkdir -p $(@D) && rm -f $@ && ar rcs $@ $^

# The heap guard must be linked as an object, not pulled from an archive,
# so that every program counts every allocation.
HEAP_GUARD_OBJ := $(OBJ)/bsp_tile64/emu/host/heap_guard.o
LINK_DEPS := $(HEAP_GUARD_OBJ) $(TOOLS_COMMON_LIB) $(FLIGHT_LIBS) $(GEN)/host_memory.ld
LINK_LIBS := $(HEAP_GUARD_OBJ) $(TOOLS_COMMON_LIB) $(FLIGHT_LIBS)

define program_rule
$(BIN)/$(1): $(call obj_of,$(SRC_prog_$(1))) $(LINK_DEPS)
	@mkdir -p $$(@D)
	$(CXX) $(LDFLAGS) $(call obj_of,$(SRC_prog_$(1))) $(LINK_LIBS) $(LDLIBS) $$(EXTRA_LDLIBS_$(1)) -o $$@
endef
$(foreach p,$(PROGRAMS),$(eval $(call program_rule,$(p))))

define test_rule
$(BIN)/tests/$(call test_name,$(1))_tests: $(call obj_of,$(SRC_test_$(1))) $(OBJ)/lib/libtestsupport.a $(LINK_DEPS)
	@mkdir -p $$(@D)
	$(CXX) $(LDFLAGS) $(call obj_of,$(SRC_test_$(1))) $(OBJ)/lib/libtestsupport.a $(LINK_LIBS) -lgmock -lgtest $(LDLIBS) -o $$@
endef
$(foreach d,$(TEST_DIRS),$(eval $(call test_rule,$(d))))

define bench_rule
$(BIN)/bench/$(1): $(OBJ)/tests/bench/$(1).o $(LINK_DEPS)
	@mkdir -p $$(@D)
	$(CXX) $(LDFLAGS) $(OBJ)/tests/bench/$(1).o $(LINK_LIBS) -lbenchmark $$(EXTRA_LDLIBS_bench_$(1)) $(LDLIBS) -o $$@
endef
$(foreach b,$(patsubst tests/bench/%.cpp,%,$(BENCH_SRC)),$(eval $(call bench_rule,$(b))))

# Tests find fixtures and the toolchain through a generated header.
# Both headers are replaced only when their text changes, so an edit of the Makefile that leaves
# them as they were recompiles no test.
$(GEN)/build_info.hpp: Makefile
	@mkdir -p $(@D)
	@printf '// Generated by the Makefile: where the tree and the toolchain are.\n#pragma once\nnamespace build_info {\ninline constexpr const char* kRepoRoot = "%s";\ninline constexpr const char* kHostCxx = "%s";\ninline constexpr const char* kLinkerScript = "%s";\n}\n' "$(CURDIR)" "$(CXX)" "$(CURDIR)/$(GEN)/host_memory.ld" > $@.tmp
	@cmp -s $@.tmp $@ && rm -f $@.tmp || mv -f $@.tmp $@
# The programs a test runs are those of its own variant (make cov runs the coverage build of
# trn_mission, not the release one): their folder is in a header per variant.
$(OBJ)/gen/build_dirs.hpp: Makefile
	@mkdir -p $(@D)
	@printf '// Generated by the Makefile: where this variant puts its programs.\n#pragma once\nnamespace build_info {\ninline constexpr const char* kBinDir = "%s";\n}\n' "$(CURDIR)/$(BIN)" > $@.tmp
	@cmp -s $@.tmp $@ && rm -f $@.tmp || mv -f $@.tmp $@
$(call obj_of,$(call src_of,tests)): $(GEN)/build_info.hpp $(GEN)/host_memory.ld $(OBJ)/gen/build_dirs.hpp
$(foreach f,$(call src_of,tests),$(eval EXTRA_CXXFLAGS_$(f) += -I$(GEN) -I$(OBJ)/gen))

-include $(patsubst %.cpp,$(OBJ)/%.d,$(ALL_SRC))
# Per-topic additions (extra link libraries of one program or benchmark, e.g.
# EXTRA_LDLIBS_bench_<name> := ...) live in mk/<topic>.mk, one file per topic.
-include $(wildcard mk/*.mk)

# ---------------------------------------------------------------- main targets
.PHONY: all run test lint size stack cov bench clean compdb control-sweep
all: $(foreach p,$(PROGRAMS),$(BIN)/$(p)) $(TEST_BINS) $(BIN)/compile_commands.json ## Build libraries, images and tests

ARGS ?=
RUN_ARGS ?= --demo-faults
run: deps ## Build and fly the default descent with the demonstration faults (RUN_ARGS='--help' for the options)
	@$(MAKE) --no-print-directory $(BIN)/trn_mission
	$(BIN)/trn_mission $(RUN_ARGS) $(ARGS)

test: deps ## Build and run every GoogleTest binary (FLIGHTS=subset: the flights of mk/flight_subset.mk only); ends with "tests: N passed, N failed, N skipped"
	@$(MAKE) --no-print-directory $(TEST_BINS) $(foreach p,$(PROGRAMS),$(BIN)/$(p))
	@# The frame budget holds for the GCC release objects (-fstack-usage); sanitizers and -O0 grow frames.
	$(if $(filter release,$(VARIANT)),@tools/build/stack_report.sh $(OBJ) $(FLIGHT_SRC))
	@TEST_FILTERS='$(TEST_FILTERS_ARG)' tools/build/run_tests.sh $(BIN)/test-results $(TEST_BINS)

compdb: $(BIN)/compile_commands.json ## Write the compilation database for tools and editors
$(BIN)/compile_commands.json: Makefile $(ALL_SRC)
	@mkdir -p $(@D)
	@{ echo "["; sep=""; \
	  $(foreach f,$(ALL_SRC),printf '%s{"directory":"%s","file":"%s","command":"%s %s -c %s"}\n' "$$sep" "$(CURDIR)" "$(f)" "$(CXX)" '$(call flags_for,$(f))' "$(f)"; sep=",";) \
	  echo "]"; } > $@
	@ln -sf $(CURDIR)/$@ compile_commands.json

lint: deps $(BIN)/flight_rules $(BIN)/compile_commands.json ## Static-analysis gates: flight rules, clang-tidy, cppcheck (fail on any finding)
	@tools/lint/lint.sh $(BIN) $(FLIGHT_SRC) $(TOOLS_COMMON_SRC) $(foreach p,$(PROGRAMS),$(SRC_prog_$(p)))

size: $(BIN)/trn_mission ## Memory budget: per region and per tile, used and free bytes
	@tools/build/size_report.sh $(BIN)/trn_mission

stack: all ## Stack budget: worst frame per flight function, checked against the budget
	@tools/build/stack_report.sh $(OBJ) $(FLIGHT_SRC)

control-sweep: deps ## Upsets of every emulated member of the declared control structs, both ends (SAN=address,undefined to fly it instrumented)
	@$(MAKE) --no-print-directory $(BIN)/tests/tools_trn_mission_tests $(BIN)/trn_mission
	CONTROL_SWEEP_FULL=1 $(BIN)/tests/tools_trn_mission_tests --gtest_filter='ControlUpsets.*'

cov: deps ## Coverage of the tests over the flight code (gcovr report under build/cov/)
	@# Counts add up across runs: a run starts from none, or it would count an earlier run's lines.
	@find build/obj/cov -name '*.gcda' -delete 2>/dev/null || true
	@$(MAKE) --no-print-directory BUILD=cov test
	@mkdir -p build/cov
	gcovr --root . --object-directory build/obj/cov $(addprefix --filter ,$(addsuffix /,$(LAYERS))) \
	  --exclude-unreachable-branches --print-summary --html-details build/cov/index.html --txt build/cov/coverage.txt
	@echo "coverage report: build/cov/index.html"
	@# The fault-management layer carries the mission's claims: its lines are held to 90 %.
	gcovr --root . --object-directory build/obj/cov --filter fdir/ --exclude-unreachable-branches \
	  --print-summary --fail-under-line 90 --txt build/cov/fdir.txt

bench: deps ## Benchmarks (Google Benchmark and whole-run figures) into build/bench/
	@tools/build/deps.sh base bench
	@$(MAKE) --no-print-directory $(BENCH_BINS) $(BIN)/trn_mission $(BIN)/trn_campaign
	@tools/build/run_bench.sh $(BIN) $(BENCH_BINS)

# ---------------------------------------------------------------- slurm
# A single-node Slurm cluster on this machine for campaign job arrays, all of it
# under build/slurm (docs/CAMPAIGNS.md). Not part of all or test.
SLURM_DIR := build/slurm
.PHONY: slurm-up slurm-down slurm-smoke
slurm-up: ## Start Slurm on this machine (munge, slurmctld, slurmd) under build/slurm
	@tools/build/deps.sh slurm
	@tools/slurm/slurm_up.sh $(SLURM_DIR)

slurm-down: ## Stop the Slurm daemons that slurm-up started
	@tools/slurm/slurm_down.sh $(SLURM_DIR)

slurm-smoke: ## Start Slurm if needed, run a 4-task job array and check its outputs
	@tools/build/deps.sh slurm
	@tools/slurm/smoke.sh $(SLURM_DIR)

# ---------------------------------------------------------------- campaigns
# Fault-injection campaigns (docs/CAMPAIGNS.md). CAMPAIGN names the spec, JOBS
# the runs in parallel (default: every core), TASKS the Slurm array's shards.
CAMPAIGN ?= campaigns/single_faults.toml
SLURM_CAMPAIGN ?= campaigns/slurm_small.toml
JOBS ?= $(shell nproc)
TASKS ?= 4
.PHONY: campaign campaign-slurm integrity docs-params docs-messages
campaign: deps ## Fly the campaign CAMPAIGN (default campaigns/single_faults.toml) on JOBS cores into out/campaign-<name>/
	@$(MAKE) --no-print-directory $(BIN)/trn_campaign $(BIN)/trn_mission
	$(BIN)/trn_campaign run $(CAMPAIGN) -j $(JOBS) --out out/campaign-$(basename $(notdir $(CAMPAIGN)))

docs-params: $(BIN)/trn_mission ## Write the FDIR parameter table (trn/tasks/fdir_params.hpp) into docs/FDIR.md, "Parameters"
	$(BIN)/trn_mission --fdir-params | tools/build/docs_params.py docs/FDIR.md

docs-messages: $(BIN)/trn_mission ## Write the table of message kinds (trn/tasks/messages.hpp) into docs/ARCHITECTURE.md, "Message kinds"
	$(BIN)/trn_mission --message-kinds | tools/build/docs_params.py docs/ARCHITECTURE.md "Message kinds" \
	  "kind | tag | channel | from | to | words | fields"

integrity: ## Fly 100 fault-free seeds (campaigns/integrity_100.toml) and report the filter's integrity into out/campaign-integrity_100/
	@$(MAKE) --no-print-directory campaign CAMPAIGN=campaigns/integrity_100.toml

campaign-slurm: deps ## Start Slurm here, fly SLURM_CAMPAIGN as a job array of TASKS shards into out/campaign-slurm/, merge
	@tools/build/deps.sh slurm
	@$(MAKE) --no-print-directory $(BIN)/trn_campaign $(BIN)/trn_mission
	tools/slurm/campaign.sh $(SLURM_DIR) $(BIN)/trn_campaign $(SLURM_CAMPAIGN) out/campaign-slurm $(TASKS)

clean: ## Remove build outputs
	@# Daemons running from build/slurm are stopped first: their pid files go with it.
	@if [ -d $(SLURM_DIR)/run ]; then tools/slurm/slurm_down.sh $(SLURM_DIR); fi
	rm -rf build compile_commands.json
