# The README's two commands (`make demo`, `make test`: the same lines), and the benchmarks.
# `make demo` installs the core dependencies only (the main job needs no extra) and replaces
# the results of an earlier `make demo`; `make test` installs the test extra.

.PHONY: demo test bench lint

demo:
	python3 -m venv .venv && .venv/bin/python -m pip install -e . && .venv/bin/ngincompat paper --out results/paper --overwrite

test:
	python3 -m venv .venv && .venv/bin/python -m pip install -e ".[test]" && .venv/bin/python -m pytest

bench:
	.venv/bin/ngincompat bench cube --out bench-results/cube

lint:
	.venv/bin/ruff check .
	.venv/bin/lint-imports
