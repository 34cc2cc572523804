"""A local worker that dies between the study's look at its futures and its next hand-over: the pool refuses the
hand-over (``BrokenProcessPool`` from ``submit``), which once ended the study with an internal error; the lost case
runs again in a new pool like any other."""

import os
import signal
import time

from poison_cases import Case, run

from mol_shell.runs import scheduling


class _DiesBeforeFourthSubmit(scheduling.ProcessPoolExecutor):
    """The first pool's worker is killed just before the pool's fourth hand-over (the worker then runs its second
    case, claimed), and the hand-over waits until the pool has seen it die."""

    made, log = 0, None

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        type(self).made += 1
        self.first, self.submits = type(self).made == 1, 0

    def submit(self, *args, **kwargs):
        self.submits += 1
        if self.first and self.submits == 4:
            deadline = time.monotonic() + 30  # until the worker has started (claimed) its second case
            while time.monotonic() < deadline and sum(
                    name.split("-")[1] != str(os.getpid()) for name in os.listdir(self.log)) < 2:
                time.sleep(0.005)
            for process in list(self._processes.values()):
                os.kill(process.pid, signal.SIGKILL)
            deadline = time.monotonic() + 30
            while not self._broken and time.monotonic() < deadline:
                time.sleep(0.01)
        return super().submit(*args, **kwargs)


def test_a_worker_dead_before_a_hand_over_has_its_case_run_again(tmp_path, monkeypatch):
    monkeypatch.setattr(scheduling, "ProcessPoolExecutor", _DiesBeforeFourthSubmit)
    me, log = os.getpid(), str(tmp_path)
    monkeypatch.setattr(_DiesBeforeFourthSubmit, "log", log)
    cases = [Case((k,), me, seconds=0.3, log=log) for k in range(10)]
    results = list(scheduling.execute(run, cases, None, 2))
    assert _DiesBeforeFourthSubmit.made == 2  # a new pool after the broken one
    by_case = {index: info for index, _, info in results}
    assert sorted(by_case) == [(k,) for k in range(10)] and len(results) == 10  # each case once
    assert all(info["status"] == "complete" for info in by_case.values()), by_case
    again = [index for index, info in by_case.items() if "run 2 times" in info["message"]]
    assert len(again) == 1, by_case  # the case the killed worker was running
