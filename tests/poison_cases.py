"""Cases for the local scheduler's fault tests, importable by name in its spawned workers.

A poisoned case kills any worker process that runs it (as a case that runs out of memory would); in the
process that made the study it just completes (so the test survives if that process takes it)."""

import os
import time
from dataclasses import dataclass


@dataclass(frozen=True)
class Case:
    index: tuple
    parent: int  # pid of the process that made the study
    poisoned: bool = False
    seconds: float = 0.0
    log: str = ""  # a folder that gets a file for every run of a case


def run(case):
    if case.log:
        with open(os.path.join(case.log, f"{case.index[0]}-{os.getpid()}-{time.time_ns()}"), "w"):
            pass
    if case.poisoned and os.getpid() != case.parent:
        os._exit(1)
    time.sleep(case.seconds)
    return case.index, None, {"status": "complete", "message": "done", "case_wall_time_s": case.seconds,
                              "worker": str(os.getpid())}
