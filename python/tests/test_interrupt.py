"""Ctrl-C: KeyboardInterrupt within a second, the next call unaffected, and an interrupted
experiment that `resume=True` finishes. Each in its own Python process, so that the SIGINT
(sent by the process to itself, as a terminal's Ctrl-C is) cannot reach pytest."""

import json
import subprocess
import sys
import textwrap

import wavetrace as wt

PRELUDE = """
import json, os, signal, sys, threading, time
import wavetrace as wt
# Python leaves SIGINT ignored when it starts with it ignored (a background job of a
# non-interactive shell, as CI may run this): install the handler an interactive session has.
signal.signal(signal.SIGINT, signal.default_int_handler)
sent = []
def interrupt_when(ready):
    def watch():
        while not ready():
            time.sleep(0.01)
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)
    threading.Thread(target=watch, daemon=True).start()
"""


def python(code, cwd):
    p = subprocess.run([sys.executable, "-c", PRELUDE + textwrap.dedent(code)], capture_output=True, text=True, cwd=cwd)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_an_interrupted_render_raises_keyboard_interrupt_within_a_second(tmp_path):
    out = python(
        """
        start = time.perf_counter()
        interrupt_when(lambda: time.perf_counter() - start > 0.3)
        try:
            wt.render("cornell", "cpu", 320, 240, spp=64, progress=False)
            result = {"interrupted": False}
        except KeyboardInterrupt:
            result = {"interrupted": True, "latency": time.perf_counter() - sent[0]}
        # The next render runs to its end: the request was withdrawn.
        result["after"] = wt.render("three-spheres", "cpu", 8, 8, spp=1).image.shape
        print(json.dumps(result))
        """,
        tmp_path,
    )
    assert out["interrupted"] and out["latency"] < 1.0, out
    assert out["after"] == [8, 8, 3]


def test_an_interrupted_experiment_resumes(tmp_path):
    config = {
        "schema": "wavetrace-experiment/1",
        "question": "Is an interrupted experiment resumable?",
        "scenes": ["cornell"],
        "resolutions": ["48x32"],
        # Plan order: spp innermost. The first run is quick; the second (about a second on the
        # software driver's machine) is interrupted, then rendered again by the resume.
        "spp": [1, 512],
        "repetitions": 1,
        "warmup": 0,
        "methods": [{"method": "cpu"}],
    }
    out = python(
        f"""
        config = {config!r}
        out = "out"
        def one_run_done():
            try:
                return len(json.load(open(os.path.join(out, "report.json")))["runs"]) >= 1
            except (OSError, ValueError, KeyError):
                return False
        interrupt_when(one_run_done)
        try:
            wt.run(config, out=out)
            result = {{"interrupted": False}}
        except KeyboardInterrupt:
            result = {{"interrupted": True, "latency": time.perf_counter() - sent[0]}}
        r = wt.load_report(out)
        result["status"], result["runs"] = r.status, [x["spp"] for x in r.runs]
        done = wt.run(config, out=out, resume=True)
        result["resumed"] = [(x["spp"], x["status"], x["resumed"]) for x in done.runs]
        result["final"] = done.status
        print(json.dumps(result))
        """,
        tmp_path,
    )
    assert out["interrupted"] and out["latency"] < 1.0, out
    assert out["status"] == "running" and out["runs"] == [1], out
    assert out["resumed"] == [[1, "ok", True], [512, "ok", False]] and out["final"] == "complete", out
