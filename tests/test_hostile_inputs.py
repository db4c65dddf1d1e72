"""A hostile user's inputs: each gets a one-line error naming what is wrong and how to fix it, or the right result."""

from __future__ import annotations

import json
import re
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

from sarsp_edu import ExperimentConfig, compare, run_experiment, run_sweep
from sarsp_edu.cli import main

from .test_cli import _usage_error as usage_error
from .worlds import FIVE_BY_FIVE


def test_exact_and_numpy_numbers_in_a_config_are_plain_numbers_that_save_as_json():
    config = ExperimentConfig(outlier_magnitude=Decimal("40"), nu=Fraction(7, 2), episodes=np.int64(3))
    assert (config.outlier_magnitude, config.nu, config.episodes) == (40.0, 3.5, 3)
    assert type(config.outlier_magnitude) is float and type(config.episodes) is int
    json.dumps(config.to_dict())  # what save() writes
    with pytest.raises(ValueError, match=r"episodes must be an integer from 1 to 100000 .*got episodes=3.5"):
        ExperimentConfig(episodes=Fraction(7, 2))


@pytest.mark.parametrize("function", [compare, run_experiment, run_sweep])
def test_a_config_of_the_wrong_type_is_named_with_the_type_expected(function):
    with pytest.raises(TypeError, match=r"config must be an ExperimentConfig, got dict; make one with "
                                        r"ExperimentConfig\(\*\*settings\)"):
        function({"episodes": 1})


TINY = ExperimentConfig(**FIVE_BY_FIVE, episodes=2)


def test_a_thousand_jobs_for_one_cell_start_one_worker_and_say_so():
    with pytest.warns(UserWarning, match=r"n_jobs=1000: running 1 worker process, for 1 cell to run on \d+ cores? "
                                         r"\(more would only wait\)"):
        results = run_sweep(TINY, magnitudes=(40,), proportions=(0.2,), n_switch_states=(1,), n_jobs=1000)
    assert len(results) == 1


def test_the_registered_world_takes_the_configs_bounds():
    import gymnasium

    import sarsp_edu  # noqa: F401  (registers the environment)

    with pytest.raises(ValueError, match=r"size must be an integer from 2 to 50 .* got size=1000000"):
        gymnasium.make("sarsp_edu/SafeGridWorld-v0", size=10**6)


@pytest.mark.parametrize("start", [(1.7, 2.2), "12", (True, False), (1, 2, 3), (1,), None])
def test_a_start_that_is_not_a_pair_of_integers_is_refused(start):
    from sarsp_edu.world.gridworld import SafeGridWorld

    env = SafeGridWorld(seed=0)
    with pytest.raises(ValueError, match=r"start must be a pair of integers \(x, y\), got start="):
        env.reset(options={"start": start})


@pytest.mark.parametrize("scale", [1e150, 1e76, 1e-300])
def test_targets_whose_squares_overflow_are_named_with_their_scale(scale):
    from sarsp_edu import GaussianProcess, StudentTProcess

    X = np.linspace(0, 5, 20)[:, None]
    y = np.sin(X[:, 0])
    for model in (GaussianProcess(), StudentTProcess()):
        if scale > 1:
            shown = re.escape(f"{scale:.3g}")
            with pytest.raises(ValueError, match=rf"y holds values as large as {shown}, beyond 1e\+75: their "
                                                 r"squares \(and the fit's squared gradients\) overflow float64; "
                                                 r"rescale y"):
                model.fit(X, scale * y / np.abs(y).max())
        else:  # tiny targets are fitted as they are: no error, no NaN
            assert np.isfinite(model.fit(X, scale * y).predict(X)).all()


SMALL_RUN = ["--episodes", "1", "--grid-size", "5", "--n-unsafe", "3", "--offline-episodes", "5", "--quiet"]


def _cli(*args, **kwargs):
    import os
    import subprocess
    import sys

    env = {**os.environ, **kwargs.pop("env", {})}
    return subprocess.run([sys.executable, "-m", "sarsp_edu.cli", *args], capture_output=True, text=True, env=env,
                          **kwargs)


def test_a_path_the_terminal_cannot_encode_is_escaped_after_the_save(tmp_path):
    out = tmp_path / "日本"
    done = _cli("run", *SMALL_RUN, "--out", str(out), env={"PYTHONIOENCODING": "ascii"})
    assert done.returncode == 0, done.stderr
    assert "saved to " in done.stdout and "\\u65e5\\u672c" in done.stdout and "Traceback" not in done.stderr
    assert (out / "result.json").is_file()


def test_a_reader_that_leaves_early_ends_the_command_quietly():
    import subprocess
    import sys
    from pathlib import Path

    folder = Path(__file__).resolve().parents[1] / "results" / "sweep-reduced"
    process = subprocess.Popen([sys.executable, "-m", "sarsp_edu.cli", "tables", str(folder)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    process.stdout.readline()
    process.stdout.close()  # 'tables ... | head -1'
    err = process.stderr.read().decode()
    assert process.wait(timeout=120) == 141
    assert "Broken pipe" not in err and "Traceback" not in err


def test_an_ablation_cell_with_a_fractional_nss_is_refused(capsys):
    err = usage_error(["ablation", "--cells", "40", "0.2", "2.7", "--episodes", "1"], capsys)
    assert err.endswith("--cells: each triple's third number, nss, must be a whole number of switch states, got 2.7")


def test_a_sweep_resumed_with_one_grid_flag_takes_the_others_from_the_stored_sweep(tmp_path):
    out = tmp_path / "sweep"
    assert main(["sweep", *SMALL_RUN, "--m", "40", "--p", "0.2", "--nss", "1", "--out", str(out)]) == 0
    assert main(["sweep", *SMALL_RUN, "--nss", "2", "--out", str(out)]) == 0
    cells = sorted(p.name for p in (out / "cells").iterdir())
    assert cells == ["m40_p0.2_nss1_seed0", "m40_p0.2_nss2_seed0"], cells  # not the paper's 3 x 3 x 1 grid


def test_a_dangling_or_looping_symlink_as_out_is_named_as_such(tmp_path, capsys):
    dangling, looping = tmp_path / "dangling", tmp_path / "looping"
    dangling.symlink_to(tmp_path / "nowhere")
    looping.symlink_to(looping)
    err = usage_error(["run", *SMALL_RUN, "--out", str(dangling)], capsys)
    assert err.endswith(f"is a symbolic link to {tmp_path / 'nowhere'}, which does not exist; make that folder or "
                        "remove the link")
    err = usage_error(["compare", *SMALL_RUN, "--out", str(looping / "sub")], capsys)
    assert err.endswith(f"cannot be made: {looping} is a symbolic link that loops")


@pytest.fixture
def sweep_copy(tmp_path):
    import shutil
    from pathlib import Path

    folder = tmp_path / "s"
    shutil.copytree(Path(__file__).resolve().parents[1] / "results" / "sweep-reduced", folder)
    return folder


def test_stored_json_nested_deep_or_holding_huge_numbers_or_wrong_types_is_named(sweep_copy, capsys):
    (sweep_copy / "sweep.json").write_text("[" * 100_000 + "]" * 100_000)
    assert usage_error(["tables", str(sweep_copy)], capsys).endswith(
        "sweep.json cannot be read: it nests lists or objects thousands deep, as no stored result does; restore it")


@pytest.mark.parametrize("edit, message", [
    (lambda text: json.dumps({**json.loads(text), "code": [1, 2]}),
     r"tp/result.json holds code=\[1, 2\], where a result stores an object \(names and values\); it was edited"),
    (lambda text: re.sub(r'"seed": \d+', '"seed": ' + "9" * 5000, text, count=1),
     r"tp/result.json cannot be read \(Exceeds the limit \(4300 digits\).*\); no stored result holds such a number"),
])
def test_a_result_json_with_a_wrong_type_or_a_huge_number_is_named(sweep_copy, capsys, edit, message):
    result = next((sweep_copy / "cells").glob("*/tp/result.json"))
    result.write_text(edit(result.read_text()))
    assert re.search(message, usage_error(["tables", str(sweep_copy)], capsys))


def test_info_lists_every_declared_dependency(capsys):
    import importlib.metadata

    assert main(["info"]) == 0
    out = capsys.readouterr().out
    for name in ("scikit-learn", "threadpoolctl", "gymnasium", "numpy"):
        assert f"\n{name} {importlib.metadata.version(name)}" in out
    assert "(extra [dask])" in out


def test_the_ablation_takes_a_stored_folders_name_for_its_setting(tmp_path):
    out = tmp_path / "ablation"
    assert main(["ablation", "--settings", "default-k-400", "--cells", "40", "0.2", "1", "--seeds", "0",
                 "--episodes", "1", "--quiet", "--out", str(out)]) == 0
    assert [p.name for p in out.iterdir() if p.is_dir()] == ["default-k-400"]


def test_a_run_shows_its_fits_progress_before_its_episodes_and_compare_shows_both_models():
    done = _cli("run", *SMALL_RUN[:-1])
    assert done.returncode == 0, done.stderr
    assert "TP: fitting the cost model (" in done.stderr and "TP episodes" in done.stderr
    assert done.stderr.index("TP: fitting") < done.stderr.index("TP episodes")
    done = _cli("compare", *SMALL_RUN[:-1], "--jobs", "2")
    assert done.returncode == 0, done.stderr
    for model in ("TP", "GP"):
        assert f"{model}: fitting the cost model (" in done.stderr and f"{model} episodes" in done.stderr


# -- the second hostile pass's findings ------------------------------------------------------------------------
def test_tables_never_write_markdown_into_the_results_they_read(sweep_copy, capsys):
    before = (sweep_copy / "sweep.json").read_bytes()
    err = usage_error(["tables", str(sweep_copy), "--markdown", str(sweep_copy / "sweep.json")], capsys)
    assert err.endswith(f"lies inside the results folder {sweep_copy}, whose files it could replace; write the "
                        "tables outside it")
    assert (sweep_copy / "sweep.json").read_bytes() == before


@pytest.mark.parametrize("kind", ["fifo", "device", "folder"])
def test_a_pipe_device_or_folder_in_a_stored_files_place_is_never_read(sweep_copy, capsys, kind):
    import os

    target = next((sweep_copy / "cells").glob("*/tp/result.json")) if kind != "folder" else \
        next((sweep_copy / "cells").glob("*/gp/records.csv"))
    target.unlink()
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "device":
        target.symlink_to("/dev/zero")
    else:
        target.mkdir()
    err = usage_error(["tables", str(sweep_copy)], capsys)  # returns: nothing hangs or fills the memory
    assert "is not a regular file (a folder, a device or a pipe in a stored file's place)" in err


@pytest.mark.parametrize("edit, message", [
    (lambda p: p.pop("settings"), r"ablation.json lacks"),
    (lambda p: p.update(settings=[1, 2]), r"holds settings=\[1, 2\], not a mapping"),
    (lambda p: next(iter(p["settings"].values())).pop("changes"), r"where an ablation stores its changes"),
    (lambda p: next(iter(p["settings"].values())).update(folder="../../sweep-reduced"),
     r"where an ablation stores its changes and its folder"),
])
def test_a_damaged_ablation_json_is_named_not_followed(tmp_path, capsys, edit, message):
    import shutil
    from pathlib import Path

    folder = tmp_path / "ablation"
    shutil.copytree(Path(__file__).resolve().parents[1] / "results" / "ablation", folder)
    payload = json.loads((folder / "ablation.json").read_text())
    edit(payload)
    (folder / "ablation.json").write_text(json.dumps(payload))
    assert re.search(message, usage_error(["tables", str(folder)], capsys))


def test_two_cells_that_would_share_a_folder_or_a_seed_are_refused_before_any_work(capsys):
    with pytest.raises(ValueError, match=r"the cells m=40.0 p=0.2 and m=40.0000001 p=0.2 \(nss=1\) would share the "
                                         r"folder m40_p0.2_nss1_seed0 or one run seed"):
        run_sweep(TINY, magnitudes=(40, 40.0000001), proportions=(0.2,), n_switch_states=(1,))


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.loc.__setitem__((0, "start"), "0 0"), r"tp/ and gp/ differ in episode 1's start"),
    (lambda t: t.loc.__setitem__((0, "start"), "\u00b2 3"), r"has start='\u00b2 3' in episode 1, not a cell 'x y'"),
])
def test_unpaired_or_unreadable_cells_are_named(sweep_copy, capsys, edit, message):
    import pandas as pd

    records = next((sweep_copy / "cells").glob("*/gp/records.csv"))
    table = pd.read_csv(records)
    if (table.loc[0, "start"] == "0 0") and "differ" in message:
        pytest.skip("the stored start is already 0 0")
    edit(table)
    table.to_csv(records, index=False)
    assert re.search(message, usage_error(["tables", str(sweep_copy)], capsys))


def test_the_cache_fingerprint_does_not_depend_on_what_was_imported_first():
    import subprocess
    import sys

    code = ("from sarsp_edu.teaching.live import fitcache; first = fitcache.fingerprint();"
            " import sklearn, sarsp_edu.experiments.experiment;"
            " fitcache.fingerprint.cache_clear(); print(first == fitcache.fingerprint())")
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip() == "True"


def test_a_sweep_json_without_its_requested_cells_is_refused_when_its_version_always_writes_them(sweep_copy, capsys):
    payload = json.loads((sweep_copy / "sweep.json").read_text())
    payload.pop("requested", None)
    payload["sarsp_edu_version"] = "0.2.1"
    (sweep_copy / "sweep.json").write_text(json.dumps(payload))
    assert "lacks 'requested' (the cells the sweep was asked for), which sarsp_edu 0.2.1 always writes" in \
        usage_error(["tables", str(sweep_copy)], capsys)


def test_a_partial_ablation_says_so(tmp_path, capsys):
    import shutil
    from pathlib import Path

    folder = tmp_path / "ablation"
    shutil.copytree(Path(__file__).resolve().parents[1] / "results" / "ablation", folder)
    shutil.rmtree(next((folder / "default-k-400" / "cells").iterdir()))
    assert main(["tables", str(folder)]) == 0
    assert "partial: 1 setting(s) hold fewer than the 6 runs the ablation plans (default, k=400)" in \
        capsys.readouterr().out


def test_a_proportion_of_minus_zero_is_the_cell_p_0_and_resumes_as_it(tmp_path, capsys):
    out = tmp_path / "sweep"
    grid = ["--m", "40", "--nss", "2", "--seeds", "0", "--out", str(out), *SMALL_RUN]
    assert main(["sweep", "--p=-0.0", *grid]) == 0
    assert main(["sweep", "--p", "0", *grid]) == 0  # resumes: the same cell, not a second copy
    assert sorted(path.name for path in (out / "cells").iterdir()) == ["m40_p0_nss2_seed0"]  # was also ..._p-0_...
