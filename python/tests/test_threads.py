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


def test_threads_sharing_one_simulation_take_turns_call_by_call(short):
    # Two threads advance one simulation in calls of 10 steps (`step(10)`, and `run` to whole
    # tens of steps) while a third reads it: each call waits for the other thread's to end, so
    # the readers only ever see whole calls, and the result is that of one thread stepping.
    sim = Simulation(short, threads=1)
    errors, seen, done = [], [], threading.Event()

    def guarded(work):
        def target():
            try:
                work()
            except Exception as e:  # reported by the assertions below
                errors.append(e)

        return threading.Thread(target=target)

    def stepper():
        for _ in range(10):
            sim.step(10)

    def runner():
        for k in range(1, 21):
            sim.run(until=k * 0.01)

    def reader():
        while True:
            last = done.is_set()
            m = sim.metrics()
            seen.append((sim.steps_done, round(m["time"] / sim.dt)))
            sim.thickness("wall", copy=True)
            sim.particles()
            if last:
                break

    workers = [guarded(stepper), guarded(runner)]
    watcher = guarded(reader)
    for t in [*workers, watcher]:
        t.start()
    for t in workers:
        t.join()
    done.set()
    watcher.join()
    assert errors == []
    assert seen and all(steps % 10 == 0 and at % 10 == 0 for steps, at in seen), seen
    assert sim.steps_done >= 200 and sim.steps_done % 10 == 0
    straight = Simulation(short, threads=1)
    straight.step(sim.steps_done)
    assert sim.metrics_json() == straight.metrics_json()


@pytest.mark.skipif(os.name == "nt", reason="SIGINT delivery by os.kill is POSIX-only")
def test_ctrl_c_interrupts_a_thread_waiting_for_a_simulation_busy_in_another():
    sim = Simulation(LONG, threads=1)
    started, stop = threading.Event(), threading.Event()

    class Stopped(Exception):
        pass

    def progress(time_s, until_s):
        started.set()
        if stop.is_set():
            raise Stopped

    def worker():
        try:
            sim.run(progress=progress)
        except Stopped:
            pass

    thread = threading.Thread(target=worker)
    thread.start()
    try:
        assert started.wait(60)
        timer = interrupt_after(0.3)
        try:
            with pytest.raises(KeyboardInterrupt):
                sim.step()  # waits for the other thread's run, until Ctrl-C
        finally:
            timer.cancel()  # when the step did not wait, no Ctrl-C must come later
            timer.join()
    finally:
        stop.set()
        thread.join()
    steps = sim.steps_done
    sim.step(2)
    assert sim.steps_done == steps + 2
