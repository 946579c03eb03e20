# The two set-up commands of the README work on a fresh machine from nothing:
#   make demo   venv → install → build the default cam into out/ (STEP, DXF, report.html + plots)
#   make test   system packages (as root) → venv → install → the whole test suite
#   make fuzz   the combination and bad-input suites with thousands of random cases
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# Debian packages the test suite drives for real (installed by `make test` when root).
DEB_PACKAGES := freecad-python3 freecad linuxcnc-uspace xvfb chromium python3-nlopt

.PHONY: demo test fuzz bench system-deps docs clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/cam-workbench build -o out

test: system-deps $(STAMP)
	$(PY) -m pytest

# the combination and bad-input suites' long profile: thousands of random cases (tests/combinations)
fuzz: system-deps $(STAMP)
	CAM_FUZZ=1 $(PY) -m pytest tests/combinations -p no:randomly --hypothesis-show-statistics

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
	rm -rf $(VENV) out .pytest_cache
