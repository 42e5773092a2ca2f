# @file unopt.mk
# @brief `make test` also runs the rendering suites with the target-specific flight code built at -O0.
#
# Code with per-function targets (the camera's AVX2 lanes) can be right only because
# the optimiser inlines it: a call that passes a 32-byte vector to a function built
# without AVX corrupts it, and -O2 hides that by inlining. So in the release build,
# the flight sources that set a function's target (UNOPT_SRC, found by grep) are
# compiled again with -O0 for -O2 and linked ahead of the libraries into a second
# binary of each suite that renders (UNOPT_TEST_DIRS), named <suite>_tests_O0.
# The rest of each binary is the release objects, so the extra cost is one compile,
# three links and the suites' run (about 40 s on 2 cores). These binaries join
# TEST_BINS, so `make test` builds and runs them and its one summary line counts them.
# BUILD=debug and BUILD=cov are unoptimised throughout and add nothing.

UNOPT_TARGET_RE := gnu::target|__attribute__ *[(][(] *target
UNOPT_SRC := $(shell grep -l -E '$(UNOPT_TARGET_RE)' $(FLIGHT_SRC) /dev/null)
UNOPT_TEST_DIRS := bsp_tile64/devices trn/vision_frame trn/pipeline
UNOPT_OBJ := $(patsubst %.cpp,$(OBJ)/O0/%.o,$(UNOPT_SRC))
UNOPT_TEST_BINS := $(if $(filter release,$(BUILD)),$(if $(UNOPT_SRC),\
  $(foreach d,$(UNOPT_TEST_DIRS),$(BIN)/tests/$(call test_name,$(d))_tests_O0)))

$(UNOPT_OBJ): $(OBJ)/O0/%.o: %.cpp | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CXX) $(patsubst -O2,-O0,$(call flags_for,$<)) -c $< -o $@

# The -O0 objects come before the libraries: the linker takes their definitions and
# never pulls the optimised copies of the same files out of the archives.
define unopt_test_rule
$(BIN)/tests/$(call test_name,$(1))_tests_O0: $(call obj_of,$(SRC_test_$(1))) $(UNOPT_OBJ) $(OBJ)/lib/libtestsupport.a $(LINK_DEPS)
	@mkdir -p $$(@D)
	$(CXX) $(LDFLAGS) $(call obj_of,$(SRC_test_$(1))) $(OBJ)/lib/libtestsupport.a $(UNOPT_OBJ) $(LINK_LIBS) -lgmock -lgtest $(LDLIBS) -o $$@
endef
$(if $(UNOPT_TEST_BINS),$(foreach d,$(UNOPT_TEST_DIRS),$(eval $(call unopt_test_rule,$(d)))))

TEST_BINS += $(UNOPT_TEST_BINS)
-include $(patsubst %.cpp,$(OBJ)/O0/%.d,$(UNOPT_SRC))
