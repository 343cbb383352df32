#!/usr/bin/env python3
"""Every test's ctest TIMEOUT holds on a slower day (issue 44).

usage: timeouts_test.py CTEST BUILD_DIR

This machine runs the suite up to 2.5x slower from one day to the next (and
slower still under other loads), so each test's TIMEOUT must be at least
MARGIN times its time on a normal run. The times are those of the suite's
last run in BUILD_DIR (last-run.xml, the JUnit file tools/dev test asks
ctest for); the limits are the TIMEOUT properties the build declares
(ctest --show-only=json-v1). A test that failed last time is left out unless
it ran into its limit (a timeout is what this check is about). Before any
run has been recorded there is nothing to compare: the check says so and
passes. It prints the tightest tests, limit against time, either way.
"""
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

MARGIN = 3.0
DEFAULT_TIMEOUT = 1500.0  # ctest's own when a test declares none (DART_TESTING_TIMEOUT)
JUNIT = "last-run.xml"    # in BUILD_DIR: tools/dev test's ctest --output-junit


def costs(build):
    """{test: seconds} of the last recorded run, and the tests that failed in it."""
    # The JUnit file of the suite's last run (tools/dev test writes it with
    # --output-junit): each test's measured time. CTestCostData.txt is not
    # usable: ctest keeps a scheduling cost there, not the time (a test of
    # 8-13 s stood at 504).
    path = os.path.join(build, JUNIT)
    times, failed = {}, set()
    if not os.path.exists(path):
        return times, failed
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        sys.exit(f"FAIL: {path}: not a JUnit file ({e})")
    for case in root.iter("testcase"):
        name, status = case.get("name"), case.get("status", "run")
        try:
            times[name] = float(case.get("time", "0"))
        except ValueError:
            continue
        if status == "fail" or case.find("failure") is not None:
            failed.add(name)
    return times, failed


def limits(ctest, build):
    """{test: TIMEOUT seconds} the build declares."""
    p = subprocess.run([ctest, "--test-dir", build, "--show-only=json-v1"], capture_output=True, text=True,
                       timeout=120)
    if p.returncode != 0:
        sys.exit(f"FAIL: ctest --show-only failed:\n{p.stderr}")
    out = {}
    for t in json.loads(p.stdout)["tests"]:
        props = {q["name"]: q["value"] for q in t.get("properties", [])}
        out[t["name"]] = float(props.get("TIMEOUT", DEFAULT_TIMEOUT))
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    ctest, build = sys.argv[1], sys.argv[2]
    times, failed = costs(build)
    limit = limits(ctest, build)
    me = "timeouts.margin"
    rows = []
    for name, seconds in times.items():
        if name == me or name not in limit or seconds <= 0:
            continue
        timed_out = name in failed and seconds >= 0.95 * limit[name]
        if name in failed and not timed_out:
            continue
        rows.append((limit[name] / seconds, name, seconds, limit[name], timed_out))
    if not rows:
        print(f"no earlier run of {build} is recorded: nothing to compare yet ({len(limit)} tests declare limits)")
        return
    rows.sort()
    print(f"{len(rows)} tests with a recorded time; the tightest (TIMEOUT / time, want >= {MARGIN:g}):")
    for ratio, name, seconds, lim, timed_out in rows[:8]:
        print(f"  {ratio:7.1f}x  {name}: {seconds:.1f} s against a TIMEOUT of {lim:.0f} s"
              f"{' (it timed out last run)' if timed_out else ''}")
    short = [r for r in rows if r[0] < MARGIN or r[4]]
    if short:
        print("FAIL: TIMEOUT below %g x the recorded time (raise the TIMEOUT in the test's CMakeLists.txt, or make "
              "the test faster):" % MARGIN)
        for ratio, name, seconds, lim, timed_out in short:
            print(f"  {name}: {seconds:.1f} s, TIMEOUT {lim:.0f} s ({ratio:.1f}x)")
        sys.exit(1)
    print(f"every recorded test has its TIMEOUT at {rows[0][0]:.1f}x its time or more")


if __name__ == "__main__":
    main()
