"""Small dense solves with the machine's default BLAS threads against one thread (what a
run uses: :mod:`mechdyn.simulate.threads`), in one run.

    python benchmarks/blas_threads.py [--repeats 200]

``np.linalg.solve`` of n x n systems (n = 10, 30, 100, 300: the sizes of the mass and
iteration matrices of mechdyn's models), timed with BLAS at its default thread count and
inside ``single_threaded_blas()``, interleaved: the minimum and the median over the
repeats (oversubscription shows in the median: threads that wait for busy cores).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from mechdyn.simulate.threads import single_threaded_blas  # noqa: E402


def solve_time(a, b):
    started = time.perf_counter()
    np.linalg.solve(a, b)
    return time.perf_counter() - started


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=200)
    args = parser.parse_args(argv)
    from threadpoolctl import threadpool_info
    threads = sorted({lib["num_threads"] for lib in threadpool_info()
                      if lib["user_api"] == "blas"})
    rng = np.random.default_rng(1)
    print(f"BLAS default threads: {threads}\n\n| n | default threads ms, min / median | "
          "one thread ms, min / median | median ratio |\n|---|---|---|---|")
    for n in (10, 30, 100, 300):
        a, b = rng.standard_normal((n, n)) + n * np.eye(n), rng.standard_normal(n)
        default, single = [], []
        for _ in range(args.repeats):
            default.append(solve_time(a, b))
            with single_threaded_blas():
                single.append(solve_time(a, b))
        print(f"| {n} | {min(default) * 1e3:.3f} / {np.median(default) * 1e3:.3f} | "
              f"{min(single) * 1e3:.3f} / {np.median(single) * 1e3:.3f} | "
              f"{np.median(default) / np.median(single):.1f}x |")


if __name__ == "__main__":
    main()
