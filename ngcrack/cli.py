"""The `ngcrack` command.

    ngcrack scenes
    ngcrack solve SCENE [--element E] [--maxh H] [--nu NU] [--E E] [--tip-h H] [--crack-h H]
                        [--qp-solver S] [--crack-model M] [--json OUT] [--plot OUT.png]

SCENE is a built-in scene name or a TOML file. Bad input exits with code 2 and a
one-line message before any meshing; output files are written only after a successful
solve, atomically (a temporary file renamed into place), so none is left half-written.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
from pathlib import Path


class UsageError(ValueError):
    """Bad command-line input (exit code 2)."""


def _atomic_write(path: Path, write) -> None:
    """Write through a temporary file in the same directory, then rename into place."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _check_output(path: str | None, field: str, suffix: str | None = None) -> Path | None:
    if path is None:
        return None
    p = Path(path)
    if not p.parent.exists():
        raise UsageError(f"{field} = {path!r}: the directory {str(p.parent)!r} does not exist")
    if suffix and p.suffix.lower() != suffix:
        raise UsageError(f"{field} = {path!r}: must end in {suffix}")
    return p


def _finite_json(obj) -> None:
    """Refuse NaN or infinity anywhere in the result (json would write invalid tokens)."""
    if isinstance(obj, float) and not math.isfinite(obj):
        raise RuntimeError("the result contains a non-finite number; nothing was written")
    if isinstance(obj, dict):
        for v in obj.values():
            _finite_json(v)
    elif isinstance(obj, list):
        for v in obj:
            _finite_json(v)


def cmd_scenes(args) -> int:
    from . import scenes

    rows = scenes.describe()
    width = max(len(n) for n, _ in rows)
    for name, desc in rows:
        print(f"{name:<{width}}  {desc}")
    return 0


def cmd_solve(args) -> int:
    from . import scenes
    from .elements import ELEMENTS

    if args.element not in ELEMENTS:
        raise UsageError(f"--element = {args.element!r}: allowed values are {', '.join(ELEMENTS)}")
    json_path = _check_output(args.json, "--json")
    plot_path = _check_output(args.plot, "--plot", ".png")
    scene = scenes.resolve(args.scene)
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    from .solve import solve

    sol = solve(scene, element=args.element, maxh=args.maxh, tip_h=args.tip_h, crack_h=args.crack_h,
                qp_solver=args.qp_solver, crack_model=args.crack_model)
    result = sol.to_json_dict()
    _finite_json(result)
    if json_path is not None:
        def write_json(tmp):
            with open(tmp, "w") as fh:
                json.dump(result, fh, indent=1)
        _atomic_write(json_path, write_json)
    if plot_path is not None:
        from .plots import plot_solution

        _atomic_write(plot_path, lambda tmp: plot_solution(sol, tmp))
    k, t, n = result["kkt"], result["time_s"], result["ndof"]
    print(f"{scene.name}: element {sol.element}, maxh {sol.maxh:g}, nu {scene.material.nu:g}, "
          f"{n['total']} dofs ({n['global']} global, {n['contact']} contact), {t['total']:.2f} s")
    print(f"KKT: penetration {k['max_penetration']:.1e}, tension {k['max_tension']:.1e}, "
          f"complementarity {k['complementarity']:.1e}")
    for path in (json_path, plot_path):
        if path is not None:
            print(f"wrote {path}")
    return 0


def _positive(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="ngcrack", description="Cracked elastic bodies with unilateral crack contact (NGSolve).")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("scenes", help="list the built-in scenes")
    p.set_defaults(func=cmd_scenes)
    p = sub.add_parser("solve", help="solve one scene")
    p.add_argument("scene", help="built-in scene name or TOML file")
    p.add_argument("--element", default="peers", help="peers (default) or bdm")
    p.add_argument("--maxh", type=_positive, help="global mesh size (overrides the scene)")
    p.add_argument("--tip-h", dest="tip_h", type=_positive, help="mesh size at crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=_positive, help="mesh size along cracks")
    p.add_argument("--nu", type=_positive, help="Poisson ratio (overrides the scene)")
    p.add_argument("--E", type=_positive, help="Young's modulus (overrides the scene)")
    p.add_argument("--qp-solver", dest="qp_solver", default="clarabel", help="clarabel (default), pdas, osqp, scs, ...")
    p.add_argument("--crack-model", dest="crack_model", default="contact", help="contact (default), free or bonded")
    p.add_argument("--json", help="write the result (DESIGN.md's contract) to this file")
    p.add_argument("--plot", help="write a PNG with isolines of sigma_nu and the deformed body")
    p.set_defaults(func=cmd_solve)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except ValueError as exc:  # SceneError, UsageError and option errors are ValueErrors
        print(f"ngcrack: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
