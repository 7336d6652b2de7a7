"""The documentation site: built with warnings as errors, every internal link resolving,
and its pages opened in a real browser, offline: MathJax and its fonts are served with the site.

The quick build (default suite) runs ``sphinx-build -W -n`` (warnings are errors, every
cross reference must resolve) with the notebooks in their quick mode (NGCRACK_QUICK=1)
and one of them executed (NGCRACK_DOCS_EXECUTE): the others are rendered without
outputs, which keeps the build within a couple of minutes on a busy 2-core machine. The
slow test builds the site with every notebook executed. The built HTML is then checked
without a browser (links and anchors, pages present, no text sending readers to files
they do not have) and in the operating system's Chromium through Playwright (the index
and the executed notebook page render, a figure is drawn, no error output), served by a
127.0.0.1 http.server that is shut down whatever happens. Screenshots go to the test's
temporary folder.
"""

from __future__ import annotations

import functools
import http.server
import os
import pkgutil
import re
import subprocess
import sys
import threading
import time
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urldefrag, urlparse

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_nb")
pytest.importorskip("pydata_sphinx_theme")

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
#: the notebook the quick build executes, and what its page must then show
EXECUTED = "05-contact-teaching"
CONCLUSION = "Compression: the crack closes"
#: the user guide's pages (docs/guide/NAME.md)
GUIDE = ("scenes", "cli", "elements", "method", "hp", "contact", "fracture", "growth", "estimates", "size-guard", "studies", "paper",
         "stability", "explore", "paraview", "performance", "solid")
#: a Sphinx warning or error in the build's log (not the Jupyter kernel's own log lines)
SPHINX_WARNING = re.compile(r"(?m)(^|: )(WARNING|ERROR|CRITICAL|SEVERE): ")
#: seconds: the quick build, the full build
QUICK_TIMEOUT, FULL_TIMEOUT = 900, 2400
#: text that would send a user to a file of the repository they do not have
OUTSIDE = re.compile(r"DESIGN\.md")
#: ... and, outside the API pages (docstrings) and the contributors' page, to the repository's files
REPOSITORY_FILES = re.compile(r"BENCHMARKS\.md|README|tests/test_|benchmarks/\w+\.py")


def _build(out: Path, execute: str, timeout: int) -> tuple[Path, str, float]:
    env = dict(os.environ, NGCRACK_QUICK="1", NGCRACK_DOCS_EXECUTE=execute,
               MPLBACKEND="module://matplotlib_inline.backend_inline",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    cmd = [sys.executable, "-m", "sphinx", "-W", "-n", "--keep-going", "-b", "html", "-d", str(out / "doctrees"),
           "-D", "nb_execution_mode=force", str(DOCS), str(out / "html")]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout, check=False)
    seconds = time.perf_counter() - t0
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log[-6000:]
    print(f"[docs] built {execute!r} in {seconds:.0f} s")
    return out / "html", log, seconds


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The quick build: its HTML folder, log and seconds."""
    return _build(tmp_path_factory.mktemp("docs"), EXECUTED, QUICK_TIMEOUT)


class _Page(HTMLParser):
    """The links, ids, images and text of one HTML page."""

    def __init__(self):
        super().__init__()
        self.links, self.ids, self.images, self.text, self.classes = [], set(), [], [], []
        self._skip = 0

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and a.get("href"):
            self.links.append(a["href"])
        if tag == "img" and a.get("src"):
            self.images.append(a["src"])
        if a.get("class"):
            self.classes.append(a["class"])
        if tag in ("script", "style"):
            self._skip += 1

    def handle_endtag(self, tag):
        if tag in ("script", "style"):
            self._skip -= 1

    def handle_data(self, data):
        if not self._skip:
            self.text.append(data)


@functools.cache
def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    return page


def _pages(html: Path) -> list[Path]:
    return sorted(p for p in html.rglob("*.html") if "_static" not in p.parts and "_modules" not in p.parts)


def test_build_has_no_warnings(site):
    html, log, _ = site
    assert not SPHINX_WARNING.search(log), log[-4000:]
    assert (html / "index.html").is_file()


def test_every_page_is_built(site):
    html = site[0]
    expected = ["index", "getting-started", "tutorials", "contributing", "api/index", "api/toplevel",
                "api/generated/index", "guide/index"] + [f"guide/{g}" for g in GUIDE]
    expected += [f"notebooks/{p.stem}" for p in sorted((ROOT / "notebooks").glob("[0-9][0-9]-*.py"))]
    import ngcrack

    modules = ["ngcrack"] + [m.name for m in pkgutil.walk_packages(ngcrack.__path__, "ngcrack.")]
    expected += [f"api/generated/{m}" for m in modules]
    missing = [name for name in expected if not (html / f"{name}.html").is_file()]
    assert missing == []
    # every module page documents something of its own beyond the title
    assert all(len("".join(_parse(html / f"api/generated/{m}.html").text)) > 500 for m in modules)


def test_internal_links_and_anchors_resolve(site):
    html = site[0]
    broken, checked = [], 0
    for page in _pages(html):
        for href in _parse(page).links:
            url = urlparse(href)
            if url.scheme or href.startswith(("mailto:", "//")):
                continue
            target, anchor = urldefrag(href)
            path = (page.parent / unquote(target)).resolve() if target else page
            if path.is_dir():
                path = path / "index.html"
            checked += 1
            if not path.is_file():
                broken.append(f"{page.relative_to(html)}: {href}")
            elif anchor and path.suffix == ".html" and unquote(anchor) not in _parse(path).ids:
                broken.append(f"{page.relative_to(html)}: {href} (no such anchor)")
    assert checked > 1000
    assert broken == []


def test_no_page_sends_readers_to_files_they_do_not_have(site):
    html = site[0]
    for page in _pages(html):
        text = " ".join(_parse(page).text)
        assert not OUTSIDE.search(text), page
        rel = page.relative_to(html).as_posix()
        if not rel.startswith(("api/", "contributing", "_modules")):
            assert not REPOSITORY_FILES.search(text), (rel, REPOSITORY_FILES.search(text).group())


def test_the_executed_notebook_has_its_figures_and_conclusion(site):
    html = site[0]
    page = _parse(html / "notebooks" / f"{EXECUTED}.html")
    text = " ".join(page.text)
    assert CONCLUSION in text
    figures = [src for src in page.images if src.endswith(".png")]
    assert len(figures) >= 2
    assert all((html / "notebooks" / unquote(src)).is_file() for src in figures)
    assert not any("traceback" in c or "stderr" in c for c in page.classes)
    # a notebook left out of the quick build is rendered as code without outputs
    other = _parse(html / "notebooks" / "01-paper-reproduction.html")
    assert not [src for src in other.images if src.endswith(".png")]
    footer = " ".join(_parse(html / "index.html").text)
    assert "quick mode" in footer and "Not executed in this build" in footer


def test_math_is_latex_for_mathjax(site):
    page = (site[0] / "guide" / "contact.html").read_text(encoding="utf-8")
    assert page.count('class="math') >= 10
    assert r"\sigma_\nu" in page and "mathjax" in page.lower()


def test_mathjax_is_served_with_the_site(site):
    """MathJax and its fonts come with the site: no page loads a script or a style from elsewhere."""
    html = site[0]
    script = html / "_static" / "mathjax" / "tex-chtml.js"
    fonts = list((html / "_static" / "mathjax" / "output" / "chtml" / "fonts" / "woff-v2").glob("*.woff"))
    assert script.is_file() and len(fonts) >= 20
    remote = re.compile(r"""<(?:script|link)\b[^>]*(?:src|href)=["'](?:https?:)?//""")
    for page in _pages(html):
        text = page.read_text(encoding="utf-8")
        assert not remote.search(text), (page.relative_to(html), remote.search(text).group())
    assert "_static/mathjax/tex-chtml.js" in (html / "guide" / "contact.html").read_text(encoding="utf-8")


def test_the_scenes_guide_covers_every_field_and_scene():
    """Every top-level key of a scene file, every key of [[hole]] and every built-in scene
    is in the scenes guide, and its example file is a valid scene with holes."""
    import ngcrack as nc
    from ngcrack.planar.scene.toml import MESH_KEYS, TOP_KEYS

    text = (DOCS / "guide" / "scenes.md").read_text(encoding="utf-8")
    keys = TOP_KEYS + MESH_KEYS + ("center", "radius", "label", "labels", "polygon", "friction", "pressure", "plane",
                                  "body_force", "kind", "at", "width")
    assert [k for k in keys if f"`{k}`" not in text and f"[{k}]" not in text and f"[[{k}]]" not in text] == []
    assert [n for n in nc.scenes.names() if f"`{n}`" not in text] == []
    example = nc.Scene.from_toml_string(re.search(r"```toml\n(.*?)```", text, re.S).group(1))
    assert len(example.holes) == 2 and example.holes[0].is_circle and example.exact is not None
    assert "~ngcrack.Hole" in (DOCS / "api" / "toplevel.md").read_text(encoding="utf-8") and nc.Hole is type(example.holes[0])


# ------------------------------------------------------------------------ browser


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture
def served(site):
    """The built site on a 127.0.0.1 http.server (a free port), shut down at the end."""
    handler = functools.partial(_Quiet, directory=str(site[0]))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()
        thread.join(timeout=10)


#: where the operating system's Chromium may be (Playwright's own download is not used)
CHROMIUM_CANDIDATES = ("/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--no-first-run", "--disable-sync"]


@pytest.fixture
def chromium():
    pytest.importorskip("playwright.sync_api", reason="playwright is not installed (pip install -e '.[test]')")
    import shutil

    path = next((c for c in (os.environ.get("NGCRACK_CHROMIUM"),) + CHROMIUM_CANDIDATES
                 if c and os.path.isfile(c) and os.access(c, os.X_OK)), None) or shutil.which("chromium")
    if path is None:
        pytest.skip("no Chromium found (apt-get install chromium, or set NGCRACK_CHROMIUM to a Chromium executable)")
    return path


def test_pages_render_in_a_browser(served, chromium, tmp_path):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            # the site is offline here: anything not served locally (MathJax's CDN) is refused at once
            refused = []
            page.route("**/*", lambda route: route.continue_() if route.request.url.startswith(served)
                       else (refused.append(route.request.url), route.abort()))
            errors = []
            page.on("pageerror", lambda exc: errors.append(str(exc)))

            page.goto(f"{served}/index.html", wait_until="load")
            page.screenshot(path=str(tmp_path / "index.png"), full_page=True)
            assert "ngcrack" in page.title()
            assert page.locator("h1").first.inner_text().strip().startswith("ngcrack")
            nav = page.locator("nav a").all_inner_texts()
            assert any("Getting started" in t for t in nav) and any("User guide" in t for t in nav)

            page.goto(f"{served}/notebooks/{EXECUTED}.html", wait_until="load")
            page.screenshot(path=str(tmp_path / "notebook.png"), full_page=True)
            sizes = page.eval_on_selector_all(
                "div.cell_output img", "els => els.map(e => [e.complete, e.naturalWidth, e.naturalHeight])")
            drawn = [s for s in sizes if s[0] and s[1] > 200 and s[2] > 100]
            assert len(drawn) >= 2, sizes
            assert page.locator(".output.traceback, .output.error, .output.stderr").count() == 0
            assert CONCLUSION in page.locator("main").inner_text()

            page.goto(f"{served}/guide/contact.html", wait_until="load")
            page.wait_for_selector("mjx-container", timeout=30_000)  # MathJax typeset offline
            assert page.locator("mjx-container").count() >= 10
            assert page.locator("mjx-merror").count() == 0 and refused == []

            page.goto(f"{served}/guide/paraview.html", wait_until="load")
            page.screenshot(path=str(tmp_path / "paraview.png"), full_page=True)
            assert page.locator("table").count() >= 1
            assert errors == []
        finally:
            browser.close()
    print(f"[docs] screenshots in {tmp_path}")


@pytest.mark.slow
def test_full_build_executes_every_notebook(tmp_path):
    html, log, _ = _build(tmp_path, "all", FULL_TIMEOUT)
    assert not SPHINX_WARNING.search(log), log[-4000:]
    for nb in sorted((ROOT / "notebooks").glob("[0-9][0-9]-*.py")):
        page = _parse(html / "notebooks" / f"{nb.stem}.html")
        assert [src for src in page.images if src.endswith(".png")], nb.stem
        assert not any("traceback" in c for c in page.classes), nb.stem


# ------------------------------------------------- plain-text docstrings as reST


@pytest.fixture(scope="module")
def plain():
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import plain_docstrings
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    return plain_docstrings


def test_plain_docstrings_become_valid_rest(plain):
    """Formulas with |.|, x_, *, lists after prose and indented displays: docutils reports
    problems on the raw text and none on what the extension makes of it, and the display
    keeps its characters unescaped."""
    text = """The Coulomb law |sigma_t| <= mu |sigma_n| with lam_ and a * b.
Where it fails:
- weak symmetry: the identity needs
  a Korn constant;
- friction.
Then prose again, and a display:

    J = int_A (sigma_ij du_i/dx_1) dq/dx_j dA
        - int_A f_i du_i/dx_1 q dA

and `code` after it."""
    lines = text.splitlines()
    assert plain._problems(lines) > 0
    out = plain.rest_lines(lines)
    assert plain._problems(out) == 0
    assert out[:2] != ["::", ""]  # not the fallback: the text stays prose
    assert "    J = int_A (sigma_ij du_i/dx_1) dq/dx_j dA" in out  # the display verbatim
    assert "        - int_A f_i du_i/dx_1 q dA" in out
    assert any("``code``" in line for line in out)
    assert any(r"\|sigma_t\|" in line for line in out)


def test_every_package_docstring_is_valid_rest(plain):
    """Every docstring of the package passes docutils after the extension (the literal-block
    fallback counts as valid, but is counted: it shows a docstring as preformatted text)."""
    import importlib
    import inspect

    import ngcrack

    problems, fallbacks = [], []
    names = ["ngcrack"] + [m.name for m in pkgutil.walk_packages(ngcrack.__path__, "ngcrack.")]
    for name in names:
        module = importlib.import_module(name)
        objects = [(name, module)] + [(f"{name}.{k}", v) for k, v in vars(module).items()
                                      if getattr(v, "__module__", None) == name
                                      and (inspect.isfunction(v) or inspect.isclass(v))]
        for qual, obj in objects:
            if not obj.__doc__:
                continue
            out = plain.rest_lines(inspect.cleandoc(obj.__doc__).splitlines())
            if plain._problems(out):
                problems.append(qual)
            if out[:2] == ["::", ""]:
                fallbacks.append(qual)
    print(f"[docs] docstrings shown preformatted: {fallbacks}")
    assert problems == []


def test_readme_links_into_the_site_resolve():
    """The README is the front page: its relative links name pages of the site (or
    CONTRIBUTING.md) that exist, and it stays under 400 lines (its changelog included)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [link for link in links if not urlparse(link).scheme]
    assert len(local) >= 10
    assert [link for link in local if not (ROOT / link).is_file()] == []
    assert all(link.startswith("docs/") or link == "CONTRIBUTING.md" for link in local)
    assert len(text.splitlines()) <= 400
    assert not OUTSIDE.search(text)
