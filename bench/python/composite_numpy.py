#!/usr/bin/env python3
"""irradia.composite from numpy against an mpi4py + numpy binary swap, on the image of
bench/composite (1280x720 RGBA8 + float32 depth, dense, random per rank).

    mpirun -np P python bench/python/composite_numpy.py [--reps 21]

Times, from a barrier, slowest rank, median of the repetitions (and, on a second
line, the minimum): (1) irradia.composite
(binary swap, then the gather onto rank 0, as the function always does); (2) the
mpi4py + numpy binary swap of bench/composite/binary_swap_mpi4py.py followed by a
Gatherv of the owned pieces onto rank 0 (the same work); (3) that binary swap alone
(bench/composite's baseline); (4) the transfer floor: the same messages as (2) (the
Sendrecv of every swap round, then the Gatherv), with no blending and no copies, i.e.
the least time any binary swap with a gather can take through this MPI on this machine.
Checks (1) equals (2) on rank 0."""

import argparse
import time

import numpy as np
from mpi4py import MPI

import irradia


def rounds(rank, p, n):
    """The binary swap's rounds for `rank` of `p` over `n` pixels: per round the
    partner, the span kept and the span given away; the last span kept is the rank's."""
    lo, hi, bit = 0, n, 1
    while bit < p:
        mid = (lo + hi) // 2
        keep, give = ((lo, mid), (mid, hi)) if rank & bit == 0 else ((mid, hi), (lo, mid))
        yield rank ^ bit, keep, give
        lo, hi = keep
        bit <<= 1


def swap_numpy(comm, color, depth, gather):
    rank, p = comm.Get_rank(), comm.Get_size()
    n = depth.size
    lo, hi = 0, n
    for partner, keep, give in rounds(rank, p, n):
        k = keep[1] - keep[0]
        rc = np.empty((k, 4), np.uint8)
        rd = np.empty(k, np.float32)
        comm.Sendrecv(np.ascontiguousarray(color[give[0]:give[1]]), dest=partner, sendtag=1,
                      recvbuf=rc, source=partner, recvtag=1)
        comm.Sendrecv(np.ascontiguousarray(depth[give[0]:give[1]]), dest=partner, sendtag=2,
                      recvbuf=rd, source=partner, recvtag=2)
        ld, lc = depth[keep[0]:keep[1]], color[keep[0]:keep[1]]
        closer = (rd <= ld) if partner < rank else (rd < ld)
        lc[closer] = rc[closer]
        ld[closer] = rd[closer]
        lo, hi = keep
    if not gather:
        return None
    spans = comm.gather((lo, hi), root=0)
    out_c = np.empty((n, 4), np.uint8) if rank == 0 else None
    out_d = np.empty(n, np.float32) if rank == 0 else None
    if rank == 0:
        counts = [spans[r][1] - spans[r][0] for r in range(p)]
        displ = [spans[r][0] for r in range(p)]
        comm.Gatherv(color[lo:hi], [out_c, [4 * c for c in counts], [4 * x for x in displ], MPI.UNSIGNED_CHAR], root=0)
        comm.Gatherv(depth[lo:hi], [out_d, counts, displ, MPI.FLOAT], root=0)
        return out_c, out_d
    comm.Gatherv(color[lo:hi], None, root=0)
    comm.Gatherv(depth[lo:hi], None, root=0)
    return None


def transfer_floor(comm, color, depth, bufs):
    """The messages of `swap_numpy(..., gather=True)` alone: the same sizes, partners
    and order, sent from and received into buffers made beforehand, no blending."""
    rank, p = comm.Get_rank(), comm.Get_size()
    n = depth.size
    lo, hi = 0, n
    for partner, keep, give in rounds(rank, p, n):
        k = keep[1] - keep[0]
        rc, rd = bufs["c"][:k], bufs["d"][:k]
        comm.Sendrecv(color[give[0]:give[1]], dest=partner, sendtag=1, recvbuf=rc, source=partner, recvtag=1)
        comm.Sendrecv(depth[give[0]:give[1]], dest=partner, sendtag=2, recvbuf=rd, source=partner, recvtag=2)
        lo, hi = keep
    spans = comm.gather((lo, hi), root=0)
    if rank == 0:
        counts = [spans[r][1] - spans[r][0] for r in range(p)]
        displ = [spans[r][0] for r in range(p)]
        comm.Gatherv(color[lo:hi], [bufs["oc"], [4 * c for c in counts], [4 * x for x in displ], MPI.UNSIGNED_CHAR], root=0)
        comm.Gatherv(depth[lo:hi], [bufs["od"], counts, displ, MPI.FLOAT], root=0)
    else:
        comm.Gatherv(color[lo:hi], None, root=0)
        comm.Gatherv(depth[lo:hi], None, root=0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--width", type=int, default=1280)
    ap.add_argument("--height", type=int, default=720)
    ap.add_argument("--reps", type=int, default=21)
    a = ap.parse_args()
    comm = MPI.COMM_WORLD
    rank, p = comm.Get_rank(), comm.Get_size()
    h, w = a.height, a.width
    rng = np.random.default_rng(rank + 1)
    color0 = rng.integers(0, 256, size=(h, w, 4), dtype=np.uint8)
    depth0 = rng.random((h, w), dtype=np.float32)
    times = {"irradia": [], "numpy_gather": [], "numpy_swap_only": [], "floor": []}
    n = h * w
    bufs = {"c": np.empty((n, 4), np.uint8), "d": np.empty(n, np.float32),
            "oc": np.empty((n, 4), np.uint8), "od": np.empty(n, np.float32)}
    check = None
    for rep in range(a.reps + 1):
        for case in times:
            color, depth = color0.copy(), depth0.copy()
            comm.Barrier()
            t0 = time.perf_counter()
            if case == "irradia":
                out = irradia.composite(color, depth, strategy="binary-swap", comm=comm)
            elif case == "floor":
                out = transfer_floor(comm, color.reshape(-1, 4), depth.reshape(-1), bufs)
            else:
                out = swap_numpy(comm, color.reshape(-1, 4), depth.reshape(-1), case == "numpy_gather")
            t = time.perf_counter() - t0
            t = max(comm.allgather(t))
            if rep:
                times[case].append(t)
            elif rank == 0 and case in ("irradia", "numpy_gather"):
                check = out if check is None else check
                if case == "numpy_gather":
                    assert np.array_equal(check[0].reshape(-1, 4), out[0]) and np.array_equal(check[1].reshape(-1), out[1])
    if rank == 0:
        m = {k: 1e3 * float(np.median(v)) for k, v in times.items()}
        print(f"RESULT np={p} irradia_ms={m['irradia']:.3f} numpy_gather_ms={m['numpy_gather']:.3f} "
              f"numpy_swap_only_ms={m['numpy_swap_only']:.3f} ratio_same_work={m['irradia'] / m['numpy_gather']:.3f} "
              f"ratio_vs_swap_only={m['irradia'] / m['numpy_swap_only']:.3f} floor_ms={m['floor']:.3f} "
              f"floor_over_numpy={m['floor'] / m['numpy_gather']:.3f}")
        # The least disturbed repetition of each case: on a loaded machine (more
        # runnable processes than cores) the medians measure the scheduler as much as
        # the code; the minima approach what a quiet machine gives.
        lo = {k: 1e3 * float(np.min(v)) for k, v in times.items()}
        print(f"MIN np={p} irradia_ms={lo['irradia']:.3f} numpy_gather_ms={lo['numpy_gather']:.3f} "
              f"floor_ms={lo['floor']:.3f} ratio_same_work={lo['irradia'] / lo['numpy_gather']:.3f}")
        # The spread: quartiles, and the share of calls over 1.5 times their case's best
        # (on 2 ranks and 2 cores, calls that waited for a descheduled partner).
        for k in ("irradia", "numpy_gather"):
            v = np.array(times[k])
            q1, q3 = (1e3 * float(np.quantile(v, q)) for q in (0.25, 0.75))
            print(f"SPREAD np={p} case={k} q1_ms={q1:.3f} q3_ms={q3:.3f} "
                  f"slow_share={float(np.mean(v > 1.5 * v.min())):.2f}")


if __name__ == "__main__":
    main()
