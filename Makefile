# The README's two commands (`make demo`, `make test`: the same lines), and the benchmarks.

.PHONY: demo test bench lint

demo:
	python3 -m venv .venv && .venv/bin/python -m pip install -e ".[test]" && .venv/bin/ngincompat paper --out results/paper

test:
	python3 -m venv .venv && .venv/bin/python -m pip install -e ".[test]" && .venv/bin/python -m pytest

bench:
	.venv/bin/ngincompat bench cube --out bench-results/cube

lint:
	.venv/bin/ruff check .
	.venv/bin/lint-imports
