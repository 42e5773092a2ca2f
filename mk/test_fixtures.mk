# @file test_fixtures.mk
# @brief Programs that tests run as their subject: a real GoogleTest program with a passing, a
#        failing, a skipped and a disabled test, for the test of tools/build/run_tests.sh.
#
# It lives under tests/fixtures/ (no suite of `make test` picks it up: run_tests.sh would count its
# failing test) and is built before the suite that runs it, in every variant.

GTEST_SAMPLE := $(BIN)/tests/fixtures/gtest_sample
$(GTEST_SAMPLE): $(OBJ)/tests/fixtures/gtest_sample/sample_suite.o $(GEN)/host_memory.ld
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $< -lgtest_main -lgtest $(LDLIBS) -o $@
$(BIN)/tests/tools_build_tests: | $(GTEST_SAMPLE)
-include $(OBJ)/tests/fixtures/gtest_sample/sample_suite.d
