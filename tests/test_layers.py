"""The package's architecture as data: imports run down the layers, nothing patches a module.

The layer order is written once, here (CONTRIBUTING.md explains it). Every module of
ngcrack belongs to the layer of the longest prefix that names it; a module may import
from its own layer or any layer below, never above, and the import graph (imports at
module level and inside functions alike) has no cycle. A new module must be placed in
LAYERS, so that its place in the architecture is a decision, not an accident.
"""

from __future__ import annotations

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1] / "ngcrack"

#: low to high: data flows from the scene to the studies and views
LAYERS: list[tuple[str, tuple[str, ...]]] = [
    ("foundations", ("core", "planar", "studies", "shell", "planar.materials", "core.memory", "core.parallel", "planar.quadrature",
                        "core.csr", "core.schur", "core.constraints", "core.contact", "core.quadrature",
                     "shell.files", "core.errors", "shell.extras", "core.element_names", "solid", "core.sparse_contact", "core.sparse_friction",
                     "core.coulomb")),
    ("scene", ("core.fields", "core.scene", "planar.scene", "scenes", "studies.references", "planar.sizing", "planar.path_sizes", "solid.scene",
               "solid.parts", "solid.points", "solid.loads",
               "solid.curve")),
    ("mesh", ("planar.crack_sides", "planar.crack_loads", "planar.geometry", "solid.geometry")),
    ("discretization", ("core.discretization", "planar.elements", "core.hybrid", "core.friction", "core.friction_setup", "core.crack_problem",
                        "core.held_means", "planar.held_means", "solid.element", "solid.friction_points",
                        "solid.h1", "solid.point_means")),
    ("post-processing", ("planar.post", "planar.post2d", "planar.tips", "planar.tstress", "planar.local_fields", "planar.estimate",
                        "planar.vtk", "planar.load_points", "solid.front", "solid.front_near",
                         "solid.face_pressure", "solid.estimate", "solid.face_friction", "solid.volume")),
    ("options and solution", ("core.options", "core.solution", "planar.solution", "solid.options",
                               "core.stages", "core.friction_checks", "solid.output")),
    ("pipeline and hp meshes", ("core.pipeline", "planar.stages", "solid.stages", "planar.hp", "solid.solve")),
    ("loops over the pipeline", ("studies.adapt", "distributed")),
    ("one-shot solve", ("core.solve", "studies.volume")),
    ("studies", ("study", "studies.sweeps", "studies.stability", "studies.growth", "studies.hydrofrac", "studies.paper", "planar.plots")),
    ("views", ("shell.explorer", "interactive", "shell.cli", "shell.cli_errors", "shell.cli_runs", "shell.interrupts",
                        "studies.growth.cli", "studies.hydrofrac.cli", "__main__", "",
               "solid.view")),
]

#: the largest module, in lines (the aim is about 500: one idea a module)
MAX_LINES = 600


def _module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _modules() -> dict[str, pathlib.Path]:
    return {_module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


def _layer(name: str) -> int:
    best, best_len = None, -1
    for k, (_, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if (name == prefix or name.startswith(prefix + ".") or prefix == "" and name == "") and len(prefix) > best_len:
                best, best_len = k, len(prefix)
    if best is None:
        raise AssertionError(f"module ngcrack.{name} is in no layer: add it to LAYERS in {__file__}")
    return best


def _imports(name: str, path: pathlib.Path) -> set[str]:
    """The ngcrack modules that `path` imports anywhere (module level or inside functions)."""
    modules = _modules()
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()

    def add(target: str) -> None:
        # the longest prefix of `target` that is a module (a from-import may name a function);
        # a module that does not exist (an optional import) is no edge
        while target and target not in modules:
            target = target.rpartition(".")[0]
            if not target:
                return
        if target in modules and target != name:
            out.add(target)

    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".") if package else []
                base = base[:len(base) - (node.level - 1)] if node.level > 1 else base
                target = ".".join([*base, *([node.module] if node.module else [])])
            elif node.module and (node.module == "ngcrack" or node.module.startswith("ngcrack.")):
                target = node.module[len("ngcrack."):] if node.module != "ngcrack" else ""
            else:
                continue
            for alias in node.names:  # `from . import elements` imports the module ngcrack.planar.elements
                full = f"{target}.{alias.name}" if target else alias.name
                add(full if full in modules else target)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("ngcrack."):
                    add(alias.name[len("ngcrack."):])
    return out


def _graph() -> dict[str, set[str]]:
    return {name: _imports(name, path) for name, path in _modules().items()}


def test_every_module_has_a_layer():
    for name in _modules():
        _layer(name)


def test_no_import_runs_up_the_layers():
    upward = []
    for name, deps in _graph().items():
        for dep in deps:
            if _layer(dep) > _layer(name):
                upward.append(f"ngcrack.{name} ({LAYERS[_layer(name)][0]}) imports ngcrack.{dep} "
                              f"({LAYERS[_layer(dep)][0]})")
    assert not upward, "imports up the layers:\n" + "\n".join(sorted(upward))


def test_no_import_cycle():
    graph = _graph()
    # a package's __init__ re-exports its modules: importing a package is not a cycle with them
    state: dict[str, int] = {}
    cycles = []

    def visit(node: str, stack: list[str]) -> None:
        state[node] = 1
        for dep in sorted(graph[node]):
            if dep == "" or node.startswith(dep + ".") or dep.startswith(node + ".") and node == "":
                continue
            if state.get(dep) == 1:
                cycles.append(" -> ".join(stack[stack.index(dep):] + [dep]) if dep in stack else f"{node} -> {dep}")
            elif state.get(dep) is None:
                visit(dep, stack + [dep])
        state[node] = 2

    for name in sorted(graph):
        if state.get(name) is None:
            visit(name, [name])
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_no_module_is_patched_at_run_time():
    """No assignment to an attribute of an imported ngcrack module, no setattr on one."""
    found = []
    for name, path in _modules().items():
        tree = ast.parse(path.read_text())
        imported = set()  # the names bound to ngcrack's own modules
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                imported |= {a.asname or a.name for a in node.names if a.name.startswith("ngcrack")}
            elif isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("ngcrack")):
                imported |= {a.asname or a.name for a in node.names}
        for node in ast.walk(tree):
            targets = node.targets if isinstance(node, ast.Assign) else \
                [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else []
            for t in targets:
                if isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id in imported:
                    found.append(f"ngcrack.{name}:{node.lineno}: {t.value.id}.{t.attr} = ...")
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr" \
                    and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id in imported:
                found.append(f"ngcrack.{name}:{node.lineno}: setattr({node.args[0].id}, ...)")
    assert not found, "modules patched at run time:\n" + "\n".join(found)


@pytest.mark.parametrize("name", sorted(_modules()))
def test_module_size_and_docstring(name):
    path = _modules()[name]
    text = path.read_text()
    lines = text.count("\n")
    assert lines <= MAX_LINES, f"ngcrack.{name} has {lines} lines (at most {MAX_LINES}: split it by idea)"
    assert ast.get_docstring(ast.parse(text)), f"ngcrack.{name} has no module docstring saying what it holds"



def test_no_module_outside_the_elements_tests_an_element_name():
    """What the post-processing needs of an element (its grad u, its estimate, whether that
    is a bound) is asked of the element (`ElementTraits`): outside ngcrack/planar/elements/ no
    module compares an object's element name (`sol.element == "tdnns"`) or looks a table
    up by it (`DEGREE[sol.element]`)."""
    import re

    pattern = re.compile(r"\.element\s*(==|!=|in\s|not\s+in\s)|\[\s*[A-Za-z_.]*\.element\s*\]")
    found = []
    for name, path in _modules().items():
        if name == "planar.elements" or name.startswith("planar.elements."):
            continue
        for k, line in enumerate(path.read_text().splitlines(), start=1):
            code = line.split("#")[0]
            if pattern.search(code) and "args.element" not in code and "rates.element" not in code:
                found.append(f"ngcrack/{path.relative_to(ROOT)}:{k}: {line.strip()}")
    assert not found, "element names compared outside ngcrack/planar/elements/:\n" + "\n".join(found)


# ------------------------------------------------------------ 2D parts and dimension-free parts

#: the modules that are 2D by nature (CONTRIBUTING.md, "2D and dimension-free"): the planar
#: scene and its built-in scenes, netgen's 2D geometry and what reads its triangles, the 2D
#: element families and the hp meshes, the crack profiles sampled along crack edges, the 2D
#: interaction integral and the estimate on triangles, the ParaView writer, the 2D views
TWO_D = ("planar.scene", "scenes", "studies.references", "planar.sizing", "planar.quadrature", "planar.materials", "planar.geometry",
         "planar.crack_sides", "planar.crack_loads", "planar.held_means", "planar.load_points", "planar.elements", "planar.hp",
         "planar.post", "planar.post2d", "planar.tips", "planar.tstress", "planar.local_fields", "planar.estimate", "planar.vtk",
         "planar.plots", "shell.explorer", "interactive")

#: the modules that must stay free of any 2D assumption: the element's protocol, the
#: condensed system and the reduction, the crack problem (QP, friction), the KKT residuals,
#: the stages, the options and the solution
DIMENSION_FREE = ("core.errors", "core.quadrature", "core.memory", "core.parallel", "shell.files", "core.csr", "core.constraints", "core.contact",
                  "core.schur", "core.crack_problem", "core.sparse_contact", "core.sparse_friction", "core.coulomb",
                  "core.element_names", "core.discretization", "core.hybrid", "core.friction", "core.friction_setup",
                  "core.stages", "core.options", "core.solution")

class _WithoutTypeChecking:
    """A module's source without its `if TYPE_CHECKING:` blocks (imports for annotations only)."""

    def __init__(self, path: pathlib.Path):
        self.name = path.name
        self._path = path

    def read_text(self) -> str:
        tree = ast.parse(self._path.read_text())

        class Strip(ast.NodeTransformer):
            def visit_If(self, node):
                if isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
                    return node.orelse or None
                return self.generic_visit(node)

        return ast.unparse(Strip().visit(tree))


def _is_2d(module: str) -> bool:
    return any(module == m or module.startswith(m + ".") for m in TWO_D)


def test_the_dimension_free_modules_import_nothing_2d():
    """No dimension-free module imports a 2D one at run time (annotations under
    TYPE_CHECKING aside): the stages reach the element through its Discretization and
    the post-processing through the post-processor the pipeline chose (post2d.PLANE in 2D)."""
    modules = _modules()
    assert not set(DIMENSION_FREE) & set(TWO_D)
    edges = set()
    for name in DIMENSION_FREE:
        assert name in modules, f"DIMENSION_FREE names a module that does not exist: {name}"
        edges |= {(name, target) for target in _imports(name, _WithoutTypeChecking(modules[name])) if _is_2d(target)}
    assert sorted(edges) == [], f"dimension-free modules import 2D ones: {sorted(edges)}"


def test_no_merge_conflict_markers_are_left():
    """No file of the repository keeps a merge's conflict markers (inside a docstring they
    pass both Python and ruff): the count of marker lines is 0."""
    top = ROOT.parent
    markers = ("<" * 7 + " ", ">" * 7 + " ")
    found = []
    for path in sorted(top.rglob("*")):
        if path.is_dir() or any(part.startswith(".") or part in ("_build", "node_modules") for part in path.parts[len(top.parts):]):
            continue
        if path.suffix not in (".py", ".md", ".toml", ".cfg", ".txt", ".yml", ".yaml", ".json", ".css", ".html", ".js") and path.name != "run":
            continue
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except (UnicodeDecodeError, OSError):
            continue
        found += [f"{path.relative_to(top)}:{k + 1}" for k, line in enumerate(lines) if line.startswith(markers)]
    assert len(found) == 0, found


# ------------------------------------------------------------ the folders: core, planar, solid and the rest

#: the run-time imports of the dimension-free core from the other folders: each is a seam the
#: one-path design still has, written down here so that the list can only shrink
CORE_SEAMS = {
    "core.options": {"planar.path_sizes"},  # path_grading, a planar option, is still coerced by SolveOptions
    "core.solve": {"distributed", "scenes", "studies.adapt"},  # the front door: names, mpiexec, adapt=TOL
}
#: what the solid body takes from the planar one at run time: the same NGSolve spaces and
#: Williams fields, the facet helpers and the TOML writer (to move to the core, never to grow)
SOLID_FROM_PLANAR = {
    "solid.element": {"planar.elements.tdnns"},
    "solid.front_near": {"planar.tips"},  # the Williams fields of the front integral
    "solid.h1": {"planar.elements.base", "planar.geometry"},
    "solid.output": {"planar.vtk"},
    "solid.scene": {"planar.scene.toml"},
}


def _runtime_imports(prefix: str, into: tuple[str, ...]) -> dict[str, set[str]]:
    modules = _modules()
    out = {}
    for name, path in modules.items():
        if name == prefix or name.startswith(prefix + "."):
            deps = {d for d in _imports(name, _WithoutTypeChecking(path)) if d.split(".")[0] in into}
            if deps:
                out[name] = deps
    return out


def test_the_core_imports_no_body_but_its_written_seams():
    """ngcrack/core/ imports nothing of planar/, solid/, distributed/, studies/ or shell/ at run time
    (annotations aside) beyond CORE_SEAMS: the bodies plug into the core (`scene.body`), not the reverse."""
    found = _runtime_imports("core", ("planar", "solid", "distributed", "studies", "shell", "scenes"))
    extra = {k: sorted(v - CORE_SEAMS.get(k, set())) for k, v in found.items() if v - CORE_SEAMS.get(k, set())}
    assert not extra, f"the core imports a body or a loop: {extra}"
    stale = {k: sorted(v - found.get(k, set())) for k, v in CORE_SEAMS.items() if v - found.get(k, set())}
    assert not stale, f"CORE_SEAMS lists seams that are gone (remove them): {stale}"


def test_the_solid_body_takes_from_the_planar_one_only_its_written_parts():
    found = _runtime_imports("solid", ("planar",))
    extra = {k: sorted(v - SOLID_FROM_PLANAR.get(k, set())) for k, v in found.items() if v - SOLID_FROM_PLANAR.get(k, set())}
    assert not extra, f"the solid body imports more of the planar one: {extra}"
    stale = {k: sorted(v - found.get(k, set())) for k, v in SOLID_FROM_PLANAR.items() if v - found.get(k, set())}
    assert not stale, f"SOLID_FROM_PLANAR lists imports that are gone (remove them): {stale}"


def test_the_planar_body_imports_nothing_of_the_solid_one():
    assert _runtime_imports("planar", ("solid",)) == {}


def test_no_module_imports_the_face_of_its_own_package():
    """No package face (an __init__) is imported back by a module of its own package: the face
    re-exports its members, never the reverse (an import circle)."""
    modules = _modules()
    found = []
    for name, path in modules.items():
        if path.name == "__init__.py" or "." not in name:
            continue
        package = name.rpartition(".")[0]
        if package and package in _imports(name, path):
            found.append(f"ngcrack.{name} imports ngcrack.{package}")
    assert not found, "\n".join(found)
