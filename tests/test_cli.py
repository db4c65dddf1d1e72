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
        (["run", "--episodes", "0"], "episodes must be an integer from 1 to 100000"),
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
    short = capsys.readouterr().out
    assert short.startswith("terms: ") and "Table 2: each metric's mean" in short and "wilcoxon" not in short
    assert "Definition 4, configuration by configuration (2 in all): TP preferred: " in short
    assert main(["tables", str(out), "--all"]) == 0
    printed = capsys.readouterr().out
    assert "table1" in printed and "wilcoxon" in printed
    # the mean beside the paper's, saying over how many configurations; (40, 0.2, 2) is a row of Table 1
    assert "beside the paper's Table 2: mean over the 2 configurations stored (the paper's: all 45)" in printed
    assert "\nlevels\n" in printed and "TP 95% CI" in printed
    assert "beside the paper's Table 1: 1 of its 6 configurations stored" in printed
    assert not (out / "tables.md").exists()  # nothing written unless asked
    assert main(["tables", str(out), "--markdown", str(tmp_path / "t" / "tables.md")]) == 0
    markdown = (tmp_path / "t" / "tables.md").read_text()
    assert markdown.startswith("# sarsp_edu sweep") and "## Table 2" in markdown
    assert "## Beside the paper's Table 2: mean over the 2 configurations stored" in markdown
    assert "| metric | ours TP | TP 95% CI | ours GP | GP 95% CI | ours % | paper TP |" in markdown
    assert "## Each model's mean over configurations with a 95% bootstrap interval" in markdown
    assert "| 40 | 0.2 | 2 | task_success_rate |" in markdown  # Table 1's configuration as the paper writes it


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


def test_cache_says_where_the_fits_are_and_clears_them(capsys, monkeypatch, tmp_path):
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path))
    (tmp_path / "tp-0123.fit.npz").write_bytes(b"x" * 2**20)
    assert main(["cache"]) == 0
    assert f"{tmp_path}: 1 stored fits, 1 MB" in capsys.readouterr().out
    assert main(["cache", "--clear"]) == 0
    assert "removed 1 stored fits" in capsys.readouterr().out and not list(tmp_path.iterdir())
    monkeypatch.setenv("SARSP_EDU_CACHE", "off")
    assert main(["cache"]) == 0
    assert "is off" in capsys.readouterr().out


def test_ablation_list_and_bad_setting(capsys):
    assert main(["ablation", "--list"]) == 0
    assert "reference preset" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["ablation", "--settings", "no such setting"])
    assert "unknown setting" in capsys.readouterr().err


# --------------------------------------------------------------------------
# output paths are checked before any work
# --------------------------------------------------------------------------
def _usage_error(argv, capsys) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err.strip().splitlines()[-1]


@pytest.mark.parametrize("command", ["run", "compare", "sweep", "ablation"])
def test_out_that_is_a_file_is_refused_before_work(tmp_path, capsys, monkeypatch, command):
    import sarsp_edu.experiments.experiment
    import sarsp_edu.experiments.sweep

    def no_work(*args, **kwargs):
        raise AssertionError("work started before --out was checked")

    for module, name in [(sarsp_edu.experiments.experiment, "run_experiment"),
                         (sarsp_edu.experiments.experiment, "compare"),
                         (sarsp_edu.experiments.sweep, "run_sweep")]:
        monkeypatch.setattr(module, name, no_work)
    afile = tmp_path / "afile"
    afile.write_text("keep me")
    line = _usage_error([command, "--out", str(afile), "--quiet"], capsys)
    assert f"--out {afile} is a file" in line
    assert afile.read_text() == "keep me"
    line = _usage_error([command, "--out", str(afile / "below"), "--quiet"], capsys)
    assert f"{afile} is a file" in line


def test_out_holding_other_results_is_refused(tmp_path, capsys):
    sweep = tmp_path / "sweep"
    sweep.mkdir()
    (sweep / "sweep.json").write_text("{}")
    line = _usage_error(["run", "--out", str(sweep), *TINY], capsys)
    assert "holds a sweep's results" in line and "'run' writes into" in line
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("x")
    assert "holds other files" in _usage_error(["compare", "--out", str(other), *TINY], capsys)
    # the markdown file of tables is checked before the folder is read
    assert "is a folder" in _usage_error(["tables", str(tmp_path), "--markdown", str(other)], capsys)


def test_run_replaces_its_own_result_and_another_only_with_overwrite(tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["run", *TINY, "--out", str(out)]) == 0
    assert main(["run", *TINY, "--out", str(out)]) == 0  # the same settings: the same result again
    with pytest.raises(SystemExit) as refused:
        main(["run", *TINY, "--seed", "1", "--out", str(out)])
    assert refused.value.code == 2
    err = capsys.readouterr().err
    assert (f"--out {out} holds a run of other settings (seed: stored 0, now 1); to keep both, give another "
            "folder; to replace it, add --overwrite") in err
    assert json.loads((out / "result.json").read_text())["config"]["seed"] == 0
    assert main(["run", *TINY, "--seed", "1", "--out", str(out), "--overwrite"]) == 0
    assert json.loads((out / "result.json").read_text())["config"]["seed"] == 1


# --------------------------------------------------------------------------
# Ctrl-C ends a run with one line and exit status 130
# --------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["run", "compare"])
def test_ctrl_c_in_a_run_is_one_line(tmp_path, capsys, monkeypatch, command):
    import sarsp_edu.experiments.experiment

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(sarsp_edu.experiments.experiment, "run_experiment" if command == "run" else "compare",
                        interrupted)
    assert main([command, *TINY, "--out", str(tmp_path / "r")]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["interrupted: nothing was saved (a run is saved only when it has finished)"]
    assert not (tmp_path / "r").exists()


def test_ctrl_c_in_a_model_sweep_says_how_many_of_its_runs_are_stored(tmp_path, capsys, monkeypatch):
    import sarsp_edu.experiments.experiment as experiment

    paired, out = tmp_path / "paired", tmp_path / "tl"
    sweep = ["sweep", *TINY, "--m", "40", "--p", "0.2", "--nss", "1", "2", "--seeds", "0", "--jobs", "1"]
    assert main([*sweep, "--out", str(paired)]) == 0
    original, runs = experiment.run_experiment, []

    def interrupted_at_the_second(config, *args, **kwargs):  # Ctrl-C while the second cell runs
        runs.append(config)
        if len(runs) == 2:
            raise KeyboardInterrupt
        return original(config, *args, **kwargs)

    monkeypatch.setattr(experiment, "run_experiment", interrupted_at_the_second)
    capsys.readouterr()
    assert main(["model-sweep", "--paired", str(paired), "--out", str(out), "--jobs", "1"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == [
        f"interrupted: 1 of 2 cells' t-likelihood runs are stored in {out}; rerun the same command to resume"]


def _the_commands_lines(err: str) -> list:
    """stderr's lines without loky's resource tracker's: where a killed worker held a semaphore, the tracker (a
    process of joblib's) says it cleans it up, at times, as the command exits (seen twice: in a busy local batch
    and in a CI run).
    A warning or traceback of the package's own still counts: only the tracker's lines and the
    ``warnings.warn(...)`` source line Python prints under each are dropped."""
    lines = err.strip().splitlines()
    return [line for i, line in enumerate(lines) if "resource_tracker" not in line
            and not (line.strip().startswith("warnings.warn(") and i and "resource_tracker" in lines[i - 1])]


def _parallel_sweep_with_a_cell_stored(out):
    """A small sweep of 8 cells on 2 workers, started in a session of its own; returned once it has stored a
    cell (or ended, or 240 s passed)."""
    import time

    # started as a terminal starts it, with Ctrl-C's SIGINT handled: a test run started in the background of a
    # script (nohup ... &) ignores SIGINT, and its children inherit that, so the sweep would run to its end
    terminal = ("import runpy, signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
                "sys.argv[0] = 'sarsp-edu'; runpy.run_module('sarsp_edu.cli', run_name='__main__')")
    argv = [sys.executable, "-c", terminal, "sweep", "--jobs", "2", "--out", str(out), "--quiet",
            "--grid-size", "5", "--n-unsafe", "3", "--offline-episodes", "5", "--k-prior", "20",
            "--cost-fit-points", "50", "--reward-fit-points", "50",
            "--m", "40", "80", "--p", "0.2", "--nss", "1", "2", "--seeds", "0", "1", "--episodes", "60"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and proc.poll() is None and not list(out.glob("cells/m*/cell.json")):
        time.sleep(0.2)
    return proc


def test_ctrl_c_in_a_parallel_sweep_keeps_finished_cells(tmp_path):
    # a terminal's Ctrl-C: SIGINT to the command's whole process group
    import os
    import re
    import signal

    out = tmp_path / "sweep"
    proc = _parallel_sweep_with_a_cell_stored(out)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    if proc.returncode == 0:
        pytest.skip("the sweep finished before it could be interrupted")
    assert proc.returncode == 130
    lines = _the_commands_lines(err)
    assert len(lines) == 1, err
    match = re.fullmatch(rf"interrupted: (\d+) of 8 cells are saved in {re.escape(str(out))}; "
                         r"rerun the same command to resume", lines[0])
    assert match, lines[0]
    saved = int(match.group(1))
    assert len(list(out.glob("cells/m*/cell.json"))) == saved
    assert not list(out.glob("cells/.*"))  # no staging folder left behind


def test_a_sigterm_to_a_parallel_sweep_stops_its_workers_and_keeps_finished_cells(tmp_path):
    # 'kill PID' or a batch system's stop: SIGTERM to the command alone, not to its workers
    import re
    import signal

    psutil = pytest.importorskip("psutil")
    out = tmp_path / "sweep"
    proc = _parallel_sweep_with_a_cell_stored(out)
    command = psutil.Process(proc.pid)
    workers = command.children(recursive=True)
    try:
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
        if proc.returncode == 0:
            pytest.skip("the sweep finished before it could be stopped")
        assert proc.returncode == 143, err
        lines = _the_commands_lines(err)
        assert len(lines) == 1, err
        match = re.fullmatch(rf"terminated: (\d+) of 8 cells are saved in {re.escape(str(out))}; "
                             r"rerun the same command to resume", lines[0])
        assert match, lines[0]
        assert len(list(out.glob("cells/m*/cell.json"))) == int(match.group(1))
        assert not list(out.glob("cells/.*"))  # no staging folder left behind
        _, alive = psutil.wait_procs(workers, timeout=30)
        assert not alive, f"workers outlived the command: {alive}"
    finally:  # a failed test leaves no process behind
        for process in [command, *workers]:
            try:
                process.kill()
            except psutil.NoSuchProcess:
                pass


def test_the_sigterm_handler_is_the_callers_again_after_a_command(capsys):
    import signal

    before = signal.getsignal(signal.SIGTERM)
    assert main(["info"]) == 0
    assert signal.getsignal(signal.SIGTERM) == before


def test_tables_name_a_damaged_file_and_refuse_a_partial_sweep(tmp_path, capsys):
    out = tmp_path / "sweep"
    settings = [a for i, a in enumerate(TINY) if a != "--nss" and (i == 0 or TINY[i - 1] != "--nss")]
    grid = ["--m", "40", "--p", "0.2", "--nss", "1", "2"]
    assert main(["sweep", *grid, *settings, "--out", str(out)]) == 0
    capsys.readouterr()
    records = out / "cells" / "m40_p0.2_nss2_seed0" / "gp" / "records.csv"
    saved = records.read_text()
    records.write_text(saved[: len(saved) // 2])
    line = _usage_error(["tables", str(out)], capsys)
    assert str(records) in line
    records.write_text(saved)
    import shutil

    shutil.rmtree(records.parent.parent)
    line = _usage_error(["tables", str(out)], capsys)
    assert "partial sweep: 1 of 2 cells are missing" in line and "--allow-partial" in line
    assert main(["tables", str(out), "--allow-partial"]) == 0
    assert "partial sweep: 1 of 2 cells stored; missing: m=40 p=0.2 nss=2 seed=0" in capsys.readouterr().out


@pytest.mark.parametrize("command", ["run", "compare", "sweep", "tables", "ablation"])
def test_every_commands_help_reads_as_written(command, capsys):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = capsys.readouterr().out
    assert "%%" not in text and "%(" not in text  # argparse formats help, not descriptions
    assert "[default: None]" not in text


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["info"], ["run", "--help"], ["sweep", "--help"],
                                  ["ablation", "--help"]])
def test_help_and_info_load_no_numerical_library(argv):
    # --help must answer at once: no scipy, pandas or matplotlib behind it
    code = (f"import sys\nfrom sarsp_edu.cli import main\ntry:\n    main({argv!r})\nexcept SystemExit:\n    pass\n"
            "heavy = sorted(m for m in ('scipy', 'pandas', 'matplotlib', 'sympy') if m in sys.modules)\n"
            "print('HEAVY', heavy)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "HEAVY []" in out, out[-300:]


def test_an_undefined_cost_rate_reads_n_a(capsys):
    # d=100: every step violates, so no episode succeeds cleanly and eq. 12 is undefined
    assert main(["run", *TINY, "--d", "100"]) == 0
    line = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("cost_rate")][0]
    assert line.split()[-1] == "n/a"
    assert main(["compare", *TINY, "--d", "100"]) == 0
    out = capsys.readouterr().out
    assert "Definition 4 (a=100) cannot decide: a cost rate is undefined" in out
    row = [ln for ln in out.splitlines() if ln.startswith("cost_rate")][0]
    assert row.split()[1:] == ["n/a", "n/a", "n/a", "n/a"]


# -- several models paired ---------------------------------------------------------------------------------
def test_compare_pairs_the_models_it_is_given_and_its_default_is_the_tp_and_gp_byte_for_byte(tmp_path, capsys):
    from sarsp_edu.experiments.results import ExperimentResult, check_paired

    assert main(["compare", *TINY, "--jobs", "1", "--out", str(tmp_path / "two")]) == 0
    assert main(["compare", *TINY, "--jobs", "1", "--models", "tp", "gp", "--out", str(tmp_path / "same")]) == 0
    for model in ("tp", "gp"):
        assert ((tmp_path / "two" / model / "records.csv").read_bytes()
                == (tmp_path / "same" / model / "records.csv").read_bytes())
    capsys.readouterr()
    assert main(["compare", *TINY, "--models", "tp", "t-likelihood", "gp", "--out", str(tmp_path / "three")]) == 0
    out = capsys.readouterr().out
    assert "tp vs t-likelihood vs gp, paired" in out and "tp vs t-likelihood" in out and "t-likelihood vs gp" in out
    runs = {model: ExperimentResult.load(tmp_path / "three" / model) for model in ("tp", "gp", "t-likelihood")}
    check_paired(runs["tp"], runs["t-likelihood"], tmp_path / "three")  # the same episodes
    assert runs["tp"].records.equals(ExperimentResult.load(tmp_path / "two" / "tp").records)
    with pytest.raises(SystemExit):
        main(["compare", *TINY, "--models", "tp", "tp"])
    assert "two or more distinct models" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["compare", *TINY, "--models", "gp", "t-likelihood", "--out", str(tmp_path / "three")])
    assert "holds runs of gp, t-likelihood already" in capsys.readouterr().err
    assert main(["compare", *TINY, "--models", "gp", "t-likelihood", "--out", str(tmp_path / "three"),
                 "--overwrite"]) == 0
    with pytest.raises(SystemExit):
        main(["compare", *TINY, "--models", "gp", "t-likelihood", "--jobs", "2"])
    assert "leave --jobs out" in capsys.readouterr().err
