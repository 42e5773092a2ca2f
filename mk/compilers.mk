# @file compilers.mk
# @brief `make compilers-agree`: the mission image built by GCC and by Clang flies the same seeds to
#        the same trace hashes (docs/RELIABILITY.md, "Same bits from either compiler").
#
# Builds build/trn_mission and build/trn_trace with GCC and build/clang/trn_mission with Clang
# (each in its own variant folders, whatever CXX this make was called with), then flies
# AGREE_SEEDS for AGREE_SECONDS emulated seconds each, and the first seed once more with a fault
# plan, with both images (tools/build/compilers_agree.sh). A difference fails the target and
# prints the first differing event (trn_trace diff); the dumps stay in build/compilers-agree/.

AGREE_SEEDS ?= 1 2 3
AGREE_SECONDS ?= 5

.PHONY: compilers-agree
compilers-agree: deps ## GCC and Clang images fly AGREE_SEEDS (default 1 2 3) for AGREE_SECONDS (5) to the same trace hashes
	@$(MAKE) --no-print-directory CXX=g++ BUILD=release SAN= build/trn_mission build/trn_trace
	@$(MAKE) --no-print-directory CXX=clang++ BUILD=release SAN= build/clang/trn_mission
	@tools/build/compilers_agree.sh build build/clang build/compilers-agree $(AGREE_SECONDS) $(AGREE_SEEDS)
