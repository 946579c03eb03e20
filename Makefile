# The two set-up commands of the README work on a fresh machine from nothing:
#   make demo   venv → install → build the default cam into out/ (STEP, DXF, report.html + plots)
#   make test   system packages (as root) → venv → install → the whole test suite
#   make fuzz   the combination and bad-input suites with thousands of random cases
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
# clean venvs of their own (tests/test_install_envs.py).
DEV_EXTRAS := cadquery,test
# Debian packages the test suite drives for real (installed by `make test` when root).
DEB_PACKAGES := freecad-python3 freecad linuxcnc-uspace xvfb chromium python3-nlopt

.PHONY: demo test test-install fuzz dist bench system-deps docs clean

$(STAMP): pyproject.toml dev-constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -c dev-constraints.txt -e '.[$(DEV_EXTRAS)]'
	$(PY) -c 'from cam_workbench.ocp_compat import main; raise SystemExit(main())'  # exactly one OCP
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/cam-workbench build -o out

test: system-deps $(STAMP)
	$(PY) -m pytest

# only the install tests: the wheel into clean venvs (build123d first, cadquery first, each extra)
test-install: $(STAMP)
	$(PY) -m pytest -m install_envs

# the combination and bad-input suites' long profile: thousands of random cases (tests/combinations)
fuzz: system-deps $(STAMP)
	CAM_FUZZ=1 $(PY) -m pytest tests/combinations -p no:randomly --hypothesis-show-statistics

# the wheel and the sdist into dist/
dist: $(STAMP)
	rm -rf dist
	$(PY) -m build --outdir dist .

bench: $(STAMP)
	$(PY) benchmarks/run_all.py

docs: $(STAMP)
	$(PY) -m generators.spec.reference > docs/spec.md

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
