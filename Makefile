# Two commands matter (see README): `make demo` and `make test`. Both set up .venv first.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= out

.PHONY: demo test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/fivebar-drake analyze --out $(OUT)/analysis
	$(BIN)/fivebar-drake simulate --duration 3 --out $(OUT)/simulation

test: $(STAMP)
	$(BIN)/pytest

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_kinematics.py
	$(BIN)/python benchmarks/bench_simulation.py

clean:
	rm -rf $(VENV) $(OUT)
