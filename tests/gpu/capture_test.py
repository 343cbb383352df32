#!/usr/bin/env python3
"""The GPU disparity pipeline end to end, through `vergence capture` (issue 4).

usage: capture_test.py VERGENCE CASE

  mid.cubes       240 frames of cubes (lang): f's MID distortion at most half of
                  h's, no range violation, and no pop at keyframe boundaries: the
                  temporal second difference of f there no larger than between them
  mid.balloon     240 frames of balloon (lang): f's MID distortion below h's, no
                  range violation (the figures are reported; see docs/method.md)
  modes.MODE      240 frames in MODE: validation (with synchronization validation)
                  stays silent (vergence exits non-zero on any message)
  graph           the full frame's graph dump names every disparity pass

Validation is on (VERGENCE_VALIDATE=1 from CTest).
"""
import json
import os
import subprocess
import sys
import tempfile


def capture(scene, frames, size, extra=()):
    out = tempfile.mkdtemp(prefix="vergence_gpu_")
    args = [VERGENCE, "capture", "--scene", f"content/{scene}.gltf", "--frames", str(frames), "--size", size,
            "--no-reference", "--out", out] + list(extra)
    p = subprocess.run(args, capture_output=True, text=True, timeout=3000)
    if p.returncode != 0:
        sys.exit(f"FAIL: {' '.join(args)} exited {p.returncode}\n{p.stderr[-4000:]}")
    with open(os.path.join(out, "capture.json")) as f:
        return out, json.load(f), p


def metrics(j, scene):
    m = j["metrics"]
    h, f = m["h"], m["f"]
    print(f"{scene}: MID distortion h {h['mid_distortion_jnd']:.3f} JND, f {f['mid_distortion_jnd']:.3f} JND "
          f"({f['mid_distortion_jnd'] / h['mid_distortion_jnd']:.3f} of h's) over {f['moving_samples']} moving samples "
          f"of {m['keyframes']} keyframes; range violation h {h['range_violation']}, f {f['range_violation']}; "
          f"static RMS f {f['static_rms']:.3f} arcmin")
    for k in ("h", "f"):
        d = m[k]["second_difference"]
        print(f"{scene}: mean |second difference| of {k}: {d['at_keyframe_boundaries']:.4f} arcmin at keyframe "
              f"boundaries, {d['between_keyframes']:.4f} between them")
    return h, f


def case_mid(scene):
    # Two real cameras make the pair: the cheapest, and the disparity passes do not depend on it.
    _, j, _ = capture(scene, 240, "320x180", ["--mode", "optimized", "--operator", "lang", "--stereo-render", "cameras"])
    h, f = metrics(j, scene)
    if f["range_violation"] != 0:
        sys.exit(f"FAIL: f leaves the target range at {f['range_violation']} of the pixels")
    if not f["mid_distortion_jnd"] < h["mid_distortion_jnd"]:
        sys.exit("FAIL: f does not reduce the MID distortion")
    if scene == "cubes":
        if f["mid_distortion_jnd"] > 0.5 * h["mid_distortion_jnd"]:
            sys.exit("FAIL: f's MID distortion is more than half of h's")
        d = f["second_difference"]
        if d["at_keyframe_boundaries"] > d["between_keyframes"]:
            sys.exit("FAIL: f changes more at keyframe boundaries than between them (a pop)")


def case_modes(mode):
    _, j, _ = capture("cubes", 240, "96x54", ["--mode", mode])
    if j["validation_messages"] != 0:
        sys.exit(f"FAIL: {j['validation_messages']} validation messages")
    print(f"{mode}: 240 frames, validation silent")


def case_graph():
    tmp = tempfile.mkdtemp(prefix="vergence_gpu_graph_")
    dot = os.path.join(tmp, "frame.dot")
    _, _, p = capture("cubes", 1, "64x36", ["--dump-graph", dot])
    for name in ("disparity.original", "disparity.operator.fit", "disparity.operator", "mid.keyframes",
                 "mid.keyframes.fit", "mid.keyframes.store", "mid.window", "mid.solve", "mid.upsample.time",
                 "mid.upsample.space", "warp.curve.range"):
        if f" {name} " not in p.stdout:
            sys.exit(f"FAIL: the graph dump lacks '{name}'")
    print("the graph dump names every disparity pass")


if __name__ == "__main__":
    VERGENCE, case = sys.argv[1], sys.argv[2]
    kind, _, arg = case.partition(".")
    {"mid": lambda: case_mid(arg), "modes": lambda: case_modes(arg), "graph": case_graph}[kind]()
