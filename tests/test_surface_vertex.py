"""The mesh refined where a surface crack's front meets the body's surface (benchmarks/surface_vertex.py), and what
it does to K_I near the surface of the slender a/c = 0.2, a/t = 0.5 crack. BENCHMARKS, "The vertex where the front
meets the surface"."""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from benchmarks.newman_raju import surface_scene
from benchmarks.surface_vertex import surface_vertices, vertex_edges, vertex_parameters
from ngcrack.solid import geometry
from ngcrack.solid.scene import SolidScene
from ngcrack.studies.newman_raju import surface_crack_K


def test_the_points_where_the_front_meets_the_surface():
    """A semi-ellipse centred on the face z = t ends at (+-c, 0, t); the same crack centred on the edge x = -b (a
    quarter-elliptical corner crack) at (-b + c, 0, t) on the top face and (-b, 0, t - a) on the side face."""
    a, c, t, b = 0.6, 3.0, 1.2, 15.0
    scene = surface_scene(0.2, 0.5, a)
    v = surface_vertices(scene.domain, scene.cracks[0])
    assert np.allclose(sorted(v.tolist()), [[-c, 0.0, t], [c, 0.0, t]], atol=1e-6)
    d = scene.to_dict()
    d["crack"][0]["center"] = [-b, 0.0, t]
    corner = SolidScene.from_dict(d)
    v = surface_vertices(corner.domain, corner.cracks[0])
    assert np.allclose(sorted(v.tolist()), [[-b, 0.0, t - a], [-b + c, 0.0, t]], atol=1e-3)


def test_the_mesh_is_refined_at_the_vertices(monkeypatch):
    """a/c = 1, a/t = 0.2 at front_h = a/3: the tetrahedra touching the front's ends have edges of 1.5-2 front_h
    without the ball and at most 0.8 front_h with front_h / 2 within 2 front_h of them."""
    scene = surface_scene(1.0, 0.2, 0.6, 1 / 3)
    plain = vertex_edges(geometry.make_mesh(scene, curve=0)) / scene.mesh_sizes()["front_h"]
    monkeypatch.setattr(geometry, "meshing_parameters", vertex_parameters(geometry.meshing_parameters, 2.0, 2.0))
    fine = vertex_edges(geometry.make_mesh(scene, curve=0)) / scene.mesh_sizes()["front_h"]
    assert plain > 1.2 and fine < 0.8, (plain, fine)


@pytest.mark.slow
def test_vertex_refinement_leaves_the_slender_shortfall(monkeypatch):
    """a/c = 0.2, a/t = 0.5, front_h = a/6 with front_h / 2 within 3 front_h of the front's ends: K_I at the first
    station (21 deg from either end) rises from -9.8% (no ball) to -7.2% against Newman and Raju's equation and stays more than 5%
    below it; the deepest point within 1% of the equation (measured -0.3%)."""
    monkeypatch.setattr(geometry, "meshing_parameters", vertex_parameters(geometry.meshing_parameters, 3.0, 2.0))
    a, c, t = 0.6, 3.0, 1.2
    sol = nc.solve(surface_scene(0.2, 0.5, a, 1 / 6))
    f = sol.fronts[0]
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    err = f.K_I / surface_crack_K(1.0, a, c, t, 5.0 * c, phi) - 1
    off = np.minimum(phi, math.pi - phi)  # from the nearer surface end
    first = np.flatnonzero((off > math.radians(15)) & (off < math.radians(25)))
    assert len(first) == 2 and np.all((err[first] > -0.09) & (err[first] < -0.05)), err[first]
    assert abs(err[int(np.argmin(np.abs(f.points[:, 0])))]) < 0.01
