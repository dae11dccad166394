# One venv in .venv, made on first use; every target below goes through it.
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-stamp

.PHONY: test run bench assets clean

$(STAMP): pyproject.toml
	python3 -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

run: $(STAMP)
	$(PY) -m marraztu

bench: $(STAMP)
	$(PY) -m marraztu bench

# Regenerates the project's own models and texture (deterministic; the results are committed).
assets: $(STAMP)
	$(PY) -m marraztu.devtools.assetgen

clean:
	rm -rf $(VENV) .pytest_cache build *.egg-info
