"""The staged pipeline: each stage is rebuilt exactly when its inputs change, and a cached
answer equals a fresh one to round-off; the options are one validated value."""

from __future__ import annotations

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.options import SolveOptions
from ngcrack.core.pipeline import Pipeline
from ngcrack.shell.explorer.loads import scaled_loads

COARSE = dict(maxh=2.0, tip_h=0.25)


@pytest.fixture(scope="module")
def scene():
    return nc.scenes.load("inclined-compression")


def _difference(a, b) -> float:
    """Largest difference of two solutions' crack profiles, tips and unknowns, relative to their size."""
    diffs = []
    for p, q in zip(a.profiles, b.profiles):
        for k in ("normal_jump", "tangential_jump", "normal_stress", "shear_stress"):
            x, y = getattr(p, k), getattr(q, k)
            diffs.append(np.max(np.abs(x - y)) / max(np.max(np.abs(y)), 1e-300))
    for s, t in zip(a.tips, b.tips):
        diffs.append(abs(s.K_II - t.K_II) / abs(t.K_II))
    va, vb = a.gfu.vec.FV().NumPy(), b.gfu.vec.FV().NumPy()
    diffs.append(np.max(np.abs(va - vb)) / np.max(np.abs(vb)))
    return float(max(diffs))


def test_each_stage_is_rebuilt_exactly_when_its_inputs_change(scene):
    pipe = Pipeline()
    opts = SolveOptions(**COARSE)
    first = pipe.run(scene, opts)
    assert pipe.counts == {"mesh": 1, "assemble": 1, "load": 0, "condense": 1, "factorize": 1}

    # a new load value: the load vector only, one solve with the kept factorization
    half = scaled_loads(scene, 0.5)
    sol = pipe.run(half, opts)
    assert pipe.counts == {"mesh": 1, "assemble": 1, "load": 1, "condense": 1, "factorize": 1}
    assert _difference(sol, nc.solve(half, **COARSE)) < 1e-10
    # contact is positively homogeneous of degree one in the load
    assert np.allclose(sol.profiles[0].tangential_jump, 0.5 * first.profiles[0].tangential_jump, rtol=0, atol=1e-12 *
                       np.max(np.abs(first.profiles[0].tangential_jump)))

    # a new material: re-assembly on the same mesh
    soft = scene.with_(nu=0.4)
    sol = pipe.run(soft, opts)
    assert pipe.counts == {"mesh": 1, "assemble": 2, "load": 1, "condense": 2, "factorize": 2}
    assert _difference(sol, nc.solve(soft, **COARSE)) < 1e-10

    # another element on the same mesh: re-assembly, no meshing
    sol = pipe.run(soft, opts.replace(element="bdm" if opts.element != "bdm" else "tdnns"))
    assert pipe.counts["mesh"] == 1 and pipe.counts["assemble"] == 3 and pipe.counts["factorize"] == 3

    # a new mesh size: everything from the mesh on
    sol = pipe.run(soft, opts.replace(maxh=1.5))
    assert pipe.counts["mesh"] == 2 and pipe.counts["assemble"] == 4 and pipe.counts["factorize"] == 4
    assert _difference(sol, nc.solve(soft, maxh=1.5, tip_h=0.25)) < 1e-10


def test_crack_models_and_friction_keep_their_own_reductions(scene):
    pipe = Pipeline()
    opts = SolveOptions(**COARSE)
    pipe.run(scene, opts)
    free = pipe.run(scene, opts.replace(crack_model="free"))
    assert pipe.counts["assemble"] == 1 and pipe.counts["factorize"] == 2
    assert _difference(free, nc.solve(scene, crack_model="free", **COARSE)) < 1e-10
    pipe.run(scene, opts)  # back to contact: the first reduction is reused
    assert pipe.counts["factorize"] == 2
    rough = scene.with_(friction=0.3)
    sol = pipe.run(rough, opts)  # the tangential jumps join the crack unknowns: one more condensation
    assert pipe.counts["assemble"] == 1 and pipe.counts["condense"] == 2 and pipe.counts["factorize"] == 3
    assert _difference(sol, nc.solve(rough, **COARSE)) < 1e-10
    assert sol.kkt["friction"] < 1e-10


def test_a_ready_mesh_is_not_meshed_again_and_hp_layers_are_a_mesh_option(scene):
    pipe = Pipeline()
    opts = SolveOptions(**COARSE)
    mesh = pipe.mesh(scene, opts)
    assert pipe.mesh(scene, opts) is mesh and pipe.counts["mesh"] == 1
    graded = pipe.mesh(scene, opts.replace(hp=2))
    assert pipe.counts["mesh"] == 2 and graded.mesh.ne > mesh.mesh.ne
    sol = pipe.run(scene, opts, crack_mesh=mesh)
    assert sol.crack_mesh is mesh and pipe.counts["mesh"] == 2


@pytest.mark.parametrize("changes, field", [
    ({"element": "q2"}, "element"), ({"maxh": 0}, "maxh"), ({"maxh": float("nan")}, "maxh"),
    ({"tip_h": True}, "tip_h"), ({"grading": 1.5}, "grading"), ({"order": True}, "order"),
    ({"order": 2.5}, "order"), ({"element": "peers", "order": 2}, "order"), ({"crack_model": "glued"}, "crack_model"),
    ({"qp_solver": "nope"}, "qp_solver"), ({"linear_solver": "lapack"}, "linear_solver"), ({"schur": 1}, "schur"),
    ({"friction_method": "bisection"}, "friction_method"), ({"tangential": "yes"}, "tangential"),
    ({"max_dof": 2.5}, "max_dof"), ({"max_dof": 0}, "max_dof"), ({"adapt": 1.0}, "adapt"), ({"hp": -1}, "hp"),
    ({"qp_options": "fast"}, "qp_options"),
])
def test_bad_options_are_refused_naming_the_field(changes, field):
    with pytest.raises(ValueError, match=field):
        SolveOptions.of(**changes)


def test_options_accept_numpy_numbers_and_refuse_unknown_names():
    o = SolveOptions.of(maxh=np.float32(0.25), max_dof=np.int64(200000), order=np.int64(2), element="bdm")
    assert o.maxh == pytest.approx(0.25) and o.max_dof == 200000 and o.order == 2
    assert isinstance(o.maxh, float) and isinstance(o.max_dof, int)
    assert SolveOptions.of(max_dof=2e5).max_dof == 200000
    with pytest.raises(TypeError, match="mxah"):
        SolveOptions.of(mxah=0.1)


def test_solve_takes_a_scene_name_and_refuses_anything_else():
    sol = nc.solve("griffith", maxh=4.0)
    assert sol.scene.name == "griffith" and sol.tips
    for bad in (None, 3, ["griffith"]):
        with pytest.raises(TypeError, match="scene"):
            nc.solve(bad)
    with pytest.raises(TypeError, match="loads"):
        nc.solve("griffith", loads="abc")
    with pytest.raises(TypeError, match="warm_start"):
        nc.solve("griffith", warm_start="abc")


def test_what_an_element_cannot_solve_is_refused_before_any_meshing(scene):
    """h1p1 at nu = 1/2 in plane strain: an InputError naming material.nu and the elements
    that can, raised by Pipeline.check (0 meshes, 0 assemblies)."""
    pipe = Pipeline()
    incompressible = scene.with_(nu=0.5, plane="strain")
    with pytest.raises(nc.InputError, match=r"material\.nu = 0\.5.*allowed elements at nu = 0\.5: peers, bdm, tdnns"):
        pipe.run(incompressible, SolveOptions(element="h1p1", **COARSE))
    assert pipe.counts["mesh"] == 0 and pipe.counts["assemble"] == 0


def test_every_family_implements_the_methods_the_stages_call():
    """Every family's Discretization overrides each method of the base class that the
    stages and the condensed system call (none is an optional attribute)."""
    from ngcrack.core.discretization import Discretization
    from ngcrack.planar.elements import base, h1, tdnns

    methods = ("fields", "boundary_values", "traction", "constraint_map", "constraint_positions", "crack_jumps",
               "tangential_jump", "held_mean_rows")
    for cls in (base.WeaklySymmetricHybrid, tdnns.TdnnsDiscretization, h1.H1Discretization):
        missing = [m for m in methods if getattr(cls, m) is getattr(Discretization, m)]
        assert missing == [], f"{cls.__name__} does not implement {missing}"


#: a tiny 3D body: a penny crack in a box, order 1, coarse (about 50 000 unknowns)
TINY_3D = {
    "name": "penny-tiny",
    "domain": {"box": [[-4.0, -4.0, -4.0], [4.0, 4.0, 4.0]]},
    "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}],
    "material": {"E": 1000.0, "nu": 0.3},
    "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                 "zmax": {"type": "traction", "value": [0.0, 0.0, 1.0]}},
    "mesh": {"maxh": 4.0, "crack_h": 0.8, "front_h": 0.5},
}


def _tiny_3d(t: float):
    import copy

    from ngcrack.solid.scene import SolidScene

    d = copy.deepcopy(TINY_3D)
    d["boundary"]["zmax"]["value"] = [0.0, 0.3 * t, t]
    return SolidScene.from_dict(d)


def test_a_3d_body_runs_through_the_same_stages_and_a_new_load_rebuilds_the_load_only():
    """A 3D scene through a kept Pipeline: a new load value re-assembles the load vector only
    (1 mesh, 1 assembly, 1 condensation); the answer equals a fresh solve's exactly, and
    under tension (every face open: a linear solve) doubling the load doubles every unknown."""
    pipe = Pipeline()
    first = nc.solve(_tiny_3d(1.0), pipeline=pipe, fronts=False)
    assert pipe.counts == {"mesh": 1, "assemble": 1, "load": 0, "condense": 1, "factorize": 0}
    shut = nc.solve(_tiny_3d(-0.5), pipeline=pipe, fronts=False)  # compression: every face closes
    assert pipe.counts == {"mesh": 1, "assemble": 1, "load": 1, "condense": 1, "factorize": 0}
    assert pipe.redone == ["load vector"]
    fresh = nc.solve(_tiny_3d(-0.5), fronts=False)
    assert np.max(np.abs(shut.y - fresh.y)) <= 1e-12 * np.max(np.abs(fresh.y))
    assert shut.contact.active.all() and max(shut.kkt.values()) < 1e-10
    double = nc.solve(_tiny_3d(2.0), pipeline=pipe, fronts=False)
    assert pipe.counts["load"] == 2 and pipe.counts["assemble"] == 1 and pipe.counts["mesh"] == 1
    assert not first.contact.active.any()
    assert np.max(np.abs(double.y - 2.0 * first.y)) <= 1e-12 * np.max(np.abs(double.y))
