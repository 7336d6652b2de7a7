"""K_I near the free surface of a slender surface crack: the domain integral against independent checks.

    python benchmarks/slender_front.py surface [--front-h-per-a 6]   # a/c = 0.2, a/t = 0.5, the free face
    python benchmarks/slender_front.py mirror [--front-h-per-a 6]    # the same half-ellipse on a symmetry plane
    python benchmarks/slender_front.py ellipse [--aspect 0.33 --front-h-per-a 4]   # a closed ellipse (memory!)

`surface`: the plate of benchmarks/newman_raju.py (a = 0.6, c = 3, t = 1.2, order 1, front_h = a/6). At each
front station up to 50 deg from the surface (phi the parametric angle, Newman and Raju's): the reported K_I (the
domain integral), the same integral with parts changed on the same solution (no closed-form disc of the curvature
terms; the Gauss rule of the closed fronts; the tube at 0.5 and 0.3 of the reach instead of 0.8; no curvature
terms at all), the part of the integral that the free face z = t contributes where the tube meets it
(`free_face_term`: the divergence theorem turns the domain integral into the front's integral plus the flux of
q v P^m through every face of the tube that is not the crack's; on the free face sigma n = 0 but neither
sigma^m n nor v . n vanishes), and K_I from the crack's opening behind the station along its in-plane normal
(`ngcrack.studies.newman_raju.front_opening_K_I`), against Newman and Raju's equation.

`mirror`: the same crack, mesh sizes and open-front code with the face the crack crosses on rollers and t = 4a
(`mirror_scene`): half of an embedded ellipse, against Irwin's closed form times Newman and Raju's finite-size
factor of the embedded crack (`embedded_F_factor`); the ratio of `surface`'s K to `mirror`'s at a station is the
free face's share, with what the extraction does to both taken out.

`ellipse`: an embedded elliptical crack of semi-axes 1 and `aspect` in the penny's block under remote
tension 1: the domain integral's K_I against Irwin's p sqrt(pi b) / E(k) (sin^2 phi + (b/a)^2 cos^2 phi)^(1/4)
at the stations, with their curvature, and the opening's (b/a = 0.2 at front_h = b/5 passed 4 GB here).
"""

from __future__ import annotations

import argparse
import math
import resource
import time

import numpy as np


def _peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0 ** 2


def free_face_term(sol, face_z: float, crack: int = 0):
    """Per station of the front (``sol.fronts``): the flux of q v P^m (m = I) and of q v P (J) through the face
    z = face_z inside the tube, divided by the bump's length on the front, in K_I's and G's units (the amounts
    the domain integral holds beyond the front's integral; the reported K_I less the first is the front's)."""
    import ngsolve as ngs

    from ngcrack.solid import front as fr
    from ngcrack.solid.front_near import aux_fields, aux_strain, near_matrix
    from ngcrack.solid.surface import bump_inside, open_arcs, surface_take

    mesh = sol.smesh.mesh
    E, nu = sol.scene.material.E, sol.scene.material.nu
    e_prime = E / (1 - nu * nu)
    geom = open_arcs(sol, fr.FrontGeometry(sol.scene.cracks[crack]))[0]
    h = sol.smesh.sizes["front_h"]
    L = fr.HALF_WIDTH_H * h
    R = max(fr.TUBE_RADIUS_H * h, fr.CLOSED_TUBE_REACH * float(np.max(geom.reach(np.linspace(geom.phi0, geom.phi1, 256)))))
    phi_i, s_i = geom.stations(h, L, R, None)
    radius_i = np.minimum(R, fr.REACH_FRACTION * geom.reach(phi_i))
    # the face's triangles near the front and a Gauss rule on them
    verts = np.array([v.point for v in mesh.vertices])
    tris = np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.BND)])
    tris = tris[np.all(np.abs(verts[tris, 2] - face_z) < 1e-9, axis=1)]
    _, x1v, x2v, _ = geom.coordinates(verts)
    tris = tris[np.any(np.hypot(x1v, x2v)[tris] < R + 2 * h, axis=1)]
    rule = ngs.IntegrationRule(ngs.TRIG, 8)
    ref = np.array([p[:2] for p in rule.points])
    wr = np.array(rule.weights)
    A, B, C = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    xyz = (A[:, None] + ref[None, :, 0, None] * (B - A)[:, None] + ref[None, :, 1, None] * (C - A)[:, None]).reshape(-1, 3)
    w = (np.linalg.norm(np.cross(B - A, C - A), axis=1)[:, None] * wr[None]).ravel()
    inside = xyz - np.array([0.0, 0.0, 1e-9])  # just inside the body
    mp = mesh(inside[:, 0], inside[:, 1], inside[:, 2])
    sigma = np.asarray(sol.fields["sigma"](mp)).reshape(-1, 3, 3)
    sigma = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    grad = np.asarray(sol.fields["grad_u"](mp)).reshape(-1, 3, 3)
    c_dev, c_tr = (1 + nu) / E, nu / E
    eps = c_dev * sigma - c_tr * np.trace(sigma, axis1=1, axis2=2)[:, None, None] * np.eye(3)
    grad = eps + 0.5 * (grad - np.swapaxes(grad, 1, 2))
    phi, x1, x2, _ = geom.coordinates(xyz)
    e1, e2, e3 = geom.frame(phi)
    Q = np.stack([e1, e2, e3], axis=1)
    QT = np.swapaxes(Q, 1, 2)
    sig_l, grad_l = Q @ sigma @ QT, Q @ grad @ QT
    eps_l = 0.5 * (grad_l + np.swapaxes(grad_l, 1, 2))
    n_l = Q @ np.array([0.0, 0.0, 1.0])  # the face's outward normal, local
    du1 = grad_l[:, :, 0]
    aux_sig, aux_du, _ = aux_fields(x1, x2, E, nu)
    aux_eps = aux_strain(aux_sig, E, nu)
    sn = np.einsum("kij,kj->ki", sig_l, n_l)
    an = np.einsum("kij,kj->ki", aux_sig[0], n_l)
    flux_I = np.sum(sn * aux_du[0], axis=1) + np.sum(an * du1, axis=1) - np.sum(sig_l * aux_eps[0], axis=(1, 2)) * n_l[:, 0]
    W = 0.5 * np.sum(sig_l * eps_l, axis=(1, 2))
    flux_J = np.sum(sn * du1, axis=1) - W * n_l[:, 0]
    s = geom.arc(phi)
    out_K, out_G = np.zeros(len(phi_i)), np.zeros(len(phi_i))
    for k in range(len(phi_i)):
        ds = s - s_i[k]
        rk = np.hypot(x1, x2)
        g = fr._radial(rk, fr.PLATEAU_FRACTION * radius_i[k], radius_i[k])[0]
        q = np.where((np.abs(ds) < L) & (rk < radius_i[k]), np.cos(0.5 * np.pi * ds / L) ** 2, 0.0) * g
        length = float(bump_inside(s_i[k], L, geom.length))
        r0 = min(fr.NEAR_DISC_H * h, fr.PLATEAU_FRACTION * radius_i[k])
        c00 = near_matrix(float(geom.turning(np.atleast_1d(phi_i[k]), np.zeros(1))[0]), r0, E, nu)[0, 0]
        out_K[k] = 0.5 * e_prime * (w * q) @ flux_I / length / (1.0 - c00)
        out_G[k] = (w * q) @ flux_J / length
    _, take = surface_take(s_i, geom.length, L, geom.surface_ends)  # the stations as reported (``sol.fronts``)
    return phi_i[take], out_K[take], out_G[take]


def surface_study(per_a: float = 6.0, crack_ratio: float = 2.0, a: float = 0.6, order: int = 1) -> None:
    import ngcrack as nc
    from benchmarks.newman_raju import surface_scene
    from ngcrack.solid import front as fr
    from ngcrack.studies.newman_raju import front_opening_K_I, surface_crack_K

    r, s = 0.2, 0.5
    c, t = a / r, a / s
    scene = surface_scene(r, s, a, 1.0 / per_a, crack_ratio)
    t0 = time.process_time()
    sol = nc.solve(scene, order=order)
    cpu = time.process_time() - t0
    print(f"a/c = {r}, a/t = {s}, front_h = a/{per_a:g}, order {order}: {sol.ndof['total']:,} unknowns, "
          f"{cpu:.1f} CPU s, peak {_peak_gb():.2f} GB", flush=True)
    variants = {"reported": fr.front_parameters(sol)[0]}
    keep = fr.NEAR_DISC_H
    fr.NEAR_DISC_H = 0.0
    variants["no disc"] = fr.front_parameters(sol)[0]
    fr.NEAR_DISC_H = keep
    keep = fr.OPEN_QUADRATURE_ORDER
    fr.OPEN_QUADRATURE_ORDER = fr.QUADRATURE_ORDER
    variants["rule 8"] = fr.front_parameters(sol)[0]
    fr.OPEN_QUADRATURE_ORDER = keep
    for reach in (0.5, 0.3):  # the tube's radius at these stations is REACH_FRACTION of the reach
        keep = fr.REACH_FRACTION
        fr.REACH_FRACTION = reach
        variants[f"tube {reach:g} reach"] = fr.front_parameters(sol)[0]
        fr.REACH_FRACTION = keep
    keep = fr.FrontGeometry.turning
    fr.FrontGeometry.turning = lambda self, phi, x1: np.zeros(np.shape(phi))
    variants["no curvature terms"] = fr.front_parameters(sol)[0]
    fr.FrontGeometry.turning = keep
    f = variants["reported"]
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    ref = surface_crack_K(1.0, a, c, t, 5.0 * c, phi)
    opening = front_opening_K_I(sol)
    _, face_K, face_G = free_face_term(sol, t)
    sel = np.flatnonzero((phi > 1e-9) & (phi <= math.radians(50.0)))
    names = list(variants)
    print("| phi (deg) | " + " | ".join(names) + " | free face term | reported less it | opening | Newman-Raju |")
    print("|---" * (len(names) + 5) + "|")
    for k in sel:
        cells = [f"{v.K_I[k]:.4f} ({v.K_I[k] / ref[k] - 1:+.1%})" for v in variants.values()]
        print(f"| {math.degrees(phi[k]):.1f} | " + " | ".join(cells)
              + f" | {face_K[k]:+.4f} | {f.K_I[k] - face_K[k]:.4f} ({(f.K_I[k] - face_K[k]) / ref[k] - 1:+.1%})"
              + f" | {opening[k]:.4f} ({opening[k] / ref[k] - 1:+.1%}) | {ref[k]:.4f} |", flush=True)


def ellipse_scene(aspect: float, per_b: float, crack_ratio: float = 2.0):
    """The penny's block (side 20, remote tension 1 on zmax, E = 1000, nu = 0.3) with an elliptical crack of
    semi-axes 1 and `aspect`, front_h = aspect / per_b."""
    import ngcrack as nc

    d = nc.scenes.load("penny").to_dict()
    d["name"] = f"ellipse-{aspect:g}"
    d["crack"] = [{"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [1.0, aspect],
                   "major_axis": [1, 0, 0]}]
    d["mesh"].update(front_h=aspect / per_b, crack_h=crack_ratio * aspect / per_b)
    return nc.Scene.from_dict(d)


def irwin_K_I(aspect: float, phi, load: float = 1.0):
    """Irwin's K_I along an embedded elliptical crack (semi-axes 1 and `aspect`) under remote tension `load`."""
    from scipy.special import ellipe

    b = aspect
    return load * math.sqrt(math.pi * b) / ellipe(1 - b * b) * (np.sin(phi) ** 2 + b * b * np.cos(phi) ** 2) ** 0.25


def ellipse_study(aspect: float = 0.2, per_b: float = 5.0, crack_ratio: float = 2.0) -> None:
    import ngcrack as nc
    from ngcrack.solid import front as fr
    from ngcrack.studies.newman_raju import front_opening_K_I

    scene = ellipse_scene(aspect, per_b, crack_ratio)
    t0 = time.process_time()
    sol = nc.solve(scene, max_dof=3_000_000)
    cpu = time.process_time() - t0
    print(f"ellipse b/a = {aspect}, front_h = b/{per_b:g}, crack_h = {crack_ratio:g} front_h: {sol.ndof['total']:,} unknowns, "
          f"{cpu:.1f} CPU s, peak {_peak_gb():.2f} GB", flush=True)
    variants = {"reported": fr.front_parameters(sol)[0]}
    keep = fr.NEAR_DISC_H
    fr.NEAR_DISC_H = 0.0
    variants["no disc"] = fr.front_parameters(sol)[0]
    fr.NEAR_DISC_H = keep
    keep = fr.QUADRATURE_ORDER, fr.DECONVOLVE
    fr.QUADRATURE_ORDER, fr.DECONVOLVE = fr.OPEN_QUADRATURE_ORDER, False
    variants["open front's rule, no unsmoothing"] = fr.front_parameters(sol)[0]
    fr.QUADRATURE_ORDER, fr.DECONVOLVE = keep
    f = variants["reported"]
    ang = np.asarray(f.angle) % (2 * np.pi)
    ref = irwin_K_I(aspect, ang)
    geom = fr.FrontGeometry(scene.cracks[0])
    kappa = geom.turning(ang, np.zeros(len(ang)))
    opening = front_opening_K_I(sol)
    sel = np.flatnonzero(ang <= 0.5 * np.pi + 1e-9)  # one quadrant
    names = list(variants)
    print("| phi (deg) | curvature x b | " + " | ".join(names) + " | opening | Irwin |")
    print("|---" * (len(names) + 4) + "|")
    for k in sel:
        cells = [f"{v.K_I[k]:.4f} ({v.K_I[k] / ref[k] - 1:+.1%})" for v in variants.values()]
        print(f"| {math.degrees(ang[k]):.1f} | {kappa[k] * aspect:.2f} | " + " | ".join(cells)
              + f" | {opening[k]:.4f} ({opening[k] / ref[k] - 1:+.1%}) | {ref[k]:.4f} |", flush=True)


def mirror_scene(per_a: float = 6.0, a: float = 0.6, thickness_per_a: float = 4.0):
    """The slender surface crack's plate (a/c = 0.2) but thicker (t = 4a) and with the face the crack crosses on rollers
    (u_z = 0, no shear): a symmetry plane, so that the half-ellipse is half of an embedded elliptical crack in a plate
    of thickness 2t, whose K_I follows Irwin's up to the plate's small finite-size factor."""
    from benchmarks.newman_raju import surface_scene
    from ngcrack.solid.scene import SolidScene

    d = surface_scene(0.2, 1.0 / thickness_per_a, a, 1.0 / per_a).to_dict()
    d["name"] = "slender-mirror"
    d["boundary"]["zmax"] = {"type": "roller"}
    from ngcrack.solid import scene as scene_module

    original = scene_module.face_problem

    def free_zmax(domain, crack, rtol, boundary, front_h):  # the scene's check lets a crack cross free faces only
        return original(domain, crack, rtol, {k: v for k, v in boundary.items() if k != "zmax"}, front_h)

    scene_module.face_problem = free_zmax
    try:
        return SolidScene.from_dict(d)
    finally:
        scene_module.face_problem = original


def embedded_F_factor(a_over_c: float, a_over_t: float, c_over_b: float, phi):
    """Newman and Raju's (1981) finite-size factor of an embedded elliptical crack (semi-axes c > a, t the plate's
    half-thickness, b its half-width) in tension relative to Irwin's infinite body: (M1 + M2 (a/t)^2 + M3 (a/t)^4) g f_w,
    M1 = 1, M2 = 0.05 / (0.11 + (a/c)^1.5), M3 = 0.29 / (0.23 + (a/c)^1.5), g = 1 - (a/t)^4 |cos phi| / (1 + 4 a/c)."""
    r, s = a_over_c, a_over_t
    m = 1.0 + 0.05 / (0.11 + r ** 1.5) * s ** 2 + 0.29 / (0.23 + r ** 1.5) * s ** 4
    g = 1.0 - s ** 4 * np.abs(np.cos(phi)) / (1.0 + 4.0 * r)
    return m * g / math.sqrt(math.cos(0.5 * math.pi * c_over_b * math.sqrt(s)))


def mirror_study(per_a: float = 6.0, a: float = 0.6) -> None:
    import ngcrack as nc
    from ngcrack.solid import front as fr
    from ngcrack.studies.newman_raju import front_opening_K_I

    c, t = a / 0.2, 4.0 * a
    scene = mirror_scene(per_a, a)
    t0 = time.process_time()
    sol = nc.solve(scene)
    cpu = time.process_time() - t0
    print(f"mirror: a/c = 0.2, t = 4a on rollers, front_h = a/{per_a:g}: {sol.ndof['total']:,} unknowns, {cpu:.1f} CPU s, "
          f"peak {_peak_gb():.2f} GB", flush=True)
    f = fr.front_parameters(sol)[0]
    others = {}
    for reach in (0.5, 0.3):
        keep = fr.REACH_FRACTION
        fr.REACH_FRACTION = reach
        others[f"tube {reach:g} reach"] = fr.front_parameters(sol)[0].K_I
        fr.REACH_FRACTION = keep
    keep = fr.FrontGeometry.turning
    fr.FrontGeometry.turning = lambda self, phi, x1: np.zeros(np.shape(phi))
    others["no curvature terms"] = fr.front_parameters(sol)[0].K_I
    fr.FrontGeometry.turning = keep
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    irwin = irwin_K_I(a / c, phi) * math.sqrt(c)  # Irwin's for semi-axes c and a
    ref = irwin * embedded_F_factor(a / c, a / t, 0.2, phi)
    geom = fr.FrontGeometry(scene.cracks[0])
    kappa = geom.turning(np.asarray(f.angle), np.zeros(len(f.angle)))
    opening = front_opening_K_I(sol)
    print("| phi (deg) | curvature x a | K domain integral | " + " | ".join(others)
          + " | opening | Irwin x Newman-Raju's finite-size factor | K / Irwin |")
    print("|---" * (len(others) + 6) + "|")
    for k in np.flatnonzero((phi > 1e-9) & (phi <= 0.5 * math.pi + 1e-9)):
        print(f"| {math.degrees(phi[k]):.1f} | {kappa[k] * a:.2f} | {f.K_I[k]:.4f} ({f.K_I[k] / ref[k] - 1:+.1%}) | "
              + " | ".join(f"{v[k]:.4f} ({v[k] / ref[k] - 1:+.1%})" for v in others.values())
              + f" | {opening[k]:.4f} ({opening[k] / ref[k] - 1:+.1%}) | {ref[k]:.4f} | {f.K_I[k] / irwin[k]:.4f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case", choices=("surface", "ellipse", "mirror"))
    ap.add_argument("--front-h-per-a", type=float, default=6.0)
    ap.add_argument("--crack-ratio", type=float, default=2.0)
    ap.add_argument("--aspect", type=float, default=0.2)
    ap.add_argument("--inset", type=float, help="the first station this many bump half-widths inside the surface "
                    "(solid.surface.SURFACE_INSET, by hand; default 1)")
    args = ap.parse_args()
    if args.inset is not None:
        from ngcrack.solid import surface

        surface.SURFACE_INSET = args.inset
    if args.case == "surface":
        surface_study(args.front_h_per_a, args.crack_ratio)
    elif args.case == "mirror":
        mirror_study(args.front_h_per_a)
    else:
        ellipse_study(args.aspect, args.front_h_per_a, args.crack_ratio)


if __name__ == "__main__":
    main()
