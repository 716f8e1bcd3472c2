"""The interpreter is released while simulations work: threads run, Ctrl-C interrupts.

These tests assert what happens, never how fast: the speed-up of two threads is measured by
python/benchmarks/threads.py.
"""

import os
import signal
import threading
import time

import pytest

import spraysim
from spraysim import Scenario, Simulation

LONG = Scenario().set_many({"simulation.duration": 60.0, "target[0].resolution": [256, 256]})


def test_python_threads_run_while_a_simulation_works(short):
    ticks, stop = [0], threading.Event()

    def ticker():
        while not stop.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    sim = Simulation(short.set("simulation.duration", 1.0), threads=1)
    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        before = ticks[0]
        sim.run()
        during = ticks[0] - before
    finally:
        stop.set()
        thread.join()
    # A run of about a tenth of a second would let no tick through if it held the interpreter.
    assert during >= 5, during


def test_two_simulations_run_at_once_in_two_threads(short):
    scenario = short.set("simulation.duration", 0.5)
    inside = []  # (thread, "in"/"out") in the order the runs start and end
    lock = threading.Lock()

    def work(name):
        sim = Simulation(scenario, threads=1)
        sim.step()  # set up before the race
        with lock:
            inside.append((name, "in"))
        sim.run()
        with lock:
            inside.append((name, "out"))
        results[name] = sim.metrics_json()

    results = {}
    threads = [threading.Thread(target=work, args=(n,)) for n in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    # Both runs were in progress at the same time: both started before either ended.
    assert [e for _, e in inside[:2]] == ["in", "in"], inside
    alone = Simulation(scenario, threads=1)
    alone.run()
    assert results["a"] == results["b"] == alone.metrics_json()


def interrupt_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.skipif(os.name == "nt", reason="SIGINT delivery by os.kill is POSIX-only")
def test_ctrl_c_interrupts_a_run_and_leaves_the_simulation_usable():
    sim = Simulation(LONG, threads=1)
    timer = interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        sim.run()
    timer.join()
    assert 0 < sim.time < 60.0
    steps = sim.steps_done
    sim.step(2)
    assert sim.steps_done == steps + 2


@pytest.mark.skipif(os.name == "nt", reason="SIGINT delivery by os.kill is POSIX-only")
def test_ctrl_c_interrupts_run_many():
    timer = interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        spraysim.run_many([LONG, LONG.set("simulation.seed", 2)], threads=2)
    timer.join()
