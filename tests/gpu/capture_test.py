#!/usr/bin/env python3
"""`vergence capture` with the GPU disparity pipeline (issue 4).

usage: capture_test.py VERGENCE CASE

  files   a short capture writes frame_NNNN_{g,h,f}.pfm for every frame and the
          `metrics` object of capture.json, shaped as `vergence optimize`'s
          metrics.json (h and f: mid_distortion_jnd, range_violation, static_rms)
  graph   the full frame's graph dump names every disparity pass
  variants  on lavapipe, frames after the first compile no new shader variant
          (Mesa's shader cache, empty at the start, counts them); exit 77
          (skipped) on another driver

Validation is on (VERGENCE_VALIDATE=1 from CTest): any message fails the run.
The 240-frame figures are tests/gpu/test_frame_gpu.c (no files: faster).
"""
import atexit
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "tools"))
import vgformats  # noqa: E402


def scratch(prefix):
    """A temporary directory removed when the test exits."""
    path = tempfile.mkdtemp(prefix=prefix)
    atexit.register(shutil.rmtree, path, True)
    return path


def capture(scene, frames, size, extra=()):
    out = scratch("vergence_gpu_")
    args = [VERGENCE, "capture", "--scene", f"content/{scene}.gltf", "--frames", str(frames), "--size", size,
            "--no-reference", "--out", out] + list(extra)
    p = subprocess.run(args, capture_output=True, text=True, timeout=1200)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(args)} exited {p.returncode}\n{p.stderr[-4000:]}")
    with open(os.path.join(out, "capture.json")) as f:
        return out, json.load(f), p


def case_files():
    frames = 25
    out, j, _ = capture("cubes", frames, "160x90", ["--stereo-render", "cameras", "--operator", "lang"])
    differ = 0
    for n in range(frames):
        maps = {k: vgformats.read_pfm(os.path.join(out, f"frame_{n:04d}_{k}.pfm"), 1, "<").reshape(-1).tolist()
                for k in "ghf"}
        if not all(0 < v < 1e4 for k in "hf" for v in maps[k]):
            sys.exit(f"FAIL: frame {n}: h or f outside (0, 1e4) arcmin")
        differ += sum(abs(a - b) > 0.01 for a, b in zip(maps["h"], maps["f"]))
    m = j.get("metrics")
    if not m:
        sys.exit("FAIL: capture.json has no metrics")
    for k in ("h", "f"):
        for key in ("mid_distortion_jnd", "range_violation", "static_rms"):
            if not isinstance(m[k].get(key), (int, float)):
                sys.exit(f"FAIL: metrics.{k}.{key} missing")
    if m["f"]["range_violation"] != 0 or not differ:
        sys.exit(f"FAIL: f range violation {m['f']['range_violation']}, f differs from h at {differ} pixels")
    print(f"{frames} frames: g, h, f written; f differs from h at {differ} pixels; metrics h MID "
          f"{m['h']['mid_distortion_jnd']:.3f}, f MID {m['f']['mid_distortion_jnd']:.3f} JND, "
          f"{m['keyframes']} keyframes")


def case_graph():
    tmp = scratch("vergence_gpu_graph_")
    dot = os.path.join(tmp, "frame.dot")
    _, _, p = capture("cubes", 1, "64x36", ["--dump-graph", dot])
    for name in ("disparity.original", "disparity.operator.fit", "disparity.operator", "mid.keyframes",
                 "mid.keyframes.fit", "mid.keyframes.store", "mid.window", "mid.solve", "mid.upsample.time",
                 "mid.upsample.space", "warp.curve.range"):
        if f" {name} " not in p.stdout:
            sys.exit(f"FAIL: the graph dump lacks '{name}'")
    print("the graph dump names every disparity pass")


def case_variants():
    """lavapipe specialises a shader on the uniform values that decide its
    branches and compiles it again for every new set (docs/architecture.md,
    "Shader variants on lavapipe"): a uniform that changes every frame costs
    an LLVM compile every frame on a fresh machine. bird's camera moves, so
    every frame has a new view; the second capture goes past the first's two
    frames and over a keyframe boundary and must compile nothing."""
    cache = scratch("vergence_mesa_cache_")
    os.environ["MESA_SHADER_CACHE_DIR"] = cache
    os.environ.pop("MESA_SHADER_CACHE_DISABLE", None)

    def entries():
        return sum(len(files) for _, _, files in os.walk(cache))

    _, j, _ = capture("bird", 2, "96x54")
    device = j["device"]["name"]
    if "llvmpipe" not in device:
        print(f"{device} is not lavapipe: nothing to count")
        sys.exit(77)
    first = entries()
    if first == 0:
        sys.exit(f"FAIL: Mesa's shader cache in {cache} stayed empty: the variants cannot be counted")
    capture("bird", 14, "96x54")
    added = entries() - first
    print(f"shader cache: {first} entries after 2 frames, {added} more after 14 frames")
    if added:
        sys.exit(f"FAIL: frames 2-13 compiled {added} new shader variant(s)")


if __name__ == "__main__":
    VERGENCE = sys.argv[1]
    {"files": case_files, "graph": case_graph, "variants": case_variants}[sys.argv[2]]()
