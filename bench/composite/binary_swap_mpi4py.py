#!/usr/bin/env python3
"""Baseline: binary swap of a 1280x720 RGBA8 + float32 depth image with mpi4py + numpy.

mpirun -np P python3 binary_swap_mpi4py.py [--width 1280] [--height 720] [--reps 9]

The same image and measurement as Irradia's composite_bench: a dense image (every pixel
active, hashed depths), binary swap rounds (Sendrecv of the half not kept, then a numpy
depth test on the half kept), timed from a barrier, slowest rank, median of the
repetitions. Power-of-two rank counts only. Prints `RESULT np=P case=dense median_ms=..`.
"""
import argparse
import time

import numpy as np
from mpi4py import MPI


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--reps", type=int, default=9)
    a = ap.parse_args()
    comm = MPI.COMM_WORLD
    rank, p = comm.Get_rank(), comm.Get_size()
    assert p & (p - 1) == 0, "power-of-two rank counts only"
    n = a.width * a.height
    rng = np.random.default_rng(rank + 1)
    color0 = rng.integers(0, 256, size=(n, 4), dtype=np.uint8)
    depth0 = rng.random(n, dtype=np.float32)
    times = []
    for _ in range(a.reps):
        color, depth = color0.copy(), depth0.copy()
        comm.Barrier()
        t0 = time.perf_counter()
        lo, hi = 0, n
        bit = 1
        while bit < p:
            partner = rank ^ bit
            mid = (lo + hi) // 2
            if rank & bit == 0:
                keep, give = (lo, mid), (mid, hi)
            else:
                keep, give = (mid, hi), (lo, mid)
            k = keep[1] - keep[0]
            rc = np.empty((k, 4), dtype=np.uint8)
            rd = np.empty(k, dtype=np.float32)
            comm.Sendrecv(np.ascontiguousarray(color[give[0]:give[1]]), dest=partner, sendtag=1,
                          recvbuf=rc, source=partner, recvtag=1)
            comm.Sendrecv(np.ascontiguousarray(depth[give[0]:give[1]]), dest=partner, sendtag=2,
                          recvbuf=rd, source=partner, recvtag=2)
            ld = depth[keep[0]:keep[1]]
            lc = color[keep[0]:keep[1]]
            closer = (rd <= ld) if partner < rank else (rd < ld)
            lc[closer] = rc[closer]
            ld[closer] = rd[closer]
            lo, hi = keep
            bit <<= 1
        t = time.perf_counter() - t0
        times.append(max(comm.allgather(t)))
    if rank == 0:
        print(f"RESULT np={p} case=mpi4py median_ms={1e3 * float(np.median(times)):.3f}")


if __name__ == "__main__":
    main()
