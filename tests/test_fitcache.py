"""The live dashboards' cache of fitted runs: reused only where it is the same bits as a new fit."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from sarsp_edu import ExperimentConfig
from sarsp_edu.experiments.experiment import experiments_on_one_world
from sarsp_edu.teaching.live import fitcache

from .worlds import FIVE_BY_FIVE_MORE_DATA

TINY = ExperimentConfig(**dict(FIVE_BY_FIVE_MORE_DATA, k_prior=30, optimizer_steps=5), n_switch_states=1, episodes=3,
                        seed=3)
SIDES = {"tp": {"model": "tp"}, "gp": {"model": "gp"}}


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(fitcache.CACHE_VARIABLE, str(tmp_path / "fits"))
    return tmp_path / "fits"


def stored_config(path) -> dict:
    """The settings an entry was fitted for, read as arrays and JSON (nothing in it can run code)."""
    with np.load(path, allow_pickle=False) as entry:
        return json.loads(str(entry["meta"]))["config"]


def records(experiment):
    while not experiment.finished:
        experiment.run_episode()
    return experiment.result().records.to_csv(index=False)


def test_a_loaded_fit_runs_exactly_as_a_new_one(cache):
    fitted = experiments_on_one_world(TINY, SIDES, cache=fitcache)
    assert not any(e.loaded_from_cache for e in fitted.values())
    assert len(fitcache.entries()) == 2
    loaded = experiments_on_one_world(TINY, SIDES, cache=fitcache)
    assert all(e.loaded_from_cache for e in loaded.values())
    fresh = experiments_on_one_world(TINY, SIDES)  # no cache: fitted again
    for name in SIDES:
        assert records(loaded[name]) == records(fresh[name])
        assert records(fitted[name]) == records(fresh[name])


T_NOISE = {"t-likelihood": {"model": "t-likelihood"}}


def test_a_loaded_fit_with_student_t_noise_runs_exactly_as_a_new_one(cache):
    fitted = experiments_on_one_world(TINY, T_NOISE, cache=fitcache)["t-likelihood"]
    assert not fitted.loaded_from_cache and len(fitcache.entries()) == 1
    loaded = experiments_on_one_world(TINY, T_NOISE, cache=fitcache)["t-likelihood"]
    assert loaded.loaded_from_cache
    fresh = experiments_on_one_world(TINY, T_NOISE)["t-likelihood"]
    for attribute in ("f_hat_", "W_", "mode_start_", "start_objectives_"):
        assert np.array_equal(getattr(loaded.agent.cost_model, attribute), getattr(fresh.agent.cost_model, attribute))
    assert loaded.result().fits == fresh.result().fits
    assert records(loaded) == records(fresh) == records(fitted)


@pytest.mark.parametrize("change", [
    lambda arrays, meta: arrays["cost.hyper_"].__imul__(1 + 1e-12),  # other hyperparameters
    lambda arrays, meta: arrays.update({"cost.hyper_": arrays["cost.hyper_"] * -1}),
    lambda arrays, meta: arrays.update({"cost.mode_start_": arrays["cost.mode_start_"][:-1]}),
    lambda arrays, meta: arrays["cost.mode_start_"].__iadd__(1.0),  # the mode searched from elsewhere
    lambda arrays, meta: meta["models"]["cost"].update(n_newton_=1.5),
    lambda arrays, meta: meta["models"]["cost"].pop("kind"),
])
def test_an_edited_entry_with_student_t_noise_is_refused(cache, change):
    experiments_on_one_world(TINY, T_NOISE, cache=fitcache)
    (path, _), = fitcache.entries()
    _edit_entry(path, change)
    with pytest.warns(UserWarning, match="was refused"):
        again = experiments_on_one_world(TINY, T_NOISE, cache=fitcache)["t-likelihood"]
    assert not again.loaded_from_cache
    assert records(again) == records(experiments_on_one_world(TINY, T_NOISE)["t-likelihood"])


def test_other_settings_or_other_code_fit_afresh(cache, monkeypatch):
    experiments_on_one_world(TINY, {"tp": {"model": "tp"}}, cache=fitcache)
    other = experiments_on_one_world(TINY.replace(nu=4.0), {"tp": {"model": "tp"}}, cache=fitcache)
    assert not other["tp"].loaded_from_cache
    monkeypatch.setattr(fitcache, "fingerprint", lambda: "another version of the package")
    again = experiments_on_one_world(TINY, {"tp": {"model": "tp"}}, cache=fitcache)
    assert not again["tp"].loaded_from_cache
    assert len(fitcache.entries()) == 3


def test_an_unreadable_entry_is_fitted_again_and_replaced(cache):
    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    path.write_bytes(b"half a fit")
    with pytest.warns(UserWarning, match=r"the stored fit .* was refused \(.*\): it is fitted again and stored anew"):
        again = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    assert not again["gp"].loaded_from_cache
    assert stored_config(path) == TINY.replace(model="gp").to_dict()
    assert not list(cache.glob(".*.tmp"))  # written through a temporary file, none left behind


def test_the_first_fit_kept_says_where_and_how_much_and_how_to_clear(cache):
    with pytest.warns(UserWarning, match=r"sarsp_edu keeps fitted runs in .*fits \(\d+ MB this one, at most \d+ MB "
                                         r"in all\).*'sarsp-edu cache --clear' removes them"):
        experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once: the folder is there now
        experiments_on_one_world(TINY, {"tp": {"model": "tp"}}, cache=fitcache)


def test_only_a_just_fitted_run_is_stored(cache):
    experiment = experiments_on_one_world(TINY, {"gp": {"model": "gp"}})["gp"]
    experiment.step()
    with pytest.raises(ValueError, match="just-fitted.*1 steps"):
        fitcache.store(experiment)


def test_the_least_recently_used_fits_go_first(cache, monkeypatch):
    experiments_on_one_world(TINY, SIDES, cache=fitcache)
    size = max(size for _, size in fitcache.entries())
    monkeypatch.setattr(fitcache, "CACHE_BYTES", size + 1)  # room for one
    experiments_on_one_world(TINY.replace(seed=4), {"tp": {"model": "tp"}}, cache=fitcache)
    (kept, _), = fitcache.entries()
    assert stored_config(kept) == TINY.replace(seed=4, model="tp").to_dict()
    assert fitcache.clear() == 1 and fitcache.entries() == []


@pytest.mark.parametrize("value", ["off", "0", ""])
def test_the_cache_can_be_turned_off(monkeypatch, tmp_path, value):
    monkeypatch.setenv(fitcache.CACHE_VARIABLE, value)
    assert fitcache.cache_directory() is None
    experiment = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)["gp"]
    assert fitcache.store(experiment) is None and fitcache.entries() == []


def test_by_default_the_cache_lives_in_the_users_cache_folder(monkeypatch, tmp_path):
    monkeypatch.delenv(fitcache.CACHE_VARIABLE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert fitcache.cache_directory() == tmp_path / "sarsp_edu" / "fits"


def _edit_entry(path, change):
    """Rewrite an entry with ``change(arrays, meta)`` applied (its digest made to match, as a careful editor would)."""
    from sarsp_edu.teaching.live.fitcache import _digest

    with np.load(path, allow_pickle=False) as entry:
        arrays = {name: entry[name].copy() for name in entry.files if name != "meta"}
        meta = json.loads(str(entry["meta"]))
    meta.pop("digest")
    change(arrays, meta)
    meta["digest"] = _digest(arrays, meta)
    with open(path, "wb") as handle:
        np.savez(handle, meta=np.array(json.dumps(meta)), **arrays)


def _factor_with_its_own_likelihood(arrays, meta):
    """A careful forger: another factor, and the likelihood the loader recomputes from it, and a new digest."""
    from sarsp_edu.models.linalg import group_rows

    arrays["cost.L_"] *= 2
    experiment = experiments_on_one_world(TINY, {"gp": {"model": "gp"}})["gp"]
    model = experiment.agent.cost_model
    model._adopt_factor(model.X_train_, model.y_train_, group_rows(model.X_train_, model.y_train_),
                        arrays["cost.L_"], meta["models"]["cost"]["jitter_"])
    meta["models"]["cost"]["log_marginal_likelihood_value_"] = float(model.log_marginal_likelihood_value_)


@pytest.mark.parametrize("change", [
    lambda arrays, meta: arrays["cost.L_"].__imul__(1 + 1e-9),  # the factor of other data (zeroed labels, say)
    lambda arrays, meta: arrays["cost.theta_"].__iadd__(0.01),  # other hyperparameters
    _factor_with_its_own_likelihood,
    lambda arrays, meta: meta["models"]["cost"].update(n_features_in_="5"),
    lambda arrays, meta: meta["models"]["cost"].update(jitter_=5.0),
    lambda arrays, meta: arrays.update({"cost.fit_indices_": arrays["cost.fit_indices_"][::-1][:-1]}),
    lambda arrays, meta: arrays.update({"cost.objective_trace_": arrays["cost.objective_trace_"][:3]}),
])
def test_an_edited_entry_is_detected_not_loaded(cache, change):
    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    _edit_entry(path, change)
    again = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    assert not again["gp"].loaded_from_cache  # refused, fitted afresh and stored anew
    fresh = experiments_on_one_world(TINY, {"gp": {"model": "gp"}})
    assert records(again["gp"]) == records(fresh["gp"])


def test_an_entry_edited_without_its_digest_is_refused(cache):
    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    with np.load(path, allow_pickle=False) as entry:
        arrays = {name: entry[name] for name in entry.files}
    arrays["reward.theta_"] = arrays["reward.theta_"] * 0
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)
    assert not experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)["gp"].loaded_from_cache


def test_a_pickle_in_an_entrys_place_is_never_unpickled(cache, tmp_path):
    import pickle

    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    marker = tmp_path / "ran"

    class Payload:
        def __reduce__(self):
            return (open, (str(marker), "w"))

    path.write_bytes(pickle.dumps(Payload()))
    assert not experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)["gp"].loaded_from_cache
    assert not marker.exists()


def test_a_folder_or_a_looping_link_in_an_entrys_place_is_skipped_with_one_warning(cache):
    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    path.unlink()
    path.mkdir()
    fitcache._warned.clear()
    with pytest.warns(UserWarning, match=r"the cache of fits is skipped: .* is not a regular file"):
        again = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    assert not again["gp"].loaded_from_cache and path.is_dir()
    assert fitcache.entries() == []  # 'sarsp-edu cache' counts no folder as a fit
    path.rmdir()
    path.symlink_to(path)
    assert fitcache.entries() == []
    assert not experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)["gp"].loaded_from_cache


def test_a_read_only_cache_with_a_corrupt_entry_is_skipped_with_a_warning(cache, monkeypatch):
    import errno
    from pathlib import Path

    experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    (path, _), = fitcache.entries()
    path.write_bytes(b"half a fit")

    def read_only(self, missing_ok=False):  # a read-only folder (root ignores chmod, so it is simulated)
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(self))

    monkeypatch.setattr(Path, "unlink", read_only)
    fitcache._warned.clear()
    with pytest.warns(UserWarning, match=r"cannot be used nor removed \(Read-only file system\)"):
        again = experiments_on_one_world(TINY, {"gp": {"model": "gp"}}, cache=fitcache)
    assert not again["gp"].loaded_from_cache
