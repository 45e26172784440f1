#!/usr/bin/env python3
"""Times render variants interleaved: round after round, each variant once per round, so that a
slow spell of a shared machine falls on all of them alike. Prints each variant's median time
(the headline `frame_seconds` where the run has it — GPU work and the host round trips between
submissions — else `gpu_seconds`, else `wall_seconds`, from `wavetrace render --report`), its
range, and each median over the first variant's. `--field NAME` times by another report field
(e.g. `wall_seconds`, which includes pipeline creation and the upload). Renders run with
`--timing frame` (no per-pass timestamps, which on some drivers wait for the work before each
one and so charge the method with the most passes) unless the arguments name `--timing`.

Usage:
    scripts/interleave.py --rounds 5 COMMON_ARGS... -v NAME ARGS... [-v NAME ARGS...]

e.g. the light-selection timings quoted in the README:
    scripts/interleave.py --rounds 5 --scene two-lights --method cpu --nee on --width 128 \\
        --height 96 --spp 64 -v uniform --light-select uniform -v power --light-select power

COMMON_ARGS go to every render (--out and --report are added); `-v NAME` starts a variant, the
arguments after it are its own. WAVETRACE_BIN overrides target/release/wavetrace; a variant's
`--bin=PATH` runs that binary instead (an A/B of two builds).
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile


def pick(rec, field):
    if field:
        return rec[field]
    for f in ("frame_seconds", "gpu_seconds"):
        if rec.get(f):
            return rec[f]
    return rec["wall_seconds"]


def parse(argv):
    rounds, field, common, variants = 3, None, [], []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--rounds":
            rounds = int(argv[i + 1])
            i += 2
        elif a == "--field":
            field = argv[i + 1]
            i += 2
        elif a == "-v":
            variants.append((argv[i + 1], []))
            i += 2
        else:
            (variants[-1][1] if variants else common).append(a)
            i += 1
    if len(variants) < 2:
        sys.exit("name at least two variants with -v NAME ARGS...")
    return rounds, field, common, variants


def main():
    rounds, field, common, variants = parse(sys.argv[1:])
    binary = os.environ.get("WAVETRACE_BIN", "target/release/wavetrace")
    times = {name: [] for name, _ in variants}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(rounds):
            for name, args in variants:
                report = os.path.join(tmp, "run.json")
                own = [a[len("--bin="):] for a in args if a.startswith("--bin=")]
                args = [a for a in args if not a.startswith("--bin=")]
                exe = own[-1] if own else binary
                timing = [] if "--timing" in common + args else ["--timing", "frame"]
                cmd = [exe, "render", *common, *args, *timing, "--out", os.path.join(tmp, "run.exr"),
                       "--report", report]
                subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                with open(report) as f:
                    rec = json.load(f)
                times[name].append(pick(rec, field))
            print(f"round {r + 1}/{rounds}: " + ", ".join(f"{n} {t[-1]:.4f} s" for n, t in times.items()),
                  file=sys.stderr)
    base = statistics.median(times[variants[0][0]])
    print(f"{'variant':<24} {'median s':>10} {'min':>10} {'max':>10} {'÷ ' + variants[0][0]:>12}")
    for name, t in times.items():
        m = statistics.median(t)
        print(f"{name:<24} {m:>10.4f} {min(t):>10.4f} {max(t):>10.4f} {m / base:>12.3f}")


if __name__ == "__main__":
    main()
