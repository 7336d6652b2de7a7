"""``ngcrack solve`` on a 3D scene: solve, write the JSON and VTK files, print a summary.

The options that have a meaning in 3D (``--element tdnns|h1p1|h1p2``, ``--order``, ``--maxh``,
``--crack-h``, ``--front-h``, ``--crack-model contact|free``, ``--qp-solver pdas``) are
checked before meshing; the 2D-only ones (``--tip-h``, ``--hp``, ``--adapt``, ``--plot``,
``--max-dof``) are refused by name. The JSON record and the VTK files are those of
``ngcrack.solid.output`` (with ``error_estimate`` for tdnns: ngcrack.solid.estimate); the
summary printed lists the unknowns, the seconds, the KKT residuals, the estimate, each
crack's opening, sliding and closed fraction and each front's range of K_I, K_II and K_III.
"""

from __future__ import annotations

import json

#: options of `ngcrack solve` that have no meaning for a 3D scene yet
UNSUPPORTED = (("tip_h", "--tip-h (use --front-h)"), ("hp", "--hp"), ("adapt", "--adapt"), ("plot", "--plot"),
               ("max_dof", "--max-dof"))


def solve_command(scene, args, json_path) -> int:
    """Run `ngcrack solve` for a 3D scene; both outputs or neither (files.Staged)."""
    for key, flag in UNSUPPORTED:
        if getattr(args, key, None) is not None:
            from ..core.errors import InputError

            raise InputError(f"{flag}: not available for a 3D scene yet")
    from ..shell.cli_errors import check_finite
    from ..shell.files import Staged
    from .solve import ESTIMATES, check_options, solve_solid

    options = {k: v for k, v in (("element", args.element), ("order", args.order), ("maxh", args.maxh),
                                 ("crack_h", args.crack_h), ("front_h", getattr(args, "front_h", None)),
                                 ("crack_model", args.crack_model), ("qp_solver", args.qp_solver)) if v is not None}
    # the error estimate where the element has one, as in 2D (the JSON's error_estimate)
    options["estimate"] = check_options(options)["element"] in ESTIMATES  # checked before meshing
    from ..distributed import active

    if active():  # under mpiexec -n N, N > 1: one solve over the ranks; rank 0 writes and prints
        from ..distributed.solid import solve_scene

        sol = solve_scene(scene, **options)
        if sol is None:
            return 0
    else:
        sol = solve_solid(scene, **options)
    result = sol.to_json_dict()
    check_finite(result)
    with Staged() as staged:
        if json_path is not None:
            def write_json(tmp):
                with open(tmp, "w") as fh:
                    json.dump(result, fh, indent=1)
            staged.write(json_path, write_json)
    paths = [json_path] if json_path is not None else []
    if args.vtk is not None:
        paths += sol.save_vtk(args.vtk)
    n, t, k = result["ndof"], result["time_s"], result["kkt"]
    print(f"{scene.name} (3D): element {sol.element} order {sol.disc.order}, {n['total']} dofs ({n['global']} global, "
          f"{n['contact']} contact), {t['total']:.2f} s ({t['contact']:.2f} s contact)")
    print(f"KKT at the constraint points: penetration {k['max_penetration']:.1e}, tension {k['max_tension']:.1e}, "
          f"complementarity {k['complementarity']:.1e}")
    if "error_estimate" in result:
        e = result["error_estimate"]
        print(f"error estimate (Prager-Synge, stress in the energy norm): {e['total']:.4g} (crack term {e['contact']:.2g})")
    for c, crack in enumerate(result["cracks"]):
        print(f"crack {c}: max opening {crack['max_opening']:.4g}, max sliding {crack['max_sliding']:.4g}, "
              f"closed {crack['closed_fraction']:.1%} of area {crack['area']:.4g}")
    for front in result["fronts"]:
        import numpy as np

        print(f"front {front['crack']} ({len(front['points'])} points): K_I {np.min(front['K_I']):.4g}..{np.max(front['K_I']):.4g}, "
              f"K_II {np.min(front['K_II']):.4g}..{np.max(front['K_II']):.4g}, "
              f"K_III {np.min(front['K_III']):.4g}..{np.max(front['K_III']):.4g}")
    if "distributed" in result:
        from ..distributed import summary_line

        print(summary_line(result["distributed"]))
    for path in paths:
        print(f"wrote {path}")
    return 0
