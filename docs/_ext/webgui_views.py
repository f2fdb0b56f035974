"""The notebooks' 3D views (``ngsolve.webgui.Draw``) on the gallery's pages: a note in their
place.

A 3D view is a Jupyter widget whose script comes from a content delivery network: on a site
that must load nothing from the network it cannot show. Executed outside a Jupyter front
end, the view's output is the widget's plain-text stand-in (with the ``anywidget`` package
the widget's ``repr``, without it netgen's "Run ``pip install anywidget``" line); each such
output becomes a one-line note that the view is interactive in Jupyter. The widget's own
output type is left out by ``nb_mime_priority_overrides`` in ``conf.py``.
"""

from docutils import nodes

#: How the plain-text stand-ins of netgen's web GUI widget begin.
STAND_INS = ("<netgen.webgui.WebGuiWidget>", "WebGuiWidget(")
NOTE = "3D view (ngsolve.webgui): interactive when the notebook runs in Jupyter."


def replace_views(app, doctree):
    for block in list(doctree.findall(nodes.literal_block)):
        if ("text_plain" in block["classes"]           # a cell's plain-text output (myst-nb)
                and block.astext().lstrip().startswith(STAND_INS)):
            block.replace_self(nodes.paragraph(text=NOTE, classes=["webgui-view"]))


def setup(app):
    app.connect("doctree-read", replace_views)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
