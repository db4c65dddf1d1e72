"""The tutorials' stored outputs hold whatever BLAS does underneath.

nbval runs the source notebooks with one BLAS thread and the students' copies with BLAS's
default (one thread per core), each against the same stored digits: tests/blas_threads.py
says why, and the root conftest.py applies it.  These tests check that arrangement itself:
which notebooks get one thread, and that the limit reaches the kernel and stays silent.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import nbformat
import pytest
from nbval.kernel import CURRENT_ENV_KERNEL_NAME, RunningKernel

from tests.blas_threads import limit_kernel, runs_with_one_blas_thread

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted((ROOT / "tutorials" / "source").glob("*.ipynb"))
STUDENTS = sorted((ROOT / "tutorials").glob("[0-9][0-9]_*.ipynb"))  # the tutorials, not live_dashboard.ipynb

BLAS_THREADS = ("import numpy, scipy.linalg\nfrom threadpoolctl import threadpool_info\n"
                "print(sorted((i['filepath'].rsplit('/', 1)[-1], i['num_threads'])\n"
                "             for i in threadpool_info() if i['user_api'] == 'blas'))")


def test_the_sources_get_one_blas_thread_and_the_students_copies_the_default():
    assert len(SOURCES) == len(STUDENTS) == 7
    assert all(runs_with_one_blas_thread(p) for p in SOURCES)
    assert not any(runs_with_one_blas_thread(p) for p in STUDENTS)
    # the two copies run the same numeric cells: each source has its student copy
    assert [p.name for p in SOURCES] == [p.name for p in STUDENTS]


def run(kernel, code: str) -> list:
    """The outputs a cell of ``code`` gives in a running nbval kernel (stream text and errors)."""
    msg_id = kernel.execute_cell_input(code, allow_stdin=False)
    kernel.await_reply(msg_id, timeout=60)
    texts = []
    while True:
        msg = kernel.get_message(stream="iopub", timeout=60)
        if msg["parent_header"].get("msg_id") != msg_id:
            texts.append(("other request", msg["msg_type"]))
            continue
        if msg["msg_type"] == "status" and msg["content"]["execution_state"] == "idle":
            return texts
        if msg["msg_type"] in ("stream", "error", "execute_result", "display_data"):
            texts.append(msg["content"].get("text") or msg["content"].get("ename") or msg["content"].get("data"))


def test_the_limit_reaches_the_kernel_silently(tmp_path):
    kernel = RunningKernel(CURRENT_ENV_KERNEL_NAME, cwd=str(tmp_path))
    try:
        before = run(kernel, BLAS_THREADS)
        limit_kernel(kernel)
        after = run(kernel, BLAS_THREADS)
        again = run(kernel, "print(1 + 1)")
    finally:
        kernel.stop()
    libraries = ast.literal_eval(before[0])  # [(library, threads)]: numpy's OpenBLAS and scipy's
    assert len(libraries) >= 2, before
    # every BLAS library at one thread, and no message of the limit's own request left over
    assert after == [repr([(library, 1) for library, _ in libraries]) + "\n"], (before, after)
    assert again == ["2\n"], again


@pytest.mark.parametrize("notebook", SOURCES, ids=lambda p: p.name)
def test_no_notebook_sets_blas_threads_through_the_environment(notebook):
    """An environment variable would reach every kernel nbval starts and mask the difference."""
    names = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
    cells = nbformat.read(notebook, as_version=4).cells
    assert not [c.source for c in cells if c.cell_type == "code" and any(n in c.source for n in names)]
    assert not any(name in os.environ for name in names), "the test run itself must keep BLAS's default"
