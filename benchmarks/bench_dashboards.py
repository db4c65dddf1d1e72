"""Each dashboard's update time for a slider move (compute + redraw of the
panels that depend on the slider, median of repeats; target < 200 ms), and
the live agent dashboard's frame rate (paired step + SVG drawing; target
>= 20 steps per second displayed).

Run by hand:  python benchmarks/bench_dashboards.py [--repeats 9]
The rate a browser actually displays is measured by tests/test_browser.py.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
import matplotlib  # noqa: E402
from _timing import one_core  # noqa: E402

matplotlib.use("Agg")

from sarsp_edu.teaching.dashboards.tutorials import (  # noqa: E402
    agent_dashboard,
    gridworld_dashboard,
    posterior_dashboard,
    tail_decay_dashboard,
)

MOVES = {
    "tail_decay_dashboard": [("nu", (3.0, 3.5)), ("lam", (5.0, 5.5))],
    "posterior_dashboard": [("nu", (3.0, 4.0)), ("magnitude", (10.0, 20.0)), ("proportion", (0.1, 0.2))],
    "gridworld_dashboard": [("n_switch_states", (6, 7)), ("magnitude", (40.0, 60.0)),
                            ("proportion", (0.2, 0.3)), ("seed", (0, 1))],
}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args(argv)
    print(f"slider move = compute + redraw, median of {args.repeats}; one BLAS thread; target < 200 ms")
    for factory in (tail_decay_dashboard, posterior_dashboard, gridworld_dashboard):
        dashboard = factory()
        for name, (a, b) in MOVES[factory.__name__]:
            times = []
            for i in range(args.repeats):
                dashboard.controls[name].value = b if i % 2 == 0 else a
                times.append(dashboard.last_update_seconds)
            note = "  (the first visit of a seed collects 100 offline episodes; later visits are cached)" \
                if name == "seed" else ""
            redrawn = f"{len(dashboard.last_redrawn)} of {len(dashboard.panels)} panels"
            print(f"  {factory.__name__:22s} {name:16s} {redrawn:14s} {statistics.median(times) * 1e3:7.1f} ms{note}")

    live = agent_dashboard(fit_ahead=False)  # slider moves alone: no fits begun in the background
    for name, (a, b) in (("n_switch_states", (2, 9)), ("proportion", (0.2, 0.4)), ("magnitude", (40, 80))):
        times = []
        for i in range(args.repeats):
            live.controls[name].value = b if i % 2 == 0 else a
            times.append(live.last_preview_seconds)
        live.controls[name].value = a  # the paper's settings again for the timing below
        print(f"  {'agent_dashboard':22s} {name:16s} {'world preview':14s} {statistics.median(times) * 1e3:7.1f} ms"
              "  (target < 1 s: the world, shift and outliers the sliders imply)")
    live.reset()
    start = time.perf_counter()
    live.build_runs()
    prepare = time.perf_counter() - start
    live.run_steps(5)
    start = time.perf_counter()
    live.run_steps(300)
    elapsed = time.perf_counter() - start
    print(f"live agent dashboard, paper's settings: preparation (data, outliers, 4 fits) {prepare:.1f} s; "
          f"300 paired steps drawn in {elapsed:.2f} s = {300 / elapsed:.1f} steps per second "
          f"(the animation runs at its speed slider, default 30)")
    # Fitted ahead: the fits begin when the dashboard is made; each side can start once its own are done.
    start = time.perf_counter()
    ahead = agent_dashboard()
    made = time.perf_counter() - start
    fits = ahead.run.fits.claim(ahead.config())
    ready = []
    for name in ahead.sides:
        fits.wait_for(name)
        ready.append(f"{name.upper()} ready {time.perf_counter() - start:.1f} s")
    print(f"fitted ahead: dashboard made in {made:.2f} s, then {', '.join(ready)} after it was made "
          "(the first agent moves at the first of these, or at once if Run comes later)")


if __name__ == "__main__":
    with one_core():
        main()
