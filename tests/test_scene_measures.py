"""The scene's plane measures on numpy give shapely's (GEOS's) numbers bit for bit.

A scene is validated without importing shapely (a tenth of a small solve's CPU at
import): the distances from points to segments and between segments, the strict
point-in-region test and the interior point of a polygon are GEOS's formulas on numpy.
Each is compared here with shapely on random data, exactly (array_equal); and the planar
checks answer the same with and without shapely's spatial index.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from ngcrack.planar.scene import SceneError, measures, planar


def _star(rng, n: int, rounded: bool) -> list[tuple[float, float]]:
    ang = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))
    rad = rng.uniform(0.5, 2.0, n)
    P = np.c_[rad * np.cos(ang), rad * np.sin(ang)] + rng.normal(size=2)
    return [tuple(map(float, p)) for p in (np.round(P, 1) if rounded else P)]


def test_distances_equal_shapely_bitwise():
    rng = np.random.default_rng(1)
    scale = 10.0 ** rng.integers(-3, 3, size=(4000, 1))
    X, A, B, C = (rng.normal(size=(4000, 2)) * scale for _ in range(4))
    B[:300] = A[:300]  # zero-length segments
    C[300:600] = A[300:600]  # segments sharing an end
    lines = shapely.linestrings(np.stack([A, B], axis=1))
    assert np.array_equal(measures.point_segment_distances(X, A, B), shapely.distance(shapely.points(X), lines))
    other = shapely.linestrings(np.stack([C, X], axis=1))
    assert np.array_equal(measures.segment_distances(A, B, C, X), shapely.distance(lines, other))
    for k in range(300, 4000, 37):  # one pair at a time, in floats (the checks' loops)
        assert measures.point_segment_distance(X[k], A[k], B[k]) == shapely.Point(X[k]).distance(
            shapely.LineString([A[k], B[k]]))


def test_inside_and_interior_point_equal_shapely():
    rng = np.random.default_rng(2)
    checked = 0
    for k in range(150):
        poly = _star(rng, int(rng.integers(3, 12)), rounded=k % 3 == 0)
        shape = shapely.Polygon(poly)
        if not shape.is_valid:
            continue
        checked += 1
        rp = shape.representative_point()
        assert measures.interior_point(poly) == (rp.x, rp.y)
        X = rng.normal(size=(100, 2)) * 2.0
        X[:15] = np.asarray(poly)[rng.integers(0, len(poly), 15)]  # vertices: on the boundary, not inside
        assert np.array_equal(measures.in_region(X, [poly]), shapely.contains_xy(shape, X[:, 0], X[:, 1]))
    assert checked > 100
    outer, hole = [(0, 0), (10, 0), (10, 10), (0, 10)], [(2, 2), (2, 5), (5, 5), (5, 2)]
    shape = shapely.Polygon(outer, [hole])
    rp = shape.representative_point()
    assert measures.interior_point(outer, [hole]) == (rp.x, rp.y)
    X = rng.uniform(-1.0, 11.0, size=(500, 2))
    assert np.array_equal(measures.in_region(X, [outer, hole]), shapely.contains_xy(shape, X[:, 0], X[:, 1]))


def test_diameter_of_many_points_is_that_of_every_pair():
    P = np.random.default_rng(3).normal(size=(300, 2))
    every = max(float(np.hypot(*(p - q))) for p in P for q in P)
    assert measures.diameter(P) == every


@pytest.mark.parametrize("limit", [planar.BRUTE_FORCE_PAIRS, 0])
def test_planar_checks_answer_the_same_with_the_spatial_index(monkeypatch, limit):
    """limit 0: every search through shapely's STRtree, as for a large scene."""
    monkeypatch.setattr(planar, "BRUTE_FORCE_PAIRS", limit)
    square = [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]
    walls = planar.Walls([(square, ("a", "b", "c", "d"), "domain.polygon")])
    P = np.array([[1.0, 1.0], [4.0, 2.0], [5.0, 5.0], [2.0, 3.9]])
    assert np.allclose(walls.distance(P), [1.0, 0.0, np.hypot(1.0, 1.0), 0.1])
    assert walls.nearest_edge(P[[0, 3]]).tolist()[1] == 2
    assert walls.inside(P).tolist() == [True, False, False, True]
    planar.check_crack_in_domain(walls, [(0.0, 2.0), (2.0, 2.0)], "crack[0]", 1e-9)
    ell = planar.Walls([([(0, 0), (4, 0), (4, 2), (2, 2), (2, 4), (0, 4)], tuple("abcdef"), "domain.polygon")])
    with pytest.raises(SceneError, match="crosses edge 2 'c'"):
        planar.check_crack_in_domain(ell, [(3.0, 1.5), (1.5, 3.0)], "crack[0]", 1e-9)
    with pytest.raises(SceneError, match="cross, touch or overlap"):
        planar.check_polyline_simple([(0, 0), (2, 2), (2, 0), (0, 2)], "domain.polygon", 1e-9, closed=True, what="edge")
    with pytest.raises(SceneError, match="crosses or touches"):
        planar.check_cracks_disjoint([[(1.0, 1.0), (3.0, 1.0)], [(2.0, 0.5), (2.0, 1.5)]], 1e-9)
    with pytest.raises(SceneError, match="only .* wide"):
        planar.check_gaps(walls, [[(1.0, 2.0), (3.0, 2.0)], [(1.0, 2.001), (3.0, 2.001)]], 4.0 * 2**0.5, 1e-9)
