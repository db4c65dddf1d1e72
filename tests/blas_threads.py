"""One BLAS thread for the source notebooks that nbval runs (the root conftest.py applies it).

A stored output is compared on other machines of the same kind, whose CPUs run other BLAS
kernels: a printed digit that is rounding noise fails CI there.  The number of BLAS threads
changes how OpenBLAS splits and orders its sums much as another CPU does, so nbval runs the
two copies of each tutorial with different thread counts against the same stored digits:

* ``tutorials/source/*.ipynb`` (with the exercises' solutions): one BLAS thread, set in the
  kernel by threadpoolctl before the first cell, never through environment variables (which
  every kernel, and this process, would inherit);
* ``tutorials/*.ipynb`` (the students' copies, the same numeric cells): BLAS's default, one
  thread per core (two on CI).

A number that differs between the two is printed with too many digits: print it to the digits
it holds (or as a bound), never sanitise a number the prose relies on.  (A third execution of
every source did this check before, at a cost of minutes of CI's fifteen; its limit was set
before numpy and scipy were imported, so it reached neither's BLAS: see :data:`LIMIT`.)
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ROOT / "tutorials" / "source"

#: run in the kernel before the notebook's first cell; the limit is kept for the kernel's life.
#: threadpoolctl limits only the libraries loaded when it is called, and numpy and scipy each
#: bring their own OpenBLAS: both are imported first, or the limit would reach neither.
LIMIT = ("import numpy, scipy.linalg\n"
         "from threadpoolctl import threadpool_limits as _sarsp_edu_limits\n"
         "_sarsp_edu_blas_limit = _sarsp_edu_limits(limits=1, user_api='blas')\n"
         "del _sarsp_edu_limits, numpy, scipy\n")


def runs_with_one_blas_thread(notebook: Path) -> bool:
    """Whether nbval runs this notebook with one BLAS thread: the sources, not the students' copies."""
    return Path(notebook).resolve().parent == SOURCES and Path(notebook).suffix == ".ipynb"


def limit_kernel(kernel, timeout: float = 60.0) -> None:
    """Run :data:`LIMIT` in a running nbval kernel (``nbval.kernel.RunningKernel``) and wait for it.

    The request is silent (no execution count, no input broadcast); nbval reads only the replies
    to its own cells' requests, so the notebook's outputs are untouched.  A failure is raised.
    """
    msg_id = kernel.kc.execute(LIMIT, silent=True, store_history=False, stop_on_error=False)
    while True:
        reply = kernel.get_message(stream="shell", timeout=timeout)
        if reply["parent_header"].get("msg_id") == msg_id:
            break
    kernel.await_idle(msg_id, timeout)
    if reply["content"]["status"] != "ok":
        raise RuntimeError(f"could not limit the kernel's BLAS threads: {reply['content']}")
