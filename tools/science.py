#!/usr/bin/python3
"""vergence science sweeps: the method's open choices measured on the content
scenes, printed as the Markdown tables of docs/method.md.

    tools/science.py look-ahead|saliency|sensitivity [--build build] [--out /tmp/vergence-science]

look-ahead: every content scene captured with the keyframe window's future
the scene's own (foresight, the default) and predicted from the past only
(causal), and each foresight capture optimised offline both ways
(`optimize --capture DIR --look-ahead ...`). Figures: MID distortion of h and
f (JND), f/h, f's range violation and static RMS. Takes about 5 minutes on 2
cores (lavapipe). sensitivity: the choices the paper leaves open, one at a time against the
defaults, with `vergence optimize` on captures of every content scene (at
keyframe strides 5, 10 and 20) and on a synthetic sequence written here (a
ball thrown toward the viewer over a static slanted background, with its
exact flow): f/h of the MID distortion and f's static RMS. About 20 minutes.

Not a test: it prints figures.
"""
import argparse
import glob
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))  # vgformats (numpy), imported by the sweeps that use it
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
            "ungated": metrics.get("ungated_mid_ratio", float("nan")),
            "violation": f["range_violation"], "static": f["static_rms"]}


def capture(a, name, extra, label, flags):
    """vergence capture of content scene `name` into OUT/<name>_<label>: (folder, figures)."""
    out = os.path.join(a.out, f"{name}_{label}")
    print(f"science: capture {name} {' '.join(flags)}", file=sys.stderr)
    vergence(a.build, ["capture", "--scene", os.path.join("content", name + ".gltf"), "--out", out] + flags +
             CAPTURE + extra, out + ".log")
    with open(os.path.join(out, "capture.json")) as f:
        return out, figures(json.load(f)["metrics"])


def look_ahead(a):
    rows = []
    for name, extra in SCENES:
        caps = {m: capture(a, name, extra, m, ["--look-ahead", m])[1] for m in ("foresight", "causal")}
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
          "optimize f/h causal | optimize causal, its solve's own f/h | f range violation (causal) | "
          "f static RMS foresight / causal (arcmin) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, c, o in rows:
        label = name + (" (throw 0)" if name == "arena" else "")
        print(f"| {label} | {c['foresight']['h']:.3f} | {c['foresight']['ratio']:.3f} | {c['causal']['ratio']:.3f} | "
              f"{o['foresight']['ratio']:.3f} | {o['causal']['ratio']:.3f} | {o['causal']['ungated']:.3f} | "
              f"{max(c['causal']['violation'], o['causal']['violation']):.4f} | "
              f"{c['foresight']['static']:.3f} / {c['causal']['static']:.3f} |")


def saliency(a):
    import numpy as np
    from vgformats import read_pfm
    print("| scene | h MID authored / computed (JND) | f/h authored / computed | mean abs h change (arcmin) | "
          "99th percentile (arcmin) |")
    print("|---|---:|---:|---:|---:|")
    for name, extra in SCENES:
        runs = {m: capture(a, name, extra, "saliency_" + m, ["--saliency", m]) for m in ("authored", "computed")}
        diffs = np.concatenate([np.abs(read_pfm(p) - read_pfm(os.path.join(runs["computed"][0], os.path.basename(p))))
                                .ravel()
                                for p in sorted(glob.glob(os.path.join(runs["authored"][0], "frame_*_h.pfm")))])
        ma, mc = runs["authored"][1], runs["computed"][1]
        label = name + (" (throw 0)" if name == "arena" else "")
        print(f"| {label} | {ma['h']:.3f} / {mc['h']:.3f} | {ma['ratio']:.3f} / {mc['ratio']:.3f} | "
              f"{diffs.mean():.3f} | {np.percentile(diffs, 99):.3f} |")


def synthetic(out, frames=121, w=320, h=180):
    """A ball thrown toward the viewer (g 250 -> 400 arcmin, accelerating)
    across a static background slanted in depth (230 .. 330 arcmin, bottom
    nearer); g, flow to the next frame, frames 0 .. frames - 1."""
    import numpy as np
    from vgformats import write_flo, write_pfm
    os.makedirs(out, exist_ok=True)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    bg = 230.0 + 100.0 * yy / (h - 1)

    def ball(t):
        s = t / (frames - 1)
        return 40.0 + 240.0 * s, 70.0 + 30.0 * s, 8.0 + 22.0 * s * s, 250.0 + 150.0 * s * s

    for t in range(frames):
        cx, cy, r, gb = ball(t)
        inside = (xx - cx) ** 2 + (yy - cy) ** 2 <= r * r
        write_pfm(os.path.join(out, f"g_{t:04d}.pfm"), np.where(inside, gb, bg).astype(np.float32))
        nx_, ny_, nr, _ = ball(min(t + 1, frames - 1))
        u = np.where(inside, nx_ + (xx - cx) * nr / r - xx, 0.0)
        v = np.where(inside, ny_ + (yy - cy) * nr / r - yy, 0.0)
        write_flo(os.path.join(out, f"flow_{t:04d}.flo"), np.stack([u, v], axis=-1).astype(np.float32))
    return frames


VARIANTS = [  # label, optimize flags (the stride variants use other captures)
    ("defaults (a on the range, per second, Gauss-Newton 4 iterations, stride 10, grid 5 px)", []),
    ("a: dh in arcmin per coarse sample", ["--edge-norm", "arcmin"]),
    ("a: dh in arcmin per pixel", ["--edge-norm", "pixel"]),
    ("velocities per keyframe interval", ["--velocity-unit", "keyframe"]),
    ("Gauss-Newton 3 iterations (the engine's per window move)", ["--iterations", "3"]),
    ("Gauss-Newton 8 iterations", ["--iterations", "8"]),
    ("Gauss-Newton 20 iterations", ["--iterations", "20"]),
    ("the paper's descent (8 x 0.5)", ["--solver", "descent"]),
    ("w_data x0.5", ["--weights", "0.025,1,0.1,0.1"]),
    ("w_data x2", ["--weights", "0.1,1,0.1,0.1"]),
    ("w_spatial x0.5", ["--weights", "0.05,0.5,0.1,0.1"]),
    ("w_spatial x2", ["--weights", "0.05,2,0.1,0.1"]),
    ("w_temporal x0.5", ["--weights", "0.05,1,0.05,0.1"]),
    ("w_temporal x2", ["--weights", "0.05,1,0.2,0.1"]),
    ("w_accel x0.5", ["--weights", "0.05,1,0.1,0.05"]),
    ("w_accel x2", ["--weights", "0.05,1,0.1,0.2"]),
    ("keyframe stride 5", "stride5"),
    ("keyframe stride 20", "stride20"),
    ("coarse grid 3 px", ["--coarse", "3"]),
    ("coarse grid 10 px", ["--coarse", "10"]),
]


def sensitivity(a):
    names = [n for n, _ in SCENES] + ["synthetic"]
    syn = os.path.join(a.out, "synthetic")
    print("science: synthetic sequence", file=sys.stderr)
    frames = synthetic(syn)
    caps = {(name, stride): capture(a, name, extra, f"stride{stride}", ["--keyframe-stride", str(stride)])[0]
            for name, extra in SCENES for stride in (5, 10, 20)}
    rows = []
    for label, flags in VARIANTS:
        stride = 5 if flags == "stride5" else 20 if flags == "stride20" else 10
        flags = [] if isinstance(flags, str) else flags
        cells = []
        for name in names:
            out = os.path.join(a.out, "sens_" + name)
            print(f"science: optimize {name}: {label}", file=sys.stderr)
            if name == "synthetic":
                src = ["--g", os.path.join(syn, "g_%04d.pfm"), "--flow-next", os.path.join(syn, "flow_%04d.flo"),
                       "--frames", f"0:{frames - 1}", "--keyframe-stride", str(stride)]
            else:
                src = ["--capture", caps[(name, stride)]]
            vergence(a.build, ["optimize"] + src + ["--out", out, "--no-video"] + flags, out + ".log")
            with open(os.path.join(out, "metrics.json")) as f:
                cells.append(figures(json.load(f)))
        rows.append((label, cells))
    print("f/h of the MID distortion (f's static RMS, arcmin); `vergence optimize` on 121 frames at 320 x 180 "
          "(the content scenes' captures from 1 s; the arena with throw 0). A `!` marks f outside the range; `–`: "
          "no sample of h moves in depth there (nothing to measure).\n")
    print("| choice | " + " | ".join(names) + " |")
    print("|---|" + "---:|" * len(names))
    for label, cells in rows:
        print(f"| {label} | " + " | ".join(("–" if c["ratio"] != c["ratio"] else f"{c['ratio']:.3f}") +
                                           f" ({c['static']:.2f}){'!' if c['violation'] > 0 else ''}"
                                           for c in cells) + " |")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sweep", choices=["look-ahead", "saliency", "sensitivity"])
    p.add_argument("--build", default=os.path.join(ROOT, "build"), help="the Release build folder")
    p.add_argument("--out", default="/tmp/vergence-science", help="captures and optimize results go here")
    a = p.parse_args()
    if not os.path.exists(os.path.join(a.build, "game", "vergence")):
        sys.exit(f"science: {a.build}/game/vergence is missing: build first (tools/dev build)")
    os.makedirs(a.out, exist_ok=True)
    {"look-ahead": look_ahead, "saliency": saliency, "sensitivity": sensitivity}[a.sweep](a)


if __name__ == "__main__":
    main()
