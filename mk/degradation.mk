# @file degradation.mk
# @brief `make degradation`: accuracy and matches per frame against the number of vision tiles used
#        (tools/study/degradation.sh; DEG_TILES and DEG_SEEDS choose the runs).

.PHONY: degradation
degradation: deps $(BIN)/trn_mission ## Navigation against vision tiles used: 40..5 tiles x 5 seeds, table and plot in build/degradation/
	@tools/build/deps.sh study
	@tools/study/degradation.sh $(BIN) $(BIN)/degradation
