"""The benchmarks' account of the machine: the cores other processes used while one ran."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import pytest
from numpy.testing import assert_allclose

from tests.benchmarks import benchmark_module

machine = benchmark_module("machine.py", "benchmark_machine")


def test_others_cores_is_the_machine_busy_time_less_the_own_processes_over_the_wall():
    # 2 s in which the machine was busy 3 core-seconds; this process used 1 s, a child 0.5 s:
    # the others used 1.5 core-seconds, 0.75 cores on average.
    before = machine.CpuSample(10.0, 100.0, {(1, 0.0): 5.0, (2, 0.5): 3.0})
    after = machine.CpuSample(12.0, 103.0, {(1, 0.0): 6.0, (2, 0.5): 3.5})
    assert_allclose(machine.others_cores(before, after), (3.0 - 1.0 - 0.5) / 2.0, rtol=1e-12)


def test_a_process_started_between_the_samples_counts_whole_even_under_a_reused_id():
    # Process id 2 ended (its last 0.2 s are unseen: the others' by the account) and a new
    # process got id 2 and used 0.4 s; another new one used 0.1 s.
    before = machine.CpuSample(0.0, 50.0, {(1, 0.0): 1.0, (2, 0.5): 2.0})
    after = machine.CpuSample(4.0, 54.0, {(1, 0.0): 2.0, (2, 3.0): 0.4, (3, 3.5): 0.1})
    own = 1.0 + 0.4 + 0.1
    assert_allclose(machine.others_cores(before, after), (4.0 - own) / 4.0, rtol=1e-12)


def test_others_cores_is_never_negative_when_the_ticks_disagree():
    # /proc/stat and the processes' counters are read a moment apart, in 10 ms ticks.
    before = machine.CpuSample(0.0, 10.0, {(1, 0.0): 0.0})
    after = machine.CpuSample(1.0, 10.99, {(1, 0.0): 1.0})
    assert machine.others_cores(before, after) == 0.0


def _spin(seconds: float) -> None:
    """Use ``seconds`` of this process's CPU time."""
    start = time.process_time()
    while time.process_time() - start < seconds:
        pass


def test_cpu_sample_reads_this_process_and_its_children():
    pytest.importorskip("psutil")
    busy = 0.3
    code = (
        "import sys, time\n"
        "print('ready', flush=True); sys.stdin.readline()\n"
        f"s = time.process_time()\nwhile time.process_time() - s < {busy}: pass\n"
        "print('done', flush=True); sys.stdin.readline()\n"
    )
    child = subprocess.Popen(
        [sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    )
    assert child.stdin is not None and child.stdout is not None
    try:
        assert child.stdout.readline().strip() == "ready"
        before, mine = machine.cpu_sample(), time.process_time()
        _spin(busy)
        mine = time.process_time() - mine
        child.stdin.write("go\n")
        child.stdin.flush()
        assert child.stdout.readline().strip() == "done"
        after = machine.cpu_sample()
    finally:
        child.kill()
        child.wait()
        child.stdin.close()  # the pipes are files: closed, not left to the collector
        child.stdout.close()
    used = {key: cpu - before.own_s[key] for key, cpu in after.own_s.items() if key in before.own_s}
    (me,) = (key for key in used if key[0] == os.getpid())
    (theirs,) = (key for key in used if key[0] == child.pid)
    # Both counters tick at 10 ms; the child also reads and writes a line.
    assert_allclose(used[me], mine, atol=0.03)
    assert_allclose(used[theirs], busy, atol=0.05)
    assert after.machine_s - before.machine_s >= used[me] + used[theirs] - 0.05
