#!/usr/bin/python3
"""vergence science sweeps: the method's open choices measured on the content
scenes, printed as the Markdown tables of docs/method.md.

    tools/science.py look-ahead|saliency [--build build] [--out /tmp/vergence-science]

look-ahead: every content scene captured with the keyframe window's future
the scene's own (foresight, the default) and predicted from the past only
(causal), and each foresight capture optimised offline both ways
(`optimize --capture DIR --look-ahead ...`). Figures: MID distortion of h and
f (JND), f/h, f's range violation and static RMS. Takes about 5 minutes on 2
cores (lavapipe). Not a test: it prints figures.
"""
import argparse
import glob
import json
import os
import struct
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = [  # name, extra capture flags
    ("balloon", []),
    ("cubes", []),
    ("bird", []),
    ("arena", ["--throw", "0"]),
]
CAPTURE = ["--size", "320x180", "--frames", "121", "--time", "1", "--no-reference"]


def vergence(build, args, log):
    exe = os.path.join(build, "game", "vergence")
    with open(log, "w") as f:
        r = subprocess.run([exe] + args, stdout=f, stderr=subprocess.STDOUT, cwd=ROOT)
    if r.returncode != 0:
        sys.exit(f"science: vergence {' '.join(args[:1])} failed (exit {r.returncode}); see {log}")


def figures(metrics):
    h, f = metrics["h"], metrics["f"]
    hm, fm = h["mid_distortion_jnd"], f["mid_distortion_jnd"]
    return {"h": hm, "f": fm, "ratio": fm / hm if hm > 0 else float("nan"),
            "violation": f["range_violation"], "static": f["static_rms"]}


def look_ahead(a):
    rows = []
    for name, extra in SCENES:
        scene = os.path.join("content", name + ".gltf")
        caps = {}
        for mode in ("foresight", "causal"):
            out = os.path.join(a.out, f"{name}_{mode}")
            print(f"science: capture {name} --look-ahead {mode}", file=sys.stderr)
            vergence(a.build, ["capture", "--scene", scene, "--out", out, "--look-ahead", mode] + CAPTURE + extra,
                     out + ".log")
            with open(os.path.join(out, "capture.json")) as f:
                caps[mode] = figures(json.load(f)["metrics"])
        opts = {}
        for mode in ("foresight", "causal"):
            out = os.path.join(a.out, f"{name}_optimize_{mode}")
            print(f"science: optimize {name} --look-ahead {mode}", file=sys.stderr)
            vergence(a.build, ["optimize", "--capture", os.path.join(a.out, f"{name}_foresight"), "--out", out,
                               "--look-ahead", mode, "--no-video"], out + ".log")
            with open(os.path.join(out, "metrics.json")) as f:
                opts[mode] = figures(json.load(f))
        rows.append((name, caps, opts))
    print("| scene | h MID (JND) | engine f/h foresight | engine f/h causal | optimize f/h foresight | "
          "optimize f/h causal | f range violation (causal) | f static RMS foresight / causal (arcmin) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, c, o in rows:
        label = name + (" (throw 0)" if name == "arena" else "")
        print(f"| {label} | {c['foresight']['h']:.3f} | {c['foresight']['ratio']:.3f} | {c['causal']['ratio']:.3f} | "
              f"{o['foresight']['ratio']:.3f} | {o['causal']['ratio']:.3f} | "
              f"{max(c['causal']['violation'], o['causal']['violation']):.4f} | "
              f"{c['foresight']['static']:.3f} / {c['causal']['static']:.3f} |")


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    w, h = map(int, parts[1].split())
    scale = float(parts[2])
    return struct.unpack(("<" if scale < 0 else ">") + "%df" % (w * h), parts[3][:4 * w * h])


def saliency(a):
    print("| scene | h MID authored / computed (JND) | f/h authored / computed | mean abs h change (arcmin) | "
          "99th percentile (arcmin) |")
    print("|---|---:|---:|---:|---:|")
    for name, extra in SCENES:
        scene = os.path.join("content", name + ".gltf")
        runs = {}
        for mode in ("authored", "computed"):
            out = os.path.join(a.out, f"{name}_saliency_{mode}")
            print(f"science: capture {name} --saliency {mode}", file=sys.stderr)
            vergence(a.build, ["capture", "--scene", scene, "--out", out, "--saliency", mode] + CAPTURE + extra,
                     out + ".log")
            with open(os.path.join(out, "capture.json")) as f:
                runs[mode] = (out, figures(json.load(f)["metrics"]))
        diffs = []
        for path in sorted(glob.glob(os.path.join(runs["authored"][0], "frame_*_h.pfm"))):
            other = os.path.join(runs["computed"][0], os.path.basename(path))
            diffs += [abs(x - y) for x, y in zip(read_pfm(path), read_pfm(other))]
        diffs.sort()
        ma, mc = runs["authored"][1], runs["computed"][1]
        label = name + (" (throw 0)" if name == "arena" else "")
        print(f"| {label} | {ma['h']:.3f} / {mc['h']:.3f} | {ma['ratio']:.3f} / {mc['ratio']:.3f} | "
              f"{sum(diffs) / len(diffs):.3f} | {diffs[int(0.99 * (len(diffs) - 1))]:.3f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sweep", choices=["look-ahead", "saliency"])
    p.add_argument("--build", default=os.path.join(ROOT, "build"), help="the Release build folder")
    p.add_argument("--out", default="/tmp/vergence-science", help="captures and optimize results go here")
    a = p.parse_args()
    if not os.path.exists(os.path.join(a.build, "game", "vergence")):
        sys.exit(f"science: {a.build}/game/vergence is missing: build first (tools/dev build)")
    os.makedirs(a.out, exist_ok=True)
    {"look-ahead": look_ahead, "saliency": saliency}[a.sweep](a)


if __name__ == "__main__":
    main()
