# @file model.mk
# @brief `make model`: the TMR protocol's Promela model checked by SPIN (tools/model/, docs/MODEL.md);
#        `make model-full` adds the two-fault run (about 8 minutes, 10 GB).
#
# Installs spin on first use (tools/build/deps.sh model). Outputs under build/model/: each run's
# SPIN report, the trails of the mutants and findings, and each trail as a fault plan (plan.toml).

.PHONY: model model-full
model: ## TMR protocol model (SPIN): every property under one fault, the mutants and findings found (docs/MODEL.md)
	@tools/build/deps.sh model
	@python3 tools/model/test_trail_to_plan.py
	@tools/model/check.sh quick build/model

model-full: ## The TMR model's runs of `make model` and two faults at any releases (about 8 min, 10 GB)
	@tools/build/deps.sh model
	@python3 tools/model/test_trail_to_plan.py
	@tools/model/check.sh full build/model
