"""What this machine has left for a run: the memory the kernel says is available, a cgroup's limit, and
``$MOL_SHELL_MEMORY``'s size as a user sets it; and sizes in bytes shown as people read them.

:mod:`mol_shell.runs.resources` turns these into refusals before work starts (its ``available_memory``).
"""

from __future__ import annotations

import re

from mol_shell._core.errors import ParameterError

#: environment variable: the memory a run may use, bytes (suffixes k, M, G, T; powers of 1024), instead of the
#: machine's available memory (for tests, and for a share of a machine)
MEMORY_ENV = "MOL_SHELL_MEMORY"


def parse_bytes(text):
    """``"8G"`` -> 8 * 1024**3; plain numbers are bytes (a sign is read, so that a negative size is refused by
    :func:`mol_shell.runs.resources.memory_limit` with the range, not as a typo)."""
    found = re.fullmatch(r"\s*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:e[+-]?[0-9]+)?)\s*([kmgt]?)i?b?\s*", str(text),
                         flags=re.IGNORECASE)
    if not found:
        raise ParameterError.invalid(MEMORY_ENV, text, "is not a size", "bytes, or a number with k, M, G or T")
    return float(found.group(1)) * 1024 ** "_kmgt".index(found.group(2).lower() or "_")


def meminfo_available():
    """``MemAvailable`` of /proc/meminfo (bytes), None where it cannot be read."""
    try:
        with open("/proc/meminfo") as f:
            info = dict(line.split(":", 1) for line in f if ":" in line)
        return float(info["MemAvailable"].split()[0]) * 1024
    except (OSError, KeyError, ValueError):
        return None


def cgroup_room():
    """Memory left under this process's cgroup (v2 or v1) limit, if there is one."""
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        try:
            with open(limit_file) as f:
                limit = f.read().strip()
            with open(usage_file) as f:
                usage = float(f.read().strip())
        except (OSError, ValueError):
            continue
        if limit.isdigit() and float(limit) < 2**60:
            return float(limit) - usage
    return None


def show_bytes(value):
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if value >= size:
            return f"{value / size:.3g} {unit}"
    return f"{value:.0f} B"
