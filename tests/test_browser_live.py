"""Tutorial 4's live dashboard in JupyterLab, as a lecturer drives it.

Cold (nothing fitted), back to settings fitted a moment ago after a slider
was moved away, and new settings (nss = 10, the lecture plan's step): the
time from a click on *Run* to each agent's first step shown, and what the
dashboard says meanwhile.  The times are written to the screenshots folder
for the notes; the test asserts what the lecturer sees (each side's progress
in words, a status line that says what is true, fits loaded where they were
made before) and the order of the times, not their size.
"""

from __future__ import annotations

import json
import re
import shutil
import time

import pytest

from tests.test_browser import (  # noqa: F401  (browser and shots are fixtures)
    FIRST_STEPS,
    browser,
    button,
    jupyterlab,
    one_cell_notebook,
    run_all,
    shots,
)

DASHBOARD = ("from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard\n\n"
             "live = agent_dashboard(nu=3.0, magnitude=40, proportion=0.2, n_switch_states=2, seed=0, episodes=30,\n"
             "                       autoplay=True)\n"
             "live")
#: each side's header line (its title, and while it waits what it waits for)
HEADERS = """() => [...document.querySelectorAll('.widget-html-content')].map(e => e.innerText.trim())
  .filter(t => /^(Student-t|Gaussian) process/.test(t))"""


#: where the notebook, the dashboard, its two grids and their key-number tables are on the page (CSS px)
GEOMETRY = """() => {
  const notebook = document.querySelector('.jp-WindowedPanel-outer').getBoundingClientRect();
  const dashboard = document.querySelector('.sarsp-dashboard').getBoundingClientRect();
  const grids = [...document.querySelectorAll('.widget-html-content svg')].slice(0, 2)
    .map(s => s.getBoundingClientRect());
  const numbers = [...document.querySelectorAll('.widget-html-content table')].slice(0, 2)
    .map(t => t.getBoundingClientRect()).map(r => ({top: r.top, right: r.right}));
  return {notebook_height: notebook.height, dashboard_top: dashboard.top, dashboard_right: dashboard.right,
          grids_bottom: Math.max(...grids.map(g => g.bottom)), numbers: numbers};
}"""


@pytest.fixture
def lab(tmp_path, browser, monkeypatch):  # noqa: F811
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path / "fits"))  # nothing fitted yet
    monkeypatch.setenv("SARSP_EDU_AUTOPLAY", "1")  # as Tutorial 4 opens (the test run keeps it off elsewhere)
    work = tmp_path / "lab"
    work.mkdir()
    try:
        with jupyterlab(one_cell_notebook(DASHBOARD, work / "live.ipynb"), tmp_path, browser) as page:
            yield page, run_all(page, ".widget-slider .noUi-handle")
    finally:
        shutil.rmtree(tmp_path / "fits", ignore_errors=True)


def first_steps(page, since: float, seen: list) -> list:
    """Seconds from ``since`` (a time.time()) to each side's first step shown (None: not within 3 minutes).
    Every header and status line shown meanwhile is appended to ``seen``."""
    # FIRST_STEPS's promise is kept in the page (evaluate would wait for it): its value lands in window.__steps
    page.evaluate(f"(s) => {{ window.__steps = null; ({FIRST_STEPS})(s).then(v => {{ window.__steps = v; }}); }}",
                  180)
    offset = time.time() - since  # FIRST_STEPS counts from its own start
    while True:
        seen.extend(page.evaluate(HEADERS))
        seen.append(page.locator(".widget-html-content").nth(0).inner_text())
        done = page.evaluate("() => window.__steps")
        if done is not None:
            return [None if ms is None else round(offset + ms / 1000, 2) for ms in done]
        time.sleep(0.25)


def click_run(page, seen: list) -> list:
    """Click Run: :func:`first_steps` from the click."""
    button(page, "Run").click()
    return first_steps(page, time.time(), seen)


def set_nss(page, value: int) -> None:
    readout = page.locator(".widget-slider", has_text="nss").locator(".widget-readout")
    readout.fill(str(value))
    readout.press("Enter")
    page.wait_for_function(f"() => document.body.innerText.includes('nss = {value}: ')", timeout=60_000)


def test_run_starts_each_side_as_its_fit_ends_back_to_fitted_settings_at_once(lab, shots):  # noqa: F811
    page, started = lab
    seen = []
    cold = first_steps(page, started, seen)  # Run All with nothing fitted: the agents start by themselves
    page.screenshot(path=str(shots / "jupyterlab-live-cold-stepping.png"))
    assert None not in cold, f"a side never stepped: {cold}"
    progress = [text for text in seen if re.search(r"fitting (cost|reward) model: step \d+ of \d+", text)]
    assert progress, f"no side said how its fit progressed: {sorted(set(seen))[:20]}, first steps {cold}"
    assert not [t for t in seen if t.startswith("Running") and "both agents step" not in t
                and "steps shown" not in t and "agent steps" not in t], "a status said 'Running' before a step"

    # the grids and their key numbers side by side, within the notebook's height once the dashboard is at the top
    fit = page.evaluate(GEOMETRY)
    assert fit["grids_bottom"] - fit["dashboard_top"] <= fit["notebook_height"], fit
    assert all(t["top"] < fit["grids_bottom"] and t["right"] <= fit["dashboard_right"] + 1 for t in fit["numbers"]), fit

    # away and back: nss 2 -> 3 starts a fit for 3; back to 2 before it ends, then Run
    set_nss(page, 3)
    time.sleep(2.0)
    set_nss(page, 2)
    back = click_run(page, [])
    loaded = page.locator(".widget-html-content td:has-text('loaded')")
    loaded.nth(1).wait_for(timeout=30_000)

    # new settings, as the lecture plan asks: nss = 10
    set_nss(page, 10)
    fresh = click_run(page, [])
    page.screenshot(path=str(shots / "jupyterlab-live-nss10-stepping.png"))
    times = {"to_first_step_s": {"cold_from_run_all": cold, "back_to_fitted_from_run": back,
                                 "new_nss_10_from_run": fresh},
             "sides": ["Student-t process", "Gaussian process"]}
    times["layout_px"] = fit
    (shots / "jupyterlab-live-start.json").write_text(json.dumps(times, indent=1))
    assert None not in back and None not in fresh, times
    assert max(back) < min(min(cold), min(fresh)), f"settings fitted before should start first: {times}"
    assert page.locator(".jp-OutputArea-output .jp-RenderedText:has-text('Traceback')").count() == 0


SMALL_DASHBOARD = ("from sarsp_edu import ExperimentConfig\n"
                   "from sarsp_edu.teaching.dashboards.tutorials import agent_dashboard\n\n"
                   "config = ExperimentConfig(grid_size=6, n_unsafe=5, offline_episodes=8, cost_fit_points=80,\n"
                   "                          reward_fit_points=80, optimizer_steps=5, k_prior=30)\n"
                   "live = agent_dashboard(n_switch_states=1, episodes=5, config=config)\n"
                   "live")


def test_a_side_picks_the_gp_with_student_t_noise_and_both_sides_step(tmp_path, browser, shots, monkeypatch):  # noqa: F811
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path / "fits"))
    work = tmp_path / "lab"
    work.mkdir()
    with jupyterlab(one_cell_notebook(SMALL_DASHBOARD, work / "pick.ipynb"), tmp_path, browser) as page:
        run_all(page, ".widget-dropdown select")
        pickers = page.locator(".widget-dropdown select")
        assert pickers.count() == 2
        assert [pickers.nth(i).input_value() for i in range(2)] == ["Student-t process", "Gaussian process"]
        pickers.nth(0).select_option(label="GP, Student-t noise")  # the left side: the GP with Student-t noise
        page.wait_for_function("() => [...document.querySelectorAll('.widget-html-content')]"
                               ".some(e => e.innerText.trim().startsWith('GP, Student-t noise'))", timeout=60_000)
        size = page.evaluate("() => parseFloat(getComputedStyle(document.querySelector('.widget-dropdown select'))"
                             ".fontSize)")
        assert size >= 18, f"the model picker's text is {size} px: too small for the back row"
        steps = click_run(page, [])
        page.screenshot(path=str(shots / "jupyterlab-live-pick-t-likelihood.png"))
        assert None not in steps, f"a side never stepped: {steps}"
        assert page.locator(".jp-OutputArea-output .jp-RenderedText:has-text('Traceback')").count() == 0
