# tendonrod: the two commands of the README, and a few helpers.
#   make demo   install what is missing (the package, matplotlib), then regenerate the
#               paper's figures
#   make test   install what is missing (every extra), then run the whole test suite
#               (notebooks included)
PY      ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
SOURCES := setup.py pyproject.toml $(wildcard tendonrod/*.c tendonrod/*.h csrc/*.c csrc/*.h)
DEMO_OUT ?= figures
# What each stamp installs (pyproject's extras): make demo only what drawing the figures
# needs; make test and the checks everything, the suite's own tools included.
DEMO_EXTRAS := plot
DEV_EXTRAS  := all,test,notebooks,lint,wheel,docs
DEMO_STAMP  := $(VENV)/.installed-demo
STAMP       := $(VENV)/.installed

.PHONY: demo test install gsl browser docs bench sanitize valgrind lint typecheck wheel \
	wheel-check wheels numpy-oldest notebooks-full clean

# GSL: install libgsl-dev through apt-get when neither pkg-config nor gsl-config finds it.
gsl:
	@if pkg-config --exists gsl 2>/dev/null || command -v gsl-config >/dev/null 2>&1; then :; else \
	  echo "GSL not found: installing libgsl-dev with apt-get"; \
	  SUDO=; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq libgsl-dev pkg-config; fi

# setuptools >= 77 in the venv too (pyproject's SPDX licence): the in-place builds of
# make sanitize / valgrind and `setup.py build_ext --inplace` use the venv's setuptools
define venv_base
	test -x $(VPY) || $(PY) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip "setuptools>=77"
endef

$(DEMO_STAMP): $(SOURCES) | gsl
	$(venv_base)
	$(VPY) -m pip install -q -e '.[$(DEMO_EXTRAS)]'
	touch $@

$(STAMP): $(SOURCES) | gsl
	$(venv_base)
	$(VPY) -m pip install -q -e '.[$(DEV_EXTRAS)]'
	touch $@

install: $(STAMP)

# (after make test or make install, the full environment serves the demo as well)
demo: $(if $(wildcard $(STAMP)),$(STAMP),$(DEMO_STAMP))
	MPLBACKEND=Agg $(VPY) -m tendonrod figures --out $(DEMO_OUT)

# Notebooks are executed by nbmake as part of the suite.
NOTEBOOKS := $(wildcard notebooks/*.ipynb)

# Headless Chromium and its driver for the 3-D view's page test (apt-get when missing).
browser:
	@tools/browser.sh

test: $(STAMP) browser
	MPLBACKEND=Agg $(VPY) -m pytest -q tests $(NOTEBOOKS) --nbmake

# Re-make the notebooks' stored outputs (what make docs renders in its gallery) at full
# resolution: each notebook in a fresh kernel with TENDONROD_FULL=1.
notebooks-full: $(STAMP)
	$(VPY) tools/notebooks_full.py

bench: $(STAMP)
	MPLBACKEND=Agg $(VPY) bench/closed_forms.py

# Memory safety.  sanitize: ASan+UBSan build in a copy of the tree
# (/tmp/tendonrod-sanitize), then pytest against it; SANITIZE_ARGS picks tests.
# valgrind: memcheck of a loop of solves and ufunc calls; VALGRIND_ARGS=--fast
# for a short run.  See bench/sanitize.sh and bench/valgrind.sh.
SANITIZE_ARGS ?= tests
VALGRIND_ARGS ?=
sanitize: $(STAMP)
	VPY=$(abspath $(VPY)) bench/sanitize.sh $(SANITIZE_ARGS)

valgrind: $(STAMP)
	VPY=$(abspath $(VPY)) bench/valgrind.sh $(VALGRIND_ARGS)

# Lint: ruff (lint + format check) over the Python, clang-format over the C
# (csrc/, the glue, bench/), and the house rules (tools/check_house.py: file sizes,
# no import cycles); clang-format is installed with apt-get when missing.
C_FILES = $(wildcard csrc/*.c csrc/*.h tendonrod/*.c tendonrod/*.h bench/*.c bench/fuzz/*.c examples/c/*.c)
lint: $(STAMP)
	@command -v clang-format >/dev/null 2>&1 || { SUDO=; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq clang-format; }
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	clang-format --dry-run --Werror $(C_FILES)
	$(VPY) tools/check_house.py

# A wheel that carries its own GSL (tools/wheel.sh): dist/ gets the sdist and the
# auditwheel-repaired manylinux_2_35 wheel of the venv's Python.  wheel-check installs it
# into a bare venv and solves a scene with the system libgsl masked (tools/wheel_check.sh;
# root or sudo).
wheel: $(STAMP)
	tools/wheel.sh $(abspath $(VPY))

wheel-check: wheel
	tools/wheel_check.sh $(abspath $(VPY))

# wheels: a repaired wheel for every CPython 3.10-3.13 found (pyenv's, or pythonX.Y on
# PATH; WHEEL_PYTHONS="3.11 3.13" picks), built from the sdist into wheelhouse/, each
# installed into a bare venv of its own Python and run against the quick tests with the
# newest NumPy and NumPy 1.26 (WHEEL_NUMPY=newest|oldest|both; tools/wheels.sh).
# numpy-oldest: the oldest NumPy the package supports, 1.26 (ROS 2 Jazzy's), under the
# quick tests with a wheel built from this tree by Python 3.11 (build/numpy-oldest/), or
# with NUMPY_OLDEST_WHEEL=dist/...whl the wheel make wheel built for the venv's Python.
WHEEL_PYTHONS ?=
WHEEL_NUMPY   ?= both
NUMPY_OLDEST_PYTHON ?= 3.11
NUMPY_OLDEST_WHEEL  ?=
wheels: $(STAMP)
	WHEEL_NUMPY=$(WHEEL_NUMPY) tools/wheels.sh $(abspath $(VPY)) $(WHEEL_PYTHONS)

numpy-oldest: $(STAMP)
ifeq ($(NUMPY_OLDEST_WHEEL),)
	WHEEL_NUMPY=oldest WHEEL_OUT=build/numpy-oldest \
	  tools/wheels.sh $(abspath $(VPY)) $(NUMPY_OLDEST_PYTHON)
else
	tools/wheel_test.sh $(abspath $(VPY)) $(NUMPY_OLDEST_WHEEL) 'numpy==1.26.*'
endif

# The documentation (docs/, Sphinx + MyST): the HTML with warnings as errors, then every
# doctest (the docstrings' Examples and the pages' doctest blocks), into build/docs.
docs: $(STAMP)
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -q -W --keep-going -b html docs build/docs/html
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -q -W --keep-going -b doctest docs build/docs/doctest

# the C core as a library of its own (libtendonrod, install-c, c-example): csrc/lib.mk
include csrc/lib.mk

# Types: mypy over the package (configuration and per-module overrides in pyproject.toml;
# the compiled core is typed by tendonrod/_core.pyi), then over what a user copies -- the
# README's Python, the docs pages' examples, the notebooks' code cells -- checked as a
# user's own code against the package's types (tools/typecheck_examples.py).
typecheck: $(STAMP)
	$(VENV)/bin/mypy
	$(VPY) tools/typecheck_examples.py

clean:
	rm -rf build dist wheelhouse $(VENV) tendonrod/*.so *.egg-info docs/api/generated docs/notebooks
