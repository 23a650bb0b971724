# Two commands do everything on a fresh machine: `make demo` and `make test`.
# Each creates the virtual environment when it is missing and installs redik into it from
# requirements.lock, the exact versions (every transitive one) the suite was last green with.
# `make lock` re-resolves the newest versions pyproject.toml allows, runs the suite on them in
# a scratch environment and rewrites the lock only when it is green.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.redik-installed
LOCK := requirements.lock
OUT ?= out/demo
# Extras the lock covers (test includes the reference libraries of `redik bench`, whose models
# the tests check against redik's; listed anyway so the lock never depends on that).
LOCK_EXTRAS := test,bench

export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: demo test check lint bench bench-placo env lock clean scenes docs measured

env: $(STAMP)

# PIP_CONSTRAINT (not only -c) so that the isolated build of redik's own wheel (hatchling and
# its dependencies) is pinned too. The last step compiles into numba's cache what the first
# solve_pose, solve_problem and `redik demo` call (the damped least-squares kernel and the QP
# plan, one process each, in parallel), so that they do not compile (tools/first_run.py times
# both); `python -m redik.core.compile_ahead --all` adds solve_batch's and the closed forms'.
$(STAMP): pyproject.toml $(LOCK)
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	PIP_CONSTRAINT=$(CURDIR)/$(LOCK) $(BIN)/python -m pip install --quiet pip
	PIP_CONSTRAINT=$(CURDIR)/$(LOCK) $(BIN)/python -m pip install --quiet -e ".[test]"
	$(BIN)/python -m redik.core.compile_ahead
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/redik demo --out $(OUT)

# ruff (with pydocstyle's Google convention and the complexity limits on redik), mypy
# (pyproject's [tool.mypy]: strict on the layers below the solvers, every module of redik), and the
# import-layer contract (tests/test_layers.py: a module may import only from its own or a lower
# layer; docs/architecture.md lists the layers).
lint: $(STAMP)
	$(BIN)/ruff check redik tests examples specs docs/hooks
	$(BIN)/ruff format --check redik tests examples specs docs/hooks
	$(BIN)/python -m mypy
	$(BIN)/python -m pytest -q -p no:cacheprovider tests/test_layers.py

# The regression scenes run first so that pytest's summary is the last line CI reads. The site
# is built before the tests, which open it in a browser (tests/test_docs_site.py builds it again,
# reusing the example runs this build caches in out/docs/runs/).
test: lint docs check

check: $(STAMP)
	$(BIN)/redik regress --fast
	$(BIN)/python -m pytest -n 2 -q

# Every benchmark with its defaults, each recorded to docs/measured/NAME.json, then README's
# Measured table rendered from those files.
bench: $(STAMP)
	$(BIN)/redik bench all --record docs/measured
	$(MAKE) measured

# README's Measured table from docs/measured/*.json (written by `redik bench NAME --record`).
measured: $(STAMP)
	$(BIN)/python -m redik.apps.measured README.md

# The documentation site, warnings as errors, into site/ (docs/hooks/site.py generates the API
# reference, the Measured page, and the output and figures of the examples the pages show).
docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

# `redik bench qp` beside PlaCo, which the lock cannot hold (requirements-placo.txt says why):
# a separate environment with the lock, then PlaCo's pins without their dependencies.
PLACO_VENV ?= .venv-placo
PLACO_STAMP := $(PLACO_VENV)/.redik-installed

$(PLACO_STAMP): pyproject.toml $(LOCK) requirements-placo.txt
	test -x $(PLACO_VENV)/bin/python || $(PYTHON) -m venv $(PLACO_VENV)
	$(PLACO_VENV)/bin/python -m pip install --quiet -r $(LOCK)
	$(PLACO_VENV)/bin/python -m pip install --quiet --no-deps -r requirements-placo.txt
	$(PLACO_VENV)/bin/python -m pip install --quiet --no-deps -e .
	touch $(PLACO_STAMP)

bench-placo: $(PLACO_STAMP)
	$(PLACO_VENV)/bin/redik bench qp --parts anchors

# Refresh the lock: newest allowed versions in a scratch environment, the whole suite on them,
# and only then the new lock; .venv is then rebuilt from it.
lock:
	rm -rf .venv-lock
	$(PYTHON) -m venv .venv-lock
	.venv-lock/bin/python -m pip install --quiet --upgrade pip hatchling
	.venv-lock/bin/python -m pip install --quiet -e ".[$(LOCK_EXTRAS)]"
	touch .venv-lock/.redik-installed
	$(MAKE) VENV=.venv-lock lint check
	{ echo "# Exact versions the suite was green with (CPython $$(.venv-lock/bin/python -c 'import platform; print(platform.python_version(), platform.machine())'), $$(date -u +%F))."; \
	  echo "# Written by 'make lock'; installed as pip constraints by 'make demo' / 'make test'."; \
	  .venv-lock/bin/python -m pip freeze --all --exclude-editable | grep -v '^redik'; } > $(LOCK).new
	mv $(LOCK).new $(LOCK)
	rm -rf .venv-lock $(VENV)
	$(MAKE) env
	@echo "$(LOCK) refreshed and $(VENV) rebuilt from it; commit it with the change that needed it."

clean:
	rm -rf $(VENV) .venv-lock out site .pytest_cache .ruff_cache .mypy_cache

# Regenerate scenes/*.xml and scenes/README.md from redik/models/scene_library.py.
scenes: $(STAMP)
	$(BIN)/python -m redik.models.scene_library
