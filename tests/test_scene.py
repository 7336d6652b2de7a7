"""Scene validation, TOML round trips, parts and the rigid-motion check (no meshing)."""

import math

import pytest

from ngcrack import scenes
from ngcrack.planar.scene import GEOMETRY_RTOL, BoundaryCondition, Crack, Material, Scene, SceneError

SQUARE = [[0, 0], [4, 0], [4, 1], [0, 1]]
LABELS = ["bottom", "right", "top", "left"]


def base(**overrides):
    """A valid scene as the TOML structure: paper-2's beam, clamped left and right."""
    d = {
        "name": "t",
        "domain": {"polygon": SQUARE, "labels": LABELS},
        "crack": [{"points": [[1, 0.5], [3, 0.5]]}],
        "material": {"E": 206900.0, "nu": 0.3},
        "load": {"body_force": [0.0, -1.0]},
        "boundary": {"left": {"type": "clamped"}, "right": {"type": "clamped"}},
        "mesh": {"maxh": 0.1},
    }
    d.update(overrides)
    return d


def refused(d, *fragments):
    """Assert that building the scene raises SceneError naming all ``fragments``."""
    with pytest.raises(SceneError) as info:
        Scene.from_dict(d)
    msg = str(info.value)
    assert isinstance(info.value, ValueError)
    assert "\n" not in msg
    for f in fragments:
        assert f in msg, f"{f!r} not in {msg!r}"
    return msg


def test_base_is_valid():
    s = Scene.from_dict(base())
    assert s.material == Material(206900.0, 0.3, "strain")
    assert s.cracks == (Crack(((1.0, 0.5), (3.0, 0.5))),)
    assert s.boundary["left"] == BoundaryCondition("clamped")


# ---------------------------------------------------------------- material and mesh


@pytest.mark.parametrize("nu", [0.5000001, -1, -1.5, float("nan"), 0.7])
def test_nu_outside_range(nu):
    refused(base(material={"E": 1.0, "nu": nu}), "material.nu", "(-1, 1/2]")


def test_nu_half_is_accepted():
    assert Scene.from_dict(base(material={"E": 1.0, "nu": 0.5})).material.nu == 0.5


@pytest.mark.parametrize("E", [0, -206900.0, float("inf")])
def test_E_not_positive(E):
    refused(base(material={"E": E, "nu": 0.3}), "material.E", "> 0")


def test_plane_unknown():
    refused(base(material={"E": 1.0, "nu": 0.3, "plane": "axisymmetric"}),
            "material.plane", "strain, stress")


@pytest.mark.parametrize("h", [0, -0.1])
def test_maxh_not_positive(h):
    refused(base(mesh={"maxh": h}), "mesh.maxh", "> 0")


def test_tip_h_not_positive():
    refused(base(mesh={"tip_h": 0.0}), "mesh.tip_h", "> 0")


def test_unknown_key_is_refused_with_allowed_keys():
    refused(base(mesh={"maxH": 0.1}), "mesh", "'maxH'", "maxh, tip_h")
    refused(base(solver={}), "'solver'", "allowed keys", "material")


def test_body_force_must_be_two_numbers():
    refused(base(load={"body_force": [0.0, -1.0, 0.0]}), "load.body_force", "2 finite")


# ---------------------------------------------------------------- polygon


def test_polygon_bow_tie_is_not_simple():
    bow = [[0, 0], [1, 1], [1, 0], [0, 1]]
    refused(base(domain={"polygon": bow}, crack=[], boundary={"e0": {"type": "clamped"}}),
            "domain.polygon", "simple")


def test_polygon_clockwise():
    refused(base(domain={"polygon": SQUARE[::-1], "labels": LABELS}),
            "domain.polygon", "clockwise", "counter-clockwise")


def test_polygon_repeated_vertex():
    refused(base(domain={"polygon": SQUARE + [[0, 0]]}, crack=[],
                 boundary={"e0": {"type": "clamped"}}),
            "domain.polygon", "zero length", "do not repeat the first vertex")


def test_labels_count_must_match_edges():
    refused(base(domain={"polygon": SQUARE, "labels": LABELS[:3]}),
            "domain.labels", "3 labels for 4 edges")


def test_default_labels_and_duplicate_labels():
    s = Scene.from_dict(base(domain={"polygon": SQUARE}, boundary={"e3": {"type": "clamped"}}))
    assert s.labels == ("e0", "e1", "e2", "e3")
    # two edges sharing the label "side": clamping "side" clamps both
    s = Scene.from_dict(base(domain={"polygon": SQUARE,
                                     "labels": ["bottom", "side", "top", "side"]},
                             boundary={"side": {"type": "clamped"}}))
    assert [lab for lab, _, _ in s.edges()].count("side") == 2


# ---------------------------------------------------------------- cracks


def test_crack_leaving_the_domain():
    msg = refused(base(crack=[{"points": [[1, 0.5], [5, 0.5]]}]), "crack[0].points")
    assert "outside domain.polygon" in msg and "inside the polygon" in msg
    # a crack between the two arms of an L's notch: both ends on the boundary, the
    # segment outside
    ell = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]
    held = {"e0": {"type": "clamped"}}
    refused(base(domain={"polygon": ell}, crack=[{"points": [[1, 1.5], [1.5, 1]]}],
                 boundary=held), "crack[0].points", "leaves the domain", "inside the polygon")
    # both points inside, the segment crossing the notch
    refused(base(domain={"polygon": ell}, crack=[{"points": [[1.5, 0.9], [0.9, 1.5]]}],
                 boundary=held), "crack[0].points", "crosses edge 2", "inside the polygon")


def test_crack_running_along_or_touching_the_boundary():
    refused(base(crack=[{"points": [[1, 0], [3, 0]]}]), "crack[0].points", "runs along")
    # interior point on the boundary
    refused(base(crack=[{"points": [[1, 0.5], [2, 1], [3, 0.5]]}]),
            "crack[0].points[1]", "strictly inside")
    # a segment grazing the reflex vertex (1, 1) of an L-shaped domain
    ell = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]
    held = {"e0": {"type": "clamped"}}
    refused(base(domain={"polygon": ell}, crack=[{"points": [[0.5, 1.5], [1.5, 0.5]]}],
                 boundary=held), "crack[0].points", "touches edge", "at (1, 1)")
    # ending at that vertex is fine
    s = Scene.from_dict(base(domain={"polygon": ell}, crack=[{"points": [[0.5, 0.5], [1, 1]]}],
                             boundary=held))
    assert s.tip_points() == [(0, (0.5, 0.5))]


def test_crack_crossing_itself():
    zigzag = [[1, 0.2], [3, 0.8], [3, 0.2], [1, 0.8]]
    refused(base(crack=[{"points": zigzag}]), "crack[0].points", "must not cross")
    # folding back onto itself
    refused(base(crack=[{"points": [[1, 0.5], [3, 0.5], [2, 0.5]]}]),
            "crack[0].points", "must not cross")


def test_two_cracks_crossing():
    cracks = [{"points": [[1, 0.5], [3, 0.5]]}, {"points": [[2, 0.2], [2, 0.8]]}]
    refused(base(crack=cracks), "crack[1].points", "crack[0]", "disjoint")
    touching = [{"points": [[1, 0.5], [3, 0.5]]}, {"points": [[3, 0.5], [3.5, 0.8]]}]
    refused(base(crack=touching), "crack[1].points", "disjoint")


def test_zero_length_crack_segment():
    refused(base(crack=[{"points": [[1, 0.5], [2, 0.5], [2, 0.5], [3, 0.5]]}]),
            "crack[0].points", "segment 1", "zero length", "must differ")
    refused(base(crack=[{"points": [[1, 0.5]]}]), "crack[0].points", "2 or more points")


def test_crack_end_points_on_the_boundary_are_allowed():
    s = Scene.from_dict(base(crack=[{"points": [[1, 0], [1.5, 0.5], [2, 0.5]]}]))
    assert s.crack_end_on_boundary(0) == (True, False)
    assert s.tip_points() == [(0, (2.0, 0.5))]
    assert len(s.parts()) == 1
    # an edge crack ending at a polygon vertex
    s = Scene.from_dict(base(crack=[{"points": [[4, 1], [3, 0.5]]}]))
    assert s.crack_end_on_boundary(0) == (True, False)


def test_crack_geometry():
    c = Crack([[0, 0], [3, 4], [3, 5]])
    assert c.length == pytest.approx(6.0)
    assert c.arclength_of_segment_start() == pytest.approx([0.0, 5.0])
    assert c.tangents() == [pytest.approx((0.6, 0.8)), pytest.approx((0.0, 1.0))]
    assert c.normals() == [pytest.approx((-0.8, 0.6)), pytest.approx((-1.0, 0.0))]
    assert c.segments == [((0.0, 0.0), (3.0, 4.0)), ((3.0, 4.0), (3.0, 5.0))]


# ---------------------------------------------------------------- boundary


def test_unknown_boundary_label():
    refused(base(boundary={"foo": {"type": "clamped"}}),
            "boundary.foo", "unknown edge label", "allowed labels: bottom, right, top, left")


def test_unknown_boundary_type():
    refused(base(boundary={"left": {"type": "clamped"}, "top": {"type": "glue"}}),
            "boundary.top.type = 'glue'",
            "allowed types are clamped, displacement, roller, traction")


def test_traction_without_value():
    refused(base(boundary={"left": {"type": "clamped"}, "top": {"type": "traction"}}),
            "boundary.top.value", "missing", "[gx, gy]", "omit [boundary.top]")


def test_clamped_with_value_and_displacement_without():
    refused(base(boundary={"left": {"type": "clamped", "value": [0, 0]}}),
            "boundary.left.value", "takes no value", "displacement")
    refused(base(boundary={"left": {"type": "displacement"}}),
            "boundary.left.value", "missing", "[ux, uy]")
    refused(base(boundary={"left": {"type": "displacement", "value": [0, "x"]}}),
            "boundary.left.value", "2 finite numbers")


def test_nothing_holds_the_body():
    refused(base(boundary={}), "boundary", "held by nothing",
            "clamped/displacement/roller", "not unique")
    refused(base(boundary={"top": {"type": "traction", "value": [0, -1]}}),
            "held by nothing")


def test_through_crack_cuts_off_a_piece_that_nothing_holds():
    # paper-1 with only the lower halves clamped: the upper half floats
    d = scenes.load("paper-1").to_dict()
    d["boundary"] = {"left-lower": {"type": "clamped"}, "right-lower": {"type": "clamped"}}
    msg = refused(d, "boundary", "held by nothing")
    # the message names a point of the upper part
    x, y = (float(t) for t in msg.split("point (")[1].split(")")[0].split(","))
    assert 0 < x < 4 and 0.5 < y < 1


def test_roller_scenes():
    square = {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]], "labels": LABELS}
    two = base(domain=square, crack=[],
               boundary={"bottom": {"type": "roller"}, "left": {"type": "roller"}})
    assert Scene.from_dict(two).boundary["left"].type == "roller"
    one = base(domain=square, crack=[], boundary={"bottom": {"type": "roller"}})
    refused(one, "boundary", "only by roller edges (bottom)",
            "translation along (1, 0)", "non-parallel")
    parallel = base(domain=square, crack=[],
                    boundary={"bottom": {"type": "roller"}, "top": {"type": "roller"}})
    refused(parallel, "boundary", "translation along (1, 0)")


def test_roller_on_slanted_edges():
    # a triangle: rollers on two edges whose normals are not parallel hold it
    tri = {"polygon": [[0, 0], [2, 0], [1, 1]], "labels": ["a", "b", "c"]}
    s = Scene.from_dict(base(domain=tri, crack=[],
                             boundary={"b": {"type": "roller"}, "c": {"type": "roller"}}))
    assert len(s.parts()) == 1


def test_parallel_rollers_leave_a_translation():
    # a roller on a straight edge always removes the rotation (v.n = theta s varies along
    # it); rollers on the two slanted sides of a parallelogram leave the slide along them
    para = {"polygon": [[0, 0], [2, 0], [3, 1], [1, 1]], "labels": ["b", "r", "t", "l"]}
    msg = refused(base(domain=para, crack=[],
                       boundary={"r": {"type": "roller"}, "l": {"type": "roller"}}),
                  "boundary", "only by roller edges (r, l)", "translation along (0.707107, 0.707107)")
    assert "non-parallel" in msg
    # a roller on the bottom as well holds it
    s = Scene.from_dict(base(domain=para, crack=[],
                             boundary={"r": {"type": "roller"}, "b": {"type": "roller"}}))
    assert s.boundary["b"].holds == "normal"


# ---------------------------------------------------------------- parts


def test_parts_of_paper_1():
    s = scenes.paper_example(1)
    parts = s.parts()
    assert len(parts) == 2
    assert s.through_cracks() == [0]
    lower, upper = sorted(parts, key=lambda p: p.point[1])
    assert set(lower.labels) == {"left-lower", "bottom", "right-lower"}
    assert set(upper.labels) == {"right-upper", "top", "left-upper"}
    assert lower.area == pytest.approx(2.0) and upper.area == pytest.approx(2.0)
    assert lower.cracks == upper.cracks == (0,)
    assert len(lower.crack_faces) == len(upper.crack_faces) == 1
    assert lower.contains((2, 0.25)) and not lower.contains((2, 0.75))
    assert upper.contains((2, 0.75))


def test_parts_of_a_polyline_through_crack_on_edge_interiors():
    # a kinked crack from the bottom edge to the right edge cuts off the corner (4, 0)
    d = base(crack=[{"points": [[3, 0], [3.2, 0.3], [4, 0.5]]}],
             boundary={"left": {"type": "clamped"}, "right": {"type": "clamped"}})
    s = Scene.from_dict(d)
    parts = s.parts()
    assert len(parts) == 2
    corner = next(p for p in parts if p.contains((3.9, 0.05)))
    rest = next(p for p in parts if p is not corner)
    assert set(corner.labels) == {"bottom", "right"}
    assert set(rest.labels) == {"bottom", "right", "top", "left"}
    assert corner.area + rest.area == pytest.approx(4.0)
    assert len(corner.crack_faces) == 2
    # the corner piece is held by the clamped lower part of the right edge
    bottom_piece = [(p, q) for lab, p, q in corner.pieces if lab == "bottom"]
    assert bottom_piece == [((3.0, 0.0), (4.0, 0.0))]
    # split edges at the crack's boundary end points
    assert len(s.edge_pieces()) == 6


def test_two_through_cracks_make_three_parts():
    d = base(crack=[{"points": [[1, 0], [1, 1]]}, {"points": [[3, 1], [3, 0]]}],
             boundary={"left": {"type": "clamped"}, "right": {"type": "clamped"}})
    msg = refused(d, "held by nothing")  # the middle part touches neither side
    assert "(2, " in msg
    d["boundary"]["bottom"] = {"type": "clamped"}
    s = Scene.from_dict(d)
    assert sorted(round(p.area, 12) for p in s.parts()) == [1.0, 1.0, 2.0]


# ---------------------------------------------------------------- round trips, with_


@pytest.mark.parametrize("name", scenes.names())
def test_builtin_scenes_load_and_round_trip(name):
    s = scenes.load(name)
    assert s.name == name
    assert s.description and "\n" not in s.description
    again = Scene.from_toml_string(s.to_toml_string())
    assert again == s
    assert hash(again) == hash(s)
    assert Scene.from_dict(s.to_dict()) == s


def test_builtin_registry():
    assert {"paper-1", "paper-2", "griffith", "uniaxial-compression", "tension-open",
            "no-crack"} <= set(scenes.names())
    assert dict(scenes.describe())["paper-2"] == scenes.load("paper-2").description
    p2 = scenes.paper_example(2)
    assert p2.material.nu == 0.49 and p2.material.E == 206900.0
    assert p2.cracks[0].points == ((1.0, 0.5), (3.0, 0.5))
    p1 = scenes.paper_example(1)
    assert p1.material.nu == 0.29 and p1.body_force == (0.0, -1.0) and p1.maxh == 0.1
    assert p1.tip_h is None
    assert sorted(p1.boundary) == ["left-lower", "left-upper", "right-lower"]
    with pytest.raises(SceneError, match="allowed values are 1, 2"):
        scenes.paper_example(3)
    g = scenes.load("griffith")
    assert dict(g.exact) == {"kind": "griffith", "a": 1.0, "p": 1.0, "center": (0.0, 0.0)}
    assert g.cracks[0].points[0] == (0.0, 0.0) and g.crack_end_on_boundary(0) == (True, False)


def test_resolve(tmp_path):
    assert scenes.resolve("paper-2") == scenes.paper_example(2)
    f = tmp_path / "mine.toml"
    f.write_text(scenes.load("no-crack").to_toml_string().replace('name = "no-crack"\n', ""))
    s = scenes.resolve(str(f))
    assert s.name == "mine" and s.polygon == scenes.load("no-crack").polygon
    with pytest.raises(SceneError, match="built-in scenes: .*paper-1"):
        scenes.resolve("paper-3")


def test_toml_file_errors(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('name = "x"\n[domain\n')
    with pytest.raises(SceneError, match="not valid TOML"):
        Scene.from_toml(f)
    f.write_text(scenes.load("paper-2").to_toml_string() + "\n[boundary.top]\ntype = 'glue'\n")
    with pytest.raises(SceneError, match=r"boundary\.top\.type = 'glue'"):
        Scene.from_toml(f)


def test_round_trip_keeps_awkward_strings_and_floats():
    s = Scene.from_dict(base(name='a "quoted" name', description="tab\tand ünïcode",
                             domain={"polygon": [[0, 0], [4, 0], [4, 1 / 3], [0, 1 / 3]],
                                     "labels": ["b", "with space", "t", "l"]},
                             crack=[{"points": [[0.1, 1 / 6], [0.7, 1 / 7]]}],
                             boundary={"l": {"type": "clamped"},
                                       "with space": {"type": "traction",
                                                      "value": [1e-17, -2.5e100]}}))
    assert Scene.from_toml_string(s.to_toml_string()) == s


def test_with_validates_and_updates_material():
    s = scenes.paper_example(2)
    t = s.with_(nu=0.5, maxh=0.05, name="p2-incompressible")
    assert t.material == Material(206900.0, 0.5, "strain")
    assert (t.maxh, t.name, t.cracks) == (0.05, "p2-incompressible", s.cracks)
    assert s.material.nu == 0.49  # unchanged
    assert s.with_(plane="stress", E=1.0).material == Material(1.0, 0.49, "stress")
    with pytest.raises(SceneError, match=r"material\.nu = 0\.6: must lie in \(-1, 1/2\]"):
        s.with_(nu=0.6)
    with pytest.raises(SceneError, match="mesh.maxh"):
        s.with_(maxh=-1.0)
    with pytest.raises(SceneError, match="held by nothing"):
        s.with_(boundary={})
    with pytest.raises(SceneError, match="unknown field nuu; allowed: .*nu"):
        s.with_(nuu=0.3)
    u = s.with_(boundary={"left": {"type": "clamped"},
                          "top": BoundaryCondition("traction", (0.0, -1.0))})
    assert u.boundary["top"].value == (0.0, -1.0)


def test_dataclasses_validate_on_construction():
    with pytest.raises(SceneError, match="material.nu"):
        Material(1.0, 0.51)
    with pytest.raises(SceneError, match="allowed types are"):
        BoundaryCondition("glue")
    with pytest.raises(SceneError, match="zero length"):
        Crack([[0, 0], [0, 0]])
    assert GEOMETRY_RTOL < 1e-6


def test_scaled_scene_keeps_friction_and_scales_every_length_and_load():
    """Scene.scaled (one function, also behind stability.scaled_scene): lengths by size,
    E by E, tractions by load, displacements by load*size/E, each crack's friction kept."""
    from ngcrack.studies.stability import scaled_scene

    s = scenes.load("paper-2").with_(friction=0.4, maxh=0.1)
    s = s.with_(boundary={**s.boundary, "bottom": {"type": "displacement", "value": [0.0, 1e-3]}})
    t = s.scaled(E=2.0, load=3.0, size=5.0)
    assert scaled_scene(s, E=2.0, load=3.0, size=5.0) == t
    assert [c.friction for c in t.cracks] == [0.4] * len(s.cracks)
    assert t.diameter == pytest.approx(5.0 * s.diameter, rel=1e-14)
    assert t.maxh == pytest.approx(0.5, rel=1e-14)
    assert t.material.E == pytest.approx(2.0 * s.material.E, rel=1e-14)
    assert t.boundary["bottom"].value[1] == pytest.approx(1e-3 * 3.0 * 5.0 / 2.0, rel=1e-14)
    for lab, bc in s.boundary.items():
        if bc.type == "traction":
            assert t.boundary[lab].value == pytest.approx(tuple(3.0 * v for v in bc.value), rel=1e-14)
    with pytest.raises(SceneError, match=r"scaled\.size"):
        s.scaled(size=0.0)


def test_diameter_is_the_farthest_vertex_pair():
    """The one polygon diameter (convex hull, chunked) against the plain pairwise maximum."""
    import numpy as np

    from ngcrack.planar.scene import diameter

    rng = np.random.default_rng(3)
    for n in (3, 4, 17, 2500):
        P = rng.normal(size=(n, 2))
        brute = max(np.hypot(*(P[i] - P[j])) for i in range(min(n, 300)) for j in range(min(n, 300)))
        if n <= 300:
            assert diameter(P) == pytest.approx(brute, rel=1e-15)
        else:
            full = float(np.max(np.hypot(P[:, None, 0] - P[None, :, 0], P[:, None, 1] - P[None, :, 1])))
            assert diameter(P) == pytest.approx(full, rel=1e-15)
    assert scenes.load("paper-2").diameter == pytest.approx(math.hypot(4, 1), rel=1e-15)
