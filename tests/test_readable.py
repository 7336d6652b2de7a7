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
