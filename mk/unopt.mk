# @file unopt.mk
# @brief `make test` also runs the camera's tests with the target-specific flight code built at -O0.
#
# Code with per-function targets (the camera's AVX2 lanes) can be right only because
# the optimiser inlines it: a call that passes a 32-byte vector to a function built
# without AVX corrupts it, and -O2 hides that by inlining. So in the release builds,
# the flight sources that set a function's target (UNOPT_SRC, found by grep) are
# compiled again with -O0 for -O2 and linked ahead of the libraries into a second
# binary of the suites that call that code (UNOPT_TESTS), named <suite>_O0_tests.
# The camera's tests render through every lane width, line order and option of the
# renderer's public entry points, which is every call into that code; the suites that
# render frames on the way to something else (vision, pipeline) would repeat the same
# calls at a higher cost, and are left to the optimised build. The extra cost is one
# compile, one link and the camera suite's run (a few seconds). These binaries join
# TEST_BINS, so `make test` builds and runs them and its one summary line counts them.
# BUILD=debug and BUILD=cov are unoptimised throughout and add nothing.

UNOPT_TARGET_RE := gnu::target|__attribute__ *[(][(] *target
UNOPT_SRC := $(shell grep -l -E '$(UNOPT_TARGET_RE)' $(FLIGHT_SRC) /dev/null)
UNOPT_TESTS := tests/bsp_tile64/devices/camera_test.cpp
UNOPT_OBJ := $(patsubst %.cpp,$(OBJ)/O0/%.o,$(UNOPT_SRC))
UNOPT_TEST_BIN := $(BIN)/tests/bsp_tile64_camera_O0_tests
UNOPT_TEST_BINS := $(if $(filter release,$(BUILD)),$(if $(UNOPT_SRC),$(UNOPT_TEST_BIN)))

$(UNOPT_OBJ): $(OBJ)/O0/%.o: %.cpp | $(DEPS_OK)
	@mkdir -p $(@D)
	$(CXX) $(patsubst -O2,-O0,$(call flags_for,$<)) -c $< -o $@

# The -O0 objects come before the libraries: the linker takes their definitions and
# never pulls the optimised copies of the same files out of the archives.
$(UNOPT_TEST_BIN): $(call obj_of,$(UNOPT_TESTS)) $(UNOPT_OBJ) $(OBJ)/lib/libtestsupport.a $(LINK_DEPS)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $(call obj_of,$(UNOPT_TESTS)) $(OBJ)/lib/libtestsupport.a $(UNOPT_OBJ) $(LINK_LIBS) -lgmock -lgtest $(LDLIBS) -o $@

TEST_BINS += $(UNOPT_TEST_BINS)
-include $(patsubst %.cpp,$(OBJ)/O0/%.d,$(UNOPT_SRC))
