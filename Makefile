# Two entry points for a fresh machine: `make demo` runs the main job on a built-in example,
# `make test` runs the test suite. Both create the virtual environment and install on first use.
PYTHON ?= $(shell for p in python3.12 python3.11 python3; do \
	  $$p -c 'import sys; assert sys.version_info >= (3, 11)' 2>/dev/null && echo $$p && break; done)
VENV := .venv
STAMP := $(VENV)/.installed-stamp

.PHONY: demo test test-slow bench bench-gpu clean

# constraints.txt pins the jax the suite passes on (pyproject.toml allows only a tested range)
$(STAMP): pyproject.toml constraints.txt
	@test -n "$(PYTHON)" || { echo "error: Python >= 3.11 not found"; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install -q --upgrade pip
	$(VENV)/bin/python -m pip install -q -c constraints.txt -e '.[test]'
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/hullopt hydro 'builtin:wigley?L=100&B=10&T=6.25&D=10'
	$(VENV)/bin/hullopt run configs/fit_cb_lcb.toml --out runs/fit_cb_lcb

# the default suite (minutes); the long validations (whole design runs, sweeps, grid studies) are marked slow
# --max-worker-restart=0: a crashed worker fails the run at once (xdist's replacement worker hung under loadfile)
test: $(STAMP)
	$(VENV)/bin/python -m pytest -n 2 --dist loadfile --max-worker-restart=0 -m "not slow"

test-slow: $(STAMP)
	$(VENV)/bin/python -m pytest -n 2 --dist loadfile --max-worker-restart=0 -m slow

# ship-model-lib pins plotly ~=5.13 (ours >= 5.20) for a module the benchmarks don't use: no deps.
# BENCH_ARGS=--quick: shorter runs where a script offers them (benchmarks/run.py).
bench: $(STAMP)
	$(VENV)/bin/python -m pip install -q -c constraints.txt -e '.[test,bench]'
	$(VENV)/bin/python -m pip install -q --no-deps 'ship-model-lib==1.0.2'
	$(VENV)/bin/python benchmarks/run.py $(BENCH_ARGS)

# the same on an NVIDIA GPU (Linux, CUDA 12): results/<name>-gpu.json beside the CPU's, side by side in the table;
# stops at once if jax does not see a GPU
bench-gpu: $(STAMP)
	$(VENV)/bin/python -m pip install -q -c constraints.txt -e '.[test,bench,gpu]'
	$(VENV)/bin/python -m pip install -q --no-deps 'ship-model-lib==1.0.2'
	$(VENV)/bin/python benchmarks/run.py --require-gpu $(BENCH_ARGS)

clean:
	rm -rf $(VENV) build *.egg-info
