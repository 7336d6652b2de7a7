"""KKT residuals where the constraints live (solve.py, contact.py).

`sol.kkt` measures the discrete Signorini conditions at the QP's constraint points
(edge mid points for P0 jumps, edge end points for P1 jumps, crack nodes for the h1
baselines) with the constrained values w = G j of the answer and the contact forces
lam computed from the residual of the solved system, not taken from the QP solver.
For a contact answer every figure must be round-off small, for every element; the
mid-point figures are a diagnostic in `sol.kkt_sampled`.

Run with `-s` to see the measured numbers (lines starting with "[kkt]").
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.core.constraints import KKT_KEYS, kkt_at_constraints
from ngcrack.planar.elements import ELEMENTS

#: what certifies an answer: every kkt figure at most this (the issue's bound)
KKT_BOUND = 1e-10
#: small meshes: the whole file runs in about a minute on 2 cores
MESH = {"paper-1": {"maxh": 0.2}, "paper-2": {"maxh": 0.2}, "griffith": {"maxh": 2.0}}


@functools.cache
def solved(name: str, element: str, crack_model: str = "contact"):
    return nc.solve(nc.scenes.load(name), element=element, crack_model=crack_model, **MESH.get(name, {"maxh": 0.3}))


@pytest.mark.parametrize("element", ELEMENTS)
@pytest.mark.parametrize("name", sorted(MESH))
def test_kkt_at_the_constraint_points_is_round_off(name, element):
    sol = solved(name, element)
    print(f"[kkt] {name} {element}: kkt {sol.kkt}; sampled {sol.kkt_sampled}")
    assert set(sol.kkt) == set(sol.kkt_sampled) == set(KKT_KEYS)
    assert max(sol.kkt.values()) <= KKT_BOUND
    assert sol.kkt["friction"] == 0.0 and sol.kkt_sampled["friction"] == 0.0
    # the forces from the system's residual are the QP's multipliers (up to the QP's
    # round-off in S, relative to the crack's force scale)
    lam, mult = sol.forces, sol.qp.multiplier
    scale = max(np.abs(mult).max(), np.abs(lam).max(), 1e-300)
    assert len(lam) == len(sol.qp.w)
    assert np.abs(lam - mult).max() <= 1e-6 * scale or np.abs(lam - mult).max() <= 1e-12


def test_paper_1_mid_points_and_constraint_points_differ_for_p1_jumps():
    """bdm's P1 jump sampled on the edge where contact ends: the sampled figure is not round-off."""
    sol = solved("paper-1", "bdm")
    print(f"[kkt] paper-1 bdm: complementarity {sol.kkt['complementarity']:.1e} (constraint points), "
          f"{sol.kkt_sampled['complementarity']:.1e} (mid points)")
    assert sol.kkt["complementarity"] <= KKT_BOUND
    assert sol.kkt_sampled["complementarity"] >= 1e-5  # measured 2.9e-3 at maxh 0.2


def test_free_crack_reports_its_penetration_and_bonded_its_tension():
    free = solved("uniaxial-compression", "bdm", "free")
    bonded = solved("tension-open", "bdm", "bonded")
    contact = solved("uniaxial-compression", "bdm")
    print(f"[kkt] free {free.kkt}; bonded {bonded.kkt}; contact {contact.kkt}")
    assert free.kkt["max_penetration"] >= 0.5 and free.kkt["max_tension"] <= KKT_BOUND
    assert bonded.kkt["max_tension"] >= 0.1 and bonded.kkt["max_penetration"] == 0.0
    assert max(contact.kkt.values()) <= KKT_BOUND


def test_no_crack_reports_zeros():
    sol = solved("no-crack", "bdm")
    assert sol.kkt == sol.kkt_sampled == dict.fromkeys(KKT_KEYS, 0.0)
    assert sol.forces is None


def test_kkt_formula_sees_each_violation():
    w = np.array([0.0, 0.0, 1.0, 2.0])
    lam = np.array([3.0, 1.0, 0.0, 0.0])
    assert max(kkt_at_constraints(w, lam, 2.0).values()) == 0.0
    k = kkt_at_constraints(np.array([-1e-3, 0.0, 1.0, 2.0]), lam, 2.0)
    assert k["max_penetration"] == pytest.approx(5e-4)
    k = kkt_at_constraints(w, np.array([3.0, 1.0, -0.03, 0.0]), 2.0)
    assert k["max_tension"] == pytest.approx(0.01) and k["complementarity"] == pytest.approx(0.03 / 6)
    # within its rounding bound a force counts as zero, beyond it not
    k = kkt_at_constraints(w, np.array([3.0, 1.0, -0.03, 0.0]), 2.0, lam_bound=np.array([0, 0, 0.01, 0]))
    assert k["max_tension"] == pytest.approx(0.02 / 3)
    # nothing open and nothing pressed: relative to the body's scales
    k = kkt_at_constraints(np.array([-1e-20, 0.0]), np.array([0.0, 0.0]), 0.0, jump_scale=1e-3, force_scale=2.0)
    assert k["max_penetration"] == pytest.approx(1e-17) and k["max_tension"] == 0.0


def test_a_wrong_contact_state_shows(monkeypatch):
    """kkt is not vacuous: hold one open point of griffith closed and the tension shows."""
    import ngcrack.core.contact as contact
    import ngcrack.core.crack_problem as problems  # the crack problem's dense strategy calls the QP
    true_qp = contact.solve_qp

    def wrong_qp(*args, **kwargs):
        r = true_qp(*args, **kwargs)
        k = int(np.argmax(r.w))  # the widest-open point, held shut
        r.w[k] = 0.0
        r.active = np.sort(np.append(r.active, k))
        G = kwargs.get("G")
        r.j = np.linalg.solve(G, r.w) if G is not None else r.w.copy()
        return r

    monkeypatch.setattr(problems, "solve_qp", wrong_qp)
    sol = nc.solve(nc.scenes.load("griffith"), element="bdm", maxh=2.0)
    print(f"[kkt] griffith bdm with one open point held shut: {sol.kkt}")
    assert sol.kkt["max_tension"] >= 0.1
