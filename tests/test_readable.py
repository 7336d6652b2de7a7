"""What a user reads and gets: a Solution printed in a few lines, the error estimate's line
saying why it is large as nu -> 1/2, and output files with the user's usual mode."""

from __future__ import annotations

import math
import os
import warnings

import pytest

import ngcrack as nc
from ngcrack.files import Staged, atomic_write

COARSE = {"element": "bdm", "maxh": 2.0, "crack_h": 0.4, "tip_h": 0.08}


@pytest.fixture(scope="module")
def griffith():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a coarse mesh on purpose
        return {nu: nc.solve(nc.scenes.load("griffith").with_(nu=nu), **COARSE) for nu in (0.3, 0.4999)}


def test_a_solution_prints_in_a_few_lines(griffith):
    sol = griffith[0.3]
    text = repr(sol)
    assert 3 <= len(text.splitlines()) <= 8 and len(text) < 1000
    assert "griffith" in text and "bdm" in text and "K_I" in text
    assert sol.estimate_pending or "error estimate" in text
    sol.error_estimate  # noqa: B018
    assert f"relative {sol.error_estimate.relative:.2%}" in repr(sol)
    assert len(repr(sol.error_estimate).splitlines()) <= 2


def test_the_estimate_says_why_it_is_large_near_incompressibility(griffith):
    low, high = griffith[0.3].error_estimate, griffith[0.4999].error_estimate
    assert low.incompressible_note == "" and "\n" not in low.line()
    lam_over_mu = 2 * 0.4999 / (1 - 2 * 0.4999)  # plane strain
    assert high.lame_ratio == pytest.approx(lam_over_mu, rel=1e-9)
    assert "sqrt(lambda/mu)" in high.line() and f"{math.sqrt(lam_over_mu):.3g}" in high.line()
    assert high.incompressible_note in high.notes
    # the number is inflated while K_I stays where it was at nu = 0.3 (the plate's K_I does
    # not depend on nu in plane strain under a traction load)
    assert high.relative > 2 * low.relative
    k_low, k_high = griffith[0.3].tips[0].K_I, griffith[0.4999].tips[0].K_I
    assert abs(k_high / k_low - 1) < 0.02


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    try:
        yield
    finally:
        os.umask(old)


def test_output_files_get_the_users_mode(tmp_path, umask_022):
    path = atomic_write(tmp_path / "a.json", lambda tmp: open(tmp, "w").write("{}"))
    assert path.stat().st_mode & 0o777 == 0o644
    with Staged() as staged:
        staged.write(tmp_path / "b.txt", lambda tmp: open(tmp, "w").write("b"))
    assert (tmp_path / "b.txt").stat().st_mode & 0o777 == 0o644
    os.umask(0o077)
    path = atomic_write(tmp_path / "c.txt", lambda tmp: open(tmp, "w").write("c"))
    assert path.stat().st_mode & 0o777 == 0o600


#: the estimate's effectivity (estimate / true energy error against a 4x finer solve, which
#: agrees with a 6x finer one to 1%) of bdm on coarse graded meshes (maxh 4, crack_h 0.4,
#: tip_h 0.04), measured: it grows from about 1.3-1.5 at nu = 0.3 to 36-48 at nu = 0.4999,
#: below sqrt(lambda/mu) = 70.7 as the printed line says, while K_I moves by under 0.1%
EFFECTIVITY = {("griffith", 0.3): 1.28, ("griffith", 0.4999): 36.2,
               ("inclined-compression", 0.3): 1.50, ("inclined-compression", 0.4999): 48.2}
EFF_COARSE = {"maxh": 4.0, "tip_h": 0.04, "crack_h": 0.4}
EFF_FINE = {"maxh": 1.0, "tip_h": 0.005, "crack_h": 0.05}


@pytest.mark.parametrize("name", ["griffith", "inclined-compression"])
def test_effectivity_as_nu_tends_to_one_half(name):
    from ngcrack.estimate import energy_error_against

    eff, k_first = {}, {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for nu in (0.3, 0.4999):
            scene = nc.scenes.load(name).with_(nu=nu)
            sol = nc.solve(scene, element="bdm", **EFF_COARSE)
            eff[nu] = sol.error_estimate.energy / energy_error_against(sol, nc.solve(scene, element="bdm", **EFF_FINE))
            k_first[nu] = sol.tips[0].K_I if name == "griffith" else sol.tips[0].K_II
            assert eff[nu] == pytest.approx(EFFECTIVITY[(name, nu)], rel=0.1)
            assert 1.0 <= eff[nu] <= math.sqrt(2 * nu / (1 - 2 * nu)) + 1.0  # the printed line's bound
    assert abs(k_first[0.4999] / k_first[0.3] - 1) < 0.01  # K stays where it was
