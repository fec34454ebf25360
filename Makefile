# The two commands a newcomer needs: `make demo` and `make test`. Both set up everything.
SHELL := /bin/bash
.SHELLFLAGS := -o pipefail -c
VENV := .venv
PY := $(VENV)/bin/python
DEPS_STAMP := $(VENV)/.deps-installed
JG := $(VENV)/bin/jointgap
DEMO := demo-output
DEMO_RUN := --t-end 0.5 --rate 10000

.PHONY: install demo test test-rust test-python browser valgrind bench bench-peers lint clean

$(DEPS_STAMP): pyproject.toml
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install -q --disable-pip-version-check "maturin>=1.5,<2" \
		"numpy>=1.26" "scipy>=1.11" "pandas>=2.0" "matplotlib>=3.8" \
		"pyarrow>=14" "dask[distributed]>=2024.1" "tomlkit>=0.12" \
		"plotly>=6,<8" \
		"pytest>=8" "ruff>=0.5" "mypy>=1.10"
	touch $(DEPS_STAMP)

## install: create .venv, build the Rust engine in release mode, install jointgap
install: $(DEPS_STAMP)
	VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
		$(VENV)/bin/maturin develop --release --quiet

## demo: the founding slider-crank (docs/physics.md section 5): ideal and clearance runs,
## the damping calibration for r = 0.55, figures, contact statistics and summaries in
## demo-output/
demo: install
	rm -rf $(DEMO) && mkdir -p $(DEMO)
	$(JG) run examples/slider_crank_ideal.toml $(DEMO_RUN) --out $(DEMO)/ideal --plot \
		| tee $(DEMO)/ideal.txt
	$(JG) run examples/slider_crank_clearance.toml $(DEMO_RUN) --out $(DEMO)/clearance \
		--ideal examples/slider_crank_ideal.toml --plot --report $(DEMO)/report.html \
		| tee $(DEMO)/clearance.txt
	$(JG) calibrate examples/slider_crank_clearance.toml --restitution 0.55 --t-end 0.5 \
		--rate 1000 --write $(DEMO)/slider_crank_calibrated.toml \
		--table $(DEMO)/calibration.csv | tee $(DEMO)/calibration.txt
	$(JG) run $(DEMO)/slider_crank_calibrated.toml $(DEMO_RUN) --out $(DEMO)/calibrated \
		--ideal examples/slider_crank_ideal.toml --plot | tee $(DEMO)/calibrated.txt
	@echo "demo-output/: report.html (open it in a browser), ideal/, clearance/ and calibrated/" \
		"(results, figures, contact statistics), calibration.txt and calibration.csv, the" \
		"printed summaries *.txt"

## test: Rust tests of the core, then pytest
test: install test-rust test-python

test-rust:
	cargo test --release -p jointgap-core

test-python: install browser
	JOINTGAP_REQUIRE_BROWSER=1 $(VENV)/bin/python -m pytest -q tests

## browser: Debian's chromium, for the browser tests of the HTML report (when missing)
browser:
	@command -v chromium >/dev/null 2>&1 || { echo "installing chromium (report tests)"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
		apt-get install -y -qq --no-install-recommends chromium >/dev/null; }

## valgrind: Debian's valgrind, for counting a run's instructions (when missing)
valgrind:
	@command -v valgrind >/dev/null 2>&1 || { echo "installing valgrind (instruction counts)"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
		apt-get install -y -qq --no-install-recommends valgrind >/dev/null; }

## bench: speed and accuracy figures (benchmarks/output/)
bench: install valgrind
	$(PY) benchmarks/instructions.py
	$(PY) benchmarks/compiled.py
	$(PY) benchmarks/study_throughput.py
	$(PY) benchmarks/jacobian.py
	cargo run --release -p jointgap-core --example bench_ideal
	cargo run --release -p jointgap-bench-diffsol
	$(PY) benchmarks/scaling.py
	$(PY) benchmarks/run.py
	$(PY) benchmarks/spatial.py
	$(PY) benchmarks/wear_convergence.py

# Exudyn goes into its own venv, never into .venv or the package's dependencies.
PEER_VENV := benchmarks/peers/.venv
PEER_STAMP := $(PEER_VENV)/.deps-installed

## bench-peers: the compiled, SciPy and Exudyn peers of the founding clearance case, and Exudyn on the spatial four-bar (about 12 min)
bench-peers: install $(PEER_STAMP)
	$(PY) benchmarks/peers/compiled_minimal.py
	$(PY) benchmarks/peers/scipy_slider_crank.py
	$(PY) benchmarks/peers/exudyn_slider_crank.py
	$(PY) benchmarks/peers/exudyn_spatial.py

$(PEER_STAMP):
	test -x $(PEER_VENV)/bin/python || python3 -m venv $(PEER_VENV)
	$(PEER_VENV)/bin/python -m pip install -q --disable-pip-version-check "exudyn==1.13.6" \
		"numpy>=1.26"
	touch $(PEER_STAMP)

## lint: rustfmt, clippy, ruff, mypy, and stubtest (the compiled engine against its stub)
lint: install
	cargo fmt --all --check
	cargo clippy --workspace --all-targets -- -D warnings
	$(VENV)/bin/ruff check python tests benchmarks
	$(VENV)/bin/ruff format --check python tests benchmarks
	$(VENV)/bin/mypy --strict python/jointgap
	$(PY) -m mypy.stubtest jointgap._jointgap

clean:
	rm -rf $(VENV) target demo-output out
