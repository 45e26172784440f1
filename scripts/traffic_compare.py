#!/usr/bin/env python3
"""Compares the modelled path-state traffic (issue 44) of two runs of the same experiment.

    scripts/traffic_compare.py BEFORE/report.json AFTER/report.json

Prints a markdown table: per job and method, bytes of path state read and written per sample
before and after, the change, and per pass the bytes per sample after. Each report's build is
named from its `environment`.
"""
import json
import sys


def runs(path):
    report = json.load(open(path))
    envs = report.get("environments") or [{}]
    build = envs[0].get("build", {}).get("git_commit", "?")
    out = {}
    for r in report["runs"]:
        t = r.get("state_traffic")
        if t:
            out[(r["scene"], r["width"], r["height"], r["spp"], r["label"])] = (r["samples"], t)
    return build, out


def main():
    before_build, before = runs(sys.argv[1])
    after_build, after = runs(sys.argv[2])
    print(f"Modelled path-state bytes per sample: before = build of {before_build}, after = build of {after_build}.\n")
    print("| job | method | before B/sample | after B/sample | change | after, per pass (B/sample) |")
    print("| --- | --- | ---: | ---: | ---: | --- |")
    for key in sorted(after):
        if key not in before:
            continue
        samples, a = after[key]
        b = before[key][1]
        change = a["bytes_per_sample"] / b["bytes_per_sample"] - 1
        per_pass = ", ".join(
            f"{p['label']} {(p['bytes_read'] + p['bytes_written']) / samples:.1f}" for p in a["passes"]
        )
        scene, w, h, spp, label = key
        print(f"| {scene} {w}x{h}x{spp} | {label} | {b['bytes_per_sample']:.1f} | {a['bytes_per_sample']:.1f} | {100 * change:+.1f}% | {per_pass} |")


if __name__ == "__main__":
    main()
