# Set-up is part of every target: a fresh clone needs only `make <target>`.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
VARIANT ?=
JOBS ?=
# Inputs per back end of `make fuzz` (bench/fuzz.py).
FUZZ_N ?= 10000

.PHONY: setup derive verify test bench fuzz demo clean

setup: $(STAMP)

$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -c constraints.txt -e ".[test]"
	touch $(STAMP)

derive: $(STAMP)
	$(PY) -m rocking.derive $(if $(VARIANT),--variant $(VARIANT))

verify: $(STAMP)
	$(VENV)/bin/rocking verify

test: $(STAMP)
	$(VENV)/bin/ruff check rocking derive tests bench
	$(PY) -m pytest -q $(if $(JOBS),-n $(JOBS))

bench: $(STAMP)
	$(PY) bench/run.py
	$(PY) bench/adaptive.py
	$(PY) bench/adaptive_spectrum.py

fuzz: $(STAMP)
	$(PY) bench/fuzz.py -n $(FUZZ_N) --json out/fuzz.json

demo: $(STAMP)
	$(VENV)/bin/rocking demo --out out

clean:
	rm -rf $(VENV) out build *.egg-info
