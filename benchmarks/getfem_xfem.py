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
  level set's cut elements) and, in a disc of radius `enrich` a around every tip (a the
  crack's half length, "a" of the problem), by GetFEM's four crack functions sqrt(r)
  {sin, cos}(theta / 2) {1, sin theta} times the P1 partition of unity ("fixed area"
  enrichment; benchmarks/getfem_peer.py runs 0.2 a, 0.5 a and a);
* the crack's level sets: the signed distance to its line, and the secondary |s| - a (two
  tips; s the coordinate along the crack from its centre) or the distance past the one tip,
  both exact in P1 where they change sign;
* quadrature: composite rules on the cut elements, a refined composite rule on the
  elements holding a tip, IM_TRIANGLE(6) on every other element;
* supports: rollers (u.n = 0) by penalisation, tractions as source terms;
* crack faces: traction free ("free"), or unilateral contact ("contact"). The contact is
  GetFEM's augmented Lagrangian (the default, "augmented"): a pressure p >= 0, one value
  per element the crack cuts (P0 on the cut elements), and the complementarity
  p = pos_part(p - r [u].n), r = E / h, solved by GetFEM's Newton (a closed crack: one
  iteration). "penalty", gamma * neg_part([u].n) with gamma = 1e6 E / a, gives the same
  K_II and sliding within the discretization error (inclined-compression, h = 0.2 and 0.1:
  K_II within 1.5e-5 and 1.7e-7, where K_II's error is 4.4e-4 and 5e-5, the sliding's error
  2.26e-3 and 4.45e-4 both ways) in 2-3 Newton iterations. The result states the
  interpenetration, L2 relative to the profile (augmented: 8e-5 at h = 0.2 down to 2e-6 at
  h = 0.05, below the sliding's error: the P0 pressure holds the mean of [u].n on each cut
  element; penalty: 6e-7);
* K_I, K_II: the interaction integral over the disc of radius R = `radius` a around each
  tip, weight q = 1 for r < 0.4 R falling linearly to 0 at r = R, in P1 (a weight whose
  gradient reaches the tip reads K 10-30% low: the quadrature cannot integrate the 1/r
  integrand there), integrated on the triangles where grad q is nonzero. The auxiliary
  fields are Williams' (K = 1) written with GetFEM's crack functions on the tip's level
  sets (its own C++ values and gradients; at h = 0.1 strings with atan2 cost 1.5-3.5 times as much). K_II
  needs no crack-face term for frictionless contact (the mode II field has no normal face
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
#: the penalty contact's coefficient, times E / a
PENALTY = 1e6
#: the augmented Lagrangian's parameter r, times E / h
AUGMENTATION = 1.0


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


#: GetFEM's crack functions, GlobalFunction('crack', k), in the tip's frame (x along the crack's
#: extension, y normal to it, r and theta polar): k = 0..3 is sqrt(r) times sin(theta/2), cos(theta/2),
#: sin(theta/2) sin(theta), cos(theta/2) sin(theta). Williams' displacement fields (K = 1, plane strain)
#: are combinations of them: WILLIAMS[mode][component] = the coefficients of the four functions, times
#: 1 / (2 mu sqrt(2 pi)), with kappa = 3 - 4 nu (see `williams_coefficients`).
CRACK_FUNCTIONS = 4


def williams_coefficients(mode: int, kappa: float, mu: float) -> np.ndarray:
    """(2, 4): the local displacement (u1 along the crack's extension, u2 normal) of Williams'
    mode-`mode` field with K = 1, as coefficients of GetFEM's four crack functions."""
    c = 1.0 / (2.0 * mu * math.sqrt(2.0 * math.pi))
    if mode == 1:   # u1 ~ cos(t/2)(kappa - 1 + 2 sin^2(t/2)), u2 ~ sin(t/2)(kappa + 1 - 2 cos^2(t/2))
        return c * np.array([[0.0, kappa - 1.0, 1.0, 0.0], [kappa + 1.0, 0.0, 0.0, -1.0]])
    # mode 2: u1 ~ sin(t/2)(kappa + 1 + 2 cos^2(t/2)), u2 ~ -cos(t/2)(kappa - 1 - 2 sin^2(t/2))
    return c * np.array([[kappa + 1.0, 0.0, 0.0, 1.0], [0.0, -(kappa - 1.0), 1.0, 0.0]])


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
    a_ref = prob.get("a", a)  # the crack's half length (griffith's mesh holds half of its crack)
    enrich = prob.get("enrich", 0.5) * a_ref
    tip_ls = []
    for (px, py, ex, ey) in tips:
        # the tip's frame: x along the crack's extension e, y the primary level set (the crack's
        # signed distance: at the tip that ends against n, a left-handed frame)
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
    method = prob.get("contact_method", "augmented")
    test_jn = f"((Xfem_plus(Test_u)-Xfem_minus(Test_u)).[{nx!r};{ny!r}])"
    # GetFEM's default direct solver (MUMPS here); on inclined-compression at h = 0.025 it stops with
    # error -9 (workspace; not settable from Python) and SuperLU crashes on these systems
    lsolver = "default"
    n_mult = 0
    if contact and method == "penalty":
        gamma = PENALTY * E / a_ref
        md.add_nonlinear_term(mim_crack, f"-{gamma!r}*neg_part(jn)*{test_jn}")
        iters = md.solve("max_res", 1e-10 * E * a_ref, "max_iter", 30)
    elif contact and method == "augmented":
        # the contact pressure p >= 0 on the cut elements (P0, one value per element the crack
        # crosses), Alart-Curnier's complementarity p = pos_part(p - r [u].n) with r = E / h
        mf_p0 = gf.MeshFem(m)
        mf_p0.set_classical_discontinuous_fem(0)
        cut = mf_p0.dof_from_im(mim_crack)
        mf_p = gf.MeshFem("partial", mf_p0, cut)
        n_mult = int(mf_p.nbdof())
        md.add_fem_variable("p", mf_p)
        r_aug = AUGMENTATION * E / h
        md.add_linear_term(mim_crack, f"-p*{test_jn}")
        md.add_nonlinear_term(mim_crack, f"-(1/{r_aug!r})*(p-pos_part(p-{r_aug!r}*jn))*Test_p")
        iters = md.solve("max_res", 1e-10 * E * a_ref, "max_iter", 30)
    elif contact:
        raise ValueError(f"contact_method {method!r}: not one of 'augmented', 'penalty'")
    else:
        iters = md.solve()

    phases["assembly and solve"] = time.process_time() - t0 - sum(phases.values())
    # interaction integrals: Williams' fields (K = 1) as GetFEM's crack functions on the tip's level set
    kappa = 3 - 4 * nu
    e_prime = E / (1 - nu**2)
    R = prob.get("radius", 0.5) * a_ref
    mfq = gf.MeshFem(m)
    mfq.set_classical_fem(1)
    qn = mfq.basic_dof_nodes()
    out_tips = []
    sigma = "(lambda*Trace(Grad_u)*Id(2)+mu*(Grad_u+Grad_u'))"
    pid = m.pid_from_cvid(np.arange(m.nbcvs()))[0].reshape(-1, 3)  # triangles: three points each
    pts = m.pts()
    for i, (px, py, ex, ey) in enumerate(tips):
        R1 = prob.get("inner", 0.4) * R
        qv = np.clip((R - np.hypot(qn[0] - px, qn[1] - py)) / (R - R1), 0.0, 1.0)
        md.add_initialized_fem_data(f"q{i}", mfq, qv)
        qp = np.clip((R - np.hypot(pts[0] - px, pts[1] - py)) / (R - R1), 0.0, 1.0)[pid]
        cvs = np.nonzero(qp.max(axis=1) > qp.min(axis=1))[0]  # the triangles where grad q is nonzero
        m.set_region(10 + i, cvs[None, :])
        mf_aux = gf.MeshFem("global function", m, tip_ls[i], funcs, 2)
        rot = np.array([[ex, -ey], [ey, ex]])  # local (along e, e turned +90 degrees) -> global
        # in a left-handed tip frame theta changes sign: the odd functions (sin(theta/2), cos(theta/2)
        # sin(theta)) with it
        flip = np.array([1.0, 1.0, 1.0, 1.0]) if ex * ny - ey * nx > 0 else np.array([-1.0, 1.0, 1.0, -1.0])
        e1, gq = f"[{ex!r};{ey!r}]", f"Grad_q{i}"
        exprs = []
        for mode in (1, 2):
            coef = rot @ williams_coefficients(mode, kappa, mu) * flip  # (global component, function)
            md.add_initialized_fem_data(f"w{i}{mode}", mf_aux, coef.T.reshape(-1))  # dof 2 k + component
            g = f"Grad_w{i}{mode}"
            s_aux = f"(lambda*Trace({g})*Id(2)+mu*({g}+{g}'))"
            exprs.append(f"(({sigma})*{gq}).({g}*{e1}) + (({s_aux})*{gq}).(Grad_u*{e1}) - ({s_aux}):(Grad_u)*({e1}.{gq})")
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
            "contact_method": method if contact else None, "multipliers": n_mult,
            "iterations": iters[0] if isinstance(iters, (tuple, list)) else iters, "tips": out_tips,
            "profile_error": math.sqrt(num / den), "profile_error_closed_form": math.sqrt(num_cf / den_cf),
            "penetration": penetration, "phases": phases, "linear_solver": lsolver, "h": h, "mesh_points": int(m.nbpts()), "elements": int(m.nbcvs())}


if __name__ == "__main__":
    print(json.dumps(solve(json.loads(sys.argv[1]))))
