# Two commands matter (see README): `make demo` and `make test`. Both set up .venv first.
PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
OUT    ?= out

.PHONY: demo test docs bench screenshot clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

# demo runs: 0.5 s standing, 1 s ramp, 3 whole gait cycles
DEMO_S ?= 4.5
# the walk's standing and ramp (2.5 s) and 3 whole cycles at 0.5 Hz
WALK_S ?= 8.5

# simulate exits 1 when a run stops early, has no verdict or did not achieve its motion (it
# still writes its summary): the seed's ellipse does that (it falls over), and the comparison reports it; any
# other failure stops make. The 8:1 and 11.5:1 designs' verdicts side by side: gear_comparison.md
demo: $(STAMP)
	$(BIN)/fivebar-drake analyze --out $(OUT)/analysis
	$(BIN)/fivebar-drake simulate --gait trot --duration $(DEMO_S) --out $(OUT)/simulation/trot
	$(BIN)/fivebar-drake simulate --gait seed_ellipse --duration $(DEMO_S) \
		--out $(OUT)/simulation/seed_ellipse || [ $$? -eq 1 ]
	$(BIN)/fivebar-drake simulate --gait walk --duration $(WALK_S) --out $(OUT)/simulation/walk
	$(BIN)/fivebar-drake compare $(OUT)/simulation/trot $(OUT)/simulation/walk \
		--out $(OUT)/gait_comparison.md
	$(BIN)/fivebar-drake simulate --gait trot --duration $(DEMO_S) --set motor.gear_ratio=11.5 \
		--step-check --out $(OUT)/simulation/trot_gear_11.5
	$(BIN)/fivebar-drake compare $(OUT)/simulation/trot $(OUT)/simulation/trot_gear_11.5 \
		--out $(OUT)/gear_comparison.md
	$(BIN)/fivebar-drake sweep fivebar_drake/data/sweep_example.yaml --out $(OUT)/sweep
	$(BIN)/fivebar-drake envelope fivebar_drake/data/envelope_demo.yaml --out $(OUT)/envelope
	$(BIN)/fivebar-drake codesign fivebar_drake/data/codesign_demo.yaml --out $(OUT)/codesign
	$(BIN)/fivebar-drake optimal --out $(OUT)/optimal
	for m in ballscrew_leg scara parallel4; do \
		$(BIN)/fivebar-drake analyze --mechanism $$m --out $(OUT)/$$m || exit 1; done
	for r in doggo minitaur; do \
		$(BIN)/fivebar-drake analyze --config fivebar_drake/data/$$r.toml --gait trot \
			--out $(OUT)/robots/$$r || exit 1; \
		$(BIN)/fivebar-drake optimal --config fivebar_drake/data/$$r.toml \
			--out $(OUT)/robots/$$r/optimal || exit 1; done
	$(BIN)/fivebar-drake index $(OUT)

test: $(STAMP)
	$(BIN)/pytest

# the documentation site (MkDocs, Material theme) into $(OUT)/site: the reference pages
# regenerated from the code first, then built with warnings as errors
docs: $(STAMP)
	$(BIN)/python tools/gen_docs.py
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir $(OUT)/site

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_kinematics.py
	$(BIN)/python benchmarks/bench_simulation.py
	$(BIN)/python benchmarks/bench_sweep.py
	$(BIN)/python benchmarks/bench_envelope.py
	$(BIN)/python benchmarks/bench_optimal.py
	$(BIN)/python benchmarks/bench_codesign.py

# the pictures of a trot's and a jump's recordings in the README (docs/recording_trot.png,
# docs/recording_jump.png): the Rerun web viewer, served locally, in headless Chromium at the
# recording's default layout; and the demo's entry page (docs/index_page.png, after make demo),
# every picture on it loaded (Debian: apt-get install chromium)
screenshot: $(STAMP)
	$(BIN)/python tools/recording_screenshot.py --out docs
	$(BIN)/python tools/page_screenshot.py $(OUT)/index.html --out docs/index_page.png

clean:
	rm -rf $(VENV) $(OUT)
