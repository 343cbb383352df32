#!/usr/bin/env python3
"""libvergence.so against the ABI of its last release (issue 42).

abidiff (Debian's abigail-tools) compares the stored dump of the release,
sdk/abi/vergence-0.1.xml (abidw over the library with the public headers,
include/vergence), with the library just built. A function or variable
removed or changed (a public type's size or a member's offset moved:
abidiff counts these as changes, and flags only removals incompatible), a
changed SONAME or an abidiff error fails; additions pass and are listed,
and so do the members a desc gains at its end (SUPPRESSIONS: the growth
vergence.h promises, its library reading a host's desc by the host's
header version).

usage: abi_test.py LIBRARY BASELINE.xml HEADERS_DIR SUPPRESSIONS
"""
import re
import shutil
import subprocess
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    lib, baseline, headers, suppressions = sys.argv[1:]
    if not shutil.which("abidiff"):
        sys.exit("FAIL: abidiff is not installed (Debian package abigail-tools; tools/dev deps installs it)")
    p = subprocess.run(["abidiff", "--headers-dir2", headers, "--suppressions", suppressions, baseline, lib],
                       capture_output=True, text=True)
    report = (p.stdout + p.stderr).strip()
    print(report or "(no difference)")
    if p.returncode & 3:
        sys.exit(f"FAIL: abidiff could not compare {baseline} with {lib} (exit {p.returncode})")
    counts = re.findall(r"(Functions|Variables) changes summary: (\d+) Removed, (\d+) Changed", report)
    if p.returncode & 4 and not counts:
        sys.exit("FAIL: abidiff reported a change this test cannot read")
    broken = [f"{what}: {removed} removed, {changed} changed" for what, removed, changed in counts
              if int(removed) or int(changed)]
    if "SONAME changed" in report:
        broken.append("the SONAME changed (a host linked against the release would not find the library)")
    if p.returncode & 8 or broken:
        sys.exit(f"FAIL: {lib} breaks the ABI of {baseline} ({'; '.join(broken) or 'incompatible'}): a host "
                 "built against that release would not run")
    print(f"ok: {lib} keeps the ABI of {baseline}" + (" (with additions)" if p.returncode & 4 else ""))


if __name__ == "__main__":
    main()
