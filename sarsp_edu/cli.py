"""The ``sarsp-edu`` command: the paper's experiments from a terminal.

Examples::

    sarsp-edu run --model tp --m 60 --p 0.3 --nss 6 --out results/tp-run
    sarsp-edu compare --episodes 50 --seed 1
    sarsp-edu sweep --jobs 2 --out results/paper
    sarsp-edu tables results/paper
    sarsp-edu info

One file of about 450 lines, one idea: the command's parser, the checks on
its paths made before any work, and the one-line errors and interruptions.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.metadata
import os
import platform
import sys

from ._version import __version__

#: the packages whose versions ``sarsp-edu info`` reports (for bug reports)
_REPORTED = ("numpy", "scipy", "sympy", "matplotlib", "ipywidgets", "gymnasium", "pandas", "tqdm", "joblib", "dask")


def _none_or(convert):
    def parse(text: str):
        return None if text.lower() == "none" else convert(text)

    parse.__name__ = convert.__name__
    return parse


_TYPES = {
    "float": float,
    "int": int,
    "str": str,
    "int | None": _none_or(int),
    "str | None": _none_or(str),
}


def add_config_arguments(parser: argparse.ArgumentParser, skip=()) -> None:
    """One flag per ``ExperimentConfig`` field, with the field's own help text.

    Defaults are left to the dataclass (one source of truth): a flag not
    given is not passed on.
    """
    from .config import LIMITS, PRESET_DOCS, PRESET_FIELDS, ExperimentConfig

    preset_fields = set(PRESET_FIELDS)

    group = parser.add_argument_group(
        "experiment settings (defaults: the 'default' preset; a flag given overrides the preset)")
    group.add_argument(
        "--preset", choices=list(PRESET_DOCS), default=None,
        help="a named set of SARSP settings: " + "; ".join(f"'{k}': {v}" for k, v in PRESET_DOCS.items())
        + " [default: default]")
    for f in dataclasses.fields(ExperimentConfig):
        if f.name in skip:
            continue
        names = [f"--{f.name.replace('_', '-')}"]
        if "flag" in f.metadata:
            names.insert(0, f"--{f.metadata['flag']}")
        bound = f"; at most {LIMITS[f.name][0]:,}" if f.name in LIMITS else ""
        help_text = f"{f.metadata['help']} [default: {f.default}{bound}]"
        if f.name in preset_fields:
            help_text = help_text[:-1] + ", or the preset's]"
        kwargs = dict(dest=f.name, default=argparse.SUPPRESS, help=help_text)
        if f.type == "bool":
            kwargs["action"] = argparse.BooleanOptionalAction
        else:
            kwargs["type"] = _TYPES[f.type]
            kwargs["metavar"] = f.name.upper() if "flag" not in f.metadata else f.metadata["flag"].upper()
            if "choices" in f.metadata:
                kwargs["choices"] = list(f.metadata["choices"])
                kwargs["metavar"] = "{" + ",".join(str(c) for c in f.metadata["choices"]) + "}"
        group.add_argument(*names, **kwargs)


def config_flags(args: argparse.Namespace) -> dict:
    """The ``ExperimentConfig`` fields given as flags (a flag not given is absent)."""
    from .config import ExperimentConfig

    names = {f.name for f in dataclasses.fields(ExperimentConfig)}
    return {k: v for k, v in vars(args).items() if k in names}


def config_from_args(parser: argparse.ArgumentParser, args: argparse.Namespace, base=None):
    """Build the config (the preset, or ``base``, then the flags given), turning a bad value into a usage error.

    A flag that the other settings leave unused (``--n-samples`` with exact
    predictions, say) is reported on standard error.
    """
    from .config import ExperimentConfig

    values = config_flags(args)
    try:
        if base is not None:
            config = base.replace(**values)
        else:
            config = ExperimentConfig.from_preset(getattr(args, "preset", None) or "default", **values)
    except ValueError as exc:
        parser.error(str(exc))
    ignored = config.ignored_settings()
    if args.command == "compare":  # both models run: the TP's settings count
        ignored = {k: v for k, v in ignored.items() if k not in ("nu", "noise_convention")}
    for name in sorted(set(values) & set(ignored)):
        print(f"warning: --{name.replace('_', '-')} is ignored: {ignored[name]}", file=sys.stderr)
    return config


#: what marks a folder as holding each command's results
_MARKERS = {"sweep": "sweep.json", "ablation": "ablation.json", "run": "result.json", "compare": "tp/result.json"}


def _check_writable(parser: argparse.ArgumentParser, flag: str, name, path) -> None:
    """Refuse a folder ``path`` (to make, or to write in) that cannot be written, before any work starts.

    The folder is made and a file written and removed in it, then whatever
    this made is removed again: a permission, a read-only or pseudo file
    system (``/proc``), a file in the way, a name too long: each is found now,
    not after the run, and nothing is left behind.
    """
    import tempfile

    made = []
    ancestor = path
    while not ancestor.exists():
        made.append(ancestor)
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        parser.error(f"{flag} {name} cannot be made: {ancestor} is a file")
    try:
        for folder in reversed(made):
            folder.mkdir()
        handle, probe = tempfile.mkstemp(prefix=".sarsp-edu-probe-", dir=path)
        os.close(handle)
        os.unlink(probe)
    except OSError as exc:
        parser.error(f"{flag} {name} cannot be written: {exc.strerror or exc}")
    finally:
        for folder in made:  # the deepest first
            try:
                folder.rmdir()
            except OSError:
                pass


def _check_out(parser: argparse.ArgumentParser, out, command: str, config=None, overwrite: bool = False) -> None:
    """Refuse an ``--out`` folder the command could not or should not write to, before any work starts.

    A command writes into a new folder, an empty one, or one holding its own
    kind of results: a sweep or an ablation resumes there; a run or a
    comparison replaces a result of the same settings there, and one of other
    settings only with ``--overwrite``.
    """
    if out is None:
        return
    from pathlib import Path

    path = Path(out)
    if path.exists() and not path.is_dir():
        parser.error(f"--out {out} is a file; give a folder (new, empty, or holding a {command}'s results)")
    _check_writable(parser, "--out", out, path)
    if not (path.is_dir() and any(not entry.name.startswith(".") for entry in path.iterdir())):
        return
    kind = next((k for k, marker in _MARKERS.items() if (path / marker).exists()), None)
    if kind != command:
        holds = f"a {kind}'s results" if kind else "other files"
        parser.error(f"--out {out} holds {holds}; '{command}' writes into a new folder, an empty one "
                     f"or one holding a {command}'s results")
    if command in ("run", "compare") and config is not None and not overwrite:
        differing = _stored_settings_differ(path / _MARKERS[command], config)
        if differing:
            parser.error(f"--out {out} holds a {command} of other settings ({differing}); to keep both, give "
                         "another folder; to replace it, add --overwrite")


def _stored_settings_differ(result_json, config) -> str:
    """The settings in which a stored run differs from ``config``, in a line ('' when none)."""
    from ._io import StoredResultError, read_json
    from .config import ExperimentConfig

    try:
        stored = read_json(result_json, keys=("config",))["config"]
    except StoredResultError:
        return f"{result_json} cannot be read"
    ours = config.replace(model=stored.get("model", config.model)).to_dict()
    known = {f.name for f in dataclasses.fields(ExperimentConfig)}
    fields_ = sorted(k for k in known if stored.get(k, ours[k]) != ours[k] or k not in stored)
    return ", ".join(f"{k}: stored {stored.get(k, 'nothing')!r}, now {ours[k]!r}" for k in fields_)


def _check_file(parser: argparse.ArgumentParser, flag: str, name) -> None:
    """Refuse an output file that could not be written, before any work starts."""
    from pathlib import Path

    path = Path(name)
    if path.is_dir():
        parser.error(f"{flag} {name} is a folder; give a file name")
    _check_writable(parser, flag, name, path.parent)


def _format_table(frame) -> str:
    """A table for the terminal; NaN (an undefined value, such as eq. 12 without a clean success) reads n/a."""
    return frame.to_string(float_format=lambda v: f"{v:,.3f}", na_rep="n/a")


def _run(args, parser) -> int:
    from .experiment import run_experiment
    from .metrics import SUMMARY_METRICS, backup_share, displayed_summary

    config = config_from_args(parser, args)
    _check_out(parser, args.out, "run", config, args.overwrite)
    result = run_experiment(config, progress=not args.quiet)
    import pandas as pd

    table = pd.DataFrame({config.model.upper(): displayed_summary(result.summary)}).loc[list(SUMMARY_METRICS)]
    print(f"SARSP with a {'Student-t' if config.model == 'tp' else 'Gaussian'} process, {_describe(config)}")
    print(_format_table(table))
    records = result.records
    print(f"corrective updates: {int(records['corrective_updates'].iloc[-1])}, "
          f"decisions with no safe action: {backup_share(records):.0%}")
    if args.out:
        print(f"saved to {result.save(args.out)}")
    return 0


def _compare(args, parser) -> int:
    from .experiment import compare

    config = config_from_args(parser, args)
    _check_out(parser, args.out, "compare", config, args.overwrite)
    try:
        comparison = compare(config, progress=not args.quiet, a=args.a, n_jobs=args.jobs)
    except ValueError as exc:
        parser.error(str(exc))
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
        print(f"saved to {comparison.save(args.out)}")
    return 0


def _sweep(args, parser) -> int:
    import shlex
    from pathlib import Path

    from .sweep import SweepResults, run_sweep, stored_sweep
    from .tables import summary_tables

    grid = {"magnitudes": args.magnitudes, "proportions": args.proportions, "nss": args.nss, "seeds": args.seeds}
    stored = None
    if args.out and (Path(args.out) / "sweep.json").exists():
        try:
            stored = stored_sweep(args.out)
        except ValueError as exc:
            parser.error(str(exc))
    resume_settings = stored is not None and not config_flags(args) and args.preset is None
    config = config_from_args(parser, args, base=stored[0] if resume_settings else None)
    _check_out(parser, args.out, "sweep")
    if args.scheduler and not _dask_installed():
        parser.error("--scheduler needs Dask, which is not installed: pip install 'sarsp_edu[dask]'")
    resume_cells = stored is not None and all(values is None for values in grid.values())
    if resume_cells:
        keys = sorted(stored[1])  # the cells the stored sweep was asked for
        print(f"resuming the sweep in {args.out}: {len(keys)} cells, preset {config.preset}"
              + (" (its stored settings)" if resume_settings else ""), file=sys.stderr)
    else:
        from .config import PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES

        defaults = {"magnitudes": PAPER_MAGNITUDES, "proportions": PAPER_PROPORTIONS, "nss": PAPER_SWITCH_STATES,
                    "seeds": (0,)}
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
    from ._io import StoredResultError, atomic_write_text
    from .sweep import SweepResults, describe_cells, stored_sweep
    from .tables import frame_to_markdown, summary_tables, tables_markdown

    if args.markdown:
        _check_file(parser, "--markdown", args.markdown)
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
    for key, frame in tables.items():
        if key == "seeds":
            continue
        print(f"\n{key}\n{_format_table(frame)}")
    sections = _beside_paper_sections(tables)
    for title, frame in sections:
        print(f"\n{title}\n{_format_table(frame)}")
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


def _beside_paper_sections(tables: dict) -> list:
    """(title, frame) pairs: the sweep's mean and Table 1 rows beside the paper's.

    The paper's Table 2 is a mean over its 45 configurations; a partial
    sweep's mean is over fewer, and the title says how many.
    """
    from . import paper
    from .config import PAPER_MAGNITUDES, PAPER_PROPORTIONS, PAPER_SWITCH_STATES
    from .tables import beside_paper, table1_beside_paper

    n = len(tables["table1"]) // 2  # a TP row and a GP row per configuration
    total = len(PAPER_MAGNITUDES) * len(PAPER_PROPORTIONS) * len(PAPER_SWITCH_STATES)
    over = (f"all {total} configurations" if n == total
            else f"the {n} configurations stored (the paper's: all {total})")
    sections = [(f"beside the paper's Table 2: mean over {over}, with each model's 95% bootstrap interval",
                 beside_paper(tables["mean"], paper.TABLE2, levels=tables["levels"]))]
    rows = table1_beside_paper(tables["table1"], paper.TABLE1)
    if len(rows):
        shown = rows.index.droplevel("metric").nunique()
        sections.append((f"beside the paper's Table 1: {shown} of its {len(paper.TABLE1)} configurations stored",
                         rows))
    return sections


def _describe(config) -> str:
    """One line: the configuration, the preset and the settings that differ from it."""
    from .config import PRESET_FIELDS, PRESETS

    text = (f"m={config.outlier_magnitude:g} p={config.outlier_proportion:g} nss={config.n_switch_states} "
            f"episodes={config.episodes} seed={config.seed}; preset {config.preset}")
    if config.preset == "custom":
        closest = min(PRESETS, key=lambda name: sum(getattr(config, k) != v for k, v in PRESETS[name].items()))
        changed = [f"{k}={getattr(config, k)!r}" for k in PRESET_FIELDS if getattr(config, k) != PRESETS[closest][k]]
        text += f" ('{closest}' with {', '.join(changed)})"
    return text


def _ablation(args, parser) -> int:
    import shlex

    from .ablation import ABLATION_SETTINGS, AblationResults, run_ablation

    if args.list:
        for name, setting in ABLATION_SETTINGS.items():
            print(f"{name}: {setting or 'the default preset'}")
        return 0
    unknown = [name for name in args.settings or () if name not in ABLATION_SETTINGS]
    if unknown:
        parser.error(f"unknown setting(s) {unknown}; 'sarsp-edu ablation --list' names them")
    settings = {name: ABLATION_SETTINGS[name] for name in (args.settings or ABLATION_SETTINGS)}
    if args.cells:
        if len(args.cells) % 3:
            parser.error(f"--cells takes m p nss triples, got {len(args.cells)} numbers")
        cells = [(args.cells[i], args.cells[i + 1], int(args.cells[i + 2])) for i in range(0, len(args.cells), 3)]
    else:
        from .config import ABLATION_CELLS as cells
    _check_out(parser, args.out, "ablation")
    if args.out:
        from pathlib import Path

        from .ablation import setting_folder

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


def _course(args, parser) -> int:
    from pathlib import Path

    from .course import execute_sources, write_handout, write_pages, write_student_notebooks

    if args.action in ("sources", "student", "pages"):
        try:
            if args.action == "sources":
                written = execute_sources(args.tutorials)
            elif args.action == "student":
                written = write_student_notebooks(args.tutorials, run=not args.no_execute)
            else:
                if args.out is None:
                    parser.error("pages needs --out DIR")
                _check_writable(parser, "--out", args.out, Path(args.out))
                written = [write_pages(args.tutorials, args.out, mathjax=args.mathjax)]
        except (FileNotFoundError, ValueError) as exc:
            parser.error(str(exc))
        for path in written:
            print(f"wrote {path}")
        return 0
    if (args.out is None) == (args.zip is None):
        parser.error("handout needs --out DIR or --zip FILE")
    if args.out is not None:
        _check_out(parser, args.out, "handout")
    else:
        _check_file(parser, "--zip", args.zip)
    try:
        made = write_handout(args.root, out=args.out, zip_path=args.zip)
    except (FileNotFoundError, ValueError) as exc:
        parser.error(str(exc))
    print(f"the students' copy of the course (no sources, no solutions) is in {made}")
    return 0


def _info(args, parser) -> int:
    from .config import PRESET_DOCS, PRESETS

    print(f"sarsp_edu {__version__}")
    print(f"python {platform.python_version()} ({sys.executable})")
    for name in _REPORTED:
        try:
            version = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            version = "not installed"
        print(f"{name} {version}")
    print("\npresets (sarsp-edu run|compare|sweep|ablation --preset NAME):")
    for name, values in PRESETS.items():
        print(f"  {name}: {PRESET_DOCS[name]}")
        print("    " + ", ".join(f"{k}={v!r}" for k, v in values.items()))
    return 0


def _cache(args, parser) -> int:
    from . import fitcache

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


def build_parser() -> argparse.ArgumentParser:
    from .config import (
        ABLATION_CELLS,
        ABLATION_SEEDS,
        DEFINITION_4_A,
        PAPER_MAGNITUDES,
        PAPER_PROPORTIONS,
        PAPER_SWITCH_STATES,
    )

    parser = argparse.ArgumentParser(
        prog="sarsp-edu",
        description=(
            "Safe reinforcement learning with Gaussian and Student-t processes: run the "
            "paper's experiment (SARSP, Algorithm 1) on the safe gridworld with outliers "
            "and a covariate shift."
        ),
        epilog="Run 'sarsp-edu COMMAND --help' for the settings of a command.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

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
    cmp_.add_argument("--out", metavar="DIR", help="save the two runs in DIR/tp and DIR/gp")
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
        "in DIR with its own settings and cells.",
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
        description="Read a sweep's results folder; print Table 1 (every configuration), Tables 2-4 "
        "(mean, median, mode) and a paired Wilcoxon test; with --markdown, write them all as Markdown.",
    )
    tables.add_argument("results_dir", metavar="RESULTS_DIR")
    tables.add_argument("--a", type=float, default=DEFINITION_4_A,
                        help=f"Definition 4's TSR threshold [default: {DEFINITION_4_A:g}]")
    tables.add_argument("--markdown", metavar="FILE", help="also write every table as Markdown to FILE")
    tables.add_argument("--allow-partial", action="store_true",
                        help="tabulate a sweep with cells still to run (and list them)")
    tables.add_argument("--seeds", type=int, nargs="+", metavar="SEED",
                        help="tabulate only these sweep seeds [default: every seed stored]")
    tables.set_defaults(func=_tables, parser=tables)

    ablation = sub.add_parser(
        "ablation",
        help="run the paired comparison under a list of settings and tabulate what each changes",
        description="Run the TP-vs-GP comparison of a few configurations and seeds once per setting (a preset "
        "with some fields changed) and tabulate TSR, steps, total cost, cost rate, backup share and trapped "
        "failures with 95% intervals. With --out every run is stored and a rerun resumes.",
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

    course = sub.add_parser(
        "course",
        help="run the source notebooks, make the student notebooks, static pages or a students' copy",
        description="'sources': execute the source notebooks in tutorials/source/ in place (answers in). "
        "'student': write the student notebooks tutorials/NN_*.ipynb from the sources (nbgrader's format: solution "
        "regions become '# YOUR CODE HERE', hidden tests go) and execute them. 'pages': static HTML pages of the "
        "student notebooks, dashboards' pictures included, to project with no Python running. 'handout': copy the "
        "student notebooks, the glossary and the stored results they read, never the sources, into a new folder "
        "or a zip file to hand out. Notebooks are stored without widget state, so that a reader without a "
        "kernel sees each dashboard's picture.",
    )
    course.add_argument("action", choices=["sources", "student", "pages", "handout"])
    course.add_argument("--tutorials", default="tutorials", metavar="DIR",
                        help="the tutorials folder, holding source/ [default: tutorials]")
    course.add_argument("--no-execute", action="store_true", help="student: write without executing")
    course.add_argument("--root", default=".", metavar="DIR",
                        help="handout: the repository, holding tutorials/ and results/ [default: .]")
    course.add_argument("--out", metavar="DIR", help="handout: a new or empty folder; pages: the pages' folder")
    course.add_argument("--mathjax", metavar="DIR",
                        help="pages: a MathJax 2 folder (holding MathJax.js) to copy beside the pages "
                        "[default: Debian's libjs-mathjax where installed, else a CDN]")
    course.add_argument("--zip", metavar="FILE", help="handout: a zip file")
    course.set_defaults(func=_course, parser=course)

    info = sub.add_parser("info", help="print the versions of sarsp_edu and its dependencies, and the presets")
    info.set_defaults(func=_info, parser=info)

    cache = sub.add_parser(
        "cache", help="where the live dashboards keep their fitted runs, and how much (--clear removes them)",
        description="The live dashboards keep each run they fit, so that the same settings start at once the "
                    "next time (sarsp_edu.fitcache); compare, the sweeps and the tests always fit afresh.")
    cache.add_argument("--clear", action="store_true", help="remove every stored fit")
    cache.set_defaults(func=_cache, parser=cache)
    return parser


def main(argv: list[str] | None = None) -> int:
    import warnings

    from ._io import one_line_warning

    warnings.formatwarning = one_line_warning  # a warning is one line to a terminal user
    parser = build_parser()
    args = parser.parse_args(argv)
    if not hasattr(args, "func"):
        parser.print_help()
        return 0
    try:
        return args.func(args, args.parser)
    except KeyboardInterrupt:
        print(_interrupted(args), file=sys.stderr)
        return 130  # the shell's code for a command ended by Ctrl-C
    except OSError as exc:  # a full disk, a folder made read-only meanwhile: one line, not a traceback
        print(f"sarsp-edu {args.command}: error: {exc}", file=sys.stderr)
        return 1


def _interrupted(args) -> str:
    """One line for Ctrl-C: what is saved and how to go on."""
    stored = getattr(args, "stored", None)
    if stored:
        from .sweep import finished_cells

        saved = sum(len(finished_cells(folder) & keys) for folder, keys in stored)
        total = sum(len(keys) for _, keys in stored)
        return (f"interrupted: {saved} of {total} cells are saved in {args.out}; "
                "rerun the same command to resume")
    if args.command in ("sweep", "ablation"):
        return "interrupted: nothing was saved (with --out DIR finished cells are kept, and a rerun resumes)"
    if args.command in ("run", "compare"):
        return "interrupted: nothing was saved (a run is saved only when it has finished)"
    return "interrupted"


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
