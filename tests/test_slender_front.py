"""K_I near the free surface of surface cracks: the domain integral against extractions and closed forms it does not use.

- the crack's opening behind every station of the front (`newman_raju.front_opening_K_I`: the jump read along the
  station's in-plane normal) against the domain integral, on the built-in surface crack (default suite) and on the
  slender a/c = 0.2, a/t = 0.5 crack near its surface (slow);
- the slender crack's half-ellipse with the face it crosses on rollers (a symmetry plane: half of an embedded
  ellipse, `benchmarks.slender_front.mirror_scene`) against Irwin's closed form at the same stations, the same
  curvature and the same open-front code path (slow).
BENCHMARKS, "Slender cracks near the surface: our extraction checked".
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.studies.newman_raju import front_opening_K_I, surface_crack_K


@pytest.mark.slow
def test_the_opening_along_the_front_of_the_built_in_surface_crack():
    """Every station off the surface of `surface-crack` (a/c = 0.6, a/t = 0.4): the opening's K_I within 6% of the
    domain integral's and 3% on average along the front (measured: -5.2% to +1.0%, -2.2% on average; the order-1
    displacement near the front scatters the opening's fit), the domain integral within Newman and Raju's stated
    5% of their equation (measured -0.4% to -3.4%)."""
    sol = nc.solve(nc.scenes.load("surface-crack"))
    f = sol.fronts[0]
    a, c, t, b = 0.6, 1.0, 1.5, 5.0
    phi = np.arctan2((t - f.points[:, 2]) / a, f.points[:, 0] / c)
    ref = surface_crack_K(1.0, a, c, t, b, phi)
    K_open = front_opening_K_I(sol)
    inner = np.arange(1, len(phi) - 1)
    assert np.all(np.isfinite(K_open[inner]))
    ratio = K_open[inner] / f.K_I[inner]
    assert np.max(np.abs(ratio - 1)) < 0.06 and abs(np.mean(ratio) - 1) < 0.03, ratio
    assert np.max(np.abs(f.K_I[inner] / ref[inner] - 1)) < 0.05


@pytest.mark.slow
def test_slender_surface_crack_near_the_surface_opening_agrees():
    """a/c = 0.2, a/t = 0.5 at front_h = a/6: at the stations 17-45 deg from the surface the opening's K_I agrees with
    the domain integral's within 5% (measured 0.8% at 21 deg, 0.5-3.3% at 29-42 deg), and both sit 3-12% below
    Newman and Raju's equation (measured -9.8%, -6.7%, -5.6%, -3.6%): the shortfall is in the solution, not the
    integral's."""
    from benchmarks.newman_raju import surface_scene

    a, c, t = 0.6, 3.0, 1.2
    sol = nc.solve(surface_scene(0.2, 0.5, a, 1 / 6))
    f = sol.fronts[0]
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    sel = np.flatnonzero((phi > math.radians(15)) & (phi < math.radians(45)))
    assert len(sel) >= 3
    K_open = front_opening_K_I(sol)[sel]
    K = f.K_I[sel]
    assert np.max(np.abs(K_open / K - 1)) < 0.05, K_open / K
    err = K / surface_crack_K(1.0, a, c, t, 5.0 * c, phi[sel]) - 1
    assert np.all((err > -0.12) & (err < -0.03)), err


@pytest.mark.slow
def test_slender_half_ellipse_on_a_symmetry_plane_follows_irwin():
    """The same crack and mesh with the face it crosses on rollers (t = 4a): half of an embedded ellipse b/a = 0.2.
    Every station off the surface (from 21 deg on either side) within 4.5% of Irwin's K_I times Newman and Raju's
    finite-size factor of the embedded crack (measured -3.4% and -3.9% at 21 deg, where the front's curvature is
    0.63/a, and -1.0% to -3.1% elsewhere), and K / Irwin flat along the front within 4% (measured 0.984-1.017): the first
    station is not the 10% low the free face's is."""
    from benchmarks.slender_front import embedded_F_factor, irwin_K_I, mirror_scene

    a, c, t = 0.6, 3.0, 2.4
    sol = nc.solve(mirror_scene(6.0, a))
    f = sol.fronts[0]
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    sel = np.flatnonzero((phi > math.radians(15)) & (phi < math.radians(165)))  # both halves, not the surface points
    irwin = irwin_K_I(a / c, phi[sel]) * math.sqrt(c)
    err = f.K_I[sel] / (irwin * embedded_F_factor(a / c, a / t, 0.2, phi[sel])) - 1
    assert np.max(np.abs(err)) < 0.045, err
    ratio = f.K_I[sel] / irwin
    assert ratio.max() - ratio.min() < 0.04, ratio
