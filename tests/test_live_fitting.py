"""The live dashboard's fits in processes of their own (sarsp_edu.teaching.live.fitting and background.FitQueue).

Both sides fitted at once, each in a worker process, must give the very runs
a fit in the kernel gives; a newer request must stop the fits it replaces at
once; a script's end must end the workers; and where no process can be
started the sides are fitted in the thread.
"""

from __future__ import annotations

import re
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

import pytest

from sarsp_edu.config import ExperimentConfig
from sarsp_edu.experiments.experiment import paired_experiments
from sarsp_edu.teaching.live import TP_AND_GP, fitting, prefit
from sarsp_edu.teaching.live.background import FitQueue, _describe, slider_config
from sarsp_edu.teaching.live.pick import model_sides

from .worlds import SIX_BY_SIX

SMALL = dict(SIX_BY_SIX, episodes=3)


@pytest.fixture(params=["cache", "off"])
def cache(request, monkeypatch, tmp_path):
    """With the fit cache on (a fresh folder) and off (the fits are handed over through a folder of its own)."""
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path / "fits") if request.param == "cache" else "off")
    return request.param


def prepared_runs(queue, config):
    queue.request(config)
    fits = queue.claim(config)
    return {name: fits.wait_for(name) for name in queue.sides}


def test_fits_in_worker_processes_give_the_runs_a_fit_in_the_kernel_gives(cache):
    config = ExperimentConfig(**SMALL)
    runs = prepared_runs(FitQueue(dict(TP_AND_GP)), config)
    expected = paired_experiments(config)
    for name in ("tp", "gp"):
        assert not runs[name].loaded_from_cache  # fitted now, in a worker
        assert runs[name].timings["offline_fit_seconds"] > 0
        while not expected[name].finished:
            runs[name].run_episode()
            expected[name].run_episode()
        assert runs[name].records().equals(expected[name].records()), name
    assert runs["tp"].agent.cost_model.theta_.tolist() == expected["tp"].agent.cost_model.theta_.tolist()


def test_settings_fitted_before_are_loaded_and_a_newer_request_stops_the_fits_it_replaces(monkeypatch, tmp_path):
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path / "fits"))
    started = []
    queue = FitQueue(dict(TP_AND_GP))
    plain = queue._take_worker  # a worker of the queue's pool, or a new one
    monkeypatch.setattr(queue, "_take_worker", lambda: started.append(plain()) or started[-1])
    fitted = ExperimentConfig(**SMALL)
    prepared_runs(queue, fitted)
    abandoned = fitted.replace(n_switch_states=2, optimizer_steps=2000)  # a fit that would take minutes
    queue.request(abandoned)
    deadline = time.monotonic() + 60
    while len(started) < 4 and time.monotonic() < deadline:
        time.sleep(0.05)
    slow = started[2:]
    assert len(slow) == 2, "the abandoned settings' fits should have begun in two workers"
    back = prepared_runs(queue, fitted)  # back to the settings fitted before
    assert all(run.loaded_from_cache for run in back.values())
    for worker in slow:  # stopped, not left running behind the wanted settings
        assert worker.process.wait(timeout=30) is not None
        assert worker.process.returncode != 0


def test_progress_is_said_in_words():
    class Worker:
        started_at = None
        steps = (0, 0)

    config = ExperimentConfig(**SMALL)
    assert _describe(Worker(), config) == "starting its fit (imports, data)"
    Worker.started_at = time.perf_counter() - 2.0
    Worker.steps = (10, 100)
    assert _describe(Worker(), config).startswith("fitting cost model: step 10 of 100, 2 s, 18 s left")
    Worker.steps = (60, 100)
    assert "fitting reward model: step 60 of 100" in _describe(Worker(), config)
    Worker.steps = (7, 0)  # L-BFGS: the total is not known
    assert _describe(Worker(), config) == "fitting models: step 7, 2 s so far"


def test_where_no_process_can_be_started_the_sides_are_fitted_in_the_thread(monkeypatch, cache):
    def refused():
        raise OSError("no processes here")

    monkeypatch.setattr(fitting, "take_worker", refused)
    config = ExperimentConfig(**SMALL)
    runs = prepared_runs(FitQueue(dict(TP_AND_GP)), config)
    expected = paired_experiments(config)
    for name in ("tp", "gp"):
        runs[name].run_episode()
        expected[name].run_episode()
        assert runs[name].records().equals(expected[name].records())


def test_a_worker_fails_with_its_message_and_ends_with_its_kernel(tmp_path):
    worker = fitting.FitWorker()
    worker.submit("not a config", tmp_path)
    word, message = worker.answer(timeout=60)
    assert word == "error" and "AttributeError" in message, message
    worker.process.stdin.close()  # the kernel has gone
    assert worker.process.wait(timeout=30) == 0


def test_a_script_that_starts_fits_ends_when_it_reaches_its_end(tmp_path):
    script = ("from sarsp_edu.config import ExperimentConfig\n"
              "from sarsp_edu.teaching.live import TP_AND_GP\nfrom sarsp_edu.teaching.live.background import FitQueue\n"
              f"FitQueue(dict(TP_AND_GP)).request(ExperimentConfig(**{dict(SMALL, optimizer_steps=5000)!r}))\n"
              "import time; time.sleep(1)\n")
    mark = f"SARSP_EDU_TEST_MARK={uuid.uuid4().hex}"  # the workers of this script, and no other, carry it
    start = time.monotonic()
    subprocess.run([sys.executable, "-c", script], check=True, timeout=120,
                   env={"SARSP_EDU_CACHE": str(tmp_path), "PATH": "/usr/bin:/bin", mark.split("=")[0]: mark[20:]})
    assert time.monotonic() - start < 100  # not the minutes the fits would take
    deadline = time.monotonic() + 30
    while _marked(mark) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not _marked(mark), "a worker outlived its script"


def _marked(mark: str) -> list:
    """The processes whose environment holds ``mark``."""
    found = []
    for entry in Path("/proc").iterdir():
        try:
            if entry.name.isdigit() and mark.encode() in (entry / "environ").read_bytes().split(b"\0"):
                found.append(entry.name)
        except OSError:  # ended meanwhile, or not ours to read
            pass
    return found


def test_prefit_fits_each_nss_once_and_then_finds_it_stored(monkeypatch, tmp_path):
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path))
    said = []
    config = ExperimentConfig(**{k: v for k, v in SMALL.items() if k != "episodes"})
    first = prefit((0, 1), episodes=3, config=config, report=said.append)
    assert [(nss, side) for nss, side, _ in first] == [(0, "tp"), (0, "gp"), (1, "tp"), (1, "gp")]
    assert all(what.startswith("fitted in") for *_, what in first), first
    again = prefit((0, 1), episodes=3, config=config, report=said.append)
    assert all(what == "stored before" for *_, what in again), again
    assert said[0].startswith("nss = 0, Student-t process: fitted in")
    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    with pytest.raises(RuntimeError, match="cache of fits is off"):
        prefit(0, config=config)


def test_prefit_keeps_the_third_models_side_for_its_pick(monkeypatch, tmp_path):
    """``sarsp-edu prefit --models t-likelihood``: the side that a pick of the GP with Student-t noise asks for
    is then loaded by the dashboard's queue, not fitted."""
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path))
    config = ExperimentConfig(**{k: v for k, v in SMALL.items() if k != "episodes"})
    sliders = dict(nu=3.0, magnitude=10.0, proportion=0.1, seed=0, episodes=3)
    done = prefit(1, **sliders, config=config, sides=model_sides(["t-likelihood"]), report=lambda line: None)
    assert [(nss, side) for nss, side, _ in done] == [(1, "t-likelihood")] and done[0][2].startswith("fitted in")
    picked = {"tp": TP_AND_GP["tp"], "gp": model_sides(["t-likelihood"])["t-likelihood"]}  # the right side picked
    queue = FitQueue(picked)
    runs = prepared_runs(queue, slider_config(config, n_switch_states=1, **sliders))
    queue.close()
    assert runs["gp"].loaded_from_cache and runs["gp"].config.model == "t-likelihood"
    assert not runs["tp"].loaded_from_cache  # not asked for


def test_a_side_with_its_own_decision_parts_runs_them_beside_the_packages(monkeypatch):
    """Tutorial 7's "your agent" beside the package's: the same fits (in the workers), each side given its parts
    in the kernel before its first step; parts that name no side are refused."""
    from sarsp_edu.agent.parts import DecisionParts
    from sarsp_edu.teaching.live import agent_dashboard

    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    calls = []

    def counted_choose(*args):
        calls.append(1)
        return DecisionParts().choose(*args)

    sides = {"yours": ("your agent", {"model": "tp"}), "package": ("the package's agent", {"model": "tp"})}
    config = ExperimentConfig(**{k: v for k, v in SMALL.items() if k != "episodes"})
    live = agent_dashboard(episodes=2, n_switch_states=1, config=config, sides=sides,
                           parts={"yours": {"choose": counted_choose}})
    live.fast_forward(2)
    assert live.experiments["yours"].agent.parts.replaced() == ["choose"]
    assert live.experiments["package"].agent.parts.replaced() == []
    assert calls and len(calls) == len(live.experiments["yours"].act_seconds)  # every decision of "yours" only
    assert live.experiments["yours"].records().equals(live.experiments["package"].records())  # the same choice
    with pytest.raises(ValueError, match=r"parts names sides \['theirs'\]"):
        agent_dashboard(config=config, sides=sides, parts={"theirs": {}}, fit_ahead=False)


# -- the live run's controls: a clean exit, one stepper at a time, no stale run after a slider move -------------
def test_a_script_that_plays_the_agents_in_the_background_exits_when_it_reaches_its_end(tmp_path):
    script = ("import atexit, threading\n"  # registered first, so run last: what the package's exit hooks left
              "atexit.register(lambda: print('left', [t.name for t in threading.enumerate()][1:]))\n"
              "from sarsp_edu.config import ExperimentConfig\nfrom sarsp_edu.teaching.live import agent_dashboard\n"
              f"config = ExperimentConfig(**{ {k: v for k, v in SMALL.items() if k != 'episodes'}!r})\n"
              "live = agent_dashboard(episodes=250, n_switch_states=1, config=config, steps_per_second=2)\n"
              "live.play_in_background()\nimport time; time.sleep(3)\nprint('end', live.running)\n")
    start = time.monotonic()
    done = subprocess.run([sys.executable, "-c", script], timeout=120, capture_output=True, text=True, check=False,
                          env={"SARSP_EDU_CACHE": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr[-2000:]
    # the agents were walking when the script ended, and no thread of the run outlived the exit hooks
    assert done.stdout.strip().split("\n") == ["end True", "left []"]
    assert time.monotonic() - start < 100  # and the script ended with it, not 250 episodes at 2 steps a second


def test_stepping_from_a_cell_while_the_agents_walk_is_refused_and_close_stops_everything(monkeypatch):
    from sarsp_edu.teaching.live import agent_dashboard

    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    config = ExperimentConfig(**{k: v for k, v in SMALL.items() if k != "episodes"})
    live = agent_dashboard(episodes=100, n_switch_states=1, config=config, steps_per_second=5)
    launched = live.play_in_background()
    deadline = time.monotonic() + 60
    while live.frames < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    assert live.running and live.frames >= 2
    for call in (lambda: live.run_steps(3), lambda: live.fast_forward(1)):
        with pytest.raises(RuntimeError, match="while the agents are running: press Stop"):
            call()
    live.close()
    assert launched.result(0) is True and not live.running and live.experiments is None
    assert live.run.fits._thread is None or not live.run.fits._thread.is_alive()


def test_a_slider_moved_while_a_run_claims_its_fits_leaves_no_stale_run(monkeypatch):
    """Run claims the fits of the sliders' settings; a slider moved meanwhile must not leave the old settings'
    run to animate (the move is taken by the run's thread after the claim, or before it: never within)."""
    from sarsp_edu.teaching.live import agent_dashboard

    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    config = ExperimentConfig(**{k: v for k, v in SMALL.items() if k != "episodes"})
    live = agent_dashboard(episodes=2, n_switch_states=1, config=config)
    launched = live.play_in_background()  # claims the nss = 1 fits, still under way
    live.controls["n_switch_states"].value = 2  # a slider move meanwhile
    assert launched.result(60) is True
    assert live.experiments is None and not live.running  # the old run is not kept: the next Run builds nss = 2
    live.build_runs()
    assert all(len(e.env.moved_indices) == 2 for e in live.experiments.values())


def test_a_side_with_student_t_noise_is_fitted_in_a_worker_saying_its_time_left(monkeypatch, cache):
    """A GP-with-Student-t-noise side is fitted in a process of its own beside the other side's, saying its
    steps and the time left, and runs as a plain paired run does."""
    from sarsp_edu.experiments.experiment import experiments_on_one_world

    config = ExperimentConfig(**dict(SMALL, optimizer_steps=40))
    sides = {"gp": ("Gaussian process", {"model": "gp"}), "t": ("Student-t noise", {"model": "t-likelihood"})}
    said, news = [], threading.Event()
    queue = FitQueue(sides, on_news=news.set)
    started = []
    plain = queue._take_worker
    monkeypatch.setattr(queue, "_take_worker", lambda: started.append(plain()) or started[-1])
    queue.request(config)
    fits = queue.claim(config)
    while not fits.ready("t"):
        news.wait(1)
        news.clear()
        said.append(fits.progress.get("t", ""))
    runs = {name: fits.wait_for(name, timeout=120) for name in sides}
    queue.close()
    assert len(started) == 2  # both sides in workers, none in the kernel's thread
    assert any(re.fullmatch(r"fitting (cost|reward) model: step \d+ of 80, \d+ s, \d+ s left", line)
               for line in said), said
    expected = experiments_on_one_world(config, {"gp": {"model": "gp"}, "t": {"model": "t-likelihood"}})
    for name in sides:
        runs[name].run_episode()
        expected[name].run_episode()
        assert runs[name].records().equals(expected[name].records()), name
    assert runs["t"].config.model == "t-likelihood" and not runs["t"].loaded_from_cache


def test_a_side_fitted_in_the_queues_thread_is_abandoned_at_its_next_step_for_newer_settings(monkeypatch, cache):
    def refused():
        raise OSError("no processes here")

    monkeypatch.setattr(fitting, "take_worker", refused)  # no worker: the sides are fitted in the queue's thread
    config = ExperimentConfig(**dict(SMALL, optimizer_steps=3000))  # a fit that would take minutes
    sides = {"t": ("Student-t noise", {"model": "t-likelihood"}), "gp": ("Gaussian process", {"model": "gp"})}
    queue = FitQueue(sides)
    queue.request(config)
    fits = queue.claim(config)
    deadline = time.monotonic() + 120
    while "step" not in fits.progress.get("t", "") and time.monotonic() < deadline:
        time.sleep(0.05)
    assert re.match(r"fitting its models here: step \d+ of 6000, \d+ s", fits.progress.get("t", "")), fits.progress
    newer = ExperimentConfig(**SMALL)
    assert prepared_runs(queue, newer)["t"].config == newer.replace(model="t-likelihood")
    assert fits.done and "t" not in fits.experiments and fits.error is None  # abandoned, not finished
