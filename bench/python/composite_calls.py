#!/usr/bin/env python3
"""Where the wall time of irradia.composite goes on a machine with as many ranks as
cores (or fewer cores): per call and rank, the wall time, the CPU time, the minor page
faults and the voluntary and involuntary context switches of the calling thread
(getrusage RUSAGE_THREAD; the composite runs on that thread with the GIL released).

    mpirun --oversubscribe --bind-to none -np 2 python bench/python/composite_calls.py [REPS]

The image is composite_numpy.py's (1280x720 RGBA8 + float32 depth, random per rank,
binary swap). Prints every call (slowest rank's wall time; SLOW when over 1.5 times the
best call), then the fast and slow calls' medians with their mean context switches and
faults: a call whose CPU time is a small part of its wall time, with involuntary
switches, spent the rest descheduled (waiting for a core), not computing."""
import resource, sys, time
import numpy as np
from mpi4py import MPI
import irradia
comm = MPI.COMM_WORLD
rank = comm.Get_rank()
h, w = 720, 1280
rng = np.random.default_rng(rank + 1)
color0 = rng.integers(0, 256, size=(h, w, 4), dtype=np.uint8)
depth0 = rng.random((h, w), dtype=np.float32)
reps = int(sys.argv[1]) if len(sys.argv) > 1 else 40
rows = []
for rep in range(reps + 1):
    color, depth = color0.copy(), depth0.copy()
    comm.Barrier()
    r0 = resource.getrusage(resource.RUSAGE_THREAD)
    t0 = time.perf_counter()
    out = irradia.composite(color, depth, strategy="binary-swap", comm=comm)
    t = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_THREAD)
    del out
    row = (t * 1e3, r1.ru_minflt - r0.ru_minflt, r1.ru_nvcsw - r0.ru_nvcsw, r1.ru_nivcsw - r0.ru_nivcsw,
           1e3 * (r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime))
    allrows = comm.gather(row, root=0)
    if rep and rank == 0:
        rows.append(allrows)
if rank == 0:
    best = min(max(r[0] for r in rs) for rs in rows)
    for rs in rows:
        t = max(r[0] for r in rs)
        print(f"{t:8.2f} ms {'SLOW' if t > 1.5 * best else '    '} " + " | ".join(
            f"r{k}: {r[0]:7.2f} ms flt {r[1]:5d} vcsw {r[2]:3d} ivcsw {r[3]:3d} cpu {r[4]:6.2f}" for k, r in enumerate(rs)))
    import statistics
    slow = [rs for rs in rows if max(r[0] for r in rs) > 1.5 * best]
    fast = [rs for rs in rows if max(r[0] for r in rs) <= 1.5 * best]
    for name, grp in (("fast", fast), ("slow", slow)):
        if grp:
            mean = lambda k: statistics.mean(sum(r[k] for r in rs) for rs in grp)
            print(f"{name} calls={len(grp)} median_ms={statistics.median(max(r[0] for r in rs) for rs in grp):.2f} "
                  f"cpu_ms_per_rank={mean(4) / len(grp[0]):.2f} ivcsw={mean(3):.1f} vcsw={mean(2):.1f} "
                  f"faults={mean(1):.1f} (means per call, summed over ranks)")
