"""The ``sarsp-edu`` command's parser and its entry point, with one-line errors and interruptions."""

from __future__ import annotations

import argparse
import errno
import functools
import os
import signal
import sys
import threading

from .._version import __version__
from .arguments import add_config_arguments
from .commands import _ablation, _cache, _compare, _info, _model_sweep, _prefit, _run, _sweep
from .course import _course
from .reading import _check_cell, _tables, _threshold_study
from .study import add_rule_study


def build_parser() -> argparse.ArgumentParser:
    """The ``sarsp-edu`` parser: one subcommand per action, each with its flags and handler (``func``)."""
    from ..config import (
        ABLATION_CELLS,
        ABLATION_SEEDS,
        DEFINITION_4_A,
        MODEL_TITLES,
        MODELS,
        NU,
        PAPER_MAGNITUDES,
        PAPER_PROPORTIONS,
        PAPER_SWITCH_STATES,
        DataSettings,
    )

    parser = argparse.ArgumentParser(
        prog="sarsp-edu",
        allow_abbrev=False,
        description=(
            "Safe reinforcement learning with Gaussian and Student-t processes: run the "
            "paper's experiment (SARSP, Algorithm 1) on the safe gridworld with outliers "
            "and a covariate shift."
        ),
        epilog="Run 'sarsp-edu COMMAND --help' for the settings of a command.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    # no flag is read as an abbreviation of a longer one (--model is not --models), in any subcommand
    sub = parser.add_subparsers(dest="command", metavar="COMMAND",
                                parser_class=functools.partial(argparse.ArgumentParser, allow_abbrev=False))

    run = sub.add_parser(
        "run",
        help="run one experiment (TP or GP) and print its summary",
        description="Run one experiment: offline data with outliers, model fits, the covariate "
        "shift, then the online episodes. Prints the paper's six metrics.",
    )
    add_config_arguments(run)
    run.add_argument("--out", metavar="DIR", help="save records.csv and result.json in DIR")
    run.add_argument("--overwrite", action="store_true",
                     help="replace a result of other settings already in --out DIR (refused without it)")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=_run, parser=run)

    cmp_ = sub.add_parser(
        "compare",
        help="run the TP and the GP paired and apply the preference criterion",
        description="Run the TP and the GP on the same world, shift, offline data, outliers and "
        "episode starts and goals; print both summaries, the % differences and Definition 4. Where this "
        "process may use two cores or more, the GP runs in a second process while the TP runs in this one "
        "(one BLAS thread each; the records are the same as one after the other); --jobs 1 runs both here.",
    )
    add_config_arguments(cmp_, skip=("model",))
    cmp_.add_argument("--a", type=float, default=DEFINITION_4_A,
                      help=f"Definition 4's TSR threshold a in [1, 100] [default: {DEFINITION_4_A:g}]")
    cmp_.add_argument("--models", nargs="+", choices=list(MODELS), metavar="MODEL",
                      help=f"pair these models instead, two or more of {', '.join(MODELS)} (e.g. --models tp gp "
                           "t-likelihood): their summaries side by side and Definition 4 for each pair "
                           "[default: tp gp]")
    cmp_.add_argument("--out", metavar="DIR", help="save the two runs in DIR/tp and DIR/gp (with --models, "
                                                   "each in DIR/<model>)")
    cmp_.add_argument("--overwrite", action="store_true",
                      help="replace a comparison of other settings already in --out DIR (refused without it)")
    cmp_.add_argument("--jobs", type=int, choices=(1, 2), default=None,
                      help="processes: 2 runs the GP beside the TP, 1 one after the other "
                      "[default: 2 where two cores are free to this process, else 1]")
    cmp_.add_argument("--quiet", action="store_true", help="no progress bars")
    cmp_.set_defaults(func=_compare, parser=cmp_)

    sweep = sub.add_parser(
        "sweep",
        help="run the paper's grid of paired comparisons (m x p x nss x seeds)",
        description="Run every (m, p, nss, seed) cell as a paired TP-vs-GP comparison, locally "
        "or on a Dask cluster. With --out each finished cell is stored at once, and a rerun "
        "skips the cells already there; 'sarsp-edu sweep --out DIR' alone resumes the sweep stored "
        "in DIR with its own settings and cells. A cell whose run raises is named with its traceback and the "
        "other cells run on; the command then exits with status 1.",
    )
    def listed(values):
        return " ".join(f"{v:g}" for v in values)

    sweep.add_argument("--m", "--magnitudes", dest="magnitudes", type=float, nargs="+", metavar="M",
                       help=f"outlier magnitudes [default: {listed(PAPER_MAGNITUDES)}, or a stored sweep's]")
    sweep.add_argument("--p", "--proportions", dest="proportions", type=float, nargs="+", metavar="P",
                       help=f"outlier proportions [default: {listed(PAPER_PROPORTIONS)}, or a stored sweep's]")
    sweep.add_argument("--nss", "--n-switch-states", dest="nss", type=int, nargs="+", metavar="NSS",
                       help=f"numbers of switch states [default: {listed(PAPER_SWITCH_STATES)}, or a stored "
                       "sweep's]")
    sweep.add_argument("--seeds", type=int, nargs="+", help="sweep seeds [default: 0, or a stored sweep's]")
    sweep.add_argument("--jobs", type=int, default=1, help="local worker processes; -1: one per core [default: 1]")
    sweep.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler address (needs sarsp_edu[dask])")
    sweep.add_argument("--a", type=float, default=DEFINITION_4_A,
                       help=f"Definition 4's TSR threshold [default: {DEFINITION_4_A:g}]")
    sweep.add_argument("--out", metavar="DIR", help="results folder (cells stored as they finish)")
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")
    add_config_arguments(sweep, skip=("model", "outlier_magnitude", "outlier_proportion", "n_switch_states", "seed"))
    sweep.set_defaults(func=_sweep, parser=sweep)

    tables = sub.add_parser(
        "tables",
        help="print the paper's Tables 1-4 for a sweep's results folder (and write them as Markdown)",
        description="Read a sweep's results folder (or an ablation's); print a legend of the terms, Table 2 (the "
        "mean over configurations) and Definition 4's verdicts; with --all also Table 1 (every configuration), "
        "Tables 3-4 (median, mode), each model's levels, a paired Wilcoxon test and all of them beside the paper's "
        "and the authors' runs; with --markdown, write them all as Markdown.",
    )
    tables.add_argument("results_dir", metavar="RESULTS_DIR")
    tables.add_argument("--a", type=float, default=DEFINITION_4_A,
                        help=f"Definition 4's TSR threshold [default: {DEFINITION_4_A:g}]")
    tables.add_argument("--markdown", metavar="FILE", help="also write every table as Markdown to FILE")
    tables.add_argument("--all", action="store_true", help="print every table, not only Table 2 and the verdicts")
    tables.add_argument("--allow-partial", action="store_true",
                        help="tabulate a sweep with cells still to run (and list them)")
    tables.add_argument("--seeds", type=int, nargs="+", metavar="SEED",
                        help="tabulate only these sweep seeds [default: every seed stored]")
    tables.add_argument("--figure", metavar="FILE",
                        help="a model sweep's folder: draw the three models' learning curves to FILE (png, svg, pdf)")
    tables.add_argument("--overwrite", action="store_true", help="replace an existing --markdown or --figure file")
    tables.set_defaults(func=_tables, parser=tables)

    check = sub.add_parser(
        "check-cell",
        help="recompute one stored cell of a sweep on this machine and compare its records",
        description="Run one stored cell of a sweep's results folder again with this code on this machine and "
        "compare the records: every column exactly, the three prediction diagnostics (whose last digits come "
        "from the processor's BLAS kernels) to 1e-7 of each one's largest value over the run. Prints the first "
        "differing episode, if any; "
        "exits 0 when the cell is what this machine computes, 1 when it is not.",
    )
    check.add_argument("results_dir", metavar="RESULTS_DIR")
    check.add_argument("cell", metavar="CELL", help="a cell folder's name, such as m40_p0.2_nss2_seed1")
    check.add_argument("--jobs", type=int, choices=[1, 2], default=None,
                       help="2 runs the GP in a second process, 1 both here [default: 2 where two cores are free]")
    check.set_defaults(func=_check_cell, parser=check)

    ablation = sub.add_parser(
        "ablation",
        help="run the paired comparison under a list of settings and tabulate what each changes",
        description="Run the TP-vs-GP comparison of a few configurations and seeds once per setting (a preset "
        "with some fields changed) and tabulate TSR, steps, total cost, cost rate, backup share and trapped "
        "failures with 95% intervals. With --out every run is stored and a rerun resumes. A cell whose run "
        "raises is named with its setting and traceback and the other runs go on; the command then exits with "
        "status 1.",
    )
    ablation.add_argument("--settings", nargs="+", metavar="NAME", help="setting names [default: all; see --list]")
    ablation.add_argument("--list", action="store_true", help="list the settings and exit")
    ablation.add_argument("--cells", type=float, nargs="+", metavar="M P NSS",
                          help=f"configurations as m p nss triples [default: {listed(sum(ABLATION_CELLS, ()))}]")
    ablation.add_argument("--seeds", type=int, nargs="+", default=list(ABLATION_SEEDS),
                          help=f"seeds [default: {listed(ABLATION_SEEDS)}]")
    ablation.add_argument("--episodes", type=int, default=80, help="episodes per run [default: 80]")
    ablation.add_argument("--jobs", type=int, default=1, help="local worker processes [default: 1]")
    ablation.add_argument("--out", metavar="DIR", help="results folder (runs stored as they finish)")
    ablation.add_argument("--quiet", action="store_true", help="no progress bars")
    ablation.set_defaults(func=_ablation, parser=ablation, record_command=True)

    thresholds = sub.add_parser(
        "threshold-study",
        help="tabulate and draw the three models against the variance threshold sigma*^2",
        description="Read the threshold study's runs: the TP and GP runs of the ablation's settings 'default, "
        "variance threshold X' beside its default row (sigma*^2 = 0.8), and the third model's runs on each of those "
        "settings' folders (model-sweep --paired ABLATION/FOLDER --out MODELS/FOLDER). Print, per threshold and "
        "model, the backup share, total cost and TSR with 95% intervals, who beats whom run by run, and where each "
        "model leaves the backup; --figure draws them against sigma*^2.",
    )
    thresholds.add_argument("--ablation", metavar="DIR", default="results/ablation",
                            help="the ablation's folder [default: results/ablation]")
    thresholds.add_argument("--models", metavar="DIR",
                            help="the third model's runs, a model sweep per setting folder (such as "
                                 "results/ablation-t-likelihood)")
    thresholds.add_argument("--markdown", metavar="FILE", help="also write the tables as Markdown to FILE")
    thresholds.add_argument("--figure", metavar="FILE", help="draw the study to FILE (.png, .svg or .pdf)")
    thresholds.add_argument("--overwrite", action="store_true", help="replace an existing --markdown or --figure file")
    thresholds.set_defaults(func=_threshold_study, parser=thresholds)

    course = sub.add_parser(
        "course",
        help="run the source notebooks, make the student notebooks, static pages or a students' copy",
        description="'sources': execute the source notebooks in tutorials/source/ in place (answers in). "
        "'student': write the student notebooks tutorials/NN_*.ipynb from the sources (nbgrader's format: solution "
        "regions become '# YOUR CODE HERE', hidden tests go) and execute them. 'pages': static HTML pages of the "
        "student notebooks, dashboards' pictures included, to project with no Python running and no network "
        "(the maths is written into them as MathML). 'handout': copy the student notebooks, the glossary and "
        "the stored results they read, never the sources, into a new folder or a zip file to hand out. "
        "Notebooks are stored without widget state, so that a reader without a kernel sees each dashboard's "
        "picture.",
    )
    course.add_argument("action", choices=["sources", "student", "pages", "handout"])
    course.add_argument("--tutorials", default="tutorials", metavar="DIR",
                        help="the tutorials folder, holding source/ [default: tutorials]")
    course.add_argument("--no-execute", action="store_true", help="student: write without executing")
    course.add_argument("--only", nargs="+", type=int, metavar="N",
                        help="sources, student: only these tutorials (by number, e.g. --only 2 5) [default: all]")
    course.add_argument("--root", default=".", metavar="DIR",
                        help="handout: the repository, holding tutorials/ and results/ [default: .]")
    course.add_argument("--out", metavar="DIR", help="handout: a new or empty folder; pages: the pages' folder")
    course.add_argument("--zip", metavar="FILE", help="handout: a zip file")
    course.add_argument("--lecturer", action="store_true",
                        help="pages: the lecturer's edition, from the sources: every reveal and answer shown")
    course.add_argument("--overwrite", action="store_true",
                        help="pages: replace pages already in --out; handout: replace an existing --zip file; "
                             "student: replace student notebooks that hold a student's answers (each old one kept "
                             "beside it as .bak)")
    course.set_defaults(func=_course, parser=course)

    info = sub.add_parser("info", help="print the versions of sarsp_edu and its dependencies, and the presets")
    info.set_defaults(func=_info, parser=info)

    cache = sub.add_parser(
        "cache", help="where the live dashboards keep their fitted runs, and how much (--clear removes them)",
        description="The live dashboards keep each run they fit, so that the same settings start at once the "
                    "next time (sarsp_edu.teaching.live.fitcache); compare, the sweeps and the tests always fit "
                    "afresh.")
    cache.add_argument("--clear", action="store_true", help="remove every stored fit")
    cache.set_defaults(func=_cache, parser=cache)

    prefit = sub.add_parser(
        "prefit", help="fit the live dashboard's runs before class, so that Tutorial 4 starts at once",
        description="Fits the sides of Tutorial 4's live dashboard (sliders at nu, m, p, seed and episodes as "
                    "given; one side per model of --models) for each nss, at once, as the dashboard does, and "
                    "keeps them in the cache of fits (see 'sarsp-edu cache'): the dashboard then loads them "
                    "instead of fitting. Run it on the "
                    "machine and in the environment the lecture uses.")
    prefit.add_argument("--nss", type=int, nargs="+", default=[2, 10], metavar="N",
                        help="the nss slider's values to fit (default: 2 10, the lecture plan's)")
    prefit.add_argument("--nu", type=float, default=NU, help=f"the nu slider (default {NU:g})")
    prefit.add_argument("--m", type=float, default=DataSettings.outlier_magnitude, dest="magnitude",
                        help=f"the m slider (default {DataSettings.outlier_magnitude:g})")
    prefit.add_argument("--p", type=float, default=DataSettings.outlier_proportion, dest="proportion",
                        help=f"the p slider (default {DataSettings.outlier_proportion:g})")
    prefit.add_argument("--seed", type=int, default=0, help="the seed slider (default 0)")
    prefit.add_argument("--episodes", type=int, default=30, help="the episodes slider (default 30, Tutorial 4's)")
    prefit.add_argument("--models", nargs="+", default=["tp", "gp"], choices=list(MODEL_TITLES), metavar="MODEL",
                        help="the models to fit, of " + ", ".join(MODEL_TITLES) + " (default: tp gp, the two "
                             "sides; add t-likelihood where the class will pick the GP with Student-t noise: its "
                             "fit takes minutes)")
    prefit.set_defaults(func=_prefit, parser=prefit)

    model_sweep = sub.add_parser(
        "model-sweep", help="run another model on every cell of a stored TP-vs-GP sweep (same worlds, resumable)",
        description="Runs MODEL on the settings of every cell of the paired sweep in --paired, on the very same "
                    "worlds, data and episodes, and stores each run in --out as it finishes; the TP and GP runs "
                    "are reused as stored. A rerun skips the cells stored. A cell whose run raises is named with "
                    "its traceback and the other cells run on; the command then exits with status 1.")
    model_sweep.add_argument("--paired", required=True, metavar="DIR", help="a stored sweep ('sarsp-edu sweep')")
    model_sweep.add_argument("--model", default="t-likelihood", choices=["t-likelihood"], help="the model to run")
    model_sweep.add_argument("--out", required=True, metavar="DIR", help="where the model's runs go")
    model_sweep.add_argument("--jobs", type=int, default=None,
                             help="worker processes; -1: one per core [default: one per core]")
    model_sweep.set_defaults(func=_model_sweep, parser=model_sweep)
    add_rule_study(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the ``sarsp-edu`` command line and return its exit status.

    Without a subcommand the help is printed. Ctrl-C (130), a closed pipe (141)
    and an operating-system error (1) end the command with one line, not a traceback.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; None: ``sys.argv[1:]``.
    """
    for stream in (sys.stdout, sys.stderr):  # a path the terminal's encoding cannot show is escaped, not fatal
        try:
            stream.reconfigure(errors="backslashreplace")
        except (AttributeError, ValueError):  # not a text stream of its own (a test's capture, say)
            pass
    try:
        import warnings

        from .._internal.io import one_line_warning

        warnings.formatwarning = one_line_warning  # a warning is one line to a terminal user
        parser = build_parser()
        args = parser.parse_args(argv)
    except KeyboardInterrupt:  # while the modules and settings load (numpy's import): nothing has begun
        print(NOT_BEGUN, file=sys.stderr)
        return 130
    if not hasattr(args, "func"):
        parser.print_help()
        return 0
    previous = _stop_on_sigterm()
    try:
        try:
            return args.func(args, args.parser)
        except ImportError as exc:  # a stop raised inside a C extension's import comes out as its ImportError
            stop = _stop_within(exc)
            if stop is None:
                raise
            raise stop from None
    except KeyboardInterrupt as stop:  # Ctrl-C, or a SIGTERM (Terminated): the same clean stop
        terminated = isinstance(stop, Terminated)
        print(_interrupted(args, "terminated" if terminated else "interrupted"), file=sys.stderr)
        # the shell's codes for a command ended by SIGTERM (143) and by Ctrl-C (130)
        return 128 + signal.SIGTERM if terminated else 130
    except BrokenPipeError:  # the reader left ('tables ... | head'): stop quietly, as other tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # so that the interpreter's final flush finds no pipe either
        return 141  # the shell's code for a command ended by SIGPIPE
    except OSError as exc:  # a full disk, a folder made read-only meanwhile: one line, not a traceback
        where = getattr(args, "out", None) or getattr(args, "markdown", None)
        if exc.errno == errno.ENOSPC and not exc.filename and where:
            exc = f"{exc} (writing to {where}; what was stored before stays whole, and a rerun resumes)"
        print(f"sarsp-edu {args.command}: error: {exc}", file=sys.stderr)
        return 1
    finally:
        if previous is not _NOT_SET:
            signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


#: what a Ctrl-C says before the command has begun its work
NOT_BEGUN = "interrupted: the command had not begun; nothing was written"


class Terminated(KeyboardInterrupt):
    """A SIGTERM (``kill PID``, a batch system's stop): the command stops as on Ctrl-C, its worker processes
    with it, and what it has stored stays; raised where the main thread is when the signal arrives."""


def _stop_within(exc: BaseException):
    """The KeyboardInterrupt (or Terminated) in ``exc``'s chain of causes, or None."""
    for _ in range(100):  # a chain that loops back on itself ends here too
        if exc is None or isinstance(exc, KeyboardInterrupt):
            return exc
        exc = exc.__cause__ or exc.__context__
    return None


def _raise_terminated(signum, frame):
    raise Terminated


_NOT_SET = object()


def _stop_on_sigterm():
    """Turn SIGTERM into :class:`Terminated` while a command runs; the handler it replaces (``_NOT_SET`` off the
    main thread, where no handler can be set; None where it was not set from Python)."""
    if threading.current_thread() is not threading.main_thread():
        return _NOT_SET
    return signal.signal(signal.SIGTERM, _raise_terminated)


def _interrupted(args, stopped: str = "interrupted") -> str:
    """One line for Ctrl-C (or, ``stopped="terminated"``, a SIGTERM): what is saved and how to go on."""
    stored = getattr(args, "stored", None)
    if stored:
        from ..experiments.sweep import finished_cells

        saved = sum(len(finished_cells(folder) & keys) for folder, keys in stored)
        total = sum(len(keys) for _, keys in stored)
        return (f"{stopped}: {saved} of {total} cells are saved in {args.out}; "
                "rerun the same command to resume")
    if args.command == "model-sweep":
        from pathlib import Path

        from ..experiments.sweep import finished_cells
        from ..experiments.sweep.models import _stored

        try:
            cells = finished_cells(args.paired)
            saved, total = len(_stored(Path(args.out), args.model) & cells), len(cells)
        except (OSError, ValueError):  # stopped before the folders were read
            return stopped
        return (f"{stopped}: {saved} of {total} cells' {args.model} runs are stored in {args.out}; "
                "rerun the same command to resume")
    if args.command in ("sweep", "ablation"):
        if getattr(args, "out", None):  # stopped before its folder was read
            return f"{stopped}: nothing was saved in {args.out} yet; rerun the same command to begin"
        return f"{stopped}: nothing was saved (with --out DIR finished cells are kept, and a rerun resumes)"
    if args.command in ("run", "compare"):
        return f"{stopped}: nothing was saved (a run is saved only when it has finished)"
    return stopped
