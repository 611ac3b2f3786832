"""Keep freed memory in the allocator instead of returning it to the OS.

glibc serves allocations above its mmap threshold (128 KiB, adapting up to 32 MiB) with fresh
``mmap`` pages and unmaps them on free, so every large temporary tensor of the CPU rasteriser is
page-faulted in anew: on a 2-core machine that costs about a fifth of a render. The ``capframe``
command raises the thresholds for its own process; library users can do the same by calling
:func:`keep_freed_memory` or by setting ``GLIBC_TUNABLES``.
"""

from __future__ import annotations

import ctypes
import ctypes.util

_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
_MMAP_THRESHOLD_MAX = 32 * 1024 * 1024  # glibc's cap on 64-bit systems


def keep_freed_memory() -> bool:
    """Raise glibc's mmap and trim thresholds; returns False where the C library is not glibc."""
    name = ctypes.util.find_library("c")
    if name is None:
        return False
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    ok = mallopt(_M_MMAP_THRESHOLD, _MMAP_THRESHOLD_MAX) == 1
    return mallopt(_M_TRIM_THRESHOLD, 1 << 30) == 1 and ok
