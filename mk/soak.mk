# @file soak.mk
# @brief `make soak`: the 10^6-message soak of the fault-tolerant UDN layer through udn_stress --ft on,
#        at bit error rates 1e-5, 1e-4 and 1e-3 per word with failed tiles, switches and links.
#
# Each run prints udn_stress's JSON object; the target fails if any run is not
# completed or reports lost, duplicated, misordered or corrupted deliveries, or
# a give-up event that says more than is true: "not delivered" of a message
# that arrived, or "delivered" (ACKs lost) of one that did not.
# SOAK_PACKETS scales the runs (default 10^6 messages each).

SOAK_PACKETS ?= 1000000
SOAK_FAULTS := --failed-tiles 8,9 --failed-switches 45 --failed-links 20E,30-38

.PHONY: soak
soak: $(BIN)/udn_stress ## Fault-tolerant UDN soak: SOAK_PACKETS messages at BER 1e-5..1e-3 with failures
	@set -e; for ber in 1e-5 1e-4 1e-3; do \
	  out=$$($(BIN)/udn_stress --ft on --packets $(SOAK_PACKETS) --ber $$ber --seed 1 --max-ms 20000 $(SOAK_FAULTS)); \
	  echo "$$out"; \
	  echo "$$out" | grep -q '"completed":true' || { echo "soak: ber $$ber did not complete"; exit 1; }; \
	  for k in lost duplicated misordered corrupted_delivered gave_up_not_delivered_arrived acks_lost_missing; do \
	    echo "$$out" | grep -q "\"$$k\":0[,}]" || { echo "soak: ber $$ber: $$k is not 0"; exit 1; }; \
	  done; \
	done
