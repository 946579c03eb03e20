# The two set-up commands of the README work on a fresh machine from nothing:
#   make demo   venv → install → build the default cam into out/ (STEP, DXF, report.html + plots)
#   make test   system packages (as root) → venv → install → the whole test suite, then the
#               FreeCAD tests again with FreeCAD 1.0 and 1.1 (Debian trixie/unstable roots, as root)
#   make fuzz   the combination and bad-input suites with thousands of random cases
#   make golden re-record every built-in example's outputs (tests/golden/README.md: deliberate changes only)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# Downloads are cached here (the dev venv and the install tests' clean venvs): re-runs are fast.
CACHE  ?= $(CURDIR)/.cache
export PIP_CACHE_DIR ?= $(CACHE)/pip
# The dev venv: the project editable with the [cadquery] extra (CadQuery 2.8 and its one OCP,
# cadquery-ocp 7.9) pinned by dev-constraints.txt, and the test tools. Never build123d here: it
# brings the other OCP build (docs/install.md). The tests that need build123d or OCP 8 run in
# clean venvs of their own (tests/test_install_envs.py). The [dask] extra: the studies' parallel
# runs and Parquet tables, which the tests drive with a real scheduler and workers.
DEV_EXTRAS := cadquery,test,dask
# Debian packages the test suite drives for real (installed by `make test` when root).
DEB_PACKAGES := freecad-python3 freecad linuxcnc-uspace xvfb chromium python3-nlopt mmdebstrap librecad libcairo2 ffmpeg
# FreeCAD 1.0 (Debian trixie) and 1.1 (Debian unstable): root filesystems made by mmdebstrap
# from Debian's packages, cached here (reused while their package list is the same; delete
# the folder to rebuild); `make test` runs the FreeCAD tests once with each, beside the host's.
FREECAD_ROOTS ?= $(CACHE)/freecad-roots
FREECAD_SUITES ?= trixie unstable
FREECAD_ROOT_PACKAGES := freecad-python3 freecad python3-numpy python3-scipy python3-nlopt \
                         python3-matplotlib xvfb xauth
# what apt's Recommends would bring a user and mmdebstrap leaves out: Qt 6's SVG image plugin
# (FreeCAD 1.1 draws its check boxes and the workbench icons from SVG; trixie's Qt 5 has it)
FREECAD_ROOT_EXTRA_unstable := qt6-svg-plugins
FREECAD_MIRROR ?= $(shell tests/freecad_roots.sh mirror)
FREECAD_TESTS := $(wildcard tests/test_freecad_*.py)

.PHONY: demo test test-host test-freecad-roots freecad-roots test-install fuzz golden dist bench system-deps docs clean

# The install says what it does, one line per step; on a terminal pip shows its own progress too
# (each package, the download bars), in a log (CI: make's stderr is not a terminal) pip is quiet.
# `make demo PIP_QUIET=` shows pip's progress in a log too, `PIP_QUIET=--quiet` hides it.
PIP_QUIET ?= $(shell [ -t 2 ] || echo --quiet)

$(STAMP): pyproject.toml dev-constraints.txt
	@echo "== 1/4 the virtual environment $(VENV)"
	$(PYTHON) -m venv $(VENV)
	@echo "== 2/4 the newest pip"
	$(PY) -m pip install $(PIP_QUIET) --upgrade pip
	@echo "== 3/4 cam-workbench with [$(DEV_EXTRAS)]: CadQuery and its OCP, Dask, the test tools (a few minutes the first time; downloads cached in $(PIP_CACHE_DIR))"
	$(PY) -m pip install $(PIP_QUIET) -c dev-constraints.txt -e '.[$(DEV_EXTRAS)]'
	@echo "== 4/4 exactly one OCP in $(VENV)"
	$(PY) -c 'from cam_workbench.kernel.ocp import main; raise SystemExit(main())'
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/cam-workbench build -o out

# The whole suite on the host (FreeCAD 0.20 from bookworm) and, beside it on the second core, the
# FreeCAD tests with FreeCAD 1.0 and 1.1 (their output in $(ROOTS_LOG), shown when they end);
# every part runs, and `make test` fails if any part failed.
ROOTS_LOG ?= $(CACHE)/freecad-roots-tests.log
test: system-deps $(STAMP)
	@status=0; mkdir -p $(CACHE); \
	echo "== the FreeCAD 1.0/1.1 tests run beside the host suite: output in $(ROOTS_LOG), shown when they end"; \
	$(MAKE) --no-print-directory test-freecad-roots > $(ROOTS_LOG) 2>&1 & roots=$$!; \
	$(MAKE) --no-print-directory test-host || status=1; \
	wait $$roots || status=1; \
	echo "== the FreeCAD 1.0/1.1 tests ($(ROOTS_LOG)):"; cat $(ROOTS_LOG); \
	exit $$status

test-host: $(STAMP)
	$(PY) -m pytest

# As root: build (or reuse) the roots; a failure (no mmdebstrap, no network) fails loudly.
# Not root: nothing to do (FreeCAD in a root filesystem needs mount namespaces and chroot).
freecad-roots:
	@if [ "$$(id -u)" != 0 ]; then \
	  echo "not root: FreeCAD 1.0/1.1 root filesystems not built (their test runs are skipped)"; \
	else for s in $(FREECAD_SUITES); do \
	  extra=; [ "$$s" = unstable ] && extra="$(FREECAD_ROOT_EXTRA_unstable)"; \
	  tests/freecad_roots.sh build $(FREECAD_ROOTS)/$$s $$s "$(FREECAD_MIRROR)" $(FREECAD_ROOT_PACKAGES) $$extra \
	    || exit 1; done; fi

test-freecad-roots: freecad-roots $(STAMP)
	@if [ "$$(id -u)" != 0 ]; then \
	  echo "SKIPPED: the FreeCAD tests with FreeCAD 1.0 (trixie) and 1.1 (unstable) need root"; \
	else status=0; for s in $(FREECAD_SUITES); do \
	  echo "=== FreeCAD tests with the FreeCAD of Debian $$s ($(FREECAD_ROOTS)/$$s)"; \
	  CAM_FREECAD_ROOT=$(FREECAD_ROOTS)/$$s $(PY) -m pytest $(FREECAD_TESTS) || status=1; \
	done; exit $$status; fi

# only the install tests: the wheel into clean venvs (build123d first, cadquery first, each extra)
test-install: $(STAMP)
	$(PY) -m pytest -m install_envs

# the combination and bad-input suites' long profile: thousands of random cases (tests/combinations)
fuzz: system-deps $(STAMP)
	CAM_FUZZ=1 $(PY) -m pytest tests/combinations -p no:randomly --hypothesis-show-statistics

# re-record what tests/test_golden.py holds the outputs to: every built-in example through the CLI
# and the API into tests/golden/data/ (only for a deliberate, reviewed change: tests/golden/README.md)
golden: $(STAMP)
	$(PY) -m tests.golden.record

# the wheel and the sdist into dist/
dist: $(STAMP)
	rm -rf dist
	$(PY) -m build --outdir dist .

bench: $(STAMP)
	$(PY) benchmarks/run_all.py

docs: $(STAMP)
	$(PY) -m cam_workbench.generators.spec.reference > docs/spec.md

system-deps:
	@missing=""; for p in $(DEB_PACKAGES); do \
	  dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -z "$$missing" ]; then echo "system packages present:$(DEB_PACKAGES)"; \
	elif [ "$$(id -u)" = 0 ]; then \
	  echo "installing$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	else echo "not root: skipping Debian packages ($$missing); tests that need them will skip"; fi

clean:
	rm -rf $(VENV) out .pytest_cache dist build
