# @file degradation.mk
# @brief The vision studies: `make degradation` (accuracy and matches per frame against the number of
#        vision tiles used; tools/study/degradation.sh, DEG_TILES and DEG_SEEDS choose the runs),
#        `make sizing` (the vision load against tiles on both chips; tools/study/sizing.py,
#        SIZING_ARGS) and `make bad-cores` (vision cores gone bad, spares on and off;
#        tools/study/bad_cores.py, BAD_CORES_ARGS).

.PHONY: degradation
degradation: deps $(BIN)/trn_mission ## Navigation against vision tiles used: 40..5 tiles x 5 seeds, table and plot in build/degradation/
	@tools/build/deps.sh study
	@tools/study/degradation.sh $(BIN) $(BIN)/degradation

.PHONY: sizing
sizing: deps $(BIN)/trn_mission ## Vision load against tiles on both chips: landmarks x rate x tiles x 3 seeds, tables and plot in build/sizing/
	@tools/study/sizing.py $(BIN) $(BIN)/sizing $(SIZING_ARGS)

.PHONY: bad-cores
bad-cores: deps $(BIN)/trn_mission ## Navigation as vision cores go bad (hung, or a lasting 2 px shift), spares on and off, both chips, into build/bad_cores/
	@tools/study/bad_cores.py $(BIN) $(BIN)/bad_cores $(BAD_CORES_ARGS)
