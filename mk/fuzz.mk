# @file fuzz.mk
# @brief `make fuzz`: libFuzzer targets (tests/fuzz/*_fuzz.cpp) built with clang++ under
#        AddressSanitizer and UBSan into build/fuzz/, each run for FUZZ_SECONDS.
#
# tests/fuzz/ is excluded from the GoogleTest binaries (Makefile TEST_DIRS filter):
# a fuzz source has its own entry point. Each target lists the flight sources it
# links in FUZZ_SRC_<name>, so a target never drags in unrelated layers.
# The corpus grows in build/fuzz/corpus/<name>/ and is reused by later runs.

FUZZ_SECONDS ?= 60
FUZZ_CXX := clang++
FUZZ_CXXFLAGS := -std=c++20 -I. -O1 -g -fno-omit-frame-pointer \
                 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
FUZZ_NAMES := $(patsubst tests/fuzz/%.cpp,%,$(wildcard tests/fuzz/*_fuzz.cpp))
FUZZ_BINS := $(addprefix build/fuzz/,$(FUZZ_NAMES))

FUZZ_SRC_ft_packet_fuzz := udn/ecc.cpp udn/crc32c.cpp udn/ft_packet.cpp

define fuzz_rule
build/fuzz/$(1): tests/fuzz/$(1).cpp $(FUZZ_SRC_$(1)) $(wildcard udn/*.hpp)
	@mkdir -p $$(@D)
	$(FUZZ_CXX) $(FUZZ_CXXFLAGS) tests/fuzz/$(1).cpp $(FUZZ_SRC_$(1)) -o $$@
endef
$(foreach f,$(FUZZ_NAMES),$(eval $(call fuzz_rule,$(f))))

.PHONY: fuzz
fuzz: ## Build the libFuzzer targets with clang (ASan+UBSan) and run each for FUZZ_SECONDS (default 60)
	@tools/build/deps.sh fuzz
	@$(MAKE) --no-print-directory $(FUZZ_BINS)
	@set -e; for f in $(FUZZ_NAMES); do \
	  mkdir -p build/fuzz/corpus/$$f; \
	  echo "=== fuzz $$f for $(FUZZ_SECONDS) s (log: build/fuzz/$$f.log)"; \
	  if ! build/fuzz/$$f -max_total_time=$(FUZZ_SECONDS) -max_len=1024 -print_final_stats=1 \
	      -artifact_prefix=build/fuzz/ build/fuzz/corpus/$$f > build/fuzz/$$f.log 2>&1; then \
	    tail -n 80 build/fuzz/$$f.log; echo "fuzz: $$f FAILED"; exit 1; \
	  fi; \
	  tail -n 15 build/fuzz/$$f.log; \
	done
