"""The explorer's words for a student: refusals as one plain sentence, a glossary, the tips' names.

A refusal is one plain sentence that names the control and says what to do ("The crack
would leave the plate: move the crack centre back towards the middle or shorten the
crack"); the library's technical line (the scene field and the rule it breaks) is kept
beside it as the detail, shown on a second, smaller line and as a tooltip. `refusal`
turns an exception raised by an update into that pair: a control's own refusal
(`controls.ControlRefused`) carries its sentence; a solve's failure is recognised by the
rule it names, and anything else gets a sentence naming the changed controls.

`GLOSSARY` is the one-line meaning of each word of the readouts (hover), and `tip_names`
names the tips by where they are ("left tip", "right tip"; "lower" and "upper" for a
crack closer to vertical; "crack 2, left tip" where there are several cracks).
"""

from __future__ import annotations

from typing import Any

from ...planar.plots import tip_names  # noqa: F401  (the tips' names, shared with the growth figures)
from .controls import LABELS, ControlRefused

#: one line per word of the readouts, shown on hover
GLOSSARY = {
    "unknowns": "how many numbers the computer solves for: the whole body's (global) and the crack "
                "faces' (contact) unknowns",
    "KKT": "contact check: how far the answer is from meeting the contact conditions exactly (faces "
           "never overlap, never pull on each other); 0 is exact, below 1e-8 is round-off "
           "(KKT: Karush-Kuhn-Tucker)",
    "contact length": "how much of the crack has its faces touching",
    "time": "from the change of a control to the new figure, split by stage",
    "K": "stress intensity factors at a crack tip: K_I opens the crack, K_II slides its faces "
         "(units: stress times square root of length)",
    "tip": "a crack tip, named by where it is: left or right (lower or upper for a steep crack)",
}


def _label(name: str) -> str:
    return LABELS.get(name, name.replace("_", " "))


def _value(value: Any) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def _changed(changes: dict) -> str:
    names = [_label(k) for k in changes]
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def refusal(exc: BaseException, changes: dict, state: dict) -> tuple[str, str]:
    """(sentence, detail) for the failure `exc` of an update that asked for `changes`
    (`state`: the controls it was applied to). The sentence names a control and what to do."""
    detail = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    if isinstance(exc, ControlRefused):
        return exc.sentence, detail
    text = str(exc)
    changed = _changed(changes) if changes else "the controls"
    if "displacement baselines" in text or ("material.nu" in text and "lambda is infinite" in text):
        element = state.get("element", "this element")
        if "element" in changes:
            return (f"The displacement element {element} cannot take Poisson's ratio 1/2 (an incompressible "
                    f"material): pick bdm, peers or tdnns, or first lower Poisson's ratio.", detail)
        return (f"Poisson's ratio 1/2 (incompressible) needs a mixed element, and {element} is not one: lower "
                f"Poisson's ratio or first pick bdm, peers or tdnns as the element.", detail)
    if "outside domain.polygon" in text or "lies outside" in text:
        return (f"The crack would leave the plate with this {changed}: move the crack centre back towards the "
                f"middle or shorten the crack.", detail)
    if "hole" in text and ("crack" in text or "inside" in text):
        return f"The crack would run into a hole with this {changed}: move the crack or shorten it.", detail
    if "cross" in text or "intersect" in text:
        return f"The cracks would cross with this {changed}: move one crack or shorten it.", detail
    if "unknowns" in text or "too fine" in text:
        return f"This {changed} would make too many unknowns to solve here: choose a larger mesh size.", detail
    return (f"The model cannot be solved with this {changed}: change it back or change another control "
            f"(details below).", detail)
