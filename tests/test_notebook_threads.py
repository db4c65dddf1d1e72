"""The tutorials' stored outputs hold whatever BLAS does underneath.

A stored output is compared (by nbval) on other machines of the same kind, whose CPUs
run other BLAS kernels: any printed digit that is rounding noise (an optimiser's end
point on a flat likelihood, a sum whose order changes) fails CI there. The number of
BLAS threads changes how OpenBLAS splits and orders its sums much as another CPU does,
so every source notebook is executed here with one BLAS thread (threadpoolctl, set in a
first cell, never through environment variables) and each printed output is compared,
after the same sanitising nbval applies, with the stored one.  The other thread count is
nbval's own run of the same sources, with BLAS's default of one thread per core (two on
CI); running them a third time with two threads cost a minute and a half of CI's fifteen.

A number that differs is printed with too many digits: print it to the digits it holds
(or as a bound), never sanitise a number the prose relies on.
"""

from __future__ import annotations

import configparser
import re
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
# The sources: the student notebooks run the same numeric cells (theirs differ only in the exercises,
# whose placeholders print one fixed line), so running both would double the time and test nothing more.
NOTEBOOKS = sorted((ROOT / "tutorials" / "source").glob("*.ipynb"))
SANITIZE = ROOT / "tutorials" / "nbval_sanitize.cfg"
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"

LIMIT_CELL = """\
from threadpoolctl import threadpool_limits
_limits = threadpool_limits(limits={threads}, user_api="blas")  # kept for the whole notebook
"""


def sanitizers() -> list[tuple[re.Pattern, str]]:
    """The regex/replace pairs of the sanitize file nbval reads (pyproject's addopts)."""
    parser = configparser.ConfigParser()
    parser.read(SANITIZE)
    return [(re.compile(parser[s]["regex"]), parser[s]["replace"]) for s in parser.sections()]


def is_skipped(cell) -> bool:
    return "NBVAL_SKIP" in cell.source or "nbval-skip" in cell.metadata.get("tags", [])


def is_checked(cell) -> bool:
    """Whether nbval compares this cell's outputs."""
    tags = cell.metadata.get("tags", [])
    return not ("NBVAL_IGNORE_OUTPUT" in cell.source or "nbval-ignore-output" in tags or is_skipped(cell))


def printed(cell, rules) -> list[str]:
    """The text nbval compares: streams and text/plain, sanitised; widget views and images left out."""
    texts = []
    for output in cell.get("outputs", []):
        kind = output.get("output_type")
        if kind == "stream":
            text = output.get("text", "")
        elif kind in ("execute_result", "display_data"):
            data = output.get("data", {})
            if WIDGET_VIEW in data:
                continue
            text = data.get("text/plain", "")
        elif kind == "error":
            text = f"{output.get('ename')}: {output.get('evalue')}"
        else:
            continue
        text = "".join(text)
        for pattern, replacement in rules:
            text = pattern.sub(replacement, text)
        texts.append(text)
    # nbval joins consecutive stream outputs; so do we
    return ["".join(texts)] if texts else []


@pytest.mark.parametrize("threads", [1])  # and nbval: the default, all cores
@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=lambda p: str(p.relative_to(ROOT / "tutorials")))
def test_printed_outputs_do_not_depend_on_blas_threads(notebook, threads):
    stored = nbformat.read(notebook, as_version=4)
    run = nbformat.read(notebook, as_version=4)
    run.cells = [c for c in run.cells if not (c.cell_type == "code" and is_skipped(c))]
    run.cells.insert(0, nbformat.v4.new_code_cell(LIMIT_CELL.format(threads=threads)))
    NotebookClient(run, timeout=600, kernel_name="python3", allow_errors=True,
                   resources={"metadata": {"path": str(notebook.parent)}}).execute()
    limit = run.cells.pop(0)
    assert not [o for o in limit.outputs if o.get("output_type") == "error"], limit.outputs

    rules = sanitizers()
    stored_code = [c for c in stored.cells if c.cell_type == "code" and not is_skipped(c)]
    run_code = [c for c in run.cells if c.cell_type == "code"]
    assert len(stored_code) == len(run_code)
    differences = []
    for index, (before, after) in enumerate(zip(stored_code, run_code)):
        if not is_checked(before):
            continue
        if printed(before, rules) != printed(after, rules):
            differences.append(f"code cell {index} ({before.source.splitlines()[0][:60]!r}):\n"
                               f"  stored: {printed(before, rules)!r}\n  {threads} thread(s): {printed(after, rules)!r}")
    assert not differences, (
        f"{notebook.name}, run with {threads} BLAS thread(s), prints other digits than its stored outputs; "
        "print these numbers only to the digits they hold:\n" + "\n".join(differences))
