#!/usr/bin/env python3
"""Loads every .gltf and .glb under a folder with scene_probe and checks the
counts it reports against the file's own JSON (the JSON chunk of a .glb is
parsed here). Standard library only.

usage: check_assets.py SCENE_PROBE ASSET_DIR
"""
import json
import os
import struct
import subprocess
import sys



def read_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":
        # GLB: 12-byte header, then chunk 0 = (length, "JSON", bytes).
        length, kind = struct.unpack_from("<II", data, 12)
        assert kind == 0x4E4F534A, "first chunk is not JSON"
        return json.loads(data[20:20 + length].decode("utf-8"))
    return json.loads(data.decode("utf-8"))


def expected(doc, max_textures):
    """What the loader should report, computed from the JSON alone."""
    meshes = doc.get("meshes", [])
    nodes = doc.get("nodes", [])
    kept = [sum(1 for p in m.get("primitives", []) if p.get("mode", 4) >= 4) for m in meshes]
    # Instances: depth-first over the default scene, children in file order.
    scenes = doc.get("scenes", [])
    if scenes:
        roots = scenes[doc.get("scene", 0)].get("nodes", [])
    else:
        children = {c for n in nodes for c in n.get("children", [])}
        roots = [i for i in range(len(nodes)) if i not in children]
    instances = 0
    stack = list(reversed(roots))
    while stack:
        i = stack.pop()
        if "mesh" in nodes[i]:
            instances += kept[nodes[i]["mesh"]]
        stack.extend(reversed(nodes[i].get("children", [])))
    base_textures = {m["pbrMetallicRoughness"]["baseColorTexture"]["index"]
                     for m in doc.get("materials", [])
                     if "baseColorTexture" in m.get("pbrMetallicRoughness", {})}
    anims = doc.get("animations", [])
    accessors = doc.get("accessors", [])
    ends = [accessors[s["input"]]["max"][0] for a in anims for s in a["samplers"]
            if "max" in accessors[s["input"]]]
    return {
        "nodes": len(nodes),
        "meshes": len(meshes),
        "primitives": sum(kept),
        "materials": len(doc.get("materials", [])),
        "cameras": len(doc.get("cameras", [])),
        "skins": len(doc.get("skins", [])),
        "animations": len(anims),
        "samplers": sum(len(a["samplers"]) for a in anims),
        "channels": sum(len(a["channels"]) for a in anims),
        "instances": instances,
        "textures": min(max_textures, len(base_textures)),
        "duration": max(ends) if ends else 0.0,
    }


def main():
    probe, root = sys.argv[1], sys.argv[2]
    files = sorted(os.path.join(d, f) for d, _, names in os.walk(root)
                   for f in names if f.endswith((".gltf", ".glb")))
    if not files:
        print(f"no .gltf/.glb under {root}")
        return 1
    failures = 0
    kinds = set()
    for path in files:
        kinds.add(os.path.basename(os.path.dirname(path)))
        doc = read_json(path)
        duration = expected(doc, 1 << 30)["duration"]
        run = subprocess.run([probe, path, "--time", str(duration * 0.5)],
                             capture_output=True, text=True, timeout=120)
        problems = []
        if run.returncode != 0:
            problems.append(f"exit {run.returncode}: {run.stderr.strip()}")
        else:
            got = json.loads(run.stdout)
            want = expected(doc, got["max_textures"])  # SCENE_MAX_TEXTURES
            for key, value in want.items():
                if key == "duration":
                    if abs(got[key] - value) > 1e-4 * max(1.0, value):
                        problems.append(f"duration {got[key]} != {value}")
                elif got[key] != value:
                    problems.append(f"{key} {got[key]} != {value}")
            if got["indices"] % 3:
                problems.append(f"{got['indices']} indices is not a triangle list")
            if got["instances"] and not got["vertices"]:
                problems.append("instances without vertices")
            if "error" in run.stderr:
                problems.append(f"stderr: {run.stderr.strip()}")
        status = "ok" if not problems else "FAIL " + "; ".join(problems)
        print(f"{path}: {status}")
        failures += bool(problems)
    print(f"{len(files)} files ({', '.join(sorted(kinds))}), {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
