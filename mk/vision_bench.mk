# @file vision_bench.mk
# @brief OpenCV for the NCC benchmark only (tests/bench/ncc_bench.cpp); no flight code links it.
# Recursive (=) so pkg-config runs only when the benchmark is built; -isystem keeps
# OpenCV's own warnings out of our -Werror build.
EXTRA_LDLIBS_bench_ncc_bench = $(shell pkg-config --libs opencv4 2>/dev/null)
EXTRA_CXXFLAGS_tests/bench/ncc_bench.cpp = $(patsubst -I%,-isystem %,$(shell pkg-config --cflags opencv4 2>/dev/null))
