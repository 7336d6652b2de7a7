"""Render the package's docstrings, written as plain text, as valid reStructuredText.

ngcrack's docstrings are written to be read in ``help()`` and in an editor: prose with
``code`` and ``x`` spans, formulas such as ``|sigma_t| <= mu |sigma_n|`` and indented
displays. Read as reStructuredText, ``|...|`` is a substitution, ``x_`` a link and an
indented display an error, so each docstring goes through :func:`rest_lines`:

1. a docstring with numpydoc sections (``Parameters`` underlined) goes to napoleon;
2. otherwise ``|``, ``*`` and a word's trailing ``_`` are escaped outside code spans and
   roles, and an indented display becomes a literal block;
3. if docutils still reports a problem, the docstring is shown as one literal block.

Attribute comments (``#:``) are one paragraph: napoleon would read ``text: more`` in them
as a type, so they are never given to it.
"""

from __future__ import annotations

import io
import re

from docutils.core import publish_doctree
from docutils.utils import Reporter

#: a numpydoc section header: a known title underlined with dashes
_SECTION = re.compile(r"^\s*(Parameters|Returns|Yields|Raises|Warns|Examples|Notes|See Also|Attributes|"
                      r"Other Parameters|References)\s*\n\s*-{3,}\s*$", re.M)
#: spans left alone: ``literal``, :role:`target`, `interpreted`
_SPAN = re.compile(r"(:[\w:.-]+:`[^`]*`|``[^`]+``|`[^`]*`)")
_BULLET = re.compile(r"^(\s*)([-*+]|\d+[.)]|\(\w\))\s+")


def _escape(text: str) -> str:
    """Escape |, * and a word's trailing _ outside code spans and roles."""
    parts = _SPAN.split(text)
    for i in range(0, len(parts), 2):  # the even parts are outside spans
        p = parts[i].replace("\\", "\\\\").replace("|", "\\|").replace("*", "\\*")
        parts[i] = re.sub(r"(?<=\w)_(?=\W|$)", r"\\_", p)
    return "".join(parts)


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _displays_as_literal(lines: list[str]) -> list[str]:
    """An indented block right after a line of prose (no blank line, no ``::``) becomes a
    literal block; bullet continuations stay as they are."""
    out: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        prev = next((p for p in reversed(out) if p.strip()), None)
        starts_block = (line.strip() and out and out[-1].strip() and prev is not None
                        and _indent(line) > _indent(prev))
        if starts_block:
            m = _BULLET.match(prev)
            if m and _indent(line) == len(m.group(0)):
                starts_block = False  # the continuation of a bullet
            elif out[-1].rstrip().endswith("::"):
                starts_block = False
        if not starts_block:
            out.append(line)
            i += 1
            continue
        base = _indent(prev)
        out[-1] = out[-1].rstrip() + (":" if out[-1].rstrip().endswith(":") else " ::")
        out.append("")
        while i < len(lines) and (not lines[i].strip() or _indent(lines[i]) > base):
            out.append(lines[i])
            i += 1
        while out and not out[-1].strip():
            out.pop()
        out.append("")
    return out


def _problems(lines: list[str]) -> int:
    """How many warnings docutils reports on `lines` (roles replaced by plain code)."""
    text = re.sub(r":[\w:.-]+:`", "`", "\n".join(lines))
    stream = io.StringIO()
    publish_doctree(text, settings_overrides={"report_level": Reporter.WARNING_LEVEL,
                                              "halt_level": Reporter.SEVERE_LEVEL + 1,
                                              "warning_stream": stream})
    return len(re.findall(r"\((WARNING/2|ERROR/3|SEVERE/4)\)", stream.getvalue()))


def rest_lines(lines: list[str]) -> list[str]:
    """The plain-text docstring `lines` as reStructuredText (steps 2 and 3 above)."""
    if not lines or _problems(lines) == 0:
        return lines
    fixed = _displays_as_literal([_escape(line) for line in lines])
    if _problems(fixed) == 0:
        return fixed
    return ["::", ""] + ["    " + line for line in lines] + [""]


def _process(app, what, name, obj, options, lines):
    if not lines:
        return
    text = "\n".join(lines)
    if what != "attribute" and _SECTION.search(text):
        from sphinx.ext.napoleon import NumpyDocstring

        lines[:] = NumpyDocstring(lines, app.config, app, what, name, obj, options).lines()
        return
    lines[:] = rest_lines(lines)


def setup(app):
    from sphinx.ext.napoleon import Config

    # napoleon's settings without its automatic docstring processing
    for name, default, rebuild, types in Config._config_values:
        if name not in app.config.values:
            app.add_config_value(name, default, rebuild, types)
    app.connect("autodoc-process-docstring", _process)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
