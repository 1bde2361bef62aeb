# Two commands a fresh machine needs: `make demo` (the main job) and `make test` (the test suite).
# Both create and use .venv in the checkout; only Python 3.11 and pip are assumed.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/lfdrom run studies/demo.toml

test: $(STAMP)
	$(PY) -m pytest -q

bench: $(STAMP)
	$(PY) bench/sysid_bench.py

clean:
	rm -rf $(VENV) demo-output results
