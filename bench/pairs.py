#!/usr/bin/env python3
"""Two commands timed side by side as whole processes, in interleaved pairs.

    python3 bench/pairs.py [-n 5] [--warmup 1] "COMMAND_A" "COMMAND_B"

Runs A B A B ... (N counted pairs after the warm-up pairs), each command split as a
shell splits words and run without a shell, and reads each process's wall time and its
user and system CPU (os.wait4's rusage: the process and the children it waited for) and
peak resident memory. Prints the medians and the median of the pair-by-pair ratios A/B:
pairing keeps the ratio meaningful when the machine's speed drifts during the series
(a loaded machine: see the load average printed first). Exits 1 if any run fails.
"""
import argparse, os, shlex, statistics, subprocess, sys, time


def run(cmd):
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.exit(f"{shlex.join(cmd)} exited {code}:\n{err[-2000:]}")
    return {"wall": wall, "user": ru.ru_utime, "sys": ru.ru_stime,
            "cpu": ru.ru_utime + ru.ru_stime, "peak_mib": ru.ru_maxrss / 1024}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-n", type=int, default=5, help="counted pairs (default 5)")
    ap.add_argument("--warmup", type=int, default=1, help="pairs run first and not counted (default 1)")
    ap.add_argument("a", help="command A (quoted)")
    ap.add_argument("b", help="command B, the baseline or the peer (quoted)")
    args = ap.parse_args()
    a, b = shlex.split(args.a), shlex.split(args.b)
    print(f"load {open('/proc/loadavg').read().split()[:3]}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"A = {args.a}\nB = {args.b}")
    for _ in range(args.warmup):
        run(a), run(b)
    ra, rb = [], []
    for _ in range(args.n):
        ra.append(run(a))
        rb.append(run(b))
    med = lambda rs, k: statistics.median(r[k] for r in rs)
    print(f"{'':12}{'A median':>10}{'B median':>10}{'A/B (pairs)':>14}{'min':>8}{'max':>8}")
    for k in ["wall", "cpu", "user", "sys", "peak_mib"]:
        ratios = [x[k] / y[k] for x, y in zip(ra, rb) if y[k] > 0]
        r = (f"{statistics.median(ratios):14.4f}{min(ratios):8.4f}{max(ratios):8.4f}"
             if ratios else f"{'-':>14}")
        print(f"{k:12}{med(ra, k):10.3f}{med(rb, k):10.3f}{r}")


if __name__ == "__main__":
    main()
