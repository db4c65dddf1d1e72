"""Stops at any moment say one line: the command's start is light enough to catch a Ctrl-C, worker processes
start deaf to it, a stop raised inside a C extension's import is still a stop, and a refused ablation writes
nothing."""
from __future__ import annotations

import errno
import importlib
import signal
import subprocess
import sys

import pytest

from sarsp_edu._internal.parallel import workers_deaf_to_interrupts
from sarsp_edu.cli import main as cli_main
from sarsp_edu.cli.main import Terminated, _stop_within


def _fresh(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          check=True).stdout.strip()


def test_the_command_imports_without_numpy_and_the_environment_registers_once_gymnasium_is_imported():
    """numpy's import was the long window in which a Ctrl-C printed a traceback: the command's modules no longer
    import it, and ``gymnasium.make`` still finds the environment, whichever of the two is imported first."""
    assert _fresh("import sys, sarsp_edu.cli; print('numpy' in sys.modules, 'gymnasium' in sys.modules)") == \
        "False False"
    for first, second in (("sarsp_edu", "gymnasium"), ("gymnasium", "sarsp_edu")):
        code = (f"import {first}, {second}, gymnasium; "
                "print(type(gymnasium.make('sarsp_edu/SafeGridWorld-v0').unwrapped).__name__)")
        assert _fresh(code) == "SafeGridWorld"


def test_a_process_started_in_the_block_ignores_ctrl_c_and_this_one_hears_it_again_after():
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # as a terminal's command (xdist ignores it)
    try:
        outside = _fresh("import signal; print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)")
        with workers_deaf_to_interrupts():
            child = _fresh("import signal; print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)")
        assert (outside, child) == ("False", "True")
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_ctrl_c_pressed_while_workers_start_is_not_lost_but_arrives_when_they_have_started():
    """In a process whose only thread is the main one (the command's while its workers start; a test process has
    BLAS's threads, which could take the signal and drop it, so a fresh interpreter runs it, with Ctrl-C handled
    as a terminal's command has it: pytest-xdist's workers start their children with SIGINT ignored)."""
    code = ("import os, signal, time\n"
            "signal.signal(signal.SIGINT, signal.default_int_handler)  # as a terminal's command (xdist's ignore)\n"
            "from sarsp_edu._internal.parallel import workers_deaf_to_interrupts\n"
            "try:\n"
            "    with workers_deaf_to_interrupts():\n"
            "        os.kill(os.getpid(), signal.SIGINT)\n"
            "        time.sleep(0.1)\n"
            "        print('the block ran to its end')\n"
            "except KeyboardInterrupt:\n"
            "    print('then the Ctrl-C arrived')\n")
    assert _fresh(code) == "the block ran to its end\nthen the Ctrl-C arrived"


def test_a_stop_inside_a_c_extensions_import_is_found_in_its_import_error():
    try:
        try:
            raise Terminated
        except Terminated as stop:
            raise ImportError("initialization failed") from stop
    except ImportError as exc:
        assert isinstance(_stop_within(exc), Terminated)
    assert _stop_within(ImportError("no module named x")) is None


def _command_doing(monkeypatch, command: str, work) -> None:
    """Make ``sarsp-edu COMMAND`` call ``work(args, parser)`` instead of its own handler."""
    module = importlib.import_module("sarsp_edu.cli.main")  # the module (the package lends its main function)
    real = module.build_parser

    def build_parser():
        parser = real()
        parser._subparsers._group_actions[0].choices[command].set_defaults(func=work)
        return parser

    monkeypatch.setattr(module, "build_parser", build_parser)


def test_a_terminated_import_in_a_command_ends_it_as_terminated(monkeypatch, capsys):
    def importing(args, parser):
        try:
            raise Terminated
        except Terminated as stop:
            raise ImportError("initialization failed") from stop

    _command_doing(monkeypatch, "info", importing)
    assert cli_main(["info"]) == 128 + signal.SIGTERM
    assert "terminated" in capsys.readouterr().err


def test_a_full_disk_names_where_the_command_was_writing(monkeypatch, capsys, tmp_path):
    def full(args, parser):
        raise OSError(errno.ENOSPC, "No space left on device")

    _command_doing(monkeypatch, "run", full)
    assert cli_main(["run", "--out", str(tmp_path / "r")]) == 1
    said = capsys.readouterr().err
    assert f"No space left on device (writing to {tmp_path / 'r'}; what was stored before stays whole" in said


@pytest.mark.parametrize("cells", [["40", "2", "2"], ["40", "0.2", "99"]])
def test_an_ablation_refused_for_its_cells_leaves_no_folder(tmp_path, cells):
    out = tmp_path / "ab"
    with pytest.raises(SystemExit) as stop:
        cli_main(["ablation", "--cells", *cells, "--out", str(out)])
    assert stop.value.code == 2 and not out.exists()  # was: ablation.json written, which then blocked the folder


def test_a_sweep_stopped_before_its_folder_was_read_says_where_it_would_have_saved(tmp_path):
    import argparse

    from sarsp_edu.cli.main import _interrupted

    said = _interrupted(argparse.Namespace(command="sweep", out=str(tmp_path / "s")))
    assert said == f"interrupted: nothing was saved in {tmp_path / 's'} yet; rerun the same command to begin"
    assert "with --out DIR" in _interrupted(argparse.Namespace(command="sweep", out=None))


def test_tables_of_an_empty_path_says_it_is_empty(capsys):
    with pytest.raises(SystemExit):
        cli_main(["tables", ""])
    assert "RESULTS_DIR is empty" in capsys.readouterr().err  # was: ". is not a sweep results folder"


def test_the_python_api_names_a_file_given_as_a_results_folder_and_a_fit_that_is_not_a_function(tmp_path):
    from sarsp_edu import ExperimentConfig
    from sarsp_edu.experiments.experiment import Experiment

    with pytest.raises(TypeError, match="fit must be a function fit"):
        Experiment(ExperimentConfig(episodes=1), fit=42)  # was: 'int' object is not callable, after the data
    from sarsp_edu.experiments.results import ExperimentResult

    a_file = tmp_path / "taken"
    a_file.write_text("")
    with pytest.raises(NotADirectoryError, match="is a file; a result is saved into a folder"):
        ExperimentResult.save(object.__new__(ExperimentResult), a_file)


@pytest.mark.parametrize("action", ["pages", "handout"])
def test_course_refuses_only_where_it_would_change_nothing(capsys, tmp_path, action):
    with pytest.raises(SystemExit):
        cli_main(["course", action, "--only", "1", "--out", str(tmp_path / "x")])
    assert "--only picks the notebooks of 'sources' and 'student'" in capsys.readouterr().err
