# The README's two commands, and the benchmarks.
PYTHON ?= python

.PHONY: demo test bench lint

demo:
	$(PYTHON) -m pip install -e ".[test]" && ngincompat paper --out results/paper

test:
	$(PYTHON) -m pip install -e ".[test]" && $(PYTHON) -m pytest

bench:
	ngincompat bench cube --out bench-results/cube

lint:
	ruff check .
