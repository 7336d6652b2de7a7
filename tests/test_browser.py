"""nc.explore in a real browser: JupyterLab started here, driven by Playwright and Chromium.

The teaching notebook (notebooks/09-explore.py, converted to .ipynb, with two cells
added at its end: a widget with the webgui view, and a construction with a bad element)
is opened in JupyterLab and run; then, as a student would:

1. the "load factor" slider is moved with the keyboard to tension: the figure is greyed
   while the kernel solves and changes, the slider, its typed box and the model agree;
2. 0.7 is typed into Poisson's ratio: the refusal shows (one plain sentence naming
   Poisson's ratio and its range, the technical line beneath it), the box and the slider
   go back to 0.3, the model keeps 0.3;
3. under tension the crack faces drawn show a gap and no overlap;
4. load factor 1 typed, crack model `free` chosen: the faces overlap, no gap (checked on
   the figure's data, which the widget keeps in a hidden element, not on pixels);
5. the webgui view is switched on: its canvas appears;
6. the construction error is a single message (one ValueError naming the element and the
   allowed values; no widget traceback);
7. the hydraulic-fracture view (`nc.explore_growth` of a KGD run): a step typed shows its
   figure and numbers beside the closed form, a step out of range is refused in one line;
8. the 3D explorer on the inclined penny: closed over the whole crack under compression, the
   load factor typed to -1: open; its checkbox shows NGSolve's view of the deformed body.

JupyterLab runs on 127.0.0.1 with a free port and a token, in a temporary root folder,
with temporary Jupyter config, data, runtime and settings folders (nothing of the user's
leaks in), and is shut down at the end whatever happens. The browser is the operating
system's Chromium (Playwright's own download is not used); the test skips, saying why,
where either is missing. A screenshot of each step goes to the folder the test prints
(NGCRACK_SCREENSHOTS, else the test's tmp_path/screenshots).
"""

from __future__ import annotations

import json
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOK = ROOT / "notebooks" / "09-explore.py"
#: where the operating system's Chromium may be
CHROMIUM_CANDIDATES = ("/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--no-first-run", "--disable-sync"]
#: seconds: JupyterLab's start, the notebook's run, one slider move
SERVER_TIMEOUT, RUN_TIMEOUT, MOVE_TIMEOUT = 90, 300, 60
#: key presses on the focused slider (step 0.1: load factor from 1.0 to -1.0, tension)
PRESSES = 20


def _chromium() -> str | None:
    for path in (os.environ.get("NGCRACK_CHROMIUM"),) + CHROMIUM_CANDIDATES:
        if path and os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


#: the cells added at the notebook's end: a widget with the webgui view, and a bad construction (last: run-all
#: stops there)
EXTRA_CELLS = ['w3 = nc.explore("griffith-plate", maxh=2.0, webgui=True)\nw3',
               'import warnings\n'
               'wings = nc.scenes.inclined_crack(angle=45.0, load=-1.0).with_(friction=0.3)\n'
               'with warnings.catch_warnings():  # (a coarse mesh on purpose: quick)\n'
               '    warnings.simplefilter("ignore")\n'
               '    res = nc.grow(wings, da=0.1, steps=2, K_Ic=1.0, maxh=2.0, tip_h=0.05)\n'
               'res.animate("wings.gif")  # a file: the figures after it still show\n'
               'g = nc.explore_growth(res)\ng',
               'plt.figure(figsize=(3, 2))\nplt.plot([0, 1], [0, 1])\nplt.title("shown after the GIF")\nplt.show()',
               'kgd = nc.hydrofrac(nc.scenes.load("kgd"), rate=1e-4, K_Ic=1e6, da=0.1, steps=3)\n'
               'h = nc.explore_growth(kgd)  # the hydraulic-fracture view\nh',
               'from ngcrack.scenes.coarse3d import inclined_penny\n'
               'p3 = nc.explore(nc.Scene.from_dict(inclined_penny()), webgui=True)  # 3D: the inclined penny\np3',
               'nc.explore("inclined-crack", element="q2")']


def _prepare_root(root: Path) -> str:
    """The teaching notebook as .ipynb (python3 kernel) in `root`, with EXTRA_CELLS; returns its file name."""
    import jupytext
    import nbformat

    nb = jupytext.read(NOTEBOOK)
    nb.cells += [nbformat.v4.new_code_cell(src) for src in EXTRA_CELLS]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}
    name = NOTEBOOK.with_suffix(".ipynb").name
    jupytext.write(nb, root / name)
    return name


def _settings(settings: Path) -> None:
    """JupyterLab user settings: no news, no update check (their notification would cover the page),
    every cell rendered."""
    d = settings / "@jupyterlab" / "apputils-extension"
    d.mkdir(parents=True)
    (d / "notification.jupyterlab-settings").write_text(json.dumps({"fetchNews": "false", "checkForUpdates": False}))
    # every cell rendered, also those out of view (JupyterLab 4 renders only the visible ones by default)
    d = settings / "@jupyterlab" / "notebook-extension"
    d.mkdir(parents=True)
    (d / "tracker.jupyterlab-settings").write_text(json.dumps({"windowingMode": "none"}))


@pytest.fixture
def chromium():
    """The system Chromium's path; skips (saying why) without Playwright or Chromium."""
    pytest.importorskip("playwright.sync_api", reason="playwright is not installed (pip install -e '.[test]')")
    path = _chromium()
    if path is None:
        pytest.skip("no Chromium found (apt-get install chromium, or set NGCRACK_CHROMIUM to a Chromium executable)")
    return path


@pytest.fixture
def jupyterlab(tmp_path, chromium):
    """(url, token, notebook name): a JupyterLab server of its own; always shut down."""
    pytest.importorskip("jupyterlab", reason="JupyterLab is not installed (pip install -e '.[test]')")
    pytest.importorskip("jupytext")
    root = tmp_path / "root"
    root.mkdir()
    name = _prepare_root(root)
    env = dict(os.environ)
    for var, sub in (("JUPYTER_CONFIG_DIR", "config"), ("JUPYTER_DATA_DIR", "data"), ("JUPYTER_RUNTIME_DIR", "runtime"),
                     ("JUPYTERLAB_SETTINGS_DIR", "settings"), ("JUPYTERLAB_WORKSPACES_DIR", "workspaces"),
                     ("IPYTHONDIR", "ipython")):
        env[var] = str(tmp_path / "jupyter" / sub)
        (tmp_path / "jupyter" / sub).mkdir(parents=True)
    _settings(tmp_path / "jupyter" / "settings")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env["NGCRACK_QUICK"] = "1"
    env.pop("MPLBACKEND", None)
    port, token = _free_port(), secrets.token_hex(16)
    cmd = [sys.executable, "-m", "jupyterlab", "--no-browser", "--ip=127.0.0.1", f"--port={port}",
           "--ServerApp.port_retries=0", f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={root}",
           "--LabApp.expose_app_in_browser=True"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-root")
    log = open(tmp_path / "jupyterlab.log", "wb")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, cwd=root, start_new_session=True)
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + SERVER_TIMEOUT
        while True:
            try:
                with urllib.request.urlopen(f"{url}/api/status?token={token}", timeout=5) as r:
                    if r.status == 200:
                        break
            except OSError:
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                log.flush()
                pytest.fail(f"JupyterLab did not start: {(tmp_path / 'jupyterlab.log').read_text()[-3000:]}")
            time.sleep(0.5)
        yield url, token, name
    finally:
        try:  # shut the kernels and the server down through the API, then make sure
            req = urllib.request.Request(f"{url}/api/shutdown?token={token}", method="POST")
            urllib.request.urlopen(req, timeout=10).close()
        except OSError:
            pass
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGTERM)
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
        log.close()


def _dismiss_dialogs(page) -> None:
    """Accept JupyterLab's start-up dialogs (kernel choice) and close its notifications (news)."""
    for _ in range(3):
        dialog = page.locator(".jp-Dialog")
        if dialog.count():
            accept = dialog.locator(".jp-Dialog-button.jp-mod-accept")
            (accept.first if accept.count() else dialog.locator("button").last).click()
            page.wait_for_timeout(300)
        for sel in (".jp-toast-button:has-text('No')", ".jp-Notification-Toast-Close", ".Toastify__close-button"):
            loc = page.locator(sel)
            for k in range(loc.count()):
                try:
                    loc.nth(k).click(timeout=2000)
                except Exception:  # noqa: BLE001  (a toast may vanish by itself)
                    pass
        page.wait_for_timeout(200)


def _wait_idle(page, timeout_s: float) -> None:
    """Wait until the notebook's kernel is idle (JupyterLab's execution indicator)."""
    page.wait_for_function(
        "() => { const s = window.jupyterapp && window.jupyterapp.shell.currentWidget;"
        " return s && s.sessionContext && s.sessionContext.session && s.sessionContext.session.kernel"
        " && s.sessionContext.session.kernel.status === 'idle'; }", timeout=timeout_s * 1000)


def _wait_settled(page, timeout_s: float) -> None:
    """Wait until the kernel is idle and the figure stays the same for a second (every
    key press is one update, queued in the kernel)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        _wait_idle(page, timeout_s)
        src = page.locator("img.ngcrack-figure").first.get_attribute("src")
        page.wait_for_timeout(1000)
        if page.locator("img.ngcrack-figure").first.get_attribute("src") == src:
            _wait_idle(page, timeout_s)
            return
    raise TimeoutError("the figure kept changing")


#: an error output as JupyterLab shows it
ERROR_OUTPUT = "[data-mime-type='application/vnd.jupyter.error'], [data-mime-type='application/vnd.jupyter.stderr']"

#: the first explorer's figure data (JSON in a hidden element), read in the page
_DATA_JS = "() => JSON.parse(document.querySelector('.ngcrack-data').textContent)"


def _data(page) -> dict:
    return page.evaluate(_DATA_JS)


def _wait_data(page, predicate_js: str, timeout_s: float) -> dict:
    """Wait until the first explorer's data satisfies `predicate_js` (a JS expression in d), then the kernel is idle."""
    page.wait_for_function(f"() => {{ const e = document.querySelector('.ngcrack-data');"
                           f" if (!e) return false; const d = JSON.parse(e.textContent); return {predicate_js}; }}",
                           timeout=timeout_s * 1000)
    _wait_idle(page, timeout_s)
    return _data(page)


def _type(page, name: str, value: str) -> None:
    """Type `value` into the box of control `name` of the first explorer and press Enter."""
    box = page.locator(f".ngcrack-typed-{name} input").first
    box.click()
    box.fill(value)
    box.press("Enter")


def _shots_dir(tmp_path: Path) -> Path:
    shots = Path(os.environ.get("NGCRACK_SCREENSHOTS") or tmp_path / "screenshots")
    shots.mkdir(parents=True, exist_ok=True)
    return shots


def test_explore_widget_in_jupyterlab(chromium, jupyterlab, tmp_path):
    from playwright import sync_api as playwright

    url, token, name = jupyterlab
    shots = _shots_dir(tmp_path)
    t0 = time.monotonic()
    seen: dict = {}
    with playwright.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, headless=True, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(f"{url}/lab/tree/{name}?token={token}")
            page.wait_for_selector(".jp-NotebookPanel", timeout=SERVER_TIMEOUT * 1000)
            page.wait_for_function("() => window.jupyterapp !== undefined", timeout=SERVER_TIMEOUT * 1000)
            _dismiss_dialogs(page)
            _wait_idle(page, SERVER_TIMEOUT)
            page.screenshot(path=str(shots / "1-opened.png"))
            page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
            page.wait_for_selector("text=Unilateral contact: closed over", timeout=RUN_TIMEOUT * 1000)
            _wait_idle(page, RUN_TIMEOUT)
            page.screenshot(path=str(shots / "2-run.png"), full_page=True)
            page.wait_for_selector(ERROR_OUTPUT, state="attached", timeout=RUN_TIMEOUT * 1000)
            _dismiss_dialogs(page)
            figure = page.locator("img.ngcrack-figure").first
            figure.wait_for(state="visible", timeout=MOVE_TIMEOUT * 1000)
            page.locator(".ngcrack-slider-load").first.scroll_into_view_if_needed()
            page.wait_for_timeout(500)
            page.screenshot(path=str(shots / "2-after-run.png"))
            seen["start"] = _data(page)
            # 1. the load factor slider, by keyboard, to tension
            before_src = figure.get_attribute("src")
            before_png = figure.screenshot(path=str(shots / "figure-before.png"))
            handle = page.locator(".ngcrack-slider-load .noUi-handle").first
            handle.focus()
            changed = "(src) => { const i = document.querySelector('img.ngcrack-figure'); return i && i.src !== src; }"
            page.evaluate("() => { window._ngcrackBusy = false; const i = document.querySelector('img.ngcrack-figure');"
                          " new MutationObserver(() => { if (i.classList.contains('ngcrack-busy'))"
                          " window._ngcrackBusy = true; }).observe(i, {attributes: true}); }")
            t_key = time.monotonic()
            page.keyboard.press("ArrowLeft")  # one step: the browser's slider-to-figure latency
            page.wait_for_function(changed, arg=before_src, timeout=MOVE_TIMEOUT * 1000)
            one_step = time.monotonic() - t_key
            for _ in range(PRESSES - 1):
                page.keyboard.press("ArrowLeft")
                page.wait_for_timeout(50)
            t_last = time.monotonic()
            _wait_settled(page, MOVE_TIMEOUT)
            settle = time.monotonic() - t_last
            seen["slider"] = _data(page)
            seen["busy_seen"] = page.evaluate("() => window._ngcrackBusy")
            seen["busy_now"] = page.locator("img.ngcrack-figure.ngcrack-busy").count()
            seen["slider_status"] = page.locator(".ngcrack-status").first.inner_text()
            seen["load_box"] = page.locator(".ngcrack-typed-load input").first.input_value()
            after_png = figure.screenshot(path=str(shots / "figure-after.png"))
            page.screenshot(path=str(shots / "3-after-slider-tension.png"))
            # 2. a typed value out of range: refused, the box and slider back to the model's value
            _type(page, "nu", "0.7")
            page.wait_for_selector(".ngcrack-status:has-text('out of range')", timeout=MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            page.wait_for_timeout(300)
            seen["refused"] = _data(page)
            seen["refused_status"] = page.locator(".ngcrack-status").first.inner_text()
            seen["nu_box"] = page.locator(".ngcrack-typed-nu input").first.input_value()
            seen["nu_handle"] = page.locator(".ngcrack-slider-nu .noUi-handle").first.get_attribute("aria-valuenow")
            page.screenshot(path=str(shots / "4-typed-nu-refused.png"))
            # 3. tension: a gap between the faces (the load is -1 after step 1)
            seen["tension"] = _data(page)
            figure.screenshot(path=str(shots / "5-tension-gap-figure.png"))
            # 4. compression with crack model free: the faces overlap
            _type(page, "load", "1")
            _wait_data(page, "d.state.load === 1.0 && d.max_gap === 0", MOVE_TIMEOUT)
            page.locator(".widget-dropdown:has(label:text-is('crack model')) select").first.select_option(label="free (no contact)")
            seen["free"] = _wait_data(page, "d.state.crack_model === 'free' && d.error === null", MOVE_TIMEOUT)
            page.wait_for_timeout(300)
            page.screenshot(path=str(shots / "6-free-compression.png"))
            figure.screenshot(path=str(shots / "6-free-overlap-figure.png"))
            # 4b. a refused combination: nu = 1/2 (fine for bdm), then the displacement element h1p1
            _type(page, "nu", "0.5")
            _wait_data(page, "d.state.nu === 0.5 && d.error === null", MOVE_TIMEOUT)
            element = page.locator(".widget-dropdown:has(label:text-is('element')) select").first
            element.select_option("h1p1")
            page.wait_for_selector(".ngcrack-status:has-text('cannot take')", timeout=MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            page.wait_for_timeout(300)
            seen["combination"] = _data(page)
            seen["combination_status"] = page.locator(".ngcrack-status").first.inner_text()
            seen["element_menu"] = element.input_value()
            page.screenshot(path=str(shots / "6b-refused-combination.png"))
            _type(page, "nu", "0.3")
            _wait_data(page, "d.state.nu === 0.3 && d.error === null", MOVE_TIMEOUT)
            # a load change and a remesh, from input to figure, in the browser
            latency = {}
            for control, value, key in (("load", "-0.5", "load change"), ("angle", "35", "remesh (crack angle)")):
                t_in = time.monotonic()
                _type(page, control, value)  # (the hidden data is written after the figure: its change is the figure's)
                page.wait_for_function(f"() => {{ const e = document.querySelector('.ngcrack-data'); return e &&"
                                       f" JSON.parse(e.textContent).state.{control} === {float(value)}; }}",
                                       timeout=MOVE_TIMEOUT * 1000)
                latency[key] = time.monotonic() - t_in
                _wait_idle(page, MOVE_TIMEOUT)
                latency[key + ", kernel side"] = _data(page)["timing"]
            seen["latency"] = latency
            figure.screenshot(path=str(shots / "6c-after-remesh-figure.png"))
            # 4c. the growth view: a step typed out of range is refused in one red line
            gfig = page.locator("img.ngcrack-growth-figure").first
            gfig.scroll_into_view_if_needed()
            g_src = gfig.get_attribute("src")
            gbox = page.locator(".ngcrack-growth-typed-step input").first
            gbox.click()
            gbox.fill("99")
            gbox.press("Enter")
            page.wait_for_selector("text=Step 99 is out of range", timeout=MOVE_TIMEOUT * 1000)
            seen["growth_refused"] = gbox.input_value()
            page.screenshot(path=str(shots / "6d-growth-step-refused.png"))
            gbox.click()
            gbox.fill("2")
            gbox.press("Enter")
            page.wait_for_function("(src) => { const i = document.querySelector('img.ngcrack-growth-figure');"
                                   " return i && i.src !== src; }", arg=g_src, timeout=MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            gfig.screenshot(path=str(shots / "6e-growth-step-2.png"))
            seen["after_gif_images"] = page.locator(".jp-Cell:has-text('shown after the GIF') .jp-OutputArea img").count()
            # 4d. the hydraulic-fracture view: a step typed, then one out of range
            hfig = page.locator("img.ngcrack-hydrofrac-figure").first
            hfig.scroll_into_view_if_needed()
            h_src = hfig.get_attribute("src")
            hbox = page.locator(".ngcrack-hydrofrac-typed-step input").first
            hbox.click()
            hbox.fill("3")
            hbox.press("Enter")
            page.wait_for_function("(src) => { const i = document.querySelector('img.ngcrack-hydrofrac-figure');"
                                   " return i && i.src !== src; }", arg=h_src, timeout=MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            seen["hydrofrac_readout"] = page.locator(".jp-Cell:has(img.ngcrack-hydrofrac-figure) pre").first.inner_text()
            hfig.screenshot(path=str(shots / "6f-hydrofrac-step-3.png"))
            hbox.click()
            hbox.fill("9")
            hbox.press("Enter")
            page.wait_for_selector("text=Step 9 is out of range", timeout=MOVE_TIMEOUT * 1000)
            seen["hydrofrac_refused"] = hbox.input_value()
            page.screenshot(path=str(shots / "6g-hydrofrac-step-refused.png"))
            # 4e. the 3D explorer: the inclined penny closed and sliding, then the load reversed: open
            sfig = page.locator("img.ngcrack-solid-figure").first
            sfig.scroll_into_view_if_needed()
            readout = page.locator(".jp-Cell:has(img.ngcrack-solid-figure) .widget-html").nth(1)
            seen["solid_start"] = readout.inner_text()
            sfig.screenshot(path=str(shots / "6h-penny-closed-sliding.png"))
            sbox = page.locator(".ngcrack-solid-typed-load input").first
            sbox.click()
            sbox.fill("-1")
            sbox.press("Enter")
            page.wait_for_selector(".jp-Cell:has(img.ngcrack-solid-figure) :text('closed 0%')",
                                   timeout=3 * MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            seen["solid_open"] = readout.inner_text()
            sfig.screenshot(path=str(shots / "6i-penny-open.png"))
            page.screenshot(path=str(shots / "6j-penny-widget.png"))
            canvases = page.locator(".jp-OutputArea canvas").count()
            box3d = page.locator(".widget-checkbox:has-text('view of the body')").first
            box3d.scroll_into_view_if_needed()
            box3d.locator("input").click()
            page.wait_for_function(f"() => document.querySelectorAll('.jp-OutputArea canvas').length > {canvases}",
                                   timeout=MOVE_TIMEOUT * 1000)
            _wait_idle(page, MOVE_TIMEOUT)
            page.wait_for_timeout(1500)
            seen["solid_canvases"] = page.locator(".jp-OutputArea canvas").count() - canvases
            page.screenshot(path=str(shots / "6k-penny-webgui-body.png"))
            # 5. the webgui view of the third widget
            box = page.locator(".widget-checkbox:has-text('NGSolve webgui')").first
            box.scroll_into_view_if_needed()
            box.locator("input").click()
            try:
                page.wait_for_selector(".jp-OutputArea canvas", timeout=MOVE_TIMEOUT * 1000)
            finally:
                page.screenshot(path=str(shots / "7-webgui.png"))
            _wait_idle(page, MOVE_TIMEOUT)
            page.wait_for_timeout(1500)
            seen["canvases"] = page.locator(".jp-OutputArea canvas").count()
            page.screenshot(path=str(shots / "7-webgui.png"))
            # 6. the construction error: one message
            err = page.locator(ERROR_OUTPUT)
            seen["errors"] = err.count()
            err.last.scroll_into_view_if_needed()
            seen["error_text"] = err.last.inner_text()
            page.screenshot(path=str(shots / "8-construction-error.png"))
            seen["broken"] = page.locator("text=Error displaying widget").count()
        finally:
            browser.close()
    print(f"[browser] {time.monotonic() - t0:.1f} s; one key press to a new figure {one_step:.2f} s, "
          f"{PRESSES - 1} more presses settled {settle:.1f} s after the last (including 1 s of stillness); "
          f"screenshots in {shots}")
    for key, value in seen.get("latency", {}).items():  # (measured, not a threshold: the machine may be loaded)
        if isinstance(value, dict):
            print(f"[browser]   {key}: " + " + ".join(f"{k} {v:.2f}" for k, v in value.items()) + " s")
        else:
            print(f"[browser] input to figure, {key}: {value:.2f} s")
    assert seen["broken"] == 0, f"{seen['broken']} widgets not displayed"
    # 1. slider
    d = seen["slider"]
    assert seen["slider_status"].strip() == "", seen["slider_status"]
    assert d["state"]["load"] < 0.0, f"the slider did not move to tension: load factor = {d['state']['load']}"
    assert d["state"]["load"] == d["controls"]["load"] == d["typed"]["load"] == float(seen["load_box"])
    assert before_png != after_png, "the figure did not change"
    assert seen["busy_seen"] and seen["busy_now"] == 0, "the figure was not greyed while solving, or stays greyed"
    # 2. refusal
    d = seen["refused"]
    sentence, _, detail = seen["refused_status"].strip().partition("\n")
    assert "The Poisson's ratio 0.7 is out of range: choose a value from 0 to 0.5." in sentence, sentence
    assert "Error" not in sentence and "details: nu (Poisson's ratio) = 0.7 refused: allowed from 0 to 0.5" in detail
    assert d["state"]["nu"] == d["controls"]["nu"] == d["typed"]["nu"] == 0.3
    assert float(seen["nu_box"]) == 0.3 and float(seen["nu_handle"]) == pytest.approx(0.3)
    # 3. tension: a gap, no overlap
    d = seen["tension"]
    assert d["state"]["crack_model"] == "contact" and d["max_gap"] > 0 and d["max_overlap"] == 0
    # 4. free under compression: overlap, no gap
    d = seen["free"]
    assert d["max_overlap"] > 0 and d["max_gap"] == 0, d
    # 4b. the refused combination: one sentence naming what to do, the menu back on bdm
    d = seen["combination"]
    sentence = seen["combination_status"].strip().split("\n")[0]
    assert "h1p1 cannot take Poisson's ratio 1/2" in sentence and "Error" not in sentence, sentence
    assert seen["element_menu"] == "bdm" and d["state"]["element"] == d["controls"]["element"] == "bdm"
    # 4c. the growth view refuses step 99 and keeps the step shown; a figure after the GIF still shows
    assert seen["growth_refused"] == "0"
    assert seen["after_gif_images"] == 1
    # 4d. the hydraulic-fracture view: step 3 beside the closed form; step 9 refused, the box back
    assert "step 3 of 3" in seen["hydrofrac_readout"] and "KGD closed form" in seen["hydrofrac_readout"]
    assert seen["hydrofrac_refused"] == "3"
    # 4e. the 3D explorer: closed over the whole crack under compression, open under tension
    assert "closed 100%" in seen["solid_start"] and "closed 0%" in seen["solid_open"], seen
    assert seen["solid_canvases"] >= 1  # NGSolve's view of the deformed body
    # 5. webgui
    assert seen["canvases"] >= 1
    # 6. the construction error
    text = seen["error_text"]
    assert seen["errors"] == 1, f"{seen['errors']} error outputs"
    assert "ValueError: element = 'q2': allowed values are peers, bdm, tdnns, h1p1, h1p2" in text, text
    assert "TraitError" not in text and text.count("Error") == 1, text
