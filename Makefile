# The two commands a newcomer needs: `make demo` and `make test`. Both set up everything.
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
DEPS_STAMP := $(VENV)/.deps-installed

.PHONY: install demo test test-rust test-python bench lint clean

$(DEPS_STAMP): pyproject.toml
	test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install -q --disable-pip-version-check "maturin>=1.5,<2" \
		"numpy>=1.26" "scipy>=1.11" "pandas>=2.0" "matplotlib>=3.8" \
		"pytest>=8" "ruff>=0.5" "mypy>=1.10"
	touch $(DEPS_STAMP)

## install: create .venv, build the Rust engine in release mode, install jointgap
install: $(DEPS_STAMP)
	VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
		$(VENV)/bin/maturin develop --release --quiet

## demo: run the founding slider-crank case, write figures and results to demo-output/
demo: install
	$(VENV)/bin/jointgap run examples/slider_crank_ideal.toml --t-end 0.5 --rate 10000 \
		--out demo-output --plot

## test: Rust tests of the core, then pytest
test: install test-rust test-python

test-rust:
	cargo test --release -p jointgap-core

test-python: install
	$(VENV)/bin/python -m pytest -q tests

## bench: speed and accuracy figures (benchmarks/output/)
bench: install
	cargo run --release -p jointgap-core --example bench_ideal
	cargo run --release -p jointgap-bench-diffsol
	$(PY) benchmarks/run.py

## lint: rustfmt, clippy, ruff
lint: install
	cargo fmt --all --check
	cargo clippy --workspace --all-targets -- -D warnings
	$(VENV)/bin/ruff check python tests benchmarks
	$(VENV)/bin/ruff format --check python tests benchmarks
	$(VENV)/bin/mypy --strict python/jointgap

clean:
	rm -rf $(VENV) target demo-output out
