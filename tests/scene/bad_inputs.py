#!/usr/bin/env python3
"""Bad glTF inputs: each case is written to a temporary folder and loaded
with scene_probe, which must fail with the expected status (exit code),
print exactly one error line naming the file, and not crash.

usage: bad_inputs.py SCENE_PROBE ASSET_DIR CASE
"""
import base64
import json
import os
import shutil
import struct
import subprocess
import sys
import tempfile

IO, FORMAT, UNSUPPORTED = 3, 4, 10  # vg_status_exit_code


def triangle(indices=(0, 1, 2), extra=None):
    """A one-triangle glTF with an embedded buffer."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    idx = struct.pack(f"<{len(indices)}H", *indices)
    idx += b"\0" * (-len(idx) % 4)
    data = pos + idx
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 2 * len(indices)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                      {"bufferView": 1, "componentType": 5123, "count": len(indices), "type": "SCALAR"}],
    }
    if extra:
        extra(doc)
    return json.dumps(doc)


def write(path, data):
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)
    return path


def box(tmp, assets):
    """Box.gltf with its external Box0.bin copied next to it."""
    src = os.path.join(assets, "Box", "glTF")
    shutil.copy(os.path.join(src, "Box0.bin"), tmp)
    with open(os.path.join(src, "Box.gltf")) as f:
        return json.load(f)


def case_truncated_gltf(tmp, assets):
    text = json.dumps(box(tmp, assets))
    return write(os.path.join(tmp, "half.gltf"), text[: len(text) // 2]), FORMAT


def case_truncated_glb(tmp, assets):
    with open(os.path.join(assets, "Box", "glTF-Binary", "Box.glb"), "rb") as f:
        data = f.read()
    return write(os.path.join(tmp, "cut.glb"), data[: len(data) * 2 // 3]), FORMAT


def case_glb_chunk_overrun(tmp, assets):
    with open(os.path.join(assets, "Box", "glTF-Binary", "Box.glb"), "rb") as f:
        data = bytearray(f.read())
    json_len = struct.unpack_from("<I", data, 12)[0]
    struct.pack_into("<I", data, 20 + json_len, 1 << 30)  # BIN chunk claims 1 GiB
    return write(os.path.join(tmp, "overrun.glb"), bytes(data)), FORMAT


def case_truncated_bin(tmp, assets):
    doc = box(tmp, assets)
    path = os.path.join(tmp, "Box0.bin")
    with open(path, "rb") as f:
        data = f.read()
    write(path, data[: len(data) // 2])
    return write(os.path.join(tmp, "shortbin.gltf"), json.dumps(doc)), FORMAT


def case_missing_bin(tmp, assets):
    doc = box(tmp, assets)
    os.remove(os.path.join(tmp, "Box0.bin"))
    return write(os.path.join(tmp, "nobin.gltf"), json.dumps(doc)), IO


def case_json_syntax(tmp, assets):
    return write(os.path.join(tmp, "syntax.gltf"), '{"asset":{"version":"2.0"},"nodes":[{"mesh":0,}]}'), FORMAT


def case_accessor_range(tmp, assets):
    text = '{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":7}}]}]}'
    return write(os.path.join(tmp, "accessor.gltf"), text), FORMAT


def case_bufferview_range(tmp, assets):
    doc = box(tmp, assets)
    doc["bufferViews"][1]["byteLength"] += 4096  # past the end of Box0.bin
    return write(os.path.join(tmp, "view.gltf"), json.dumps(doc)), FORMAT


def case_accessor_past_view(tmp, assets):
    doc = box(tmp, assets)
    doc["accessors"][1]["count"] = 1 << 30  # lying count: must fail, not allocate
    return write(os.path.join(tmp, "count.gltf"), json.dumps(doc)), FORMAT


def case_index_range(tmp, assets):
    return write(os.path.join(tmp, "index.gltf"), triangle((0, 1, 5))), FORMAT


def case_node_cycle(tmp, assets):
    def cycle(doc):
        doc["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [2]}, {"children": [1]}]
        doc["scenes"] = [{"nodes": [0]}]
    return write(os.path.join(tmp, "cycle.gltf"), triangle(extra=cycle)), FORMAT


def case_node_loop(tmp, assets):
    def loop(doc):
        doc["nodes"] = [{"mesh": 0}, {"children": [2]}, {"children": [1]}]
    return write(os.path.join(tmp, "loop.gltf"), triangle(extra=loop)), FORMAT


def case_missing_file(tmp, assets):
    return os.path.join(tmp, "does-not-exist.gltf"), IO


def case_empty_file(tmp, assets):
    return write(os.path.join(tmp, "empty.glb"), b""), FORMAT


def case_deep_nesting(tmp, assets):
    # tinygltf copies extras recursively: deep nesting must not reach it.
    text = triangle()
    text = text.replace('"nodes": [{"mesh": 0}]', '"nodes": [{"mesh": 0, "extras": ' + "[" * 5000 + "]" * 5000 + "}]")
    return write(os.path.join(tmp, "deep.gltf"), text), FORMAT


def case_required_extension(tmp, assets):
    def ext(doc):
        doc["extensionsRequired"] = doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    return write(os.path.join(tmp, "draco.gltf"), triangle(extra=ext)), UNSUPPORTED


def case_bad_sampler(tmp, assets):
    def anim(doc):
        doc["animations"] = [{"channels": [{"sampler": 3, "target": {"node": 0, "path": "translation"}}],
                              "samplers": [{"input": 1, "output": 0}]}]
    return write(os.path.join(tmp, "sampler.gltf"), triangle(extra=anim)), FORMAT


def case_sampler_counts(tmp, assets):
    def anim(doc):
        # 3 key times against 3 VEC3 values is fine; as CUBICSPLINE it needs 9.
        doc["accessors"].append({"bufferView": 0, "componentType": 5126, "count": 3, "type": "SCALAR"})
        doc["animations"] = [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                              "samplers": [{"input": 2, "output": 0, "interpolation": "CUBICSPLINE"}]}]
    return write(os.path.join(tmp, "counts.gltf"), triangle(extra=anim)), FORMAT


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}


def main():
    probe, assets, name = sys.argv[1], sys.argv[2], sys.argv[3]
    with tempfile.TemporaryDirectory(prefix="vergence-scene-") as tmp:
        path, want = CASES[name](tmp, assets)
        run = subprocess.run([probe, path], capture_output=True, text=True, timeout=120)
    errors = [l for l in run.stderr.splitlines() if l.startswith("vergence: error:")]
    problems = []
    if run.returncode < 0 or run.returncode >= 128:
        problems.append(f"crashed (exit {run.returncode})")
    elif run.returncode != want:
        problems.append(f"exit {run.returncode}, expected {want}")
    if len(errors) != 1:
        problems.append(f"{len(errors)} error lines, expected exactly 1")
    elif path not in errors[0]:
        problems.append("the error line does not name the file")
    for bad in ("runtime error", "AddressSanitizer", "LeakSanitizer"):
        if bad in run.stderr:
            problems.append(f"sanitizer: {bad}")
    print(f"case {name}: exit {run.returncode}")
    print(run.stderr.rstrip())
    if problems:
        print("FAIL: " + "; ".join(problems))
        return 1
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
