#!/usr/bin/env python3
"""Where one function's time goes, by the inlined functions it is made of.

    perf record -F 2000 -o P.perf BINARY ARGS...   (a build with line tables:
        CARGO_PROFILE_RELEASE_DEBUG=line-tables-only cargo build --release ...)
    python3 bench/inline_profile.py P.perf BINARY SYMBOL [--skip a.rs,b.rs] [--top N]
        [--by-line]

The path kernel is one function whose callees are inlined (`#[inline(always)]`), so
`perf report` puts nearly all of a render under one symbol. This reads the samples
whose symbol contains SYMBOL, asks `addr2line -i` for each address's chain of inlined
calls, and charges each sample to the innermost frame whose file is not in --skip
(by default the lane primitives `lanes.rs` and `dw.rs` and the standard library):
the kernel's own stages show as `kernel.rs` lines, the rest by file and function.
Prints percentages of the symbol's samples, by file (and with --by-line, by line).
"""
import argparse, collections, re, subprocess


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("perf_data")
    ap.add_argument("binary")
    ap.add_argument("symbol", help="a substring of the (demangled) symbol's name")
    ap.add_argument("--skip", default="lanes.rs,dw.rs")
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--by-line", action="store_true")
    a = ap.parse_args()
    skip = set(a.skip.split(","))
    # Symbol addresses from the binary; samples as symbol + offset (PIE-proof).
    base = {}
    for line in subprocess.run(["nm", "-C", a.binary], capture_output=True,
                               text=True, check=True).stdout.splitlines():
        p = line.split(" ", 2)
        if len(p) == 3 and p[0] and p[1] in ("t", "T"):
            base.setdefault(p[2], int(p[0], 16))
    out = subprocess.run(["perf", "script", "-i", a.perf_data, "-F", "ip,sym,symoff"],
                         capture_output=True, text=True).stdout
    counts = collections.Counter()
    for line in out.splitlines():
        m = re.match(r"[0-9a-f]+\s+(.*)\+0x([0-9a-f]+)$", line.strip())
        if m and a.symbol in m.group(1) and m.group(1) in base:
            counts[base[m.group(1)] + int(m.group(2), 16)] += 1
    if not counts:
        raise SystemExit(f"no samples in a symbol containing {a.symbol!r}")
    addrs = list(counts)
    text = subprocess.run(["addr2line", "-a", "-i", "-f", "-C", "-e", a.binary],
                          input="\n".join(hex(x) for x in addrs),
                          capture_output=True, text=True).stdout
    total = sum(counts.values())
    by_file, by_line = collections.Counter(), collections.Counter()
    for block in ("\n" + text).split("\n0x")[1:]:
        lines = block.splitlines()
        addr = int(lines[0], 16)
        frames = list(zip(lines[1::2], lines[2::2]))
        key_file, key_line = "?", "?"
        for fn, loc in frames:
            f = loc.rsplit("/", 1)[-1].split(" ")[0]
            if f.split(":")[0] in skip or "/rustc/" in loc or "/.cargo/" in loc:
                continue
            key_file = f.split(":")[0]
            key_line = f"{f}  {fn.rsplit('::', 1)[-1][:40]}"
            break
        by_file[key_file] += counts[addr]
        by_line[key_line] += counts[addr]
    print(f"{total} samples in symbols containing {a.symbol!r}")
    for name, c in (by_line if a.by_line else by_file).most_common(a.top):
        print(f"{100 * c / total:6.2f}  {name}")


if __name__ == "__main__":
    main()
