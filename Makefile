# Set-up and checks. Everything a fresh machine needs is installed from here.
PY ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
export VIRTUAL_ENV := $(abspath $(VENV))
export PATH := $(abspath $(VENV))/bin:$(PATH)
# One BLAS thread: idle OpenBLAS workers spin and steal the cores of the Rust loop and of
# other processes on small machines (100x slower small expm() calls measured on 2 cores).
export OPENBLAS_NUM_THREADS ?= 1

.PHONY: all install test test-rust test-python lint demo bench clean

all: install

$(VPY):
	$(PY) -m venv $(VENV)
	$(VPY) -m pip install --quiet --upgrade pip

# Python dependencies (runtime + test + plot + store + xarray + dask + ross + opensees extras; ross as pyproject.toml pins
# it per Python: about 210 MB and 40 s on first install); redone when pyproject.toml changes.
$(VENV)/.deps: pyproject.toml | $(VPY)
	$(VPY) -m pip install --quiet "maturin>=1.7,<2" "numpy>=2" "scipy>=1.11" "matplotlib>=3.8" \
		"tqdm>=4.66" "pytest>=8" "mpmath>=1.3" "ruff==0.17.6" "hypothesis==6.170.15" "mypy==1.20.2" \
		"ross-rotordynamics==2.3.0; python_version < '3.12'" "plotly>=4.7,<7; python_version < '3.12'" \
		"ross-rotordynamics==3.0.0; python_version == '3.12'" \
		"ross-rotordynamics==3.1.0; python_version >= '3.13'" "zarr>=3,<4" "xarray>=2024.1" \
		"dask[distributed]>=2024.1" "openseespy>=3.5"
	touch $@

# Release build of the Rust core, installed into the venv (cargo makes it incremental).
install: $(VENV)/.deps
	$(VENV)/bin/maturin develop --release --quiet --extras test,plot

test-rust:
	cargo test --release -p duhamel-core --quiet

test-python: install
	$(VPY) -m pytest -q

lint: $(VENV)/.deps
	cargo fmt --all -- --check
	cargo clippy --workspace --all-targets --quiet -- -D warnings
	$(VENV)/bin/ruff check python tests benchmarks
	$(VENV)/bin/ruff format --check python tests benchmarks
	$(VENV)/bin/mypy --strict python/duhamel/_engine

test: install test-rust test-python

demo: install
	$(VENV)/bin/duhamel reproduce --out results/

bench: install
	$(VPY) benchmarks/run.py --write BENCHMARKS.md
	$(VPY) benchmarks/rotor.py --append BENCHMARKS.md
	$(VPY) benchmarks/local.py --append BENCHMARKS.md

clean:
	rm -rf target $(VENV) results
