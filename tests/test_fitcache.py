"""The live dashboards' cache of fitted runs: reused only where it is the same bits as a new fit."""

from __future__ import annotations

import pickle

import pytest

from sarsp_edu import ExperimentConfig, fitcache
from sarsp_edu.experiment import experiments_on_one_world

TINY = ExperimentConfig(
    grid_size=5, n_unsafe=3, n_switch_states=1, episodes=3, offline_episodes=6,
    cost_fit_points=60, reward_fit_points=60, k_prior=30, optimizer_steps=5, seed=3,
)
SIDES = {"tp": {"model": "tp"}, "gp": {"model": "gp"}}


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(fitcache.CACHE_VARIABLE, str(tmp_path / "fits"))
    return tmp_path / "fits"


def records(experiment):
    while not experiment.finished:
        experiment.run_episode()
    return experiment.result().records.to_csv(index=False)


def test_a_loaded_fit_runs_exactly_as_a_new_one(cache):
    fitted = experiments_on_one_world(TINY, SIDES, cache=True)
    assert not any(e.loaded_from_cache for e in fitted.values())
    assert len(fitcache.entries()) == 2
    loaded = experiments_on_one_world(TINY, SIDES, cache=True)
    assert all(e.loaded_from_cache for e in loaded.values())
    fresh = experiments_on_one_world(TINY, SIDES)  # no cache: fitted again
    for name in SIDES:
        assert records(loaded[name]) == records(fresh[name])
        assert records(fitted[name]) == records(fresh[name])


def test_other_settings_or_other_code_fit_afresh(cache, monkeypatch):
    experiments_on_one_world(TINY, {"tp": {"model": "tp"}}, cache=True)
    other = experiments_on_one_world(TINY.replace(nu=4.0), {"tp": {"model": "tp"}}, cache=True)
    assert not other["tp"].loaded_from_cache
    monkeypatch.setattr(fitcache, "fingerprint", lambda: "another version of the package")
    again = experiments_on_one_world(TINY, {"tp": {"model": "tp"}}, cache=True)
    assert not again["tp"].loaded_from_cache
    assert len(fitcache.entries()) == 3


def test_an_unreadable_entry_is_fitted_again_and_replaced(cache):
    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=True)
    (path, _), = fitcache.entries()
    path.write_bytes(b"half a fit")
    again = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=True)
    assert not again["gp"].loaded_from_cache
    assert pickle.loads(path.read_bytes()).config == TINY.replace(model="gp")
    assert not list(cache.glob(".*.tmp"))  # written through a temporary file, none left behind


def test_only_a_just_fitted_run_is_stored(cache):
    experiment = experiments_on_one_world(TINY, {"gp": {"model": "gp"}})["gp"]
    experiment.step()
    with pytest.raises(ValueError, match="just-fitted.*1 steps"):
        fitcache.store(experiment)


def test_the_least_recently_used_fits_go_first(cache, monkeypatch):
    experiments_on_one_world(TINY, SIDES, cache=True)
    size = max(size for _, size in fitcache.entries())
    monkeypatch.setattr(fitcache, "CACHE_BYTES", size + 1)  # room for one
    experiments_on_one_world(TINY.replace(seed=4), {"tp": {"model": "tp"}}, cache=True)
    (kept, _), = fitcache.entries()
    assert pickle.loads(kept.read_bytes()).config == TINY.replace(seed=4, model="tp")
    assert fitcache.clear() == 1 and fitcache.entries() == []


@pytest.mark.parametrize("value", ["off", "0", ""])
def test_the_cache_can_be_turned_off(monkeypatch, tmp_path, value):
    monkeypatch.setenv(fitcache.CACHE_VARIABLE, value)
    assert fitcache.cache_directory() is None
    experiment = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=True)["gp"]
    assert fitcache.store(experiment) is None and fitcache.entries() == []


def test_by_default_the_cache_lives_in_the_users_cache_folder(monkeypatch, tmp_path):
    monkeypatch.delenv(fitcache.CACHE_VARIABLE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert fitcache.cache_directory() == tmp_path / "sarsp_edu" / "fits"
