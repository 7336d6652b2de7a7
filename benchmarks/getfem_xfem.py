"""The XFEM peer: one solve of a straight-crack scene with GetFEM, for benchmarks/getfem_peer.py.

Runs under the system Python with Debian's python3-getfem (not ngcrack's environment):

    /usr/bin/python3 benchmarks/getfem_xfem.py '<json problem>'

and prints one JSON line: unknowns, CPU seconds of the answer ("cpu": from after the
imports to the fields and K) and of measuring it ("cpu_errors"), K_I and K_II at every
interior tip, the profile's relative L2 error against the given reference.

The method (written for this benchmark from GetFEM's documentation: level sets,
`MeshFem('levelset')`, the 'crack' global functions, GWFL's Xfem_plus / Xfem_minus):

* a structured triangle mesh (h from 0.4 down), uniform (size h) in a box around the crack and graded
  geometrically (factor 1.3, cells at most 1) out to the boundary, its lines offset so
  that neither the crack nor a tip lies on one;
* P2 Lagrange displacements enriched by the Heaviside function across the crack (the
  level set's cut elements) and, in a disc of radius `enrich` around every tip, by the
  four crack-tip functions sqrt(r) {sin, cos}(theta / 2) {1, sin theta} times the P1
  partition of unity ("fixed area" enrichment; radius a / 2: on griffith at h = 0.1,
  radii 0.2 a, 0.4 a, 0.5 a, 1 a gave opening errors 1e-3, 2.4e-4, 1.9e-4, 1.7e-4);
* the crack's level sets: the signed distance to its line, and the secondary |s| - a (two
  tips; s the coordinate along the crack from its centre) or the distance past the one tip,
  both exact in P1 where they change sign;
* quadrature: composite rules on the cut elements, a refined composite rule on the
  elements holding a tip, IM_TRIANGLE(6) on every other element;
* supports: rollers (u.n = 0) by penalisation, tractions as source terms;
* crack faces: traction free ("free"), or unilateral contact ("contact"), by a penalty on
  the negative part of the normal jump, gamma * neg_part([u].n) (gamma = 1e6 E / a;
  semi-smooth Newton; the result states the interpenetration, L2 relative to the profile:
  about 6e-7). An augmented Lagrangian with the multiplier on the crack's integration
  points (MeshImData) stops GetFEM 5.4.2 with a segmentation fault, so the penalty is the
  contact used here;
* K_I, K_II: the interaction integral with the Williams fields (K = 1) over the disc of
  radius R = a / 2 around each tip, weight q = 1 for r < 0.4 R falling linearly to 0 at
  r = R, in P1 (a weight whose gradient reaches the tip reads K 10-30% low: the
  quadrature cannot integrate the 1/r integrand there); K_II needs no
  crack-face term for frictionless contact (the mode II field has no normal face
  displacement); K_I of a contact solve does, and is not reported then (None);
* the crack profile ([u].n or [u].t) on the level set's integration points: its
  relative L2 error against the reference, integrated by the same quadrature.
"""

from __future__ import annotations

import json
import math
import sys
import time

import getfem as gf
import numpy as np

BOTTOM, RIGHT, TOP, LEFT = 1, 2, 3, 4
GROWTH, CELL_MAX = 1.3, 1.0


def graded(lo: float, hi: float, f_lo: float, f_hi: float, h: float, offset: float) -> np.ndarray:
    """Grid lines of [lo, hi]: spacing h on [f_lo, f_hi] (lines at offset + k h), growing by GROWTH outside."""
    k0, k1 = math.ceil((f_lo - offset) / h), math.floor((f_hi - offset) / h)
    fine = offset + h * np.arange(k0, k1 + 1)
    fine = fine[(fine > lo) & (fine < hi)]
    left, x, d = [], fine[0], h
    while True:
        d = min(d * GROWTH, CELL_MAX)
        x -= d
        if x <= lo + 0.5 * d:
            break
        left.append(x)
    right, x, d = [], fine[-1], h
    while True:
        d = min(d * GROWTH, CELL_MAX)
        x += d
        if x >= hi - 0.5 * d:
            break
        right.append(x)
    return np.concatenate([[lo], left[::-1], fine, right, [hi]])


class S:
    """A GWFL expression that composes with + - * / and the functions below (strings)."""

    def __init__(self, e):
        self.e = e if isinstance(e, str) else repr(float(e))

    def _b(self, o, op):
        return S(f"({self.e}){op}({S(o).e if not isinstance(o, S) else o.e})")

    def __add__(self, o): return self._b(o, "+")
    def __radd__(self, o): return S(o)._b(self, "+")
    def __sub__(self, o): return self._b(o, "-")
    def __rsub__(self, o): return S(o)._b(self, "-")
    def __mul__(self, o): return self._b(o, "*")
    def __rmul__(self, o): return S(o)._b(self, "*")
    def __truediv__(self, o): return self._b(o, "/")
    def __rtruediv__(self, o): return S(o)._b(self, "/")
    def __neg__(self): return S(f"(-({self.e}))")


def f(name, x):
    return S(f"{name}({x.e})")


def williams(mode: int, kappa: float, mu: float, r: S, th: S):
    """Williams mode-`mode` field, K = 1, local frame: (s11, s22, s12), (du1/dx1, du2/dx1)."""
    c, s = f("cos", 0.5 * th), f("sin", 0.5 * th)
    c3, s3 = f("cos", 1.5 * th), f("sin", 1.5 * th)
    ct, st = f("cos", th), f("sin", th)
    k = 1.0 / f("sqrt", 2 * math.pi * r)
    if mode == 1:
        sig = (k * c * (1.0 - s * s3), k * c * (1.0 + s * s3), k * c * s * c3)
        f1, f2 = c * (kappa - 1.0 + 2.0 * s * s), s * (kappa + 1.0 - 2.0 * c * c)
        g1 = -0.5 * s * (kappa - 1.0 + 2.0 * s * s) + c * st   # d f1 / d theta
        g2 = 0.5 * c * (kappa + 1.0 - 2.0 * c * c) + s * st
    else:
        sig = (-k * s * (2.0 + c * c3), k * s * c * c3, k * c * (1.0 - s * s3))
        f1, f2 = s * (kappa + 1.0 + 2.0 * c * c), -c * (kappa - 1.0 - 2.0 * s * s)
        g1 = 0.5 * c * (kappa + 1.0 + 2.0 * c * c) - s * st
        g2 = 0.5 * s * (kappa - 1.0 - 2.0 * s * s) + c * st
    a = 1.0 / (2.0 * mu * f("sqrt", 2 * math.pi * r))
    return sig, (a * (0.5 * ct * f1 - st * g1), a * (0.5 * ct * f2 - st * g2))


def legendre_poly(coeffs) -> list[float]:
    """Power-series coefficients of sum c_k P_k."""
    return list(np.polynomial.legendre.leg2poly(np.asarray(coeffs, float)))


def horner(p, t: str) -> str:
    e = repr(float(p[-1]))
    for c in reversed(p[:-1]):
        e = f"({e})*({t})+({float(c)!r})"
    return e


def solve(prob: dict) -> dict:
    gf.util_trace_level(0)
    gf.util_warning_level(0)
    t0 = time.process_time()
    (x0, y0), (x1, y1) = prob["box"]
    (ax, ay), (bx, by) = prob["crack"]
    h, E, nu = prob["h"], prob["E"], prob["nu"]
    L = math.hypot(bx - ax, by - ay)
    tx, ty = (bx - ax) / L, (by - ay) / L
    nx, ny = -ty, tx
    cx, cy = 0.5 * (ax + bx), 0.5 * (ay + by)
    a = 0.5 * L
    margin = prob.get("margin", 0.6)
    X = graded(x0, x1, min(ax, bx) - margin, max(ax, bx) + margin, h, prob.get("offset", [0.5, 0.5])[0] * h + 1e-3 * h)
    Y = graded(y0, y1, min(ay, by) - margin, max(ay, by) + margin, h, prob.get("offset", [0.5, 0.5])[1] * h + 2e-3 * h)
    m = gf.Mesh("regular simplices", X, Y)
    for reg, (d, _val) in {BOTTOM: ([0, -1], y0), RIGHT: ([1, 0], x1), TOP: ([0, 1], y1), LEFT: ([-1, 0], x0)}.items():
        m.set_region(reg, m.outer_faces_with_direction(d, 0.01))

    # the crack: primary level set the signed distance to its line, secondary < 0 on the crack
    prim = f"({nx!r})*(x-({cx!r}))+({ny!r})*(y-({cy!r}))"
    tan = f"(({tx!r})*(x-({cx!r}))+({ty!r})*(y-({cy!r})))"
    tips = [t for t in prob["tips"]]  # [(x, y, e1x, e1y)] of the interior tips
    if len(tips) == 2:  # |s| - a: exact in P1 wherever it changes sign (at the tips)
        ls = gf.LevelSet(m, prob.get("ls_degree", 1), prim, f"abs({tan})-({a!r})")
    else:
        ex, ey = tips[0][2], tips[0][3]
        ls = gf.LevelSet(m, 1, prim, f"({ex!r})*(x-({tips[0][0]!r}))+({ey!r})*(y-({tips[0][1]!r}))")
    mls = gf.MeshLevelSet(m)
    mls.add(ls)
    mls.adapt()
    phases = {"mesh and level set": time.process_time() - t0}

    mf_pre = gf.MeshFem(m)
    mf_pre.set_fem(gf.Fem("FEM_PK(2,2)"))
    mf_heav = gf.MeshFem("levelset", mls, mf_pre)
    pu = gf.MeshFem(m)
    pu.set_classical_fem(1)
    nodes = pu.basic_dof_nodes()
    parts = [mf_heav]
    funcs = [gf.GlobalFunction("crack", i) for i in range(4)]
    enrich = prob.get("enrich", 0.5) * a
    tip_ls = []
    for (px, py, ex, ey) in tips:
        lsi = gf.LevelSet(m, 1, prim, f"({ex!r})*(x-({px!r}))+({ey!r})*(y-({py!r}))")
        tip_ls.append(lsi)
        sing = gf.MeshFem("global function", m, lsi, funcs, 1)
        prod = gf.MeshFem("product", pu, sing)
        near = np.nonzero((nodes[0] - px) ** 2 + (nodes[1] - py) ** 2 <= enrich**2)[0]
        prod.set_enriched_dofs(near)
        parts.insert(0, prod)
    mf_u = gf.MeshFem("sum", *parts)
    mf_u.set_qdim(2)

    q = prob.get("quad", 6)
    # cut elements: a composite rule on their sub-triangles; elements holding a tip: a refined
    # composite rule; every other element: IM_TRIANGLE(q), exact for the P2 stiffness
    mim = gf.MeshIm("levelset", mls, "all",
                    gf.Integ(f"IM_STRUCTURED_COMPOSITE(IM_TRIANGLE({q}),3)"),
                    gf.Integ(f"IM_STRUCTURED_COMPOSITE(IM_GAUSS_PARALLELEPIPED(2,{q}),9)"),
                    gf.Integ(f"IM_TRIANGLE({q})"))
    mim_crack = gf.MeshIm("levelset", mls, "boundary(a)", gf.Integ(f"IM_STRUCTURED_COMPOSITE(IM_TRIANGLE({q}),3)"))

    phases["spaces and quadrature"] = time.process_time() - t0 - sum(phases.values())
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    md = gf.Model("real")
    md.add_fem_variable("u", mf_u)
    md.add_initialized_data("lambda", [lam])
    md.add_initialized_data("mu", [mu])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    regions = {"bottom": BOTTOM, "right": RIGHT, "top": TOP, "left": LEFT}
    for side, bc in prob["boundary"].items():
        reg = regions[side]
        if bc["type"] == "roller":
            md.add_linear_term(mim, f"{1e8 * E!r}*(u.Normal)*(Test_u.Normal)", reg)
        elif bc["type"] == "traction":
            name = f"F{reg}"
            md.add_initialized_data(name, bc["value"])
            md.add_source_term_brick(mim, "u", name, reg)
        else:
            raise ValueError(f"boundary {side}: type {bc['type']!r} not supported here (roller, traction)")
    md.add_macro("jn", f"(Xfem_plus(u)-Xfem_minus(u)).[{nx!r};{ny!r}]")
    md.add_macro("jt", f"(Xfem_plus(u)-Xfem_minus(u)).[{tx!r};{ty!r}]")
    contact = prob["faces"] == "contact"
    method = prob.get("contact_method", "penalty")
    test_jn = f"((Xfem_plus(Test_u)-Xfem_minus(Test_u)).[{nx!r};{ny!r}])"
    # GetFEM's default direct solver (MUMPS here); on inclined-compression at h = 0.025 it stops with
    # error -9 (workspace; not settable from Python) and SuperLU crashes on these systems
    lsolver = "default"
    if contact and method == "penalty":
        gamma = 1e6 * E / a
        md.add_nonlinear_term(mim_crack, f"-{gamma!r}*neg_part(jn)*{test_jn}")
        iters = md.solve("max_res", 1e-10 * E * a, "max_iter", 30)
    elif contact:
        raise ValueError("contact_method 'augmented': not available (GetFEM 5.4.2 stops with a segmentation fault "
                         "when a multiplier is stored on the crack's integration points, MeshImData)")
    else:
        iters = md.solve()

    phases["assembly and solve"] = time.process_time() - t0 - sum(phases.values())
    # interaction integrals
    kappa = 3 - 4 * nu
    e_prime = E / (1 - nu**2)
    R = prob.get("radius", 0.5) * a
    mfq = gf.MeshFem(m)
    mfq.set_classical_fem(1)
    qn = mfq.basic_dof_nodes()
    out_tips = []
    sigma = "(lambda*Trace(Grad_u)*Id(2)+mu*(Grad_u+Grad_u'))"
    pid = m.pid_from_cvid(np.arange(m.nbcvs()))
    centers = m.pts()[:, pid[0].reshape(-1, 3)].mean(axis=2)  # triangles: three points each
    for i, (px, py, ex, ey) in enumerate(tips):
        R1 = prob.get("inner", 0.4) * R
        qv = np.clip((R - np.hypot(qn[0] - px, qn[1] - py)) / (R - R1), 0.0, 1.0)
        md.add_initialized_fem_data(f"q{i}", mfq, qv)
        dist = np.hypot(centers[0] - px, centers[1] - py)
        cvs = np.nonzero((dist <= R + 2 * h) & (dist >= R1 - 2 * h))[0]  # where grad q may be nonzero
        m.set_region(10 + i, cvs[None, :])
        x1 = S(f"(({ex!r})*(X(1)-({px!r}))+({ey!r})*(X(2)-({py!r})))")
        x2 = S(f"((-({ey!r}))*(X(1)-({px!r}))+({ex!r})*(X(2)-({py!r})))")
        r = f("sqrt", x1 * x1 + x2 * x2)
        th = S(f"atan2({x2.e},{x1.e})")
        exprs = []
        for mode in (1, 2):
            (s11, s22, s12), (d1, d2) = williams(mode, kappa, mu, r, th)
            Rm = f"[{ex!r},{ey!r};{-ey!r},{ex!r}]"
            s_aux = f"(({Rm})'*[{s11.e},{s12.e};{s12.e},{s22.e}]*({Rm}))"
            du_aux = f"(({Rm})'*[{d1.e};{d2.e}])"
            e1 = f"[{ex!r};{ey!r}]"
            gq = f"Grad_q{i}"
            exprs.append(f"(({sigma})*{gq}).{du_aux} + (({s_aux})*{gq}).(Grad_u*{e1})"
                         f" - ({s_aux}):(Sym(Grad_u))*({e1}.{gq})")
        # both modes in one assembly: the enriched field's gradient is the costly part
        Ks = 0.5 * e_prime * np.asarray(gf.asm_generic(mim, 0, f"[{exprs[0]};{exprs[1]}]", 10 + i, md))
        out_tips.append({"x": px, "y": py, "K_I": None if contact else Ks[0], "K_II": Ks[1]})

    phases["K"] = time.process_time() - t0 - sum(phases.values())
    cpu_answer = time.process_time() - t0  # the answer (fields and K); what follows measures it
    # the profile against the reference
    ref = prob["reference"]
    d = f"(({tx!r})*(X(1)-({ref['center'][0]!r}))+({ty!r})*(X(2)-({ref['center'][1]!r})))"
    tt = f"({d}/{ref['a']!r})"
    ref_expr = (f"({ref['factor']!r})*sqrt(pos_part({ref['a'] ** 2!r}-({d})*({d})))"
                f"*({horner(legendre_poly(ref['coefficients']), tt)})")
    jump = "jn" if ref["profile"] == "normal" else "jt"
    num = gf.asm_generic(mim_crack, 0, f"sqr({jump}-({ref_expr}))", -1, md)
    den = gf.asm_generic(mim_crack, 0, f"sqr({ref_expr})", -1, md)
    closed = (f"({ref['factor']!r})*sqrt(pos_part({ref['a'] ** 2!r}-({d})*({d})))")
    num_cf = gf.asm_generic(mim_crack, 0, f"sqr({jump}-({closed}))", -1, md)
    den_cf = gf.asm_generic(mim_crack, 0, f"sqr({closed})", -1, md)
    penetration = (math.sqrt(gf.asm_generic(mim_crack, 0, "sqr(neg_part(jn))", -1, md) / den) if contact else None)
    cpu = time.process_time() - t0
    return {"unknowns": int(mf_u.nbdof()), "cpu": cpu_answer, "cpu_errors": cpu - cpu_answer,
            "contact_method": method if contact else None, "iterations": iters[0] if isinstance(iters, (tuple, list)) else iters, "tips": out_tips,
            "profile_error": math.sqrt(num / den), "profile_error_closed_form": math.sqrt(num_cf / den_cf),
            "penetration": penetration, "phases": phases, "linear_solver": lsolver, "h": h, "mesh_points": int(m.nbpts()), "elements": int(m.nbcvs())}


if __name__ == "__main__":
    print(json.dumps(solve(json.loads(sys.argv[1]))))
