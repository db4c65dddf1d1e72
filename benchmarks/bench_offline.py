"""Time the offline phase's data: 100 random-policy episodes on the paper's
10x10 world, then outlier injection (m = 80, p = 0.4), median of repeats.

Run by hand:  python benchmarks/bench_offline.py [--repeats 7]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))
from _timing import one_core  # noqa: E402

from sarsp_edu import SafeGridWorld, collect_offline_data, inject_outliers  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    collect, inject = [], []
    for seed in range(args.repeats):
        env = SafeGridWorld(seed=seed)
        t0 = time.perf_counter()
        data = collect_offline_data(env, episodes=100, rng=seed)
        t1 = time.perf_counter()
        inject_outliers(data, 80, 0.4, rng=seed)
        t2 = time.perf_counter()
        collect.append(t1 - t0)
        inject.append(t2 - t1)
    collect.sort()
    inject.sort()
    total = sorted(c + i for c, i in zip(collect, inject))
    mid = args.repeats // 2
    print(f"100 offline episodes + outlier injection, one core, median of {args.repeats}")
    print(f"  collect  : {collect[mid] * 1e3:7.1f} ms  ({data.transitions} transitions; "
          f"buffers {len(data.cost)} cost, {len(data.reward)} reward)")
    print(f"  inject   : {inject[mid] * 1e3:7.1f} ms")
    print(f"  total    : {total[mid] * 1e3:7.1f} ms  (target < 1000 ms)")


if __name__ == "__main__":
    with one_core():
        main()
