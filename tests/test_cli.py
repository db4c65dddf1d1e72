from __future__ import annotations

import json
import subprocess
import sys

import pytest

from sarsp_edu.cli import build_parser, main

TINY = ["--grid-size", "5", "--n-unsafe", "3", "--nss", "1", "--episodes", "2", "--offline-episodes", "5",
        "--cost-fit-points", "50", "--reward-fit-points", "50", "--k-prior", "20", "--optimizer-steps", "3", "--quiet"]


def test_run_prints_a_summary_and_saves(tmp_path, capsys):
    assert main(["run", "--model", "gp", "--m", "60", "--p", "0.3", *TINY, "--out", str(tmp_path / "r")]) == 0
    out = capsys.readouterr().out
    assert "Gaussian process, m=60 p=0.3 nss=1" in out
    for metric in ("mean_reward", "total_cost", "task_success_rate", "cost_rate"):
        assert metric in out
    payload = json.loads((tmp_path / "r" / "result.json").read_text())
    assert payload["config"]["outlier_magnitude"] == 60.0 and payload["config"]["model"] == "gp"


def test_compare_prints_the_verdict(tmp_path, capsys):
    assert main(["compare", *TINY, "--a", "90", "--out", str(tmp_path / "c")]) == 0
    out = capsys.readouterr().out
    assert "TP vs GP (%)" in out and "Definition 4 (a=90)" in out
    assert (tmp_path / "c" / "tp" / "result.json").exists() and (tmp_path / "c" / "gp" / "result.json").exists()


def test_every_config_field_has_a_flag():
    import dataclasses

    from sarsp_edu import ExperimentConfig

    run = build_parser()._subparsers._group_actions[0].choices["run"]
    dests = {action.dest for action in run._actions}
    assert {f.name for f in dataclasses.fields(ExperimentConfig)} <= dests


@pytest.mark.parametrize(
    "argv, message",
    [
        (["run", "--nu", "2"], "nu must be a finite number > 2"),
        (["run", "--p", "1.5"], r"outlier_proportion must lie in \[0, 1\]"),
        (["run", "--nss", "20"], "n_switch_states must be an integer from 0 to n_unsafe=15"),
        (["run", "--episodes", "0"], "episodes must be an integer >= 1"),
        (["run", "--model", "svm"], "invalid choice"),
        (["compare", "--a", "0", *TINY], r"a must lie in \[1, 100\]"),
    ],
)
def test_bad_values_are_usage_errors(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    import re

    assert re.search(message, capsys.readouterr().err)


def test_none_values_parse():
    args = build_parser().parse_args(["run", "--reward-fit-points", "none", "--prior", "None", "--max-steps", "30"])
    assert args.reward_fit_points is None and args.prior is None and args.max_steps == 30


def test_console_script_help_and_info():
    help_text = subprocess.run([sys.executable, "-m", "sarsp_edu.cli", "--help"], capture_output=True, text=True,
                               check=True).stdout
    assert "run" in help_text and "compare" in help_text
    info = subprocess.run([sys.executable, "-m", "sarsp_edu.cli", "info"], capture_output=True, text=True,
                          check=True).stdout
    assert info.startswith("sarsp_edu ")


def test_sweep_and_tables(tmp_path, capsys):
    out = tmp_path / "sweep"
    settings = [a for i, a in enumerate(TINY) if a != "--nss" and (i == 0 or TINY[i - 1] != "--nss")]
    grid = ["--m", "40", "--p", "0.2", "--nss", "1", "2"]
    assert main(["sweep", *grid, *settings, "--out", str(out)]) == 0
    assert "2 cells, each a paired TP-vs-GP run of 2 episodes" in capsys.readouterr().out
    assert main(["tables", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "table1" in printed and "wilcoxon" in printed
    markdown = (out / "tables.md").read_text()
    assert markdown.startswith("# sarsp_edu sweep") and "## Table 2" in markdown


def test_tables_of_a_missing_folder(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["tables", str(tmp_path)])
    assert exit_info.value.code == 2
    assert "not a sweep results folder" in capsys.readouterr().err


def test_preset_flag_then_overrides(capsys):
    from sarsp_edu.cli import config_from_args

    parser = build_parser()
    args = parser.parse_args(["run", "--preset", "reference", "--k-prior", "50"])
    config = config_from_args(args.parser, args)
    assert config.prior_draw == "per_action" and config.predictive == "sample" and config.k_prior == 50
    assert config.preset == "custom"
    args = parser.parse_args(["compare", "--preset", "paper_text"])
    assert config_from_args(args.parser, args).preset == "paper_text"


def test_info_lists_the_presets(capsys):
    assert main(["info"]) == 0
    out = capsys.readouterr().out
    for name in ("default", "reference", "paper_text"):
        assert f"  {name}: " in out


def test_ablation_list_and_bad_setting(capsys):
    assert main(["ablation", "--list"]) == 0
    assert "reference preset" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["ablation", "--settings", "no such setting"])
    assert "unknown setting" in capsys.readouterr().err
