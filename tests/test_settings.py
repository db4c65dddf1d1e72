"""Each setting is declared once, as a field of ExperimentConfig tagged with its group; the groups derive from it."""

from __future__ import annotations

import dataclasses

import pytest

from sarsp_edu.config import (
    GROUPS,
    AgentSettings,
    DataSettings,
    ExperimentConfig,
    ModelSettings,
    WorldSettings,
)

DERIVED = {"world": WorldSettings, "data": DataSettings, "model": ModelSettings, "agent": AgentSettings}


@pytest.mark.parametrize("group", GROUPS)
def test_a_group_holds_exactly_the_settings_tagged_with_it_with_their_defaults_and_help(group):
    declared = {f.name: f for f in dataclasses.fields(ExperimentConfig) if group in f.metadata["groups"]}
    derived = {f.name: f for f in dataclasses.fields(DERIVED[group])}
    assert list(derived) == list(declared)  # the declaration's order
    for name, f in derived.items():
        assert (f.default, f.metadata["help"], f.type) == (declared[name].default, declared[name].metadata["help"],
                                                           declared[name].type)
    config = ExperimentConfig(seed=3, k_prior=7, grid_size=8, n_unsafe=9, outlier_magnitude=60.0, nu=4.0)
    assert getattr(config, f"{group}_settings") == DERIVED[group](**{name: getattr(config, name) for name in derived})


def test_every_setting_but_the_runs_own_belongs_to_a_group():
    ungrouped = [f.name for f in dataclasses.fields(ExperimentConfig) if not f.metadata["groups"]]
    assert ungrouped == ["n_switch_states", "episodes", "seed"]
    assert [f.name for f in dataclasses.fields(ExperimentConfig) if len(f.metadata["groups"]) > 1] == ["d"]


def test_a_group_checks_its_settings_as_the_config_does():
    with pytest.raises(ValueError, match=r"k_prior .*got k_prior=0"):
        AgentSettings(k_prior=0)
    with pytest.raises(ValueError, match=r"k_prior .*got k_prior=0"):
        ExperimentConfig(k_prior=0)
    with pytest.raises(ValueError, match="grid_size"):
        WorldSettings(grid_size=2)
    assert WorldSettings(grid_size=6, n_unsafe=5).env_kwargs()["size"] == 6
