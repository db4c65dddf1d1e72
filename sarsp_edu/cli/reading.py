"""The commands that read stored results: ``tables`` (a sweep's tables, or an ablation's) and ``check-cell``."""

from __future__ import annotations

from .arguments import check_file
from .commands import _format_table
from .figures import check_figure, new_figure, save_figure


def _tables(args, parser) -> int:
    from pathlib import Path

    from .._internal.io import StoredResultError
    from ..experiments.sweep import SweepResults, describe_cells, stored_sweep
    from ..experiments.tables import frame_to_markdown, summary_tables, tables_markdown

    if not str(args.results_dir).strip():
        parser.error("RESULTS_DIR is empty: name a results folder ('sarsp-edu sweep --out DIR' makes one)")
    _distinct_outputs(parser, args.markdown, args.figure)
    _outside(parser, "--figure", args.figure, [args.results_dir])
    if args.markdown is not None:
        check_file(parser, "--markdown", args.markdown, overwrite=True)  # a folder, a link, a device in the way
        folder = Path(args.results_dir).resolve()
        if folder in Path(args.markdown).resolve().parents:
            parser.error(f"--markdown {args.markdown} lies inside the results folder {args.results_dir}, whose files "
                         "it could replace; write the tables outside it")
        check_file(parser, "--markdown", args.markdown, overwrite=args.overwrite)

    if (Path(args.results_dir) / "paired" / "ablation.json").is_file():  # a rule study's folder: its tables
        from ..experiments.rules import RuleStudy
        from .study import show_study

        if args.markdown is not None:
            parser.error("--markdown is not written for a rule study's folder: its tables print; --figure draws it")
        check_figure(parser, args.figure, args.overwrite)
        results = Path(args.results_dir)
        try:  # the stored runs it is set beside: the ablation's folders next to it, as results/ holds them
            study = RuleStudy.load(results, results.parent / "ablation", results.parent / "ablation-t-likelihood")
        except (StoredResultError, FileNotFoundError, ValueError) as exc:
            parser.error(str(exc))
        show_study(study, figure=args.figure)
        return 0
    model_sweep = (Path(args.results_dir) / "model_sweep.json").is_file()  # another model on a paired sweep's cells
    ablation = _ablation_of_model_sweeps(Path(args.results_dir))  # another model on each of an ablation's settings
    if args.figure is not None and not (model_sweep or ablation):
        parser.error("--figure draws the learning curves of a model sweep's three models, or the threshold study of "
                     f"a folder of model sweeps on an ablation's settings; {args.results_dir} is neither")
    check_figure(parser, args.figure, args.overwrite)
    if (Path(args.results_dir) / "ablation.json").is_file():  # an ablation's folder: its table
        return _ablation_table(args, parser)
    if model_sweep:
        return _model_tables(args, parser)
    if ablation is not None:
        args.ablation, args.models = str(ablation), args.results_dir
        return _threshold_study(args, parser)
    try:
        stored_sweep(args.results_dir)  # sweep.json itself, which a rerun would refuse too
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    try:
        results = SweepResults.load(args.results_dir, a=args.a, allow_partial=args.allow_partial, seeds=args.seeds)
        tables = summary_tables(results)
    except StoredResultError as exc:
        parser.error(f"{exc}; rerun the sweep's command, which computes a damaged cell again")
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    if results.missing:
        print(f"partial sweep: {len(results)} of {len(results) + len(results.missing)} cells stored; "
              f"missing: {describe_cells(results.missing)}")
    _say_versions(results.code_versions(), "the runs")
    print(_LEGEND)
    print(f"\nTable 2: each metric's mean over the configurations, TP against GP\n{_format_table(tables['mean'])}")
    print("\n" + _verdict_counts(tables["table1"]))
    _print_backup((key, name, getattr(comparison, name.lower())) for key, comparison in results.comparisons.items()
                  for name in ("TP", "GP"))
    sections = _beside_paper_sections(tables) + _beside_authors_sections(tables, results.base.episodes)
    if args.all:
        for key, frame in tables.items():
            if key not in ("seeds", "mean"):
                print(f"\n{key}\n{_format_table(frame)}")
        for title, frame in sections:
            print(f"\n{title}\n{_format_table(frame)}")
    else:
        print("\n--all prints the rest: Table 1 (every configuration), each model's levels with 95% intervals, "
              "Tables 3-4 (median, mode), the Wilcoxon tests, and these beside the paper's and the authors' runs")
    if args.markdown:
        markdown = tables_markdown(tables)
        for title, frame in sections:
            markdown += f"\n## {title[0].upper()}{title[1:]}\n\n{frame_to_markdown(_flat(frame))}\n"
        _write_markdown(parser, args, markdown + "\n")
        print(f"\nMarkdown tables written to {args.markdown}")
    return 0


def _flat(frame, digits=None):
    """A table for markdown: its index as columns, m and p as 40 and 0.2 (not 40.000 and 0.200)."""
    flat = (frame if digits is None else frame.round(digits)).reset_index()
    for column in {"m", "p"} & set(flat.columns):
        flat[column] = flat[column].map(lambda v: f"{v:g}")
    return flat


def _check_cell(args, parser) -> int:
    from pathlib import Path

    from .._internal.io import StoredResultError
    from ..experiments.sweep import check_cell

    if (Path(args.results_dir) / "model_sweep.json").is_file():  # another model's runs on a paired sweep's cells
        return _check_model_cell(args, parser)
    try:
        report = check_cell(args.results_dir, args.cell, n_jobs=args.jobs)
    except StoredResultError as exc:
        parser.error(f"{exc}; rerun the sweep's command, which computes a damaged cell again")
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    print(report)
    return 0 if report.identical else 1


def _check_model_cell(args, parser) -> int:
    """check-cell on a model sweep's folder: its one model's run of the cell, recomputed and compared."""
    from .._internal.io import StoredResultError
    from ..experiments.sweep.models import check_model_cell

    try:
        side = check_model_cell(args.results_dir, args.cell)
    except StoredResultError as exc:
        parser.error(f"{exc}; rerun the model sweep's command, which computes a damaged run again")
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    largest = ", ".join(f"{name} {value:.1e}" for name, value in side.diagnostics.items())
    if side.differing_columns or any(value > 1e-7 for value in side.diagnostics.values()):
        print(f"{args.cell}: differs from episode {side.first_differing_episode} in {list(side.differing_columns)}; "
              f"largest difference of the prediction diagnostics relative to scale: {largest}")
        return 1
    print(f"{args.cell}: identical: all {side.episodes} episodes equal; largest difference of the prediction "
          f"diagnostics relative to scale: {largest}")
    return 0


#: what the tables' terms mean, printed above them
_LEGEND = """terms: % change = (TP - GP) / |GP| x 100; better = the model with the better value (n/a: undefined);
Definition 4 (eq. 12): a model is preferred when its TSR is at least a and its cost rate p_c is lower;
"neither" when no model is preferred; "n/a (p_c undefined)", Definition 4 cannot decide: a cost rate p_c is
undefined (violations, but no episode reached the goal without one)"""


def _verdict_counts(table1) -> str:
    """One line: how many configurations Definition 4 decides each way."""
    verdicts = table1.query("model == 'TP'")["result"] if "result" in table1 else table1.iloc[:0]
    counts = verdicts.value_counts()
    named = ", ".join(f"{label}: {int(counts.get(value, 0))}" for value, label in (
        ("TP > GP", "TP preferred"), ("GP > TP", "GP preferred"), ("neither", "neither"),
        ("n/a (p_c undefined)", "cannot decide (p_c undefined)")))
    return f"Definition 4, configuration by configuration ({len(verdicts)} in all): {named}"


def _beside_paper_sections(tables: dict) -> list:
    """(title, frame) pairs: the sweep's mean and Table 1 rows beside the paper's.

    The paper's Table 2 is a mean over its 45 configurations; a partial
    sweep's mean is over fewer, and the title says how many.
    """
    from ..config import PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES
    from ..experiments.tables import beside_paper, table1_beside_paper
    from ..paper import published as paper

    n = len(tables["table1"]) // 2  # a TP row and a GP row per configuration
    total = len(PAPER_MAGNITUDES) * len(PAPER_PROPORTIONS) * len(PAPER_SWITCH_STATES)
    over = (f"all {total} configurations" if n == total
            else f"the {n} configurations stored (the paper's: all {total})")
    sections = [(f"beside the paper's Table 2: mean over {over}, with each model's 95% bootstrap interval",
                 beside_paper(tables["mean"], paper.TABLE2, levels=tables["levels"], percents=paper.TABLE2_PERCENT))]
    rows = table1_beside_paper(tables["table1"], paper.TABLE1)
    if len(rows):
        shown = rows.index.droplevel("metric").nunique()
        sections.append((f"beside the paper's Table 1: {shown} of its {len(paper.TABLE1)} configurations stored",
                         rows))
    return sections


def _beside_authors_sections(tables: dict, episodes: int) -> list:
    """(title, frame) pairs: Tables 2 and 3 and Definition 4 per configuration, computed from the authors' runs.

    Their per-episode records give what the paper's tables do not: every
    configuration's cost rate, hence its verdict, and medians computed as ours.
    """
    from ..experiments.tables import summary_tables
    from ..paper.authors import AUTHORS_EPISODES, AuthorsRuns, tables_beside_authors, verdicts_beside_authors

    configurations = {(row.m, row.p, row.nss) for row in tables["table1"].itertuples(index=False)}
    authors = AuthorsRuns(episode=min(episodes, AUTHORS_EPISODES)).only(configurations)
    if not len(authors):
        return []
    over = (f"the {len(authors)} configurations stored" if len(authors) < 45 else "all 45 configurations")
    at = ("" if episodes == 250 else f", at episode {episodes} of their 250 (our runs' length)" if episodes < 250
          else f", at their last episode (250; ours run to {episodes})")
    authors_tables = summary_tables(authors)
    verdicts = verdicts_beside_authors(tables, authors_tables)
    same = int((verdicts["ours verdict"] == verdicts["authors verdict"]).sum())
    for column in [c for c in verdicts.columns if "p_c" in c]:  # four decimals: the verdicts turn on the third
        verdicts[column] = verdicts[column].map(lambda v: "n/a" if v != v else f"{v:.4f}")
    return [
        (f"beside the authors' own runs: Table 2 (mean over {over}) computed from their per-episode records{at}",
         tables_beside_authors(tables, authors_tables, "mean")),
        ("beside the authors' own runs: Table 3 (median), computed the same way",
         tables_beside_authors(tables, authors_tables, "median")),
        (f"Definition 4 per configuration, cost rates and verdicts, ours beside the authors' runs{at} "
         f"(the same verdict in {same} of {len(verdicts)})", verdicts),
    ]


def _ablation_table(args, parser) -> int:
    """``tables`` on an ablation's folder: its stored runs' table (``--markdown`` writes it too)."""
    from pathlib import Path

    from .._internal.io import StoredResultError, read_json
    from ..experiments.ablation import AblationResults
    from ..experiments.tables import frame_to_markdown

    try:
        table = AblationResults.load(args.results_dir).table()
        design = read_json(Path(args.results_dir) / "ablation.json", keys=("cells", "seeds"))
        planned = len(design["cells"]) * len(design["seeds"])
    except (StoredResultError, FileNotFoundError, ValueError, TypeError) as exc:
        parser.error(str(exc))
    print(f"the ablation stored in {args.results_dir}\n{_format_table(table)}")
    short = sorted({setting for (setting, _), runs in table["runs"].items() if runs < planned})
    if short:
        print(f"\npartial: {len(short)} setting(s) hold fewer than the {planned} runs the ablation plans "
              f"({', '.join(short)}); rerun its command to complete them")
    if args.markdown:
        _write_markdown(parser, args, frame_to_markdown(table.reset_index()) + "\n")
        print(f"\nMarkdown table written to {args.markdown}")
    return 0


def _say_versions(versions: dict, what: str) -> None:
    """A note where ``what`` (a sweep's runs) come from more than one version of the code."""
    if len(versions) > 1:
        print(f"note: {what} were computed by {len(versions)} versions of the code, whose numbers may differ: "
              + "; ".join(f"{label}: {runs} runs" for label, runs in versions.items()))


def _model_tables(args, parser) -> int:
    """A model sweep's folder: Table 2 of three models over the cells run so far, the tests, Definition 4, and
    each configuration's three models."""
    from .._internal.io import StoredResultError
    from ..experiments.provenance import code_versions

    unsupported = [flag for flag, given in (("--all", args.all), ("--seeds", args.seeds)) if given]
    if unsupported:
        parser.error(f"{', '.join(unsupported)}: not for a model sweep's folder, whose tables are Table 2 with a "
                     "third column, its tests, Definition 4 and each configuration over the cells run so far")
    from ..experiments.sweep.model_tables import MODEL_NAMES, model_sweep_tables
    from ..experiments.sweep.models import load_model_sweep

    try:
        paired, runs = load_model_sweep(args.results_dir)
    except (StoredResultError, FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    if not runs:
        print(f"{args.results_dir}: none of the {len(paired)} cells of its paired sweep (TP and GP) run yet with "
              "the third model")
        return 0
    tables = model_sweep_tables(paired, runs, a=args.a)
    if len(runs) < len(paired):
        print(f"partial: {len(runs)} of the paired sweep's {len(paired)} cells run so far")
    _say_versions(code_versions(runs.values()), "the third model's runs")
    print(_LEGEND)
    print(f"\nTable 2 with a third model: each metric's mean over the configurations run\n"
          f"{_format_table(tables['mean'])}")
    _print_backup((key, name, result) for key, run in sorted(runs.items())
                  for name, result in (("TP", paired.comparisons[key].tp), ("GP", paired.comparisons[key].gp),
                                       (MODEL_NAMES[run.config.model], run)))
    print(f"\nThe third model against TP and GP over configurations\n{_format_table(tables['tests'])}")
    print(f"\nDefinition 4 in each configuration\n{_format_table(tables['definition4'])}")
    print(f"\nEach configuration: the mean over its seeds run\n{_format_table(tables['configurations'])}")
    if args.markdown:
        from ..experiments.tables import frame_to_markdown

        digits = {"mean": 3, "tests": 3, "definition4": 3, "configurations": 1}
        _write_markdown(parser, args, "\n\n".join(frame_to_markdown(_flat(tables[key], places), places)
                                                      for key, places in digits.items()) + "\n")
        print(f"\nMarkdown tables written to {args.markdown}")
    if args.figure:
        from ..experiments.sweep.model_tables import model_sweep_curves
        from ..teaching.plotting import plot_model_curves

        figure, axes = new_figure(1, 2, (11, 4.2))
        for ax, metric in zip(axes, ("task_success_rate", "total_cost")):
            plot_model_curves(ax, model_sweep_curves(paired, runs, metric), metric=metric, settle=10,
                              title=f"mean over the {len(runs)} cells run")
        save_figure(figure, args.figure, args.overwrite)
    return 0


def _ablation_of_model_sweeps(folder):
    """The ablation whose settings the model sweeps in ``folder``'s subfolders ran on (as
    ``results/ablation-t-likelihood`` holds them), or None where ``folder`` holds no such sweep."""
    from .._internal.io import read_json

    for meta in sorted(folder.glob("*/model_sweep.json")) if folder.is_dir() else ():
        paired = (meta.parent / read_json(meta, keys=("paired",))["paired"]).resolve()
        if (paired.parent / "ablation.json").is_file():
            return paired.parent
    return None


def _threshold_study(args, parser) -> int:
    """``threshold-study``: the three models against sigma*^2, from an ablation's folder and the third model's."""
    from pathlib import Path

    from .._internal.io import StoredResultError
    from ..experiments.ablation import setting_folder
    from ..experiments.tables import frame_to_markdown
    from ..experiments.thresholds import ThresholdStudy, threshold_settings

    for flag, name in (("--markdown", args.markdown), ("--figure", args.figure)):
        _outside(parser, flag, name, [args.ablation, args.models])
    _distinct_outputs(parser, args.markdown, args.figure)
    if args.markdown is not None:
        check_file(parser, "--markdown", args.markdown, overwrite=args.overwrite)
    check_figure(parser, args.figure, args.overwrite)
    if args.models is not None:
        _check_models_folder(parser, Path(args.models))
    try:
        study = ThresholdStudy.load(args.ablation, args.models)
    except (StoredResultError, FileNotFoundError, ValueError, TypeError) as exc:
        parser.error(str(exc))
    if not len(study.runs):
        print(f"{args.ablation} holds none of the study's settings yet: run 'sarsp-edu ablation --settings "
              + " ".join(f'"{name}"' for name in threshold_settings()) + f" --out {args.ablation}'")
        return 0
    if args.models is not None and "t-likelihood GP" not in set(study.runs["model"]):
        folders = ", ".join(setting_folder(name) for name in threshold_settings())
        print(f"note: {args.models} holds no run of the third model on the study's settings (a model sweep in "
              f"{args.models}/<setting folder>, for the folders {folders}), so the study holds the TP and the GP only")
    missing = study.missing
    study = study.complete()  # each mean over the same runs: the thresholds and models still running left out
    if not len(study.runs):
        print("no threshold and model has all its runs stored yet")
        return 0
    table, pairs = study.table(), study.pairs()
    shown = table[["runs", *[c for m in ("backup_share", "total_cost", "task_success_rate")
                             for c in (m, f"{m} low", f"{m} high")]]]
    print(f"the threshold study: {args.ablation}" + (f" and {args.models}" if args.models else "")
          + "\neach measure's mean over the runs (configurations x seeds) and its 95% t-interval (low, high)\n"
          + _format_table(shown.round(2)))
    print(f"\nthe models run by run, at each threshold\n{_format_table(pairs.round(2))}")
    if missing:
        print(f"\nleft out, their runs not all stored (of {study.planned}): "
              + ", ".join(f"{model} at {threshold:g} ({runs})" for (threshold, model), runs in missing.items()))
    left = study.lowest_threshold_off_backup()
    print("\nthe smallest threshold at which a model's backup share falls below 50%: "
          + ", ".join(f"{model} {value:g}" if value == value else f"{model} at none of them"
                      for model, value in left.items()))
    if args.markdown:
        _write_markdown(parser, args, frame_to_markdown(shown.round(2).reset_index()) + "\n\n"
                          + frame_to_markdown(pairs.round(2).reset_index()) + "\n")
        print(f"\nMarkdown tables written to {args.markdown}")
    if args.figure:
        from ..teaching.plotting import plot_threshold_study

        figure, axes = new_figure(1, 3, (13, 4.2))
        plot_threshold_study(axes, study.runs)
        save_figure(figure, args.figure, args.overwrite)
    return 0


def _outside(parser, flag: str, name, folders) -> None:
    """Refuse an output file inside a results folder being read: it could replace one of its files."""
    from pathlib import Path

    if not name:
        return
    target = Path(name).resolve()
    for folder in folders:
        if folder is not None and Path(folder).resolve() in target.parents:
            parser.error(f"{flag} {name} lies inside the results folder {folder}, whose files it could replace; write "
                         "it outside")


def _distinct_outputs(parser, markdown, figure) -> None:
    """Refuse --markdown and --figure naming one file: the second would replace the first."""
    from pathlib import Path

    if markdown and figure and Path(markdown).resolve() == Path(figure).resolve():
        parser.error(f"--markdown and --figure name the same file {figure}; give each its own")


def _check_models_folder(parser, folder) -> None:
    """Refuse a ``--models`` folder that is missing, or that is one model sweep rather than the folder of them."""
    if not folder.is_dir():
        parser.error(f"--models {folder} is not a folder; give the folder that holds the third model's sweeps, one "
                     "per setting (results/ablation-t-likelihood)")
    if (folder / "model_sweep.json").is_file():
        parser.error(f"--models {folder} is one model sweep; give the folder that holds one per setting (its parent, "
                     f"{folder.parent})")


def _write_markdown(parser, args, text: str) -> None:
    """Write ``--markdown``: a file made meanwhile by another command is refused, not replaced (unless
    ``--overwrite``)."""
    from .._internal.io import atomic_write_text

    try:
        atomic_write_text(args.markdown, text, replace=args.overwrite)
    except FileExistsError:
        parser.error(f"--markdown {args.markdown} was written by another command meanwhile; --overwrite replaces it")


def _print_backup(runs) -> None:
    """Each model's share of decisions left to the backup rule, over the configurations of ``runs``."""
    from ..experiments.decisions import backup_levels, backup_shares

    print("\nDecisions left to the backup rule (no action safe): each model's share over the configurations, "
          f"with a 95% bootstrap interval\n{_format_table(backup_levels(backup_shares(runs)))}")
