"""Resolve references to public names that a package re-exports.

The pages and docstrings refer to objects by the names a user imports: ``ngcrack.Scene``,
``ngcrack.planar.scene.SceneError``, ``Scene.scaled`` from a module that imports ``Scene``. The
API pages document each object once, where it is defined (``ngcrack.planar.scene.body.Scene``).
When Sphinx finds no target for a Python reference, this extension imports the name as
written (relative to the reference's module and its parents, as Python would see it),
follows it to the module and qualified name where the object is defined, and links there.
A name that cannot be imported, or whose definition is not documented, stays unresolved,
so that ``-n`` still reports it.

A bare builtin name in an annotation or a type field (``type``, ``str``, ``dict[str, type]``)
means the builtin: Sphinx would otherwise search every documented object whose name ends
in it and link ``type`` to an attribute called ``type`` (``PointCondition.type``), or warn
that several such attributes exist. Such a reference is looked up exactly (and, found
nowhere, left to ``nitpick_ignore``).
"""

from __future__ import annotations

import builtins
import importlib
import inspect

from sphinx import addnodes
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util.nodes import make_refnode

#: the builtin names (classes, None) an annotation may use bare
BUILTIN_NAMES = frozenset(name for name, value in vars(builtins).items()
                          if isinstance(value, type) or value is None)


class BuiltinsExactly(SphinxPostTransform):
    """A Python reference to a bare builtin name is searched exactly, never by suffix."""

    default_priority = 5  # before the references are resolved (10)

    def run(self, **kwargs) -> None:
        for node in self.document.findall(addnodes.pending_xref):
            if node.get("refdomain") == "py" and node.get("reftarget", "").lstrip("~.") in BUILTIN_NAMES:
                node.attributes.pop("refspecific", None)  # the Python domain tests its presence


def _import(path: str):
    """The object at the dotted `path` (module prefix imported, the rest by getattr)."""
    parts = path.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        owner = None
        try:
            for attr in parts[k:]:
                owner, obj = obj, getattr(obj, attr)
        except AttributeError:
            return None
        return obj, owner, parts[-1]
    return None


def _defined_name(found, objects: dict) -> str | None:
    """Where the object is defined, as a documented dotted name."""
    obj, _, attr = found
    target = obj.fget if isinstance(obj, property) else obj
    if inspect.ismodule(target):
        return target.__name__
    module, qualname = getattr(target, "__module__", None), getattr(target, "__qualname__", None)
    if isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname:
        return f"{module}.{qualname}"
    # data: the documented name ending in .attr whose module or class holds the same object
    for name in objects:
        if name.rsplit(".", 1)[-1] != attr:
            continue
        holder = _import(name.rsplit(".", 1)[0])
        if holder is not None and getattr(holder[0], attr, None) is obj:
            return name
    return None


def _missing_reference(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    domain = env.get_domain("py")
    objects, modules = domain.objects, domain.modules
    target = node["reftarget"].lstrip("~.")
    context = node.get("py:module") or ""
    prefixes = [""] + [".".join(context.split(".")[:k]) + "." for k in range(len(context.split(".")), 0, -1)]
    for prefix in prefixes:
        found = _import(prefix + target)
        if found is None:
            continue
        name = _defined_name(found, objects)
        if name in objects:
            entry = objects[name]
            return make_refnode(app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, name)
        if name in modules:
            entry = modules[name]
            return make_refnode(app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, name)
    return None


def setup(app):
    app.connect("missing-reference", _missing_reference)
    app.add_post_transform(BuiltinsExactly)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
