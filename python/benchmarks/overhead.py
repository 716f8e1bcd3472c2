"""Overhead of the Python layer against the `spraysim` command, on the default scene.

Times whole processes (start-up, run, outputs), the median of --repeats runs of each, after
one untimed warm-up of each:

    command:  spraysim run -q -j THREADS -o DIR
    python:   python -c "import spraysim; s = spraysim.Simulation(threads=THREADS);
              s.run(); s.write_outputs(DIR)"

and, inside one Python process, `Simulation.run()` alone (no start-up, no outputs).

    python python/benchmarks/overhead.py [--cli target/release/spraysim] [--repeats 5] [--threads 2]
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[2]


def timed(args, cwd):
    start = time.perf_counter()
    subprocess.run(args, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", default=str(REPO / "target" / "release" / "spraysim"))
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    a = parser.parse_args()
    code = (
        "import spraysim; s = spraysim.Simulation(threads={t}); s.run(); s.write_outputs('out')"
    ).format(t=a.threads)
    runs = {
        "spraysim run (command)": [a.cli, "run", "-q", "-j", str(a.threads), "-o", "out"],
        "Python: Simulation().run(); write_outputs()": [sys.executable, "-c", code],
        "Python: import spraysim only": [sys.executable, "-c", "import spraysim"],
    }
    with tempfile.TemporaryDirectory() as tmp:
        times = {name: [] for name in runs}
        for name, args in runs.items():
            timed(args, tmp)  # warm-up: page cache, first-run costs
        for _ in range(a.repeats):  # interleaved, so that load changes hit both alike
            for name, args in runs.items():
                times[name].append(timed(args, tmp))
        # In-process: the run alone, without start-up or outputs.
        import spraysim

        inproc = []
        for _ in range(a.repeats):
            sim = spraysim.Simulation(threads=a.threads)
            start = time.perf_counter()
            sim.run()
            inproc.append(time.perf_counter() - start)
    load = ", load average before: %.2f" % os.getloadavg()[0] if hasattr(os, "getloadavg") else ""
    print(f"default scene, {a.threads} threads, median of {a.repeats} (min–max), wall seconds{load}")
    print(f"{'what':<48}{'median':>8}{'min':>8}{'max':>8}")
    for name, t in times.items():
        print(f"{name:<48}{statistics.median(t):>8.3f}{min(t):>8.3f}{max(t):>8.3f}")
    name = "Python, in process: Simulation.run() alone"
    print(f"{name:<48}{statistics.median(inproc):>8.3f}{min(inproc):>8.3f}{max(inproc):>8.3f}")
    cli = statistics.median(times["spraysim run (command)"])
    py = statistics.median(times["Python: Simulation().run(); write_outputs()"])
    print(f"Python layer overhead, whole process: {py - cli:+.3f} s ({100 * (py - cli) / cli:+.1f} %)")


if __name__ == "__main__":
    sys.exit(main())
