"""Reference counts and memory stay flat over 1,000 renders of a tiny image."""

import gc
import sys

import numpy as np

import irradia


def rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def test_thousand_renders_leak_nothing():
    s = irradia.builtin("whitted")
    opts = dict(width=8, height=6, threads=1, aovs=["depth"])
    for _ in range(50):  # warm up allocators and caches
        s.render(**opts)
    gc.collect()
    refs_scene = sys.getrefcount(s)
    objects = len(gc.get_objects())
    rss = rss_kib()
    counts = set()
    for _ in range(1000):
        r = s.render(**opts)
        counts.add((sys.getrefcount(r), sys.getrefcount(r["color"]), sys.getrefcount(r["depth"])))
    del r
    assert len(counts) == 1, counts  # every result is referenced the same way
    gc.collect()
    assert sys.getrefcount(s) == refs_scene
    assert len(gc.get_objects()) <= objects + 10
    grown = rss_kib() - rss
    assert grown < 8 * 1024, "RSS grew by %d KiB over 1,000 renders" % grown


def test_arrays_own_their_memory():
    s = irradia.builtin("whitted")
    a = s.render(width=4, height=4)
    assert a.flags["OWNDATA"] or a.base is not None
    assert a.flags["C_CONTIGUOUS"] and a.flags["WRITEABLE"]
    a[:] = 0  # writable, and no other array sees it
    assert np.any(s.render(width=4, height=4) != 0)
