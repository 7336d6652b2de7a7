"""nc.explore in a real browser: JupyterLab started here, driven by Playwright and Chromium.

The teaching notebook (notebooks/09-explore.py, converted to .ipynb) is opened in
JupyterLab, run, and the widget's "load x" slider is moved with the keyboard; the figure
image must change and no error output may appear. JupyterLab runs on 127.0.0.1 with a
free port and a token, in a temporary root folder, with temporary Jupyter config, data,
runtime and settings folders (nothing of the user's leaks in), and is shut down at the
end whatever happens. The browser is the operating system's Chromium (Playwright's own
download is not used); the test skips, saying why, where either is missing. Screenshots
go to the test's tmp_path. This checks the wiring of the widget, not the mechanics
(tests/test_explore.py does those without a browser).
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
SERVER_TIMEOUT, RUN_TIMEOUT, MOVE_TIMEOUT = 90, 420, 120
#: key presses on the focused slider (step 0.1: load x from 1.0 to -1.0, tension)
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


def _prepare_root(root: Path) -> str:
    """The teaching notebook as .ipynb (python3 kernel) in `root`; returns its file name."""
    import jupytext

    nb = jupytext.read(NOTEBOOK)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}
    name = NOTEBOOK.with_suffix(".ipynb").name
    jupytext.write(nb, root / name)
    return name


def _settings(settings: Path) -> None:
    """JupyterLab user settings: no news, no update check (their notification would cover the page)."""
    d = settings / "@jupyterlab" / "apputils-extension"
    d.mkdir(parents=True)
    (d / "notification.jupyterlab-settings").write_text(json.dumps({"fetchNews": "false", "checkForUpdates": False}))


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


def test_explore_widget_in_jupyterlab(chromium, jupyterlab, tmp_path):
    from playwright import sync_api as playwright

    url, token, name = jupyterlab
    shots = tmp_path / "screenshots"
    shots.mkdir()
    t0 = time.monotonic()
    with playwright.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, headless=True, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1500, "height": 1100})
            page.goto(f"{url}/lab/tree/{name}?token={token}")
            page.wait_for_selector(".jp-NotebookPanel", timeout=SERVER_TIMEOUT * 1000)
            page.wait_for_function("() => window.jupyterapp !== undefined", timeout=SERVER_TIMEOUT * 1000)
            _dismiss_dialogs(page)
            _wait_idle(page, SERVER_TIMEOUT)
            page.screenshot(path=str(shots / "1-opened.png"))
            page.evaluate("() => window.jupyterapp.commands.execute('notebook:run-all-cells')")
            page.wait_for_selector("text=Unilateral contact: closed over", timeout=RUN_TIMEOUT * 1000)
            _wait_idle(page, RUN_TIMEOUT)
            _dismiss_dialogs(page)
            figure = page.locator("img.ngcrack-figure").first
            figure.wait_for(state="visible", timeout=MOVE_TIMEOUT * 1000)
            figure.scroll_into_view_if_needed()
            page.wait_for_timeout(500)
            page.screenshot(path=str(shots / "2-after-run.png"))
            before_src = figure.get_attribute("src")
            before_png = figure.screenshot(path=str(shots / "figure-before.png"))
            slider = page.locator(".widget-slider:has(.widget-label:text-is('load x'))").first
            handle = slider.locator(".noUi-handle").first
            handle.focus()
            changed = "(src) => { const i = document.querySelector('img.ngcrack-figure'); return i && i.src !== src; }"
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
            readout = slider.locator(".widget-readout").first.inner_text()
            after_png = figure.screenshot(path=str(shots / "figure-after.png"))
            page.screenshot(path=str(shots / "3-after-slider.png"))
            errors = page.locator("[data-mime-type='application/vnd.jupyter.error']").count()
            broken = page.locator("text=Error displaying widget").count()
            status = page.locator(".ngcrack-status").first.inner_text()
        finally:
            browser.close()
    print(f"[browser] {time.monotonic() - t0:.1f} s; one key press to a new figure {one_step:.2f} s, "
          f"{PRESSES - 1} more presses settled {settle:.1f} s after the last (including 1 s of stillness); "
          f"screenshots in {shots}")
    assert errors == 0 and broken == 0, f"{errors} error outputs, {broken} widgets not displayed"
    assert status.strip() == "", status
    assert float(readout.replace("\u2212", "-")) < 0.0, f"the slider did not move to tension: load x = {readout}"
    assert before_png != after_png, "the figure did not change"
