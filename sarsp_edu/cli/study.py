"""``sarsp-edu rule-study``: run the rule study's settings not stored yet, and print its tables."""

from __future__ import annotations

import argparse
from pathlib import Path

from .arguments import check_writable
from .commands import _format_table
from .figures import check_figure, new_figure, save_figure

HELP = "run and tabulate the rule study: the three models under other safety rules, nu, fits and outliers"
DESCRIPTION = (
    "The three-model comparison under the choices it was first measured at, each changed in turn, on the "
    "ablation's six worlds (cells x seeds, 80 episodes): the safety rule (latent variance, tail rule), the "
    "Student-t noise's nu, fits with a restart and more steps, thresholds up to 100, outliers in the targets only, "
    "and the third model as cost model beside the TP's reward model. With --run, every setting not stored yet is "
    "run first (resumable: each run is stored as it finishes; a rerun goes on). Then, per question, each "
    "setting's and model's mean total cost, TSR and backup share with 95% t-intervals over the runs, the cost "
    "model's fitted noise, nu and gradient norm, and the models run by run.")


def add_rule_study(sub) -> None:
    """The ``rule-study`` subcommand's parser."""
    from ..config import RULE_QUESTIONS as QUESTIONS

    parser = sub.add_parser("rule-study", help=HELP, description=DESCRIPTION)
    parser.add_argument("--out", metavar="DIR", default="results/rule-study", help="the study's folder "
                        "[default: results/rule-study]")
    parser.add_argument("--ablation", metavar="DIR", default="results/ablation",
                        help="the ablation's folder, with the stored TP and GP runs [default: results/ablation]")
    parser.add_argument("--models", metavar="DIR", default="results/ablation-t-likelihood",
                        help="the third model's stored runs on the ablation's settings "
                             "[default: results/ablation-t-likelihood]")
    parser.add_argument("--questions", nargs="+", choices=list(QUESTIONS), metavar="Q",
                        help=f"only these questions, of {', '.join(repr(q) for q in QUESTIONS)} [default: all]")
    parser.add_argument("--run", action="store_true", help="run the settings not stored yet before printing")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes for --run [default: 1]")
    parser.add_argument("--figure", metavar="FILE", help="draw each question's settings, runs and means to FILE "
                        "(.png, .svg or .pdf)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --figure file")
    parser.set_defaults(func=_rule_study, parser=parser)


def _rule_study(args, parser: argparse.ArgumentParser) -> int:
    from .._internal.io import StoredResultError
    from ..experiments.rules import RuleStudy, run_rule_study

    if args.jobs < 1:
        parser.error(f"--jobs takes a whole number >= 1, got {args.jobs}")
    check_figure(parser, args.figure, args.overwrite)
    if Path(args.out).exists() and not Path(args.out).is_dir():
        parser.error(f"--out {args.out} is a file; give the study's folder")
    for flag, folder, marker in (("--ablation", args.ablation, "ablation.json"), ("--models", args.models, None)):
        if not Path(folder).is_dir() or (marker and not (Path(folder) / marker).is_file()):
            what = "an ablation results folder (no ablation.json)" if marker else "a folder"
            parser.error(f"{flag} {folder} is not {what}; the study reads the stored TP and GP runs and the third "
                         "model's from there")
    if args.run:
        check_writable(parser, "--out", "the study's folder", Path(args.out))
        run_rule_study(args.out, args.ablation, questions=args.questions, n_jobs=args.jobs,
                       report=lambda line: print(line, flush=True))
    try:
        study = RuleStudy.load(args.out, args.ablation, args.models, questions=args.questions)
    except (StoredResultError, FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    show_study(study, args.questions, args.figure)
    return 0


def show_study(study, questions=None, figure=None) -> None:
    """Print a rule study's tables per question and draw it where a figure is named (``tables`` on the study's
    folder calls it too).

    Parameters
    ----------
    study : RuleStudy
        The stored runs (:meth:`~sarsp_edu.experiments.rules.RuleStudy.load`).
    questions : iterable of str, optional
        Only these questions; default all.
    figure : path-like, optional
        Draw each question's settings, runs and means to this file.
    """
    from ..experiments.rules import study_settings
    from ..teaching.plotting import plot_rule_study

    questions = list(dict.fromkeys(setting.question for setting in study_settings(questions)))
    for question in questions:
        table = study.table(question)
        print(f"\n== {question} ==")
        if table.empty:
            print("no run stored yet (--run runs them)")
            continue
        print("each measure's mean over the runs (configurations x seeds) and its 95% t-interval\n"
              + _format_table(table.round(3)))
        pairs = study.pairs(question)
        if not pairs.empty:
            print(f"\nthe models run by run\n{_format_table(pairs.round(3))}")
    fairest = study.fairest_rule()
    if "rule" in questions:
        print("\nthe fairer rule (of the latent variance at 0.8 and the tail rule at 0.05, the lower largest "
              f"backup share of the three models, once both have every run stored): {fairest or 'not decided yet'}")
    if figure and len(study.runs) and (study.runs["question"].isin(questions)).any():
        shown = [q for q in questions if len(study.runs) and (study.runs["question"] == q).any()]
        drawn, axes = new_figure(len(shown), 3, (14, 1.2 + 0.55 * len(study.runs.drop_duplicates("setting"))))
        counts = study.runs.groupby(["setting", "model"]).size().groupby("setting").min()
        runs = study.runs.assign(setting=[name if counts[name] == study.planned else
                                          f"{name} ({counts[name]} of {study.planned} runs)"
                                          for name in study.runs["setting"]])  # a setting still running, said
        for row, question in zip(axes.reshape(len(shown), 3), shown):
            plot_rule_study(row, runs[runs["question"] == question])
            row[0].set_title(f"{question}: {row[0].get_title()}")
        save_figure(drawn, figure)
