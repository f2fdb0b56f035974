"""One page of the API reference per public module, written when the build starts.

For every module of the packages in ``api_packages`` (``conf.py``) whose name has no part
starting with an underscore, ``api/<module>.rst`` holds the module's docstring and members
(``automodule``; the options in ``autodoc_default_options``), a table of the classes and
functions it defines, and the pages of its submodules. Modules are found by walking the
packages on disk, not by attribute lookup: ``geometries.cube`` is a module although the
package ``geometries`` re-exports the function ``cube`` under the same name (which
autosummary's recursive mode would document instead of the module).

A page is rewritten only when its text changes, so an unchanged module is not read again.
"""

import importlib
import inspect
import pkgutil
from pathlib import Path


def public_modules(package):
    """The names of ``package`` and of every module under it without a private part."""
    root = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(root.__path__, prefix=package + "."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def defined(module):
    """The public classes and functions that ``module`` defines (not those it imports)."""
    members = []
    for name, obj in vars(module).items():
        if (not name.startswith("_") and (inspect.isclass(obj) or inspect.isfunction(obj))
                and getattr(obj, "__module__", None) == module.__name__):
            members.append(name)
    return members


def page(name, modules):
    """The reStructuredText of the page of the module ``name``."""
    module = importlib.import_module(name)
    lines = [name, "=" * len(name), "", f".. automodule:: {name}", ""]
    members = defined(module)
    if members:
        lines += [".. rubric:: Contents", "", ".. autosummary::", ""]
        lines += [f"   {member}" for member in members] + [""]
    children = [m for m in modules if m.rpartition(".")[0] == name]
    if children:
        lines += [".. rubric:: Modules", "", ".. toctree::", "   :maxdepth: 1", ""]
        lines += [f"   {child}" for child in children] + [""]
    return "\n".join(lines)


def write_pages(app):
    folder = Path(app.srcdir) / "api"
    folder.mkdir(exist_ok=True)
    wanted = set()
    for package in app.config.api_packages:
        modules = public_modules(package)
        for name in modules:
            path = folder / f"{name}.rst"
            text = page(name, modules)
            wanted.add(path)
            if not path.exists() or path.read_text(encoding="utf-8") != text:
                path.write_text(text, encoding="utf-8")
    for stale in set(folder.glob("*.rst")) - wanted:      # a module removed or renamed
        stale.unlink()


def setup(app):
    app.add_config_value("api_packages", [], "env")
    app.connect("builder-inited", write_pages)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
