"""Numpy-style sections of docstrings (sphinx.ext.napoleon) for modules, classes and
functions only.

napoleon reads the docstring of an attribute, a property or a module constant (a ``#:``
comment) as ``type: text`` when its first line holds a colon; here those are prose ("The
named settings of every scene, from the cheapest to the finest: ...") and stay as written.
"""

from sphinx.ext import napoleon

#: What autodoc documents whose docstring is prose, not ``type: text``.
PROSE = ("data", "attribute", "property")


def process(app, what, name, obj, options, lines):
    if what not in PROSE:
        napoleon._process_docstring(app, what, name, obj, options, lines)


def setup(app):
    app.setup_extension("sphinx.ext.napoleon")
    for listener in list(app.events.listeners["autodoc-process-docstring"]):
        if listener.handler is napoleon._process_docstring:
            app.disconnect(listener.id)
    app.connect("autodoc-process-docstring", process)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
