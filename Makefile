# Radiometer: two commands do everything on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.radiometer-installed

.PHONY: setup demo test test-fast test-bpy bench zip validate clean

setup: $(STAMP)

# Creates the venv, installs the pinned dependencies and makes the repo root importable as
# `radiometer` (a symlink in site-packages), so tests and `python -m radiometer` see the package.
$(STAMP): requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r requirements.txt
	ln -sfn "$(CURDIR)" "$$($(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/radiometer"
	$(PY) -c "import radiometer, bpy, numpy, OpenEXR, colour, matplotlib; print('radiometer setup ok, bpy', bpy.app.version_string)"
	touch $(STAMP)

demo: setup
	$(PY) -m radiometer demo --out out

test: setup
	$(PY) -m pytest -q tests

test-fast: setup
	$(PY) -m pytest -q tests --ignore=tests/bpy

bench: setup
	$(PY) -m bench.run

validate: setup
	$(PY) -m radiometer.tools.extension validate

zip: setup
	$(PY) -m radiometer.tools.extension build --out dist

clean:
	rm -rf $(VENV) out dist .pytest_cache
