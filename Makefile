# Two commands a fresh machine needs: `make demo` (the main job) and `make test` (the test suite).
# Both create and use .venv in the checkout; only Python 3.11 and pip are assumed.
# Installs are locked to constraints.txt (the versions the suite last passed with); `make test-latest`
# builds .venv-latest with the newest versions PyPI serves and runs the suite there, so that drift in
# numpy / scipy / cvxpy / clarabel / control is seen before users see it.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
LATEST := .venv-latest

.PHONY: demo test test-latest bench clean

$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -c constraints.txt -e '.[dev]'
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/lfdrom run studies/demo.toml

test: $(STAMP)
	$(PY) -m pytest -q

test-latest:
	rm -rf $(LATEST)
	$(PYTHON) -m venv $(LATEST)
	$(LATEST)/bin/python -m pip install --quiet --upgrade pip
	$(LATEST)/bin/python -m pip install --quiet --upgrade -e '.[dev]'
	$(LATEST)/bin/python -m pip freeze --exclude-editable | grep -iE '^(numpy|scipy|cvxpy|clarabel|control|matplotlib)=='
	$(LATEST)/bin/python -m pytest -q

bench: $(STAMP)
	$(PY) bench/sysid_bench.py

clean:
	rm -rf $(VENV) $(LATEST) demo-output results
