"""Vertical bars in docstrings are plain-text math, not reStructuredText.

The docstrings write absolute values and norms as plain-text math does: ``|b|``,
``|grad theta x f0|``, ``||Ein||_g``. reStructuredText would read ``|b|`` as a substitution
reference and a line that starts with a bar as a line block; the package defines no
substitutions and writes no line blocks, so every bar outside inline literals and roles is
escaped before the docstring is parsed.
"""

import re

#: Spans left as written: inline literals, then roles and interpreted text.
QUOTED = re.compile(r"(``.+?``|(?::[\w:.-]+:)?`[^`]*`_{0,2})")


def escape_bars(line):
    """``line`` with every bar outside :data:`QUOTED` spans escaped."""
    parts = QUOTED.split(line)
    return "".join(part if i % 2 else part.replace("|", r"\|") for i, part in enumerate(parts))


def process(app, what, name, obj, options, lines):
    lines[:] = [escape_bars(line) for line in lines]


def setup(app):
    app.setup_extension("sphinx.ext.autodoc")
    # before napoleon (priority 500), which could otherwise move a bar into a field
    app.connect("autodoc-process-docstring", process, priority=400)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
