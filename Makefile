# tendonrod: the two commands of the README, and a few helpers.
#   make demo   install what is missing, then regenerate the paper's figures
#   make test   install what is missing, then run the whole test suite (notebooks included)
PY      ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
SOURCES := setup.py pyproject.toml $(wildcard tendonrod/*.c tendonrod/*.h csrc/*.c csrc/*.h)
DEMO_OUT ?= figures

.PHONY: demo test install gsl docs bench sanitize valgrind lint typecheck wheel wheel-check clean

# GSL: install libgsl-dev through apt-get when neither pkg-config nor gsl-config finds it.
gsl:
	@if pkg-config --exists gsl 2>/dev/null || command -v gsl-config >/dev/null 2>&1; then :; else \
	  echo "GSL not found: installing libgsl-dev with apt-get"; \
	  SUDO=; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq libgsl-dev pkg-config; fi

# setuptools >= 77 in the venv too (pyproject's SPDX licence): the in-place builds of
# make sanitize / valgrind and `setup.py build_ext --inplace` use the venv's setuptools
$(STAMP): $(SOURCES) | gsl
	test -x $(VPY) || $(PY) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip "setuptools>=77"
	$(VPY) -m pip install -q -e '.[plot,test,notebooks,lint,wheel,docs]'
	touch $@

install: $(STAMP)

demo: $(STAMP)
	MPLBACKEND=Agg $(VPY) -m tendonrod figures --out $(DEMO_OUT)

# Notebooks are executed by nbmake as part of the suite.
NOTEBOOKS := $(wildcard notebooks/*.ipynb)

test: $(STAMP)
	MPLBACKEND=Agg $(VPY) -m pytest -q tests $(NOTEBOOKS) --nbmake

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
# auditwheel-repaired manylinux_2_35 wheel.  wheel-check installs it into a bare venv
# and solves a scene with the system libgsl masked (tools/wheel_check.sh; root or sudo).
wheel: $(STAMP)
	tools/wheel.sh $(abspath $(VPY))

wheel-check: wheel
	tools/wheel_check.sh $(abspath $(VPY))

# The documentation (docs/, Sphinx + MyST): the HTML with warnings as errors, then every
# doctest (the docstrings' Examples and the pages' doctest blocks), into build/docs.
docs: $(STAMP)
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -q -W --keep-going -b html docs build/docs/html
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -q -W --keep-going -b doctest docs build/docs/doctest

# the C core as a library of its own (libtendonrod, install-c, c-example): csrc/lib.mk
include csrc/lib.mk

# Types: mypy over the package (configuration and per-module overrides in pyproject.toml;
# the compiled core is typed by tendonrod/_core.pyi).
typecheck: $(STAMP)
	$(VENV)/bin/mypy

clean:
	rm -rf build dist $(VENV) tendonrod/*.so *.egg-info docs/api/generated
