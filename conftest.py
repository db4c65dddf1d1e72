"""Settings for the whole test run (tests, doctests and the notebooks under nbval).

The kernels nbval starts inherit this process's environment: Tutorial 4's
live dashboard then shows its world without starting the agents by itself
(``autoplay``), as nobody watches a batch run.  The browser test that
measures autoplay turns it back on for the server it starts.  The live
dashboards' cache of fitted runs (``sarsp_edu.teaching.live.fitcache``) is off, so that
no test depends on what an earlier one fitted; the tests of the cache give
it a folder of their own.
"""

import os
from pathlib import Path

os.environ["SARSP_EDU_AUTOPLAY"] = "0"
os.environ["SARSP_EDU_CACHE"] = "off"


import pytest  # noqa: E402

try:  # the notebook plugin: installed with the test extra; the units run without it
    from nbval.plugin import IPyNbFile
except ImportError:  # pragma: no cover
    IPyNbFile = None

ROOT = Path(__file__).parent

#: test modules of the slow tier: whole runs and sweeps, worker processes, servers and browsers (a fast module
#: marks its few slow tests itself, ``@pytest.mark.slow``)
SLOW_MODULES = {
    "test_ablation", "test_accessibility", "test_binder", "test_browser", "test_browser_live", "test_capstone",
    "test_cli", "test_cli_fuzz", "test_course", "test_dashboards", "test_experiment", "test_exercises",
    "test_audit", "test_fitcache", "test_hostile_inputs", "test_likelihood_agent", "test_live_fitting",
    "test_live_run",
    "test_notebook_threads", "test_outputs", "test_pages", "test_prose", "test_stored_results", "test_sweep",
}


def pytest_configure(config):
    """nbval on, on the tutorials, with the package's settings: unless nbval is missing or switched off."""
    option = config.option
    if IPyNbFile is None or not hasattr(option, "nbval") or option.nbval_lax:
        return
    option.nbval = True
    option.nbval_current_env = True
    if option.nbval_sanitize_with is None:
        option.nbval_sanitize_with = str(ROOT / "tutorials" / "nbval_sanitize.cfg")


# nbval runs the source notebooks with one BLAS thread and the students' copies with BLAS's
# default; both are compared with the same stored digits (tests/blas_threads.py says why).
from tests import binder_build  # noqa: E402
from tests.blas_threads import limit_kernel, runs_with_one_blas_thread  # noqa: E402


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    if IPyNbFile is None:
        yield
        return
    if (isinstance(item.parent, IPyNbFile) and getattr(item.config, "_binder_test_last", False)
            and not os.environ.get("PYTEST_XDIST_WORKER")):  # under xdist the test builds it (binder_build.py)
        binder_build.start()  # once: in a thread, while nbval runs the tutorials
    yield  # the notebook's kernel is started by the first cell's setup
    notebook = item.parent
    if (isinstance(notebook, IPyNbFile) and notebook.kernel is not None
            and not getattr(notebook, "_one_blas_thread", False)
            and runs_with_one_blas_thread(Path(str(notebook.fspath)))):
        limit_kernel(notebook.kernel)
        notebook._one_blas_thread = True


# The Binder test's environment is built in a thread while nbval runs the tutorials, and the test
# that uses it runs last (tests/binder_build.py says why).
BINDER_TEST = "test_binder_environment_imports_every_tutorial_and_runs_the_first"


def pytest_itemcollected(item):
    """The tiers (before -m selects): notebooks, browsers and Binder are slow, so are the modules of SLOW_MODULES."""
    path = Path(str(item.fspath))
    kinds = []
    if path.suffix == ".ipynb":
        kinds = ["notebook", "slow"]
    elif path.stem in ("test_browser", "test_browser_live"):
        kinds = ["browser", "slow", "serial"]
    elif path.stem == "test_binder":
        kinds = ["binder", "slow"]
    elif path.stem in SLOW_MODULES:
        kinds = ["slow"]
    for kind in kinds:
        item.add_marker(kind)


@pytest.hookimpl(trylast=True)  # after -k and -m have deselected
def pytest_collection_modifyitems(config, items):
    last = [item for item in items if item.name == BINDER_TEST]
    if last:
        items[:] = [item for item in items if item.name != BINDER_TEST] + last
        config._binder_test_last = True


def pytest_sessionfinish(session):
    binder_build.clean_up()
