#!/usr/bin/env python3
"""The example host from an installed vergence (issue 21).

usage: host_test.py BUILD_DIR VERGENCE

`cmake --install` of the build into a scratch prefix; examples/host built
against that prefix twice, with find_package(vergence) (CMake) and with
pkg-config (its Makefile); both run headless with validation and must agree
with each other bit for bit, and with `vergence capture` of the same scene,
camera, time and rig within the tolerances below. Validation messages fail
the run (the host exits 3).
"""
import atexit
import os
import shutil
import struct
import subprocess
import sys
import tempfile

SCENE, SIZE, TIME = "content/balloon.gltf", "320x180", "1"
# Per pixel |host - capture|: two renderers rasterise the same triangles
# with matrices built by different code, so silhouettes may differ by a
# pixel; everywhere else the figures are float round-off.
TOLERANCE = {  # file: (99th percentile, largest share of pixels above 1e-2)
    "depth": (1e-3, 0.002),
    "g": (1e-3, 0.002),
    "h": (1e-3, 0.002),
}


def run(args, env=None, cwd=None):
    p = subprocess.run(args, capture_output=True, text=True, env=env, cwd=cwd, timeout=600)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(args)} exited {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-4000:]}")
    return p


def pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"Pf":
            sys.exit(f"FAIL: {path} is not a one-channel PFM")
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = f.read()
    if scale >= 0 or len(data) != 4 * w * h:
        sys.exit(f"FAIL: {path}: {len(data)} bytes for {w}x{h}, scale {scale}")
    return (w, h), struct.unpack(f"<{w * h}f", data)


def main():
    build, vergence = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="vergence_sdk_")
    atexit.register(shutil.rmtree, tmp, True)
    prefix = os.path.join(tmp, "prefix")
    run(["cmake", "--install", build, "--prefix", prefix, "--component", "sdk"])
    for need in ["include/vergence/vergence.h", "lib/cmake/vergence/vergenceConfig.cmake",
                 "lib/pkgconfig/vergence.pc", "lib/libvergence.so"]:
        if not os.path.exists(os.path.join(prefix, need)):
            sys.exit(f"FAIL: the install lacks {need}")

    # find_package(vergence): the CMake package of the install only.
    cm = os.path.join(tmp, "host-cmake")
    run(["cmake", "-S", "examples/host", "-B", cm, f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"])
    run(["cmake", "--build", cm])
    # pkg-config: the Makefile, told nothing but PKG_CONFIG_PATH.
    mk = os.path.join(tmp, "host-make")
    env = dict(os.environ, PKG_CONFIG_PATH=os.path.join(prefix, "lib", "pkgconfig"))
    run(["make", "-s", "-C", "examples/host", f"OUT={mk}"], env=env)

    outs = {}
    for name, exe in [("cmake", os.path.join(cm, "vergence_host")), ("pkg-config", os.path.join(mk, "vergence_host"))]:
        out = os.path.join(tmp, f"out-{name}")
        p = run([exe, "--scene", SCENE, "--size", SIZE, "--time", TIME, "--out", out, "--validate"])
        print(f"{name}: {p.stdout.strip()}")
        outs[name] = out
    cap = os.path.join(tmp, "capture")
    run([vergence, "capture", "--scene", SCENE, "--size", SIZE, "--time", TIME, "--mode", "manipulated",
         "--stereo-render", "cameras", "--no-reference", "--out", cap])

    failed = False
    for kind, (p99_max, share_max) in TOLERANCE.items():
        size, a = pfm(os.path.join(outs["cmake"], f"{kind}.pfm"))
        _, b = pfm(os.path.join(outs["pkg-config"], f"{kind}.pfm"))
        csize, c = pfm(os.path.join(cap, f"frame_0000_{kind}.pfm"))
        if a != b:
            print(f"FAIL: {kind}: the CMake and the pkg-config builds of the host differ")
            failed = True
        if size != csize:
            sys.exit(f"FAIL: {kind}: host {size}, capture {csize}")
        d = sorted(abs(x - y) for x, y in zip(a, c))
        p99, worst = d[int(0.99 * (len(d) - 1))], d[-1]
        share = sum(1 for x in d if x > 1e-2) / len(d)
        spread = max(c) - min(c)
        ok = p99 <= p99_max and share <= share_max and spread > 1.0
        print(f"{kind}: |host - capture| 99th pct {p99:.3g}, max {worst:.3g}, share > 1e-2 {share:.4f} "
              f"(capture spans {spread:.1f}) {'ok' if ok else 'FAIL'}")
        failed |= not ok
    if failed:
        sys.exit("FAIL: the host's maps are not vergence capture's")
    print("host: ok")


if __name__ == "__main__":
    main()
