# Two commands do everything on a fresh machine: `make demo` and `make test`.
# Each creates the virtual environment when it is missing and installs redik into it.

PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.redik-installed
OUT ?= out/demo

export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: demo test lint bench env clean scenes

env: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/redik demo --out $(OUT)

lint: $(STAMP)
	$(BIN)/ruff check redik tests examples tasks
	$(BIN)/ruff format --check redik tests examples tasks

# The regression scenes run first so that pytest's summary is the last line CI reads.
test: lint
	$(BIN)/redik regress --fast
	$(BIN)/python -m pytest -n 2 -q

bench: $(STAMP)
	$(BIN)/redik bench all

clean:
	rm -rf $(VENV) out .pytest_cache .ruff_cache

# Regenerate scenes/*.xml and scenes/README.md from redik/scene_library.py.
scenes: $(STAMP)
	$(BIN)/python -m redik.scene_library
