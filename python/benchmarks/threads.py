"""Speed-up from releasing the interpreter: two simulations in two Python threads, and
run_many on two worker threads, against the same runs one after the other.

    python python/benchmarks/threads.py [--duration 1.0] [--repeats 3]

Each simulation runs single-threaded (threads=1), so any speed-up comes from the two Python
threads (or run_many's workers) running at once. On a machine shared with other work the
figure drops towards 1; the CPU time the process used per wall second (near 2 when two
threads work at once on two cores) shows the parallelism whatever the wall times.
"""

import argparse
import os
import statistics
import threading
import time

import spraysim


def sequential(scenarios):
    for s in scenarios:
        spraysim.Simulation(s, threads=1).run()


def two_threads(scenarios):
    threads = [threading.Thread(target=lambda s=s: spraysim.Simulation(s, threads=1).run()) for s in scenarios]
    for t in threads:
        t.start()
    for t in threads:
        t.join()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--duration", type=float, default=1.0)
    parser.add_argument("--repeats", type=int, default=3)
    a = parser.parse_args()
    base = spraysim.Scenario().set("simulation.duration", a.duration)
    scenarios = [base, base.set("simulation.seed", 2)]
    cases = {
        "two simulations one after the other": lambda: sequential(scenarios),
        "two simulations in two Python threads": lambda: two_threads(scenarios),
        "run_many(threads=1)": lambda: spraysim.run_many(scenarios, threads=1),
        "run_many(threads=2)": lambda: spraysim.run_many(scenarios, threads=2),
    }
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    times = {k: [] for k in cases}
    busy = {k: [] for k in cases}  # process CPU time / wall time: cores kept busy at once
    for _ in range(a.repeats):
        for name, f in cases.items():
            start, cpu = time.perf_counter(), time.process_time()
            f()
            wall = time.perf_counter() - start
            times[name].append(wall)
            busy[name].append((time.process_time() - cpu) / wall)
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"default scene, {a.duration} s simulated each, median of {a.repeats}, wall seconds, "
          f"load average before: {load:.2f}")
    print(f"{'':<40}{'wall':>8}{'cpu/wall':>10}")
    for name, t in med.items():
        print(f"{name:<40}{t:>8.3f}{statistics.median(busy[name]):>10.2f}")
    seq = med["two simulations one after the other"]
    print(f"speed-up of two Python threads: {seq / med['two simulations in two Python threads']:.2f}x")
    print(f"speed-up of run_many on 2 threads: {med['run_many(threads=1)'] / med['run_many(threads=2)']:.2f}x")


if __name__ == "__main__":
    main()
