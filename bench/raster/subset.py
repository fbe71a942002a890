#!/usr/bin/env python3
"""Writes the first N triangles of a raster_bench workload (same view and light) to a
new workload file: a small frame for instruction-count comparisons under callgrind /
cachegrind, which are stable on a loaded machine where wall times are not.

    python3 bench/raster/subset.py IN.bin OUT.bin N
"""
import sys

import numpy as np


def main():
    src, dst, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    b = open(src, "rb").read()
    assert b[:4] == b"IRRT", f"{src}: not a raster_bench workload"
    head = 4 + 8 + 24 * 4
    nv, nt = np.frombuffer(b, "<u4", 2, head)
    at = head + 8
    pos = np.frombuffer(b, "<f4", 3 * nv, at).reshape(-1, 3)
    nrm = np.frombuffer(b, "<f4", 3 * nv, at + 12 * nv).reshape(-1, 3)
    idx = np.frombuffer(b, "<u4", 3 * nt, at + 24 * nv).reshape(-1, 3)[:n]
    used, remap = np.unique(idx, return_inverse=True)
    out = bytearray(b[:head])
    out += np.array([len(used), len(idx)], "<u4").tobytes()
    out += pos[used].astype("<f4").tobytes() + nrm[used].astype("<f4").tobytes()
    out += remap.reshape(-1, 3).astype("<u4").tobytes()
    open(dst, "wb").write(bytes(out))


if __name__ == "__main__":
    main()
