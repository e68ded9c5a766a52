# Radiometer: two commands do everything on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.radiometer-installed

.PHONY: setup demo test test-fast test-lts bench zip validate clean

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
	$(PY) -m radiometer demo --daylight --out out

test: setup
	$(PY) -m pytest -q -n 2 --dist loadfile tests

# Blender-free: bpy is shadowed (tests/blender_free/bpy refuses to import, in this process and in every
# child), the bpy tier is left out and so are tests marked `subprocess` (they run the Blender-backed CLI).
test-fast: setup
	PYTHONPATH=tests/blender_free $(PY) -m pytest -q tests --ignore=tests/bpy -m "not subprocess"

bench: setup
	$(PY) bench/run.py

# The bpy tier on Blender 4.5 LTS (bpy 4.5.15 from PyPI, Python 3.11) in its own venv, same pinned deps.
VENV_LTS := .venv-lts
PY_LTS := $(VENV_LTS)/bin/python
BPY_LTS := 4.5.15
STAMP_LTS := $(VENV_LTS)/.radiometer-installed-$(BPY_LTS)

$(STAMP_LTS): requirements.txt
	$(PYTHON) -m venv $(VENV_LTS)
	$(PY_LTS) -m pip install --quiet --upgrade pip
	$(PY_LTS) -m pip install --quiet bpy==$(BPY_LTS) $$(grep -v -e '^bpy==' -e '^#' -e '^$$' requirements.txt)
	ln -sfn "$(CURDIR)" "$$($(PY_LTS) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/radiometer"
	$(PY_LTS) -c "import radiometer, bpy; print('radiometer LTS setup ok, bpy', bpy.app.version_string)"
	touch $(STAMP_LTS)

test-lts: $(STAMP_LTS)
	$(PY_LTS) -m pytest -q -n 2 --dist loadfile tests/bpy

validate: setup
	$(PY) -m radiometer.tools.extension validate

zip: setup
	$(PY) -m radiometer.tools.extension build --out dist

clean:
	rm -rf $(VENV) out dist wheels build .pytest_cache
