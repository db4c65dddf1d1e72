"""What each ``sarsp-edu`` command does once its arguments are checked: one function per command."""

from __future__ import annotations

import contextlib
import importlib.metadata
import os
import platform
import sys

from .._version import __version__
from .arguments import check_file, check_out, check_writable, config_flags, config_from_args


#: the packages whose versions ``sarsp-edu info`` reports (for bug reports)
def _dependencies() -> list[tuple[str, str]]:
    """(name, extra) of every requirement the installed package declares ('' for the core ones), in order."""
    import re

    try:
        declared = importlib.metadata.requires("sarsp_edu") or []
    except importlib.metadata.PackageNotFoundError:  # run from a source tree that was never installed
        return []
    found = []
    for requirement in declared:
        name = re.match(r"[A-Za-z0-9_.\-]+", requirement).group(0)
        extra = re.search(r"extra\s*==\s*['\"]([^'\"]+)['\"]", requirement)
        if name.lower().replace("_", "-") != "sarsp-edu":
            found.append((name, extra.group(1) if extra else ""))
    return found


def _format_table(frame) -> str:
    """A table for the terminal; NaN (an undefined value, such as eq. 12 without a clean success) reads n/a."""
    return frame.to_string(float_format=lambda v: f"{v:,.3f}", na_rep="n/a")


def _run(args, parser) -> int:
    from ..experiment import run_experiment
    from ..metrics import SUMMARY_METRICS, backup_share, displayed_summary

    config = config_from_args(parser, args)
    check_out(parser, args.out, "run", config, args.overwrite)
    with _out_lock(parser, args.out, "run"):
        result = run_experiment(config, progress=not args.quiet)
        if args.out:
            saved = result.save(args.out)
    import pandas as pd

    table = pd.DataFrame({config.model.upper(): displayed_summary(result.summary)}).loc[list(SUMMARY_METRICS)]
    print(f"SARSP with a {'Student-t' if config.model == 'tp' else 'Gaussian'} process, {_describe(config)}")
    print(_format_table(table))
    records = result.records
    print(f"corrective updates: {int(records['corrective_updates'].iloc[-1])}, "
          f"decisions with no safe action: {backup_share(records):.0%}")
    if args.out:
        print(f"saved to {saved}")
    return 0


@contextlib.contextmanager
def _out_lock(parser, out, command: str):
    """Hold ``--out``'s lock (the one a sweep takes) from the run's start to its save: two commands never
    write one folder at once."""
    from pathlib import Path

    from .._io import lock_folder
    from ..sweep import LOCK_NAME

    if out is None:
        yield
        return
    folder = Path(out)
    made = []  # the folders this makes, the deepest first
    for ancestor in (folder, *folder.parents):
        if ancestor.exists():
            break
        made.append(ancestor)
    folder.mkdir(parents=True, exist_ok=True)
    try:
        lock = lock_folder(folder, LOCK_NAME, "sarsp-edu command")
    except ValueError as exc:
        parser.error(str(exc))
    try:
        yield
    finally:
        if lock is not None:
            lock.close()
        if made and [p.name for p in folder.iterdir()] == [LOCK_NAME]:  # nothing was saved: leave no trace
            (folder / LOCK_NAME).unlink(missing_ok=True)
            for made_folder in made:
                made_folder.rmdir()


def _compare(args, parser) -> int:
    from ..experiment import compare

    config = config_from_args(parser, args)
    check_out(parser, args.out, "compare", config, args.overwrite)
    with _out_lock(parser, args.out, "compare"):
        try:
            comparison = compare(config, progress=not args.quiet, a=args.a, n_jobs=args.jobs)
        except ValueError as exc:
            parser.error(str(exc))
        if args.out:
            saved = comparison.save(args.out)
    print(f"TP vs GP, paired: {_describe(config)}")
    print(_format_table(comparison.table()))
    verdict = comparison.verdict
    if verdict["tp_preferred"] is None:
        print(f"Definition 4 (a={args.a:g}) cannot decide: a cost rate is undefined (violations, but no "
              "episode reached the goal without one)")
    else:
        print(f"Definition 4 (a={args.a:g}): TP preferred to GP: {verdict['tp_preferred']}; "
              f"GP preferred to TP: {verdict['gp_preferred']}")
    if args.out:
        print(f"saved to {saved}")
    return 0


def _sweep(args, parser) -> int:
    import shlex
    from pathlib import Path

    from ..sweep import SweepResults, run_sweep, stored_sweep
    from ..tables import summary_tables

    grid = {"magnitudes": args.magnitudes, "proportions": args.proportions, "nss": args.nss, "seeds": args.seeds}
    stored = None
    if args.out and (Path(args.out) / "sweep.json").exists():
        try:
            stored = stored_sweep(args.out)
        except ValueError as exc:
            parser.error(str(exc))
    resume_settings = stored is not None and not config_flags(args) and args.preset is None
    config = config_from_args(parser, args, base=stored[0] if resume_settings else None)
    check_out(parser, args.out, "sweep")
    if args.scheduler and not _dask_installed():
        parser.error("--scheduler needs Dask, which is not installed: pip install 'sarsp_edu[dask]'")
    resume_cells = stored is not None and all(values is None for values in grid.values())
    if resume_cells:
        keys = sorted(stored[1])  # the cells the stored sweep was asked for
        print(f"resuming the sweep in {args.out}: {len(keys)} cells, preset {config.preset}"
              + (" (its stored settings)" if resume_settings else ""), file=sys.stderr)
    else:
        from ..config import PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES

        defaults = {"magnitudes": PAPER_MAGNITUDES, "proportions": PAPER_PROPORTIONS, "nss": PAPER_SWITCH_STATES,
                    "seeds": (0,)}
        if stored is not None and stored[1]:  # flags not given: the stored sweep's values, as the help says
            defaults = {name: sorted({key[axis] for key in stored[1]}) for axis, name in enumerate(defaults)}
        grid = {name: defaults[name] if values is None else values for name, values in grid.items()}
        keys = [(float(m), float(p), int(nss), int(seed)) for seed in grid["seeds"] for m in grid["magnitudes"]
                for p in grid["proportions"] for nss in grid["nss"]]
    if args.out:
        args.stored = [(args.out, set(keys))]
    try:
        if resume_cells:
            for seed in sorted({key[3] for key in keys}):  # a stored sweep's cells, seed by seed
                run_sweep(config, cells=[key[:3] for key in keys if key[3] == seed], seeds=[seed],
                          results_dir=args.out, n_jobs=args.jobs, scheduler=args.scheduler,
                          progress=not args.quiet, a=args.a)
            results = SweepResults.load(args.out, a=args.a)
        else:
            results = run_sweep(
                config,
                magnitudes=grid["magnitudes"],
                proportions=grid["proportions"],
                n_switch_states=grid["nss"],
                seeds=grid["seeds"],
                results_dir=args.out,
                n_jobs=args.jobs,
                scheduler=args.scheduler,
                progress=not args.quiet,
                a=args.a,
            )
    except ValueError as exc:
        parser.error(str(exc))
    tables = summary_tables(results)
    cells = f"{len(results)} cell{'' if len(results) == 1 else 's'}"
    print(f"{cells}, each a paired TP-vs-GP run of {config.episodes} episodes; preset {config.preset}")
    print(_format_table(tables["mean"]))
    if args.out:
        print(f"cells stored in {args.out}; print every table with: sarsp-edu tables {shlex.quote(str(args.out))}")
    return 0


def _dask_installed() -> bool:
    import importlib.util

    try:
        return importlib.util.find_spec("dask.distributed") is not None
    except ModuleNotFoundError:
        return False


def _tables(args, parser) -> int:
    from .._io import StoredResultError, atomic_write_text
    from ..sweep import SweepResults, describe_cells, stored_sweep
    from ..tables import frame_to_markdown, summary_tables, tables_markdown

    from pathlib import Path

    if args.markdown:
        check_file(parser, "--markdown", args.markdown)
        folder = Path(args.results_dir).resolve()
        if folder in Path(args.markdown).resolve().parents:
            parser.error(f"--markdown {args.markdown} lies inside the results folder {args.results_dir}, whose files "
                         "it could replace; write the tables outside it")

    if (Path(args.results_dir) / "ablation.json").is_file():  # an ablation's folder: its table
        return _ablation_table(args, parser)
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
    versions = results.code_versions()
    if len(versions) > 1:
        print(f"note: the runs were computed by {len(versions)} versions of the code, whose numbers may differ: "
              + "; ".join(f"{label}: {runs} runs" for label, runs in versions.items()))
    print(_LEGEND)
    print(f"\nTable 2: each metric's mean over the configurations, TP against GP\n{_format_table(tables['mean'])}")
    print("\n" + _verdict_counts(tables["table1"]))
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
            flat = frame.reset_index()
            for column in {"m", "p"} & set(flat.columns):  # 40 and 0.2, not 40.000 and 0.200
                flat[column] = flat[column].map(lambda v: f"{v:g}")
            markdown += f"\n## {title[0].upper()}{title[1:]}\n\n{frame_to_markdown(flat)}\n"
        atomic_write_text(args.markdown, markdown + "\n")
        print(f"\nMarkdown tables written to {args.markdown}")
    return 0


def _check_cell(args, parser) -> int:
    from .._io import StoredResultError
    from ..sweep import check_cell

    try:
        report = check_cell(args.results_dir, args.cell, n_jobs=args.jobs)
    except StoredResultError as exc:
        parser.error(f"{exc}; rerun the sweep's command, which computes a damaged cell again")
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    print(report)
    return 0 if report.identical else 1


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
    from .. import paper
    from ..config import PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES
    from ..tables import beside_paper, table1_beside_paper

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
    from ..authors import AUTHORS_EPISODES, AuthorsRuns, tables_beside_authors, verdicts_beside_authors
    from ..tables import summary_tables

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


def _describe(config) -> str:
    """One line: the configuration, the preset and the settings that differ from it."""
    from ..config import PRESET_FIELDS, PRESETS

    text = (f"m={config.outlier_magnitude:g} p={config.outlier_proportion:g} nss={config.n_switch_states} "
            f"episodes={config.episodes} seed={config.seed}; preset {config.preset}")
    if config.preset == "custom":
        closest = min(PRESETS, key=lambda name: sum(getattr(config, k) != v for k, v in PRESETS[name].items()))
        changed = [f"{k}={getattr(config, k)!r}" for k in PRESET_FIELDS if getattr(config, k) != PRESETS[closest][k]]
        text += f" ('{closest}' with {', '.join(changed)})"
    return text


def _ablation_table(args, parser) -> int:
    """``tables`` on an ablation's folder: its stored runs' table (``--markdown`` writes it too)."""
    from .._io import StoredResultError, atomic_write_text
    from ..ablation import AblationResults
    from ..tables import frame_to_markdown

    from pathlib import Path

    from .._io import read_json

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
        atomic_write_text(args.markdown, frame_to_markdown(table.reset_index()) + "\n")
        print(f"\nMarkdown table written to {args.markdown}")
    return 0


def _ablation(args, parser) -> int:
    import shlex

    from ..ablation import ABLATION_SETTINGS, AblationResults, run_ablation, setting_folder

    if args.list:
        for name, setting in ABLATION_SETTINGS.items():
            print(f"{name} (folder {setting_folder(name)}): {setting or 'the default preset'}")
        return 0
    by_folder = {setting_folder(name): name for name in ABLATION_SETTINGS}  # the stored folders' names too
    chosen = [name if name in ABLATION_SETTINGS else by_folder.get(name, name) for name in args.settings or ()]
    unknown = [name for name in chosen if name not in ABLATION_SETTINGS]
    if unknown:
        parser.error(f"unknown setting(s) {unknown}; 'sarsp-edu ablation --list' names them (a stored folder's "
                     "name, such as default-k-400, works too)")
    settings = {name: ABLATION_SETTINGS[name] for name in (chosen or ABLATION_SETTINGS)}
    if args.cells:
        if len(args.cells) % 3:
            parser.error(f"--cells takes m p nss triples, got {len(args.cells)} numbers")
        cells = [(args.cells[i], args.cells[i + 1], args.cells[i + 2]) for i in range(0, len(args.cells), 3)]
        fractional = [nss for _, _, nss in cells if not float(nss).is_integer()]
        if fractional:
            parser.error(f"--cells: each triple's third number, nss, must be a whole number of switch states, got "
                         f"{fractional[0]:g}")
        cells = [(m, p, int(nss)) for m, p, nss in cells]
    else:
        from ..config import ABLATION_CELLS as cells
    check_out(parser, args.out, "ablation")
    if args.out:
        from pathlib import Path

        keys = {(float(m), float(p), int(nss), int(seed)) for seed in args.seeds for m, p, nss in cells}
        args.stored = [(Path(args.out) / setting_folder(name), keys) for name in settings]
    command = "sarsp-edu " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if args.record_command else None
    try:
        results = run_ablation(settings, cells=cells, seeds=args.seeds, episodes=args.episodes,
                               results_dir=args.out, n_jobs=args.jobs, progress=not args.quiet, command=command)
    except ValueError as exc:
        parser.error(str(exc))
    if args.out:
        results = AblationResults.load(args.out)
    print(_format_table(results.table()))
    return 0


def _check_pages_out(parser, out, overwrite: bool) -> None:
    """Refuse a pages folder that holds results, or pages already unless ``--overwrite``."""
    from .arguments import _MARKERS

    held = next((kind for kind, marker in _MARKERS.items() if (out / marker).exists()), None)
    if held:
        parser.error(f"--out {out} holds {'an' if held[0] in 'aeiou' else 'a'} {held}'s results; give the pages a "
                     "folder of their own")
    pages = sorted(p.name for p in out.glob("*.html")) if out.is_dir() else []
    if pages and not overwrite:
        parser.error(f"--out {out} holds pages already ({', '.join(pages[:3])}{' ...' if len(pages) > 3 else ''}); "
                     "add --overwrite to replace them, or give a new folder")
    check_writable(parser, "--out", str(out), out)


def _course(args, parser) -> int:
    from pathlib import Path

    from ..course import execute_sources, write_handout, write_pages, write_student_notebooks

    if args.action in ("sources", "student", "pages"):
        try:
            if args.action == "sources":
                written = execute_sources(args.tutorials, only=args.only)
            elif args.action == "student":
                written = write_student_notebooks(args.tutorials, run=not args.no_execute, only=args.only)
            else:
                if args.out is None:
                    parser.error("pages needs --out DIR")
                _check_pages_out(parser, Path(args.out), args.overwrite)
                written = [write_pages(args.tutorials, args.out, mathjax=args.mathjax)]
        except (FileNotFoundError, ValueError) as exc:
            parser.error(str(exc))
        for path in written:
            print(f"wrote {path}")
        return 0
    if (args.out is None) == (args.zip is None):
        parser.error("handout needs --out DIR or --zip FILE")
    if args.out is not None:
        if any(Path(args.out).glob("tutorials/[0-9][0-9]_*.ipynb")):
            parser.error(f"--out {args.out} holds a course hand-out already (written earlier); give a new or empty "
                         "folder, or remove it first")
        check_out(parser, args.out, "handout")
    else:
        check_file(parser, "--zip", args.zip, overwrite=args.overwrite)
    try:
        made = write_handout(args.root, out=args.out, zip_path=args.zip)
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    print(f"the students' copy of the course (no sources, no solutions) is in {made}")
    return 0


def _info(args, parser) -> int:
    from ..config import PRESET_DOCS, PRESETS

    print(f"sarsp_edu {__version__}")
    print(f"python {platform.python_version()} ({sys.executable})")
    dependencies = _dependencies()
    if not dependencies:
        print("(not installed: pip install -e . lists its dependencies here)")
    for name, extra in dependencies:
        try:
            version = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            version = "not installed"
        print(f"{name} {version}" + (f"  (extra [{extra}])" if extra else ""))
    print("\npresets (sarsp-edu run|compare|sweep|ablation --preset NAME):")
    for name, values in PRESETS.items():
        print(f"  {name}: {PRESET_DOCS[name]}")
        print("    " + ", ".join(f"{k}={v!r}" for k, v in values.items()))
    return 0


def _cache(args, parser) -> int:
    from .. import fitcache

    directory = fitcache.cache_directory()
    if directory is None:
        print(f"the live dashboards' cache of fits is off ({fitcache.CACHE_VARIABLE}="
              f"{os.environ.get(fitcache.CACHE_VARIABLE)!r})")
        return 0
    if args.clear:
        print(f"removed {fitcache.clear()} stored fits from {directory}")
        return 0
    found = fitcache.entries()
    print(f"{directory}: {len(found)} stored fits, {sum(size for _, size in found) / 2**20:.0f} MB "
          f"(at most {fitcache.CACHE_BYTES / 2**20:.0f} MB are kept; {fitcache.CACHE_VARIABLE}=off turns it off)")
    return 0
