"""The tutorials in a real browser: Voila and JupyterLab driven by Playwright and Debian's Chromium.

Skipped where Chromium or Playwright is missing; ``.ci/run`` installs both.
Screenshots land in ``$SARSP_SCREENSHOTS`` (default: the test's tmp folder).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
ROOT = Path(__file__).resolve().parents[1]
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]

if not Path(CHROMIUM).exists():
    if os.environ.get("CI"):  # CI installs it: a missing browser there is a failure, not a skip
        raise RuntimeError(f"{CHROMIUM} is missing on CI: .ci/run should have installed Debian's chromium")
    pytest.skip("Debian's chromium is not installed (apt-get install chromium)", allow_module_level=True)
playwright_api = pytest.importorskip("playwright.sync_api")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_http(url: str, timeout: float = 60.0) -> None:
    deadline = time.time() + timeout
    while time.time() < deadline:
        try:
            urllib.request.urlopen(url, timeout=2)
            return
        except Exception:
            time.sleep(0.3)
    raise TimeoutError(f"{url} did not answer within {timeout} s")


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    folder = Path(os.environ.get("SARSP_SCREENSHOTS", tmp_path_factory.mktemp("screenshots")))
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.fixture(scope="module")
def browser():
    with playwright_api.sync_playwright() as p:
        instance = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield instance
        instance.close()


def serve(command, cwd, url):
    env = dict(os.environ, MPLBACKEND="Agg")
    process = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        wait_for_http(url)
    except TimeoutError:
        process.kill()
        raise
    return process


def voila(notebook: Path, port: int):
    binary = shutil.which("voila") or str(Path(sys.prefix, "bin", "voila"))
    return serve([binary, notebook.name, "--no-browser", f"--port={port}", "--Voila.ip=127.0.0.1"],
                 notebook.parent, f"http://127.0.0.1:{port}/")


def image_settled(page, selector: str, timeout: float = 30.0, changed_from: str | None = None) -> str:
    """The image's src once it has stopped changing for 1.5 s (several redraws may be queued).

    With ``changed_from``, first wait for the src to differ from it: a redraw
    takes a round trip to the kernel, longer than the settling time.
    """
    deadline = time.time() + timeout
    if changed_from is not None:
        while page.get_attribute(selector, "src") == changed_from and time.time() < deadline:
            time.sleep(0.1)
    last, since = page.get_attribute(selector, "src"), time.time()
    while time.time() < deadline:
        time.sleep(0.15)
        now = page.get_attribute(selector, "src")
        if now != last:
            last, since = now, time.time()
        elif time.time() - since > 1.5:
            return now
    return last


def button(page, text: str):
    """An ipywidgets button by its visible text (its icon glyph is part of the accessible name)."""
    return page.locator("button", has_text=re.compile(rf"^\s*{re.escape(text)}\s*$")).first


def slider_handle(page, label: str):
    slider = page.locator(".widget-slider", has=page.locator(".widget-label", has_text=label)).first
    return slider.locator(".noUi-handle").first


@contextlib.contextmanager
def tutorial_in_voila(name: str, tmp_path, browser, width: int, height: int):
    """A copy of a tutorial served by Voila and opened in a page of the given size; the server stops after."""
    notebook = tmp_path / name
    shutil.copy(ROOT / "tutorials" / name, notebook)
    port = free_port()
    server = voila(notebook, port)
    try:
        page = browser.new_page(viewport={"width": width, "height": height})
        page.goto(f"http://127.0.0.1:{port}/", timeout=180_000)
        yield page
    finally:
        server.kill()


def test_tail_decay_dashboard_in_voila(tmp_path, browser, shots):
    with tutorial_in_voila("01_tail_decay.ipynb", tmp_path, browser, 1400, 1000) as page:
        page.wait_for_selector("img.widget-image", timeout=180_000)
        info = page.locator(".widget-htmlmath").last
        before_src = image_settled(page, "img.widget-image")
        before_info = info.inner_text()
        handle = slider_handle(page, "ν")
        handle.focus()
        for _ in range(4):  # nu 3 -> 5
            page.keyboard.press("ArrowRight")
        after_src = image_settled(page, "img.widget-image", changed_from=before_src)
        assert after_src != before_src  # the figure was redrawn
        deadline = time.time() + 30
        while info.inner_text() == before_info and time.time() < deadline:
            time.sleep(0.2)
        assert info.inner_text() != before_info  # and the sympy limit re-evaluated
        page.locator("img.widget-image").first.scroll_into_view_if_needed()
        page.screenshot(path=str(shots / "voila_tail_decay.png"), full_page=False)


LIVE = """
from sarsp_edu import ExperimentConfig
from sarsp_edu.widgets import agent_dashboard

agent_dashboard(episodes=30, n_switch_states=2,
                config=ExperimentConfig(grid_size=7, n_unsafe=6, offline_episodes=20, cost_fit_points=150, reward_fit_points=150,
                                        optimizer_steps=20))
"""


def test_live_agent_dashboard_in_voila(tmp_path, browser, shots):
    import nbformat

    notebook = tmp_path / "live.ipynb"
    nb = nbformat.v4.new_notebook()
    nb.cells.append(nbformat.v4.new_code_cell(LIVE))
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, notebook)
    port = free_port()
    server = voila(notebook, port)
    try:
        page = browser.new_page(viewport={"width": 1400, "height": 1100})
        page.goto(f"http://127.0.0.1:{port}/", timeout=180_000)
        button(page, "Run").click(timeout=120_000)
        shown = r"/\d+ steps shown, [\d.]+ steps per second/"
        page.wait_for_function(f"() => {shown}.test(document.body.innerText)", timeout=120_000)
        time.sleep(3.0)
        status = re.search(r"(\d+) steps shown, ([\d.]+) steps per second", page.inner_text("body"))
        rate = float(status.group(2))
        worlds = page.locator("svg")
        before = [worlds.nth(i).inner_html() for i in range(worlds.count())]
        time.sleep(0.5)
        assert [worlds.nth(i).inner_html() for i in range(worlds.count())] != before  # the agents move
        page.screenshot(path=str(shots / "voila_live_agent.png"), full_page=True)
        button(page, "Stop").click()
        page.wait_for_function("() => /Paused|Stopped|Finished/.test(document.body.innerText)", timeout=30_000)
        # The rate is a measurement for the closing note, not a pass/fail criterion.
        (shots / "live_rate.json").write_text(json.dumps({"displayed_steps_per_second": rate}))
        assert rate > 0
    finally:
        server.kill()


def test_gp_vs_tp_tutorial_runs_in_jupyterlab(tmp_path, browser, shots):
    work = tmp_path / "lab"
    work.mkdir()
    shutil.copy(ROOT / "tutorials" / "02_gp_vs_tp_outliers.ipynb", work / "02.ipynb")
    port = free_port()
    command = [sys.executable, "-m", "jupyter", "lab", "--no-browser", "--allow-root", f"--port={port}",
               "--ServerApp.token=", "--ServerApp.password=", "--ServerApp.ip=127.0.0.1",
               f"--ServerApp.root_dir={work}"]
    server = serve(command, work, f"http://127.0.0.1:{port}/lab")
    try:
        page = browser.new_page(viewport={"width": 1500, "height": 1100})
        page.goto(f"http://127.0.0.1:{port}/lab/tree/02.ipynb", timeout=120_000)
        page.wait_for_selector('.jp-Notebook-ExecutionIndicator[data-status="idle"]', timeout=120_000)
        # A saved widget output renders no image in a fresh JupyterLab: the dashboard's
        # image appears only once Run All has executed the cells (the busy indicator
        # can come and go before a test sees it).
        for attempt in range(2):
            page.locator(".lm-MenuBar-itemLabel", has_text=re.compile(r"^Run$")).click()
            page.locator("li[data-command='runmenu:run-all']").click()
            try:
                page.wait_for_selector("img.widget-image", timeout=120_000)
                break
            except playwright_api.TimeoutError:
                if attempt:
                    raise
        page.wait_for_selector('.jp-Notebook-ExecutionIndicator[data-status="idle"]', timeout=300_000)
        page.wait_for_function("() => document.querySelectorAll('.jp-InputPrompt').length > 0 && "
                               "![...document.querySelectorAll('.jp-InputPrompt')].some(e => e.textContent.includes('*'))",
                               timeout=300_000)
        assert page.locator('.jp-RenderedText[data-mime-type="application/vnd.jupyter.stderr"]').count() == 0
        assert page.locator(".jp-OutputArea-output .jp-RenderedText:has-text('Traceback')").count() == 0
        dashboard = page.locator("img.widget-image").first
        dashboard.wait_for(timeout=60_000)
        dashboard.scroll_into_view_if_needed()
        time.sleep(1.0)
        page.screenshot(path=str(shots / "jupyterlab_posterior_dashboard.png"))
    finally:
        server.kill()


# --------------------------------------------------------------------------
# Without a kernel: a static HTML export, opened with the network off (issue 25, section 3)
# --------------------------------------------------------------------------
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
DASHBOARD_NOTEBOOKS = [p for p in sorted((ROOT / "tutorials").glob("*.ipynb"))
                       if WIDGET_VIEW in p.read_text()]

#: mean and spread of an image's pixels (0-255), read in the page through a canvas
PIXELS = """(img) => {
  const canvas = document.createElement('canvas');
  canvas.width = img.naturalWidth; canvas.height = img.naturalHeight;
  const context = canvas.getContext('2d');
  context.drawImage(img, 0, 0);
  const data = context.getImageData(0, 0, canvas.width, canvas.height).data;
  let sum = 0, squares = 0, n = 0;
  for (let i = 0; i < data.length; i += 4) { const v = (data[i] + data[i + 1] + data[i + 2]) / 3; sum += v; squares += v * v; n++; }
  const mean = sum / n;
  return {width: img.naturalWidth, height: img.naturalHeight, mean: mean, spread: Math.sqrt(squares / n - mean * mean)};
}"""


@pytest.mark.parametrize("notebook", DASHBOARD_NOTEBOOKS, ids=lambda p: p.name)
def test_a_static_export_shows_every_dashboards_picture_offline(notebook, tmp_path, browser, shots):
    import nbformat

    assert len(DASHBOARD_NOTEBOOKS) >= 4
    stored = nbformat.read(notebook, as_version=4)
    assert "widgets" not in stored.metadata, "stored widget state makes an export load the widgets from the network"
    dashboards = [i for i, cell in enumerate(stored.cells)
                  if any(WIDGET_VIEW in output.get("data", {}) for output in cell.get("outputs", []))]
    assert dashboards
    # exported as a reader would, with nbconvert's defaults
    subprocess.run([sys.executable, "-m", "nbconvert", "--to", "html", "--output-dir", str(tmp_path), str(notebook)],
                   check=True, capture_output=True)
    page_file = tmp_path / f"{notebook.stem}.html"
    context = browser.new_context(viewport={"width": 1280, "height": 720}, offline=True)
    try:
        page = context.new_page()
        requested = []
        page.route(re.compile(r"^https?://"), lambda route: (requested.append(route.request.url), route.abort()))
        page.goto(page_file.as_uri())
        page.wait_for_load_state("load")
        cells = page.query_selector_all(".jp-Cell")
        assert len(cells) == len(stored.cells)
        for index in dashboards:
            images = cells[index].query_selector_all(".jp-OutputArea-output img")
            assert images, f"{notebook.name} cell {index}: the dashboard's place holds no picture"
            stats = images[0].evaluate(PIXELS)
            assert stats["width"] > 200 and stats["height"] > 100, stats
            assert stats["spread"] > 20, f"{notebook.name} cell {index}: a blank picture {stats}"
            images[0].scroll_into_view_if_needed()
            page.screenshot(path=str(shots / f"static-{notebook.stem}-cell{index}.png"))
    finally:
        context.close()


# --------------------------------------------------------------------------
# Sliders a lecturer can grab: wide tracks, nothing off screen (issue 30, item 4)
# --------------------------------------------------------------------------
TRACKS = """() => [...document.querySelectorAll('.widget-slider')].map(s => [
  s.querySelector('.widget-label').innerText, s.querySelector('.noUi-target').getBoundingClientRect().width])"""
RIGHTMOST = """() => Math.max(...[...document.querySelectorAll(
  '.widget-slider, .widget-readout, .widget-label, .widget-checkbox, .widget-button')].map(e => e.getBoundingClientRect().right))"""


@pytest.mark.parametrize("name", ["01_tail_decay.ipynb", "02_gp_vs_tp_outliers.ipynb", "03_gridworld_and_shift.ipynb"])
def test_every_slider_track_is_wide_and_nothing_runs_off_a_small_screen(name, tmp_path, browser, shots):
    with tutorial_in_voila(name, tmp_path, browser, 1280, 720) as page:
        page.wait_for_selector(".widget-slider .noUi-target", timeout=180_000)
        for width, height in ((1280, 720), (800, 600)):
            page.set_viewport_size({"width": width, "height": height})
            page.wait_for_timeout(1000)
            tracks = page.evaluate(TRACKS)
            assert tracks and all(track >= 150 for _, track in tracks), f"{name} at {width}x{height}: {tracks}"
            assert page.evaluate(RIGHTMOST) <= width, f"{name} at {width}x{height}: a control runs off the screen"
            page.locator(".widget-slider").first.scroll_into_view_if_needed()
            page.screenshot(path=str(shots / f"sliders-{Path(name).stem}-{width}.png"))
