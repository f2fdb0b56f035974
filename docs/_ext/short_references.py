"""Resolve a short Python cross-reference to the one documented object it can mean.

The docstrings name things as the code around them does: ``:data:`PRESETS``` in
:mod:`ngincompat.parameters`, ``:meth:`Sweep.record```, ``:class:`Results```. Where Sphinx's
own lookup (the current module and class, then the name as written) finds nothing, the
reference resolves to the member of a base class of the current class (a docstring the
class inherits names the base's methods: ``:meth:`spaces```), else to the documented object
whose full name ends with ``.<name>``, if there is exactly one (or, for ``package.name``, the
one under ``package`` whose name ends with ``.name``: a name the package re-exports); an
ambiguous or unknown name stays unresolved (a warning under ``-n``).
"""

import importlib

from sphinx.util.nodes import make_refnode

#: The object types a role may point to (Sphinx's python domain's roles, minus the aliases).
ROLE_TYPES = {"class": ("class", "exception"), "exc": ("exception", "class"),
              "func": ("function", "method", "classmethod", "staticmethod"),
              "meth": ("method", "classmethod", "staticmethod", "property", "function"),
              "data": ("data", "attribute"), "attr": ("attribute", "property", "data"),
              "mod": ("module",), "obj": None, "const": ("data", "attribute")}


def bases(module, qualname):
    """The full names of the base classes of the class ``module.qualname``, nearest first."""
    try:
        obj = importlib.import_module(module)
        for part in qualname.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError):
        return []
    return [f"{base.__module__}.{base.__qualname__}" for base in getattr(obj, "__mro__", ())[1:]]


def resolve(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    types = ROLE_TYPES.get(node["reftype"], ())
    if types == ():
        return None
    domain = env.get_domain("py")
    if node.get("py:class") and node.get("py:module"):    # a docstring a class inherits
        for base in bases(node["py:module"], node["py:class"]):
            obj = domain.objects.get(f"{base}.{target}")
            if obj is not None:
                return make_refnode(app.builder, node["refdoc"], obj.docname, obj.node_id,
                                    contnode, f"{base}.{target}")
    found = [(name, obj) for name, obj in domain.objects.items()
             if (name == target or name.endswith("." + target))
             and (types is None or obj.objtype in types) and not obj.aliased]
    if not found and "." in target:      # a name re-exported by a package: geometries.FOOTPRINTS
        package, _, last = target.rpartition(".")
        found = [(name, obj) for name, obj in domain.objects.items()
                 if name.startswith(package + ".") and name.endswith("." + last)
                 and (types is None or obj.objtype in types) and not obj.aliased]
    if len(found) != 1:
        return None
    name, obj = found[0]
    return make_refnode(app.builder, node["refdoc"], obj.docname, obj.node_id, contnode, name)


def setup(app):
    app.connect("missing-reference", resolve)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
