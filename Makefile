# The README's two commands (`make demo`, `make test`: the same lines), and the benchmarks.
# `make demo` installs the core dependencies only (the main job needs no extra) and replaces
# the results of an earlier `make demo`; `make test` installs the test extra. `make docs` installs
# the docs extra and builds the site into docs/_build/html, offline, with warnings as errors
# (-W) and every cross-reference checked (-n); the gallery's notebooks run on coarse settings
# (a notebook is run again only when it changed: docs/_build/.jupyter_cache).

.PHONY: demo test docs bench lint

demo:
	python3 -m venv .venv && .venv/bin/python -m pip install -e . && .venv/bin/ngincompat paper --out results/paper --overwrite

test:
	python3 -m venv .venv && .venv/bin/python -m pip install -e ".[test]" && .venv/bin/python -m pytest

docs:
	python3 -m venv .venv && .venv/bin/python -m pip install -e ".[docs]" && .venv/bin/python -m sphinx -W -n --keep-going -b html docs docs/_build/html

bench:
	.venv/bin/ngincompat bench cube --out bench-results/cube

lint:
	.venv/bin/ruff check .
	.venv/bin/lint-imports
