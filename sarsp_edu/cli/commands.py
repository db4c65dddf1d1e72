"""What each ``sarsp-edu`` command does once its arguments are checked: one function per command."""

from __future__ import annotations

import contextlib
import importlib.metadata
import os
import platform
import sys

from .._version import __version__
from .arguments import _MARKERS, check_out, check_writable, config_flags, config_from_args, results_of


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
    from ..experiments.experiment import run_experiment
    from ..experiments.metrics import SUMMARY_METRICS, backup_share, displayed_summary

    config = config_from_args(parser, args)
    check_out(parser, args.out, "run", config, args.overwrite)
    with _out_lock(parser, args.out, "run"):
        result = run_experiment(config, progress=not args.quiet)
        if args.out:
            saved = result.save(args.out)
    import pandas as pd

    table = pd.DataFrame({config.model.upper(): displayed_summary(result.summary)}).loc[list(SUMMARY_METRICS)]
    from ..config import MODEL_TITLES

    if len(config.model_kinds) == 1:
        models = f"cost and reward model: {MODEL_TITLES[config.model]}"
    else:
        models = f"cost model: {MODEL_TITLES[config.model]}, reward model: {MODEL_TITLES[config.reward_model]}"
    print(f"SARSP, {models}, {_describe(config)}")
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

    from .._internal.io import lock_folder
    from ..experiments.sweep import LOCK_NAME

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
    from ..experiments.experiment import compare

    config = config_from_args(parser, args)
    if args.models is not None and args.models != ["tp", "gp"]:
        return _compare_models(args, parser, config)
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


def _compare_models(args, parser, config) -> int:
    """``compare --models ...``: several models paired, their summaries and Definition 4 for each pair."""
    from pathlib import Path

    from ..experiments.comparison import compare_models

    if len(set(args.models)) != len(args.models) or len(args.models) < 2:
        parser.error(f"--models takes two or more distinct models, got {' '.join(args.models)}")
    if args.jobs is not None:
        parser.error("--jobs runs the GP beside the TP of the default pair; with --models the runs are made one "
                     "after the other: leave --jobs out")
    if args.out:
        check_writable(parser, "--out", args.out, Path(args.out))
        kind = next((k for k, marker in _MARKERS.items() if k != "compare" and (Path(args.out) / marker).exists()),
                    None)
        if kind:
            parser.error(f"--out {args.out} holds {results_of(kind)}; 'compare' writes into a new folder, an empty "
                         "one or one holding a comparison's results")
        held = [model for model in args.models if (Path(args.out) / model / "result.json").exists()]
        if held and not args.overwrite:
            parser.error(f"--out {args.out} holds runs of {', '.join(held)} already; to keep them, give another "
                         "folder; to replace them, add --overwrite")
    with _out_lock(parser, args.out, "compare"):
        try:
            comparison = compare_models(config, args.models, progress=not args.quiet, a=args.a)
        except ValueError as exc:
            parser.error(str(exc))
        if args.out:
            saved = comparison.save(args.out)
    print(f"{' vs '.join(args.models)}, paired: {_describe(config)}")
    print(_format_table(comparison.table()))
    print(f"Definition 4 (a={args.a:g}) for each pair:\n{comparison.verdicts().to_string()}")
    if args.out:
        print(f"saved to {saved}")
    return 0


def _sweep(args, parser) -> int:
    import shlex
    from pathlib import Path

    from ..experiments.sweep import CellsFailed, SweepResults, run_sweep, stored_sweep
    from ..experiments.sweep.failures import collecting
    from ..experiments.tables import summary_tables

    grid = {"magnitudes": args.magnitudes, "proportions": args.proportions, "nss": args.nss, "seeds": args.seeds}
    stored = None
    if args.out and (Path(args.out) / "sweep.json").exists():
        try:
            stored = stored_sweep(args.out)
        except ValueError as exc:
            parser.error(str(exc))
    resume_settings = stored is not None and not config_flags(args) and args.preset is None
    if args.nss and getattr(args, "n_unsafe", None) is not None:
        from ..config import ExperimentConfig

        if ExperimentConfig.from_preset(args.preset or "default").n_switch_states > args.n_unsafe:
            vars(args)["n_switch_states"] = min(args.nss)  # the preset's nss does not fit; each cell sets its own
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
            with collecting(args.out) as failures:
                for seed in sorted({key[3] for key in keys}):  # a stored sweep's cells, seed by seed
                    try:
                        run_sweep(config, cells=[key[:3] for key in keys if key[3] == seed], seeds=[seed],
                                  results_dir=args.out, n_jobs=args.jobs, scheduler=args.scheduler,
                                  progress=not args.quiet, a=args.a)
                    except CellsFailed as exc:  # the other seeds still run
                        failures.update(exc.failures)
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
    except CellsFailed as exc:
        return _cells_failed(exc)
    tables = summary_tables(results)
    cells = f"{len(results)} cell{'' if len(results) == 1 else 's'}"
    print(f"{cells}, each a paired TP-vs-GP run of {config.episodes} episodes; preset {config.preset}")
    print(_format_table(tables["mean"]))
    if args.out:
        print(f"cells stored in {args.out}; print every table with: sarsp-edu tables {shlex.quote(str(args.out))}")
    return 0


def _cells_failed(exc) -> int:
    """A sweep command's end where cells raised: each traceback once, then the error (which says what ran)."""
    from ..experiments.sweep.failures import tracebacks

    print(tracebacks(exc.failures), file=sys.stderr)
    print(f"error: {exc}", file=sys.stderr)
    return 1


def _dask_installed() -> bool:
    import importlib.util

    try:
        return importlib.util.find_spec("dask.distributed") is not None
    except ModuleNotFoundError:
        return False


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


def _ablation(args, parser) -> int:
    import shlex

    from ..experiments.ablation import ABLATION_SETTINGS, AblationResults, run_ablation, setting_folder
    from ..experiments.sweep import CellsFailed

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
    except CellsFailed as exc:
        return _cells_failed(exc)
    if args.out:
        results = AblationResults.load(args.out)
    print(_format_table(results.table()))
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
    from ..teaching.live import fitcache

    try:
        directory = fitcache.cache_directory()
    except ValueError as exc:
        parser.error(str(exc))
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


def _prefit(args, parser) -> int:
    from ..config import ExperimentConfig
    from ..teaching.live import prefit
    from ..teaching.live.pick import model_sides

    try:  # the settings' own checks, as run and compare make them: one line naming the setting and its range
        for nss in args.nss:
            ExperimentConfig(nu=args.nu, outlier_magnitude=args.magnitude, outlier_proportion=args.proportion,
                             seed=args.seed, episodes=args.episodes, n_switch_states=nss)
        prefit(args.nss, nu=args.nu, magnitude=args.magnitude, proportion=args.proportion, seed=args.seed,
               episodes=args.episodes, sides=model_sides(dict.fromkeys(args.models)))
    except (RuntimeError, ValueError) as exc:  # a setting out of range, or the cache off or unusable
        parser.error(str(exc))
    return 0


def _model_sweep(args, parser) -> int:
    from .._internal.io import StoredResultError
    from ..experiments.sweep.models import CellsFailed, run_model_sweep
    from ..experiments.sweep.stored import stored_sweep

    if args.jobs is not None and args.jobs < 1 and args.jobs != -1:
        parser.error(f"--jobs takes a whole number >= 1, or -1 (one per core), got {args.jobs}")
    try:
        requested = stored_sweep(args.paired)[1]
    except (FileNotFoundError, StoredResultError) as exc:
        parser.error(f"--paired: {exc}")
    try:
        done = run_model_sweep(args.paired, args.out, model=args.model, n_jobs=args.jobs,
                               report=lambda line: print(line, flush=True))
    except CellsFailed as exc:
        return _cells_failed(exc)
    except ValueError as exc:  # --out is the paired sweep, holds another sweep, or is locked by a running one
        parser.error(str(exc).replace(f"results_dir={str(args.out)!r}", f"--out {args.out}"))
    print(f"{args.model}: {len(done)} of {len(requested)} cells stored in {args.out}")
    return 0
