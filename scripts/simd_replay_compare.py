#!/usr/bin/env python3
"""The device's SIMD counters beside the lockstep replay's, slot by slot (issue 25).

Reads the report.json of device_figures.sh's simd-replay step:
    {scene: {"device": {method: render report or null}, "replay": replay JSON or null}}
and prints a Markdown table per scene (device %, replay %, difference in points) and a summary
line: how many slots were compared, the largest difference, and how many lie beyond the 3-point
bar the replay is validated to on the software driver (tests/suite/simd_replay.rs).

Usage: simd_replay_compare.py REPORT.json
"""

import json
import sys

BAR_POINTS = 3.0


def main(path):
    with open(path) as f:
        report = json.load(f)
    compared, beyond, largest, missing = 0, 0, 0.0, []
    print("| scene | method | slot | device | replay | difference (points) |")
    print("| --- | --- | --- | ---: | ---: | ---: |")
    for scene, entry in report.items():
        replay = entry.get("replay")
        for method, device in (entry.get("device") or {}).items():
            if device is None or replay is None or method not in replay.get("methods", {}):
                missing.append(f"{scene} {method}")
                continue
            widths = replay["methods"][method]["widths"]
            if len(widths) != 1:
                sys.exit(f"{path}: {scene} {method}: expected one replayed width, found {list(widths)}")
            replayed = next(iter(widths.values()))["simd"]
            for slot, d in sorted((device.get("simd") or {}).items()):
                r = replayed.get(slot)
                if r is None:
                    missing.append(f"{scene} {method} {slot} (not replayed)")
                    continue
                diff = 100.0 * (d["efficiency"] - r["efficiency"])
                compared += 1
                largest = max(largest, abs(diff))
                beyond += abs(diff) > BAR_POINTS
                print(
                    f"| {scene} | {method} | {slot} | {100 * d['efficiency']:.2f}% "
                    f"| {100 * r['efficiency']:.2f}% | {diff:+.2f} |"
                )
    print()
    if missing:
        print(f"Not compared: {', '.join(missing)}.")
    print(
        f"{compared} slots compared; largest difference {largest:.2f} points; "
        f"{beyond} beyond {BAR_POINTS:.0f} points."
    )


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
