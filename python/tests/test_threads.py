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


@pytest.mark.skipif(os.name == "nt", reason="SIGINT delivery by os.kill is POSIX-only")
def test_a_second_thread_runs_a_whole_simulation_while_the_first_one_runs(short):
    # The main thread runs a long simulation; meanwhile a second thread runs a short one to
    # its end, then interrupts the first. A run holding the interpreter throughout would keep
    # the second thread from starting before the long run had ended.
    long_sim = Simulation(LONG, threads=1)
    short_run = {}
    started, running = threading.Event(), threading.Event()

    def second():
        started.wait()
        sim = Simulation(short, threads=1)
        sim.run()
        short_run["metrics"] = sim.metrics_json()
        short_run["during"] = running.is_set()
        if running.is_set():
            os.kill(os.getpid(), signal.SIGINT)

    thread = threading.Thread(target=second)
    thread.start()
    running.set()
    started.set()
    try:
        long_sim.run()
    except KeyboardInterrupt:
        pass
    finally:
        running.clear()
        thread.join()
    assert short_run["during"], "the short run ended only after the long one"
    assert long_sim.time < LONG.duration
    alone = Simulation(short, threads=1)
    alone.run()
    assert short_run["metrics"] == alone.metrics_json()


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
