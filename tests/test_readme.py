"""The front page (README.md) and the getting-started page show what the program prints today.

- the README is at most `MAX_LINES` lines and names what the project covers (2D, 3D, growth,
  hydraulic fracture, MPI), the 3D guide and the penny notebook, and no test count;
- the sample output of `ngcrack solve griffith` in both files is the command's current output:
  every number to the digits it is printed with, the wall time excepted, and values below
  `ROUND_OFF` (KKT residuals) read as round-off on both sides;
- the sample table of `ngcrack sweep` is the command's current table (the time column
  excepted), and the text under it says what its NaN rows are;
- every output a command of the README writes goes into a folder that the lines before it
  create; the slow test runs them all as written in an empty folder.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
GETTING_STARTED = ROOT / "docs" / "getting-started.md"
#: a front page reads in one screenful per section: the rest is on the documentation site
MAX_LINES = 300
#: printed values below this are round-off (the KKT residuals): their digits are not the program's
ROUND_OFF = 1e-10
#: a number as printed (integers, decimals, exponents, percentages)
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?%?")
#: the options of the commands that name an output file
OUTPUT_FLAGS = ("--json", "--plot", "--vtk", "--out", "--gif", "--csv", "--png")


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def _indented_block_after(text: str, marker: str) -> list[str]:
    """The indented (4 spaces) lines of the first block after the line containing `marker`."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if marker in line) + 1
    while not lines[start].strip():
        start += 1
    block = []
    for line in lines[start:]:
        if not line.startswith("    "):
            break
        block.append(line[4:])
    assert block, marker
    return block


def _env() -> dict:
    bindir = str(Path(sys.executable).parent)
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
                PATH=bindir + os.pathsep + os.environ.get("PATH", ""), MPLBACKEND="Agg")


def _ngcrack(args: list[str], cwd: Path) -> str:
    cmd = [sys.executable, "-c", "import sys; from ngcrack.shell.cli import main; sys.exit(main())", *args]
    proc = subprocess.run(cmd, cwd=cwd, env=_env(), capture_output=True, text=True, timeout=600, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout


def _compare_line(shown: str, printed: str, skip_times: bool = True) -> list[str]:
    """The differences between a sample line and the program's line: its words, and its numbers
    to their printed digits (round-off as round-off; a number followed by ' s', a time, skipped)."""
    problems = []
    words = lambda s: NUMBER.sub("#", s).split()  # noqa: E731
    if words(shown) != words(printed):
        return [f"text differs:\n  shown:   {shown}\n  printed: {printed}"]
    a = list(NUMBER.finditer(shown))
    b = list(NUMBER.finditer(printed))
    for x, y in zip(a, b):
        if skip_times and re.match(r"\s*s\b", shown[x.end():]):
            continue
        vx, vy = (float(m.group().rstrip("%")) for m in (x, y))
        if abs(vx) < ROUND_OFF and abs(vy) < ROUND_OFF:
            continue
        if x.group() != y.group():
            problems.append(f"{x.group()} shown, {y.group()} printed: {printed}")
    return problems


def test_the_front_page_is_short_and_says_what_the_project_is():
    text = _text(README)
    assert len(text.splitlines()) <= MAX_LINES
    opening = text.split("## ")[0]  # the title and the opening paragraphs
    for topic in ("2D", "3D", "contact", "friction", "growth", "hydraulic fracture", "MPI"):
        assert topic.lower() in opening.lower(), topic
    assert "docs/guide/solid.md" in text and "12-penny" in text
    assert "docs/guide/distributed.md" in text
    assert not re.search(r"\d[\d,]*\s+tests\b", text), "a test count goes stale: leave it out"
    assert re.search(r"\d+(\.\d+)? GB on disk", text) and "MKL is" in text  # the install's size


@pytest.mark.parametrize("page", [README, GETTING_STARTED], ids=lambda p: p.name)
def test_the_sample_solve_output_is_the_programs(page, tmp_path):
    shown = _indented_block_after(_text(page), "`ngcrack solve griffith` prints:")
    printed = _ngcrack(["solve", "griffith"], tmp_path).strip().splitlines()
    assert len(shown) == len(printed), "\n".join(printed)
    problems = [p for s, q in zip(shown, printed) for p in _compare_line(s, q)]
    assert problems == []


def test_compare_line_catches_a_changed_digit():
    """The comparison itself: a stale estimate is caught, a time and round-off are not numbers to match."""
    line = "error estimate (prager-synge): energy norm 3.532e-03, relative 0.82%"
    assert _compare_line(line, line) == []
    assert _compare_line(line.replace("3.532e-03", "8.047e-03"), line)
    assert _compare_line("griffith: 29469 dofs, 0.46 s", "griffith: 29469 dofs, 0.44 s") == []
    assert _compare_line("tension 8.9e-14", "tension 1.3e-13") == []
    assert _compare_line("tension 8.9e-14", "tension 1.3e-03")


def test_the_sample_sweep_table_is_the_programs_and_explains_its_nan_rows(tmp_path):
    pytest.importorskip("pandas")
    text = _text(README)
    shown = _indented_block_after(text, "The sweep prints one row per run")
    printed = _ngcrack(["sweep", "paper-2", "--element", "peers", "bdm", "--maxh", "0.2", "0.1", "0.05",
                        "--out", "results.csv", "--jobs", "2"], tmp_path).splitlines()
    header = printed.index(shown[0].rstrip()) if shown[0].rstrip() in printed else None
    assert header is not None, "\n".join(printed)
    table = printed[header:header + len(shown)]
    time_col = shown[0].split().index("time_total")
    for s, q in zip(shown, table):
        assert s.split()[:time_col] == q.split()[:time_col], (s, q)
    assert sum("NaN" in line for line in shown) == 2
    after = text.split("\n".join("    " + line for line in shown))[1].split("\n\n")[1]
    assert "finest run" in after and "reference" in after and "NaN" in after


def _cli_block(text: str) -> list[str]:
    return [line.split("#")[0].strip() for line in _indented_block_after(text, "## On the command line")]


@pytest.mark.parametrize("page", [README, GETTING_STARTED], ids=lambda p: p.name)
def test_every_output_goes_into_a_folder_made_before(page):
    made = {"."}
    checked = 0
    for line in _cli_block(_text(page)):
        words = shlex.split(line)
        if words[:2] == ["mkdir", "-p"]:
            made.update(words[2:])
            continue
        for flag, value in zip(words, words[1:]):
            if flag in OUTPUT_FLAGS:
                checked += 1
                assert (os.path.dirname(value) or ".") in made, f"{value}: its folder is not made before: {line}"
    assert checked >= 3


@pytest.mark.slow
def test_the_command_line_examples_run_as_written(tmp_path):
    """Every line of the README's command-line block, in an empty folder (mpiexec lines excepted)."""
    env = _env()
    entry = "import sys; from ngcrack.shell.cli import main; sys.exit(main())"
    script = f"ngcrack() {{ {shlex.quote(sys.executable)} -c {shlex.quote(entry)} \"$@\"; }}\nset -e\n"
    lines = [line for line in _cli_block(_text(README)) if line and not line.startswith("mpiexec")]
    proc = subprocess.run(["bash", "-c", script + "\n".join(lines)], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=1800, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    for name in ("paper2.json", "paper2.png", "paper2.vtu", "paper2_cracks.vtu", "penny.json", "results.csv",
                 "growth.json", "kgd.json"):
        assert (tmp_path / "out" / name).stat().st_size > 0, name
