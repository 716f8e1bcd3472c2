"""How soon Ctrl-C interrupts a run: SIGINT sent to the process 0.3 s into a long run of the
default scene, and the time until `KeyboardInterrupt` reaches Python, for Simulation.run and
run_many.

    python python/benchmarks/interrupt.py [--repeats 5]
"""

import argparse
import os
import signal
import threading
import time

import spraysim


def latency(call):
    sent = {}

    def fire():
        sent["t"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Timer(0.3, fire).start()
    try:
        call()
    except KeyboardInterrupt:
        return time.perf_counter() - sent["t"]
    raise RuntimeError("the run ended before it was interrupted")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    a = parser.parse_args()
    long = spraysim.Scenario().set("simulation.duration", 60.0)
    cases = {
        "Simulation(threads=2).run()": lambda: spraysim.Simulation(long, threads=2).run(),
        "run_many(2 scenarios, threads=2)": lambda: spraysim.run_many(
            [long, long.set("simulation.seed", 2)], threads=2
        ),
    }
    print(f"SIGINT to KeyboardInterrupt, ms, {a.repeats} runs each, load average {os.getloadavg()[0]:.2f}")
    for name, call in cases.items():
        ms = sorted(1e3 * latency(call) for _ in range(a.repeats))
        print(f"{name:<36} median {ms[len(ms) // 2]:6.1f}   max {ms[-1]:6.1f}")


if __name__ == "__main__":
    main()
