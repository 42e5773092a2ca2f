# @file fuzz.mk
# @brief `make fuzz`: libFuzzer targets (tests/fuzz/*_fuzz.cpp) built with clang++ under
#        AddressSanitizer and UBSan into build/fuzz/, each run for FUZZ_SECONDS or FUZZ_RUNS.
#
# tests/fuzz/ is excluded from the GoogleTest binaries (Makefile TEST_DIRS filter):
# a fuzz source has its own entry point. The flight layers and tools/common are
# compiled once more with clang (coverage-instrumented, sanitized) into archives
# under build/fuzz/obj/; a target links only the members it uses. The host heap
# guard is left out: AddressSanitizer owns the allocator.
#
# Each run starts from the corpus in the repo (tests/fuzz/corpus/<name>/, read
# only) and the one that grows in build/fuzz/corpus/<name>/ (reused by later
# runs). A run fails on any crash, property violation (abort), leak (ASan leak
# detection is on by default), or input slower than FUZZ_TIMEOUT seconds.
#
#   make fuzz                       every target for FUZZ_SECONDS (default 60) each
#   make fuzz FUZZ_RUNS=10000000    10^7 executions in all, no target longer than FUZZ_SECONDS
#                                   (a slow target's unreached share goes to the next ones)
#   make fuzz FUZZ_TARGETS=ft_packet_fuzz   only those targets
# The per-target executions and the total are printed and written to
# build/fuzz/summary.txt (tools/build/run_fuzz.sh).

FUZZ_SECONDS ?= 60
FUZZ_RUNS ?=
FUZZ_TIMEOUT ?= 10
FUZZ_MAX_LEN ?= 4096
FUZZ_CXX := clang++
FUZZ_BASE_FLAGS := -std=c++20 -I. -isystem /usr/include/eigen3 -DEIGEN_RUNTIME_NO_MALLOC -ffp-contract=off -O1 -g -fno-omit-frame-pointer \
                   -fno-sanitize-recover=all -MMD -MP
FUZZ_LIB_FLAGS := $(FUZZ_BASE_FLAGS) -fsanitize=fuzzer-no-link,address,undefined
FUZZ_LINK_FLAGS := -fsanitize=fuzzer,address,undefined
FUZZ_OBJ := build/fuzz/obj
FUZZ_NAMES := $(patsubst tests/fuzz/%.cpp,%,$(wildcard tests/fuzz/*_fuzz.cpp))
# Run order: the slowest first, so that with FUZZ_RUNS the fast ones make up what they miss.
FUZZ_ORDER := state_block_fuzz scenario_fuzz fault_plan_fuzz ft_packet_fuzz flight_msg_fuzz
FUZZ_TARGETS ?= $(filter $(FUZZ_NAMES),$(FUZZ_ORDER)) $(filter-out $(FUZZ_ORDER),$(FUZZ_NAMES))
FUZZ_BINS := $(addprefix build/fuzz/,$(FUZZ_TARGETS))

# The archives in link order (highest layer first), as the main build links them.
FUZZ_LIB_SRC_tools := $(TOOLS_COMMON_SRC)
$(foreach l,$(LAYERS),$(eval FUZZ_LIB_SRC_$(l) := $(filter-out bsp_tile64/emu/host/heap_guard.cpp,$(SRC_$(l)))))
FUZZ_LIB_NAMES := tools $(LINK_LAYERS)
FUZZ_LIBS := $(foreach l,$(FUZZ_LIB_NAMES),$(FUZZ_OBJ)/lib/lib$(l).a)

fuzz_flags_for = $(FUZZ_LIB_FLAGS) $(if $(call is_flight,$(1)),-fno-exceptions -fno-rtti)

$(FUZZ_OBJ)/%.o: %.cpp
	@mkdir -p $(@D)
	$(FUZZ_CXX) $(call fuzz_flags_for,$<) -c $< -o $@

$(foreach l,$(FUZZ_LIB_NAMES),$(eval $(FUZZ_OBJ)/lib/lib$(l).a: $(patsubst %.cpp,$(FUZZ_OBJ)/%.o,$(FUZZ_LIB_SRC_$(l))) ; \
  @mkdir -p $$(@D) && rm -f $$@ && ar rcs $$@ $$^))

define fuzz_rule
build/fuzz/$(1): $(FUZZ_OBJ)/tests/fuzz/$(1).o $(FUZZ_LIBS) $(GEN)/host_memory.ld
	@mkdir -p $$(@D)
	$(FUZZ_CXX) $(FUZZ_LINK_FLAGS) -Wl,-T,$(GEN)/host_memory.ld $(FUZZ_OBJ)/tests/fuzz/$(1).o $(FUZZ_LIBS) -lpthread -o $$@
endef
$(foreach f,$(FUZZ_NAMES),$(eval $(call fuzz_rule,$(f))))

-include $(shell find $(FUZZ_OBJ) -name '*.d' 2>/dev/null)

.PHONY: fuzz fuzz-build
fuzz-build: ## Build the libFuzzer targets (clang, ASan+UBSan) into build/fuzz/
	@tools/build/deps.sh fuzz
	@$(MAKE) --no-print-directory $(FUZZ_BINS)

fuzz: fuzz-build ## Run every fuzz target for FUZZ_SECONDS (default 60) each, or to FUZZ_RUNS executions in all; fails on a crash, hang or leak
	@tools/build/run_fuzz.sh "$(FUZZ_SECONDS)" "$(FUZZ_RUNS)" "$(FUZZ_TIMEOUT)" "$(FUZZ_MAX_LEN)" $(FUZZ_TARGETS)
