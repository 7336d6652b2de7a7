"""The 3D solution: its fields, the crack summaries, the JSON record and the VTK files.

JSON (`ngcrack solve --json` on a 3D scene): the 2D keys that apply ("scene",
"element", "order", "E", "nu", "maxh", "ndof", "time_s", "kkt") plus
"dimension": 3, "fronts": [{"crack", "points", "K_I", "K_II", "K_III", "G"}] and
"cracks": [{"max_opening", "max_sliding", "closed_fraction", "area"}]. max_opening
is the largest normal jump at the constraint points, max_sliding the largest tangential
jump |[u]_t| at the same points, closed_fraction the area fraction of the crack faces
whose constraint points are all closed; a crack with a pressure (uniform or varying,
`solid.loads`) adds "pressure_force", the pressure's resultant on one face (int p dA,
the load the element took). "error_estimate": {"total", "stress", "contact", "data"}
(`solid.estimate`; "data" the traction faces' data term). With point supports or loads (``[[point]]``),
"points": {label: {"type", "force", "displacement"}}: each point's force on the body (the
applied one, or a support's reaction) and its patch's mean displacement
(`solid.point_means.point_values`).

VTK (ParaView): OUT.vtu with the body's displacement and stress, OUT_cracks.vtu with
the crack faces' opening (normal jump), sliding (|tangential jump|), closed flag and
contact pressure (-sigma_nn less the faces' applied pressure, where closed; 0 where open)
at their corners.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import ngsolve as ngs
import numpy as np

from ..core.constraints import KKT_KEYS
from ..core.solution import Solution, summary_line

#: the estimate's traction data term is printed when above this fraction of the estimate (below: round-off)
DATA_SHOWN_RTOL = 1e-8


@dataclass
class SolidSolution(Solution):
    """The answer of one solve of a 3D scene (a kind of `ngcrack.core.solution.Solution`; module docstring)."""

    scene: object
    smesh: object
    disc: object
    system: object
    y: np.ndarray
    gf: ngs.GridFunction
    contact: object  # a contact.ContactResult, or None (free crack, no crack)
    G: object
    options: dict
    timings: dict = field(default_factory=dict)
    fronts: list = field(default_factory=list)
    #: a distributed solve's ranks, CG steps, preconditioner and memory per rank (ngcrack.distributed.solid)
    distributed: dict | None = None
    #: the error estimate (ngcrack.solid.estimate.prager_synge: a dict) once computed, why there is none, and
    #: the computation a solve leaves pending (`Solution.error_estimate`)
    _estimate: object = field(default=None, repr=False)
    _no_estimate: str = field(default="", repr=False)
    _pending_estimate: object = field(default=None, repr=False, compare=False)
    dimension = 3

    @property
    def crack_mesh(self):
        """The mesh with its cracks (a SolidMesh; also `smesh`), as a 2D solution's `crack_mesh`."""
        return self.smesh

    @property
    def element(self) -> str:
        return self.disc.element

    @property
    def fields(self) -> dict:
        return self.disc.fields(self.gf)

    @property
    def u(self) -> ngs.CoefficientFunction:
        return self.fields["u"]

    @property
    def sigma(self) -> ngs.CoefficientFunction:
        return self.fields["sigma"]

    @property
    def kkt(self) -> dict:
        if self.contact is None:
            return dict.fromkeys(KKT_KEYS, 0.0)
        return dict(self.contact.kkt)

    @property
    def ndof(self) -> dict:
        return {"total": int(self.disc.fes.ndof), "global": int(self.system.n), "contact": int(len(self.system.contact))}

    # ---------------------------------------------------------------- crack quantities
    def normal_jumps(self) -> np.ndarray:
        """[u].nu at the constraint points (disc.constraint_points), crack by crack in order."""
        if self.disc.jn is None:
            return np.zeros(0)
        V = getattr(self.disc, "value_map", None)
        return np.asarray((self.G if V is None else V) @ self.y[self.system.contact])

    def tangential_jumps(self) -> np.ndarray:
        """|[u]_t| at the constraint points, from the + side's jump field (the element's "jump")."""
        if self.disc.jn is None:
            return np.zeros(0)
        mesh = self.smesh.mesh
        pts = self.disc.constraint_points
        owner = self.point_crack()
        nrm = np.array([c.normal for c in self.smesh.cracks])[owner]
        c = np.array([pts[owner == i].mean(axis=0) for i in range(len(self.smesh.cracks))])[owner]
        # a point just inside the + side's tetrahedron, a little towards its crack's centre (of its points: inside
        # the crack's part in the body; the mean over every crack may lie outside the body, in a hole)
        p = pts + 1e-5 * self.scene.size * nrm + 1e-3 * (c - pts)
        vals = np.asarray(self.fields["jump"](mesh(p[:, 0], p[:, 1], p[:, 2])))
        vt = vals - np.sum(vals * nrm, axis=1)[:, None] * nrm
        return np.linalg.norm(vt, axis=1)

    def _per_face(self) -> int:
        k = self.disc.order
        return (k + 1) * (k + 2) // 2

    def point_crack(self) -> np.ndarray:
        """The crack index of each constraint point."""
        if self.disc.point_crack is not None:
            return self.disc.point_crack
        return np.repeat(np.arange(len(self.smesh.cracks)), [len(c.elements) * self._per_face() for c in self.smesh.cracks])

    def face_points(self) -> np.ndarray:
        """Per crack face (crack by crack) its constraint points, vertices first (-1: no jump there, the front)."""
        if self.disc.face_points is not None:
            return self.disc.face_points
        return np.arange(len(self.disc.constraint_points)).reshape(-1, self._per_face())

    def crack_constraints(self, index: int) -> tuple[np.ndarray, np.ndarray]:
        """The constraint points of crack `index` and whether each is closed."""
        mine = self.point_crack() == index
        active = np.zeros(int(mine.sum()), dtype=bool) if self.contact is None else self.contact.active[mine]
        return self.disc.constraint_points[mine], active

    def crack_summaries(self) -> list[dict]:
        if self.disc.jn is None:
            return []
        w = self.normal_jumps()
        s = self.tangential_jumps()
        closed = np.zeros(len(w), dtype=bool) if self.contact is None else self.contact.active
        owner = self.point_crack()
        table = self.face_points()
        out, start = [], 0
        pts = self.smesh.points
        mesh = self.smesh.mesh
        for i, c in enumerate(self.smesh.cracks):
            nf = len(c.elements)
            corners = [pts[[v.nr for v in mesh[ngs.ElementId(ngs.BND, int(e))].vertices]] for e in c.elements]
            areas = np.array([0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0])) for p in corners])
            rows = table[start:start + nf]
            # a face is closed where all its points with a jump unknown are (a front node has none)
            face_closed = np.where(rows >= 0, closed[np.maximum(rows, 0)], True).all(axis=1)
            mine = owner == i
            out.append({"max_opening": float(max(w[mine].max(), 0.0)), "max_sliding": float(s[mine].max()),
                        "closed_fraction": float(areas[face_closed].sum() / areas.sum()), "area": float(c.area),
                        **self._pressure_force(c)})
            start += nf
        return out

    def _pressure_force(self, c) -> dict:
        """{"pressure_force": the applied pressure's resultant on one face, int p dA} for a crack with a pressure
        (uniform or varying: the CoefficientFunction the element took, solid.loads); {} without one."""
        from .loads import element_pressure

        pressure = element_pressure(getattr(self.scene.cracks[c.index], "pressure", 0.0))
        if pressure is None:
            return {}
        mesh = self.smesh.mesh
        force = ngs.Integrate(ngs.CF(pressure), mesh, ngs.BND, definedon=mesh.Boundaries(c.label), order=6)
        return {"pressure_force": float(force)}

    # ------------------------------------------------------------------------ outputs
    def to_json_dict(self) -> dict:
        """The `solve --json` record of a 3D scene (module docstring); a pending error estimate is computed first."""
        estimate = self.error_estimate
        sizes = self.smesh.sizes
        t = self.timings
        return {
            "scene": self.scene.name, "dimension": 3, "element": self.element, "order": self.disc.order,
            "maxh": sizes["maxh"], "crack_h": sizes["crack_h"], "front_h": sizes["front_h"],
            "E": self.scene.material.E, "nu": self.scene.material.nu,
            "ndof": self.ndof,
            "time_s": {k: float(t.get(k, 0.0)) for k in ("total", "mesh", "assemble", "condense", "linear", "contact",
                                                        "fronts", "estimate")},
            "kkt": self.kkt,
            "contact_iterations": 0 if self.contact is None else int(self.contact.iterations),
            "fronts": [f.to_json_dict() for f in self.fronts],
            "cracks": self.crack_summaries(),
            **({} if estimate is None else {"error_estimate": {k: float(estimate.get(k, 0.0))
                                                               for k in ("total", "stress", "contact", "data")}}),
            **({} if self.distributed is None else {"distributed": self.distributed}),
            **({} if not getattr(self.scene, "points", ()) else {"points": self._point_values()}),
        }

    def _point_values(self) -> dict:
        from .point_means import point_values

        return {k: {"type": v["type"], "force": list(v["force"]), "displacement": list(v["displacement"])}
                for k, v in point_values(self).items()}

    def report_lines(self, result: dict | None = None) -> list[str]:
        """What `ngcrack solve` prints of a 3D solve: sizes and seconds, the KKT residuals, the estimate, each
        crack's opening, sliding and closed fraction, each front's range of K_I, K_II and K_III."""
        result = result if result is not None else self.to_json_dict()  # (the record, when already made)
        n, t, k = result["ndof"], result["time_s"], result["kkt"]
        lines = [f"{self.scene.name} (3D): element {self.element} order {self.disc.order}, {n['total']} dofs "
                 f"({n['global']} global, {n['contact']} contact), {t['total']:.2f} s ({t['contact']:.2f} s contact)",
                 f"KKT at the constraint points: penetration {k['max_penetration']:.1e}, tension {k['max_tension']:.1e}, "
                 f"complementarity {k['complementarity']:.1e}"]
        if "error_estimate" in result:
            e = result["error_estimate"]
            lines.append(f"error estimate (Prager-Synge, stress in the energy norm): {e['total']:.4g} (crack term "
                         f"{e['contact']:.2g}" + (f", traction data {e['data']:.2g}"
                                                   if e.get("data", 0.0) > DATA_SHOWN_RTOL * e["total"] else "")
                         + f"), {t['estimate']:.2f} s")
        for c, crack in enumerate(result["cracks"]):
            lines.append(f"crack {c}: max opening {crack['max_opening']:.4g}, max sliding {crack['max_sliding']:.4g}, "
                         f"closed {crack['closed_fraction']:.1%} of area {crack['area']:.4g}")
        for front in result["fronts"]:
            lines.append(f"front {front['crack']} ({len(front['points'])} points): K_I {np.min(front['K_I']):.4g}.."
                         f"{np.max(front['K_I']):.4g}, K_II {np.min(front['K_II']):.4g}..{np.max(front['K_II']):.4g}, "
                         f"K_III {np.min(front['K_III']):.4g}..{np.max(front['K_III']):.4g}")
        for label, v in result.get("points", {}).items():
            lines.append(f"{label} ({v['type']}): force [{', '.join(f'{c:.4g}' for c in v['force'])}], mean displacement "
                         f"[{', '.join(f'{c:.4g}' for c in v['displacement'])}]")
        if "distributed" in result:
            lines.append(summary_line(result["distributed"]))
        return lines

    def save_vtk(self, path, subdivision: int = 0) -> list[Path]:
        """OUT.vtu (displacement, stress) and OUT_cracks.vtu (the crack faces: opening, sliding, closed).

        Written to a temporary folder beside them and moved into place: an error leaves no partial file.
        """
        import os
        import shutil
        import tempfile

        from ..planar.vtk import vtk_stem

        base = vtk_stem(path)
        base.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".ngcrack-vtk-", dir=base.parent))
        try:
            f = self.fields
            ngs.VTKOutput(self.smesh.mesh, coefs=[f["u"], f["sigma"]], names=["displacement", "stress"],
                          filename=str(tmp / "body"), subdivision=int(subdivision)).Do()
            written = [(tmp / "body.vtu", base.with_name(base.name + ".vtu"))]
            if self.smesh.cracks:
                import meshio

                points, tris, data = self.crack_arrays()
                meshio.write(tmp / "cracks.vtu", meshio.Mesh(points, [("triangle", tris)], point_data=data), binary=True)
                written.append((tmp / "cracks.vtu", base.with_name(base.name + "_cracks.vtu")))
            for src, dst in written:
                os.replace(src, dst)
            return [dst for _, dst in written]
        finally:
            shutil.rmtree(tmp, ignore_errors=True)

    def crack_arrays(self) -> tuple[np.ndarray, np.ndarray, dict]:
        """The crack faces as separate triangles (points, triangles) with the opening, the sliding
        and the closed flag at their corners (0 where a corner carries no jump: the front)."""
        w, s = self.normal_jumps(), self.tangential_jumps()
        closed = np.zeros(len(w)) if self.contact is None else self.contact.active.astype(float)
        pick = self.face_points()[:, :3].ravel()
        mesh, pts = self.smesh.mesh, self.smesh.points
        points = np.concatenate([pts[[v.nr for v in mesh[ngs.ElementId(ngs.BND, int(e))].vertices]]
                                 for c in self.smesh.cracks for e in c.elements])
        tris = np.arange(len(pick)).reshape(-1, 3)
        has = pick >= 0
        at = np.maximum(pick, 0)
        data = {"opening": np.where(has, w[at], 0.0), "sliding": np.where(has, s[at], 0.0),
                "closed": np.where(has, closed[at], 0.0)}
        data["contact_pressure"] = np.where(data["closed"] > 0, self._face_compression(points), 0.0)
        return points, tris, data

    def _face_compression(self, corners: np.ndarray) -> np.ndarray:
        """-sigma_nn - p at the crack faces' corners (the mean of the two sides, a little inside each
        face): the contact pressure where the faces are closed (p the faces' applied pressure)."""
        mesh = self.smesh.mesh
        nrm = np.concatenate([np.tile(c.normal, (3 * len(c.elements), 1)) for c in self.smesh.cracks])
        applied, start = [], 0
        for c in self.smesh.cracks:  # the applied pressure at the corners (a varying one: solid.loads)
            p, n = getattr(self.scene.cracks[c.index], "pressure", 0.0), 3 * len(c.elements)
            applied.append(p.values(corners[start:start + n])[:, 0] if hasattr(p, "values") else np.full(n, p))
            start += n
        applied = np.concatenate(applied)
        centre = np.repeat(corners.reshape(-1, 3, 3).mean(axis=1), 3, axis=0)
        x = corners + 1e-3 * (centre - corners)
        sig = self.fields["sigma"]
        out = np.zeros(len(x))
        for side in (1.0, -1.0):
            y = x + side * 1e-6 * self.scene.size * nrm
            sv = np.asarray(sig(mesh(y[:, 0], y[:, 1], y[:, 2]))).reshape(-1, 3, 3)
            out -= 0.5 * np.einsum("ki,kij,kj->k", nrm, sv, nrm)
        return out - applied

