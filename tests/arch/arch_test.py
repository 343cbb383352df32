#!/usr/bin/env python3
"""The house, checked (issue 14): the folders are the layers, and the docs say so.

usage: arch_test.py BUILD_DIR CASE

  layers     every folder of engine/ and game/ listed in its CMakeLists
             (VG_MODULES, VG_WINGS: bottom-up) holds exactly one library; no
             file includes a header of a folder listed after its own, and
             render/ (the scene's passes) includes nothing of disparity/, and
             the pass kit (pass/), the disparity passes and the screen-space
             warp passes (the SDK's) nothing of scene/ or render/
  circles    no two source files of the project (engine, game, the content
             tool) use each other's functions, directly or around a longer
             circle (nm on BUILD_DIR's objects)
  prefixes   a pass module X_gpu.c defines functions named X_gpu_* only;
             its X_gpu_create takes the frame_ctx, its own X_gpu_desc (or
             nothing) and its out, and frame_ctx holds no settings desc
  libraries  docs/architecture.md's table names every library of the build in
             its folder, and no other
  graph      the frame-graph dump in docs/architecture.md is what the binary
             prints for the settings the doc states (vergence capture --dump-graph)
  constants  each thing C and GLSL share has one definition: the Weber
             fraction in stereo/stereo_shared.h alone (no other 0.08 or 12.5
             defined in the sources); the cascade's stage ids, the curve's
             bins, reach and layout in include/vergence/warp_shared.h alone,
             the curve's evaluation in include/vergence/curve.h alone (both
             compiled by C and GLSL); the shared subset's markers in
             include/vergence/lang.h alone, and every shared header's structs
             through VGX_STRUCT; arcmin per radian, spelt again in the SDK's
             display.glsl for hosts, read on both sides and equal, and
             written inline (180 * 60 / pi) nowhere
  barriers   the frame graph records every barrier: no vkCmdPipelineBarrier*
             in the sources outside engine/graph and engine/gpu (a pass of
             dependent dispatches is several steps of the graph; the example
             host records its own), and the pre-synchronization2
             vkCmdPipelineBarrier nowhere, tests included; nor the older
             submission, events, timestamps or stage masks (vkQueueSubmit,
             vkCmdWaitEvents, VkPipelineStageFlags, ...)
  sdk        libvergence.so needs the Vulkan loader and libc / libm only
             (readelf -d), links no scene module, glTF loader, keyframe
             renderer, stb or C++ symbol (nm), and its link closure (the
             libraries build.ninja links it with) holds no library that
             draws the scene, no glTF loader and no C++ runtime
  names      every vkCreate* / vkAllocate* call in engine/ names the object
             it made (its last argument; GPU_NAME within a dozen lines; the
             instance excepted)
  docs       docs/ describe the present (issue 41): PERFORMANCE.md and
             method.md under 500 lines each; no doc or source names a stop or
             session ("since stop 33"); and every `vergence CMD [MODE] --flag`
             a doc or the README quotes is a command (and mode) the binary has,
             each flag in that command's --help
  formats    one Python module reads the tests' and tools' PFM, .flo and PNG
             files and writes their PFM and .flo (issue 41): tools/vgformats.py
             defines the readers and writers, and no other Python file under
             tests/ or tools/ holds a PFM or .flo header (the Pf / PF magic,
             the .flo's magic or its float), defines a function named for PFM
             or .flo, or decodes a PNG (PIL's open, imread, zlib.decompress)
"""
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def fail(msg):
    sys.exit(f"FAIL: {msg}")


def listed(cmake, var):
    """The folders a CMakeLists lists in set(VAR a b c)."""
    text = open(os.path.join(ROOT, cmake)).read()
    m = re.search(r"set\(%s ([^)]*)\)" % var, text)
    if not m:
        fail(f"{cmake} has no set({var} ...)")
    return m.group(1).split()


def layers():
    """[(folder, library)] bottom-up: engine's modules, then game's wings."""
    out = []
    for top, var in (("engine", "VG_MODULES"), ("game", "VG_WINGS")):
        for folder in listed(f"{top}/CMakeLists.txt", var):
            path = f"{top}/{folder}"
            text = open(os.path.join(ROOT, path, "CMakeLists.txt")).read()
            targets = re.findall(r"add_(?:library|executable)\((\S+)", text)
            if len(targets) != 1:
                fail(f"{path}/CMakeLists.txt defines {len(targets)} targets ({targets}); a folder is one library")
            out.append((path, targets[0]))
    return out


def sources():
    files = subprocess.run(["git", "ls-files", "engine", "game"], capture_output=True, text=True, cwd=ROOT,
                           check=True).stdout.split()
    return [f for f in files if f.endswith((".c", ".h", ".cpp"))]


def folder_of(path, folders):
    """The deepest listed folder holding path."""
    best = None
    for f in folders:
        if path.startswith(f + "/") and (best is None or len(f) > len(best)):
            best = f
    return best


# Folders kept apart though the lower may be below: the scene's passes know
# nothing of the science core (the frame hands each pass module its desc),
# and what the SDK links draws no scene.
APART = {("engine/render", "engine/disparity"): "the scene's passes do not depend on the science core",
         ("engine/render", "engine/disparity/gpu"): "the scene's passes do not depend on the disparity passes",
         ("engine/pass", "engine/scene"): "the pass kit names the scene but draws none (no scene in the SDK)",
         ("engine/disparity/gpu", "engine/scene"): "the disparity passes draw no scene (they are the SDK's)",
         ("engine/disparity/gpu", "engine/render"): "the disparity passes draw no scene (they are the SDK's)",
         ("engine/warp/screen", "engine/scene"): "the screen-space warp passes draw no scene (they are the SDK's)",
         ("engine/warp/screen", "engine/render"): "the screen-space warp passes draw no scene (they are the SDK's)"}


def case_layers():
    lay = layers()
    folders = [f for f, _ in lay]
    rank = {f: i for i, f in enumerate(folders)}
    for top in ("engine", "game"):
        for d in sorted(os.listdir(os.path.join(ROOT, top))):
            if os.path.isdir(os.path.join(ROOT, top, d)) and f"{top}/{d}" not in rank:
                fail(f"{top}/{d} is not listed in {top}/CMakeLists.txt: every folder is a layer")
    bad = []
    for src in sources():
        own = folder_of(src, folders)
        if own is None:
            fail(f"{src} is in no library's folder")
        for inc in re.findall(r'^#include "([^"]+)"', open(os.path.join(ROOT, src)).read(), re.M):
            target = None
            for base in (os.path.dirname(src), "engine", "game"):
                cand = os.path.normpath(os.path.join(base, inc))
                if os.path.exists(os.path.join(ROOT, cand)):
                    target = cand
                    break
            if target is None:
                continue  # generated (shaders) or a system header
            theirs = folder_of(target, folders)
            if theirs is not None and rank[theirs] > rank[own]:
                bad.append(f"{src} ({own}) includes {inc} ({theirs}, a higher layer)")
            elif (own, theirs) in APART:
                bad.append(f"{src} ({own}) includes {inc} ({theirs}): {APART[(own, theirs)]}")
    for b in bad:
        print(b)
    if bad:
        fail(f"{len(bad)} includes run up (or across a line kept apart)")
    print(f"{len(folders)} layers, each one library: " + " < ".join(f"{f} ({t})" for f, t in lay))


def objects(build):
    """The object file of every source of the libraries and of vergence (not
    tests or tools), where the build puts it."""
    lay = layers()
    folders = [f for f, _ in lay]
    target = dict(lay)
    out = []
    for src in sources():
        if not src.endswith((".c", ".cpp")):
            continue
        own = folder_of(src, folders)
        obj = os.path.join(build, own, "CMakeFiles", target[own] + ".dir", os.path.relpath(src, own) + ".o")
        if not os.path.exists(obj):
            fail(f"{obj} is missing: build {build} first")
        out.append(obj)
    return sorted(out)


def symbols(obj):
    text = subprocess.run(["nm", obj], capture_output=True, text=True, check=True).stdout
    defined, used = set(), set()
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] == "U":
            used.add(parts[1])
        elif len(parts) == 3 and parts[1] in "TDBRCV":
            defined.add(parts[2])
    return defined, used


def short(obj, build):
    """The source of an object file."""
    rel = os.path.relpath(obj, build)
    return re.sub(r"CMakeFiles/[^/]+\.dir/", "", rel)[:-len(".o")]


def tool_objects(build):
    """The content tool's objects (tools/content, one executable)."""
    files = subprocess.run(["git", "ls-files", "tools/content"], capture_output=True, text=True, cwd=ROOT,
                           check=True).stdout.split()
    out = []
    for src in files:
        if src.endswith(".c"):
            obj = os.path.join(build, "tools", "content", "CMakeFiles", "vergence-content.dir",
                               os.path.basename(src) + ".o")
            if not os.path.exists(obj):
                fail(f"{obj} is missing: build {build} first")
            out.append(obj)
    return out


def case_circles(build):
    objs = objects(build) + tool_objects(build)
    table = {o: symbols(o) for o in objs}
    owner = {}
    for o, (defined, _) in table.items():
        for s in defined:
            owner.setdefault(s, o)
    edges = {o: sorted({owner[s] for s in used if s in owner and owner[s] != o}) for o, (_, used) in table.items()}
    # Tarjan's strongly connected components.
    index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            comps.append(comp)

    sys.setrecursionlimit(10000)
    for v in objs:
        if v not in index:
            visit(v)
    circles = [c for c in comps if len(c) > 1]
    for c in circles:
        print("circle: " + " <-> ".join(short(o, build) for o in sorted(c)))
    if circles:
        fail(f"{len(circles)} circles of files that use each other")
    print(f"{len(objs)} object files, {sum(len(e) for e in edges.values())} uses between them, no circle")


def case_prefixes(build):
    bad = []
    n = 0
    for o in objects(build):
        stem = os.path.basename(o)[:-len(".c.o")]
        if not stem.endswith("_gpu") or not o.endswith(".c.o"):
            continue
        n += 1
        text = subprocess.run(["nm", o], capture_output=True, text=True, check=True).stdout
        for line in text.splitlines():
            parts = line.split()
            if len(parts) == 3 and parts[1] == "T" and not parts[2].startswith(stem + "_"):
                bad.append(f"{short(o, build)} defines {parts[2]} (not {stem}_*)")
    # The pass kit shares no settings: a pass module's create takes the frame
    # context, its own desc (X_gpu_desc) where it has settings, and its out.
    create = re.compile(r"^vg_status (\w+_gpu)_create\(([^)]*)\);", re.M)
    descs = 0
    for src in sources():
        if not src.endswith("_gpu.h"):
            continue
        for m in create.finditer(open(os.path.join(ROOT, src)).read()):
            args = [a.strip() for a in m.group(2).split(",")]
            if args[0] != "frame_ctx *fc":
                continue  # not a pass module of the frame (the SDK's disparity passes)
            if len(args) > 2 and not args[1].startswith(f"const {m.group(1)}_desc *") and \
                    not args[1].startswith("const uint32_t"):
                bad.append(f"{src}: {m.group(1)}_create takes {args[1]}, not its own {m.group(1)}_desc")
            descs += len(args) > 2
    frame_ctx = open(os.path.join(ROOT, "engine/pass/frame_ctx.h")).read()
    body = frame_ctx[frame_ctx.index("typedef struct frame_ctx {"):frame_ctx.index("} frame_ctx;")]
    if re.search(r"\b\w+_desc\s+\w+;", body):
        bad.append("engine/pass/frame_ctx.h: frame_ctx holds a settings desc the passes would share")
    for b in bad:
        print(b)
    if bad:
        fail(f"{len(bad)} functions of pass modules do not carry their file's prefix or take another's settings")
    print(f"{n} pass modules, every function named after its file; {descs} creates take their own desc, "
          f"frame_ctx holds no shared settings")


def doc():
    return open(os.path.join(ROOT, "docs", "architecture.md")).read()


def case_libraries():
    built = {(f, t) for f, t in layers()}
    rows = set(re.findall(r"^\| ((?:engine|game)/\S+) \| `([^`]+)` \|", doc(), re.M))
    missing, extra = sorted(built - rows), sorted(rows - built)
    if missing or extra:
        fail(f"docs/architecture.md's table of libraries lacks {missing} and has {extra}, which the build lacks")
    print(f"docs/architecture.md's table names all {len(built)} libraries of the build, each in its folder")


def case_graph(vergence):
    text = doc()
    m = re.search(r"<!-- graph-dump: (.*?) -->\n```\n(.*?)```", text, re.S)
    if not m:
        fail("docs/architecture.md has no <!-- graph-dump: ARGS --> block")
    args, want = m.group(1).split(), m.group(2)
    with tempfile.TemporaryDirectory(prefix="vergence_arch_") as tmp:
        p = subprocess.run([vergence, "capture", "--out", os.path.join(tmp, "c"), "--dump-graph",
                            os.path.join(tmp, "frame.dot")] + args, capture_output=True, text=True, timeout=600,
                           cwd=ROOT)
    if p.returncode:
        fail(f"vergence capture {' '.join(args)} failed:\n{p.stderr}")
    got = p.stdout
    if got.strip() != want.strip():
        w, g = want.strip().splitlines(), got.strip().splitlines()
        for i, (a, b) in enumerate(zip(w, g)):
            if a != b:
                fail(f"the dump in docs/architecture.md differs from the binary's at line {i + 1}:\n"
                     f"  doc:    {a}\n  binary: {b}\n(regenerate it: vergence capture {' '.join(args)} --dump-graph F)")
        fail(f"the dump in docs/architecture.md has {len(w)} lines, the binary prints {len(g)}")
    print(f"docs/architecture.md's graph dump is the binary's: {got.splitlines()[0]}")


SOURCE_EXT = (".c", ".h", ".cpp", ".glsl", ".comp", ".vert", ".frag", ".tesc", ".tese")


def source_texts():
    for top in ("engine", "game", "shaders", "include", "sdk", "examples"):
        for root, _, names in os.walk(os.path.join(ROOT, top)):
            for n in names:
                if n.endswith(SOURCE_EXT):
                    path = os.path.join(root, n)
                    yield os.path.relpath(path, ROOT), open(path, encoding="utf-8").read()


def defined(path, name):
    """The text of `#define NAME v` or `const T NAME = v;` in ROOT/path."""
    text = open(os.path.join(ROOT, path)).read()
    m = re.search(r"^[ \t]*(?:#define[ \t]+%s[ \t]+([^\n]+?)[ \t]*(?:/[*/].*)?$|const\s+\w+\s+%s\s*=\s*([^;]+);)"
                  % (name, name), text, re.M)
    if not m:
        fail(f"{path} defines no {name}")
    return m.group(1) or m.group(2)


def number(text):
    """A constant's value: a literal (f, u suffixes) or arithmetic of them."""
    expr = re.sub(r"(\d(?:\.\d*)?(?:[eE][-+]?\d+)?)[fFuU]\b", r"\1", text)
    if not re.fullmatch(r"[\d.eE+\-*/() ]+", expr):
        fail(f"not a number: {text}")
    return float(eval(expr, {"__builtins__": {}}))


def case_constants():
    # One definition: the Weber fraction's value is written in one file.
    home = "engine/stereo/stereo_shared.h"
    k, inv = number(defined(home, "STEREO_WEBER_K")), number(defined(home, "STEREO_INV_WEBER_K"))
    if abs(k * inv - 1.0) > 1e-6:
        fail(f"{home}: STEREO_INV_WEBER_K {inv} is not 1 / STEREO_WEBER_K {k}")
    pattern = re.compile(r"^\s*(?:#define\s+\w+|(?:static\s+)?const\s+\w+\s+\w+\s*=)\s*\(?\s*(0\.08|12\.5)f?\b", re.M)
    for path, text in source_texts():
        if path == home:
            continue
        m = pattern.search(text)
        if m:
            line = text[:m.start()].count("\n") + 1
            fail(f"{path}:{line} defines the Weber fraction again ({m.group(1)}): include {home}")
    # Written twice by necessity (the SDK's display.glsl is GLSL for hosts,
    # STEREO_ARCMIN_PER_RAD a double for C): the same value.
    what, fa, na, fb, nb = ("arcmin per radian", "engine/stereo/stereo_shared.h", "STEREO_ARCMIN_PER_RAD",
                            "include/vergence/display.glsl", "VGX_ARCMIN_PER_RAD")
    a, b = number(defined(fa, na)), number(defined(fb, nb))
    if abs(a - b) > 1e-5 * max(abs(a), 1.0):
        fail(f"{what}: {fa} {na} = {a}, {fb} {nb} = {b}")
    print(f"{what}: {na} = {nb} = {a:g}")
    texts = dict(source_texts())
    # Nor is it spelt inline: 180 * 60 / pi (or 60 * 180, or 10800 / pi).
    inline = re.compile(r"(?:180(?:\.0*)?f?\s*\*\s*60|60(?:\.0*)?f?\s*\*\s*180|10800(?:\.0*)?f?)(?:\.0*)?f?\s*\)?\s*/\s*"
                        r"(?:M_PI|3\.14159|PI\b)")
    for path, text in texts.items():
        if path in (fa, fb):
            continue
        m = inline.search(text)
        if m:
            fail(f"{path}:{text[:m.start()].count(chr(10)) + 1} spells arcmin per radian ({m.group(0)}): "
                 f"use {na} ({fa})")
    # The warp's share (stage ids, curve bins and reach, the curve's layout)
    # is defined once, in include/vergence/warp_shared.h; the names of the
    # copies it replaced are defined nowhere.
    share = "include/vergence/warp_shared.h"
    once = ["VGX_CURVE_BINS", "VGX_CURVE_REACH"] + [f"VGX_STAGE_{s}" for s in
                                                    ("NONE", "DIRECT", "NEIGHBORHOOD", "HALTON", "CURVE")]
    gone = ["VG_CURVE_BINS", "DISP_CURVE_REACH"] + [f"VG_STAGE_{s}" for s in
                                                                      ("NONE", "DIRECT", "NEIGHBORHOOD", "HALTON", "CURVE")]
    for name in once + gone:
        where = [p for p, t in texts.items()
                 if re.search(r"^\s*(?:#define\s+%s\b|(?:static\s+)?const\s+\w+\s+%s\s*=)" % (name, name), t, re.M)]
        want = [share] if name in once else []
        if where != want:
            fail(f"{name} is defined in {where or 'no file'}; want {want or 'no file'}")
    layout = [p for p, t in texts.items() if re.search(r"\bfloat\s+inv_depth_near\s*;", t)]
    if layout != [share]:
        fail(f"the curve's layout is declared in {layout}; want {share} alone")
    # The curve's evaluation has one source, compiled by C and GLSL alike.
    curve = "include/vergence/curve.h"
    evals = [p for p, t in texts.items()
             if re.search(r"inv_depth\[[^\]]*\+\s*1\]", t) or re.search(r"\w*curve_(?:between|segment|eval)\s*\([^;]*\)\s*\{", t)]
    if evals != [curve]:
        fail(f"the curve is evaluated in {evals}; want {curve} alone")
    print(f"the warp's share: {len(once)} constants and the curve's layout in {share} alone, "
          f"the curve's evaluation in {curve} alone")
    # One style of shared header: only vergence/lang.h defines the subset's
    # markers (function, struct) and C's uint; shared headers declare their
    # structs through VGX_STRUCT.
    prelude = "include/vergence/lang.h"
    shared = [p for p in texts if p.endswith(("_shared.h", "/shared.h")) or p in (curve, prelude)]
    for p, t in texts.items():
        if p == prelude:
            continue
        m = re.search(r"^\s*#define\s+\w*_(?:FN|STRUCT)\b|^\s*typedef\s+unsigned\s+int\s+uint\s*;", t, re.M)
        if m:
            fail(f"{p}:{t[:m.start()].count(chr(10)) + 2} defines a marker of the shared subset again: "
                 f"include {prelude}")
        if p in shared and re.search(r"^\s*(?:typedef\s+)?struct\s+\w+\s*\{", t, re.M):
            fail(f"{p} declares a struct without VGX_STRUCT")
        if p in shared and p != curve and "vergence/lang.h" not in t and "warp_shared.h" not in t and \
                re.search(r"\bVGX_(?:FN|STRUCT)\b", t):
            fail(f"{p} uses the shared subset without including vergence/lang.h")
    print(f"one style of shared header: {len(shared)} headers, markers in {prelude} alone")
    print(f"the Weber fraction {k:g} (1 / {inv:g}) is defined in {home} alone")


BARRIER_HOMES = ("engine/graph/", "engine/gpu/")


def case_barriers():
    call = re.compile(r"\bvkCmdPipelineBarrier(2(?:KHR)?)?\s*\(")
    found, homes, checked = [], 0, 0
    tests = []
    for root, _, names in os.walk(os.path.join(ROOT, "tests")):
        for n in names:
            if n.endswith((".c", ".h", ".cpp")):
                path = os.path.join(root, n)
                tests.append((os.path.relpath(path, ROOT), open(path, encoding="utf-8").read()))
    for path, text in tests:  # the tests record their own barriers, in synchronization2 terms
        for m in call.finditer(text):
            if not m.group(1):
                found.append(f"{path}:{text[:m.start()].count(chr(10)) + 1}: vkCmdPipelineBarrier (synchronization2: "
                             "vkCmdPipelineBarrier2)")
    for path, text in source_texts():
        checked += 1
        for m in call.finditer(text):
            line = text[:m.start()].count("\n") + 1
            if not m.group(1):
                found.append(f"{path}:{line}: vkCmdPipelineBarrier (synchronization2: vkCmdPipelineBarrier2)")
            elif path.startswith("examples/"):
                continue  # a host's own barriers around the SDK's dispatch
            elif not path.startswith(BARRIER_HOMES):
                found.append(f"{path}:{line}: a barrier outside the frame graph (declare the pass's uses, or "
                             f"split it into steps)")
            else:
                homes += 1
    # Synchronization2 everywhere: no submission, event, timestamp or stage
    # mask of the older API, tests and the example host included (the
    # released 0.1 header under sdk/abi is history and is not read here).
    older = re.compile(r"\b(vkQueueSubmit|vkCmdWaitEvents|vkCmdSetEvent|vkCmdResetEvent|vkCmdWriteTimestamp)\s*\(|"
                       r"\b(VkSubmitInfo|VkPipelineStageFlags|VkPipelineStageFlagBits)\b")
    for path, text in tests + list(source_texts()):
        for m in older.finditer(text):
            found.append(f"{path}:{text[:m.start()].count(chr(10)) + 1}: {m.group(1) or m.group(2)} "
                         f"(synchronization2: its 2 form)")
    if found:
        fail("barriers outside engine/graph and engine/gpu, or synchronization of the older API:\n  " +
             "\n  ".join(found))
    print(f"{checked} source files: {homes} barrier calls, all in {' and '.join(BARRIER_HOMES)}; "
          f"synchronization2 everywhere")


VK_CREATE = re.compile(r"\bvk(?:Create|Allocate)(\w+)\(")
UNNAMED = {"Instance": "lavapipe crashes in vkDestroyInstance once an instance is named (docs/architecture.md)",
           "DebugUtilsMessengerEXT": "the messenger reports the names"}


def last_argument(text, start):
    """The last argument of the call whose '(' is at start, and where it ends."""
    depth, arg_start = 0, start + 1
    for i in range(start, len(text)):
        c = text[i]
        if c in "({[":
            depth += 1
        elif c in ")}]":
            depth -= 1
            if depth == 0:
                return text[arg_start:i].strip(), i
        elif c == "," and depth == 1:
            arg_start = i + 1
    return None, start


def case_names():
    """Every Vulkan object the engine and the SDK make is named: each
    vkCreate* / vkAllocate* call in engine/ is followed, within a dozen lines,
    by a GPU_NAME of the object it made (its last argument, `&x` or a
    pointer `out`; RenderDoc and Nsight show names, and a host gets them with
    VGX_CONTEXT_DEBUG_UTILS). A call whose last argument it cannot read fails."""
    bad, named = [], 0
    for path, text in source_texts():
        if not path.startswith("engine/") or not path.endswith(".c"):
            continue
        for m in VK_CREATE.finditer(text):
            kind, line = m.group(1), text[:m.start()].count("\n") + 1
            if kind in UNNAMED:
                continue
            arg, end = last_argument(text, m.end() - 1)
            obj = re.fullmatch(r"&\s*([\w\->.\[\]]+)|([\w\->.]+)", arg or "")
            if not obj:
                bad.append(f"{path}:{line}: vk*{kind}'s last argument '{arg}' is not an object this test can follow")
                continue
            name = obj.group(1) or obj.group(2)
            # A pointer argument is named through *out, an array through out[i].
            target = re.escape(name) + r"(?![\w\[])" if obj.group(1) else \
                r"(?:\*%s(?!\w)|%s\[)" % (re.escape(name), re.escape(name))
            deref = "" if obj.group(1) else "*"
            after = "\n".join(text[end:].split("\n")[:12])
            if re.search(r"GPU_NAME\([^,]+,\s*\w+,\s*\(?%s" % target, after):
                named += 1
            else:
                bad.append(f"{path}:{line}: vk*{kind} makes {deref}{name}, named nowhere after it")
    if bad:
        fail("objects without a debug name (GPU_NAME):\n  " + "\n  ".join(bad))
    print(f"{named} vkCreate / vkAllocate calls in engine/, each followed by the name of what it made")


SDK_NEEDED = ("libvulkan.so", "libm.so", "libc.so", "ld-linux")
SDK_FOREIGN = re.compile(r"\b(scene_\w+|keyframe_gpu_\w+|\w*gltf\w*|stbi\w*|_Z\w+)\b", re.I)


def case_sdk(build):
    """libvergence.so is a C library over the Vulkan loader and libc / libm:
    no libstdc++ or other library in its dynamic section, and no scene module,
    glTF loader, keyframe renderer, image codec or C++ symbol linked in."""
    lib = os.path.join(build, "sdk", "libvergence.so")
    if not os.path.exists(lib):
        fail(f"{lib} is missing: build {build} first")
    dyn = subprocess.run(["readelf", "-d", lib], capture_output=True, text=True, check=True).stdout
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dyn)
    # The sanitizer build's library carries the sanitizers' runtimes.
    cache = open(os.path.join(build, "CMakeCache.txt")).read()
    sanitized = re.search(r"^VG_SANITIZE:BOOL=ON$", cache, re.M) is not None
    allowed = SDK_NEEDED + (("libasan.so", "libubsan.so") if sanitized else ())
    extra = [n for n in needed if not n.startswith(allowed)]
    if extra:
        fail(f"libvergence.so needs {extra} beyond the Vulkan loader and libc / libm (readelf -d)")
    syms = subprocess.run(["nm", lib], capture_output=True, text=True, check=True).stdout
    if not re.search(r"\bT vgx_context_create\b", syms):
        fail("libvergence.so shows no vgx_context_create to nm (stripped?): its symbols cannot be checked")
    foreign = sorted({m.group(1) for m in SDK_FOREIGN.finditer(syms)})
    if foreign:
        fail(f"libvergence.so links {len(foreign)} symbols of modules a host does not need: {foreign[:8]}")
    # Its link closure, as the build links it (build.ninja): C, and no
    # library that draws the scene, no glTF loader, no C++ runtime.
    ninja = os.path.join(build, "build.ninja")
    if not os.path.exists(ninja):
        fail(f"{ninja} is missing: the link closure is read from a Ninja build")
    rule = re.search(r"^build sdk/libvergence\.so\S*: (\w+)_LINKER\S* (.*?)(?=^build |\Z)",
                     open(ninja).read(), re.M | re.S)
    if not rule:
        fail(f"{ninja} links no sdk/libvergence.so")
    libs = re.search(r"LINK_LIBRARIES = (.*)", rule.group(2))
    closure = sorted({os.path.basename(w) for w in (libs.group(1).split() if libs else []) if not w.startswith("-")})
    drawn = [n for n in closure if re.match(r"lib(vg_(scene|render|warp_gpu|frame|output|content)|tinygltf|stdc\+\+)", n)]
    if rule.group(1) != "C_SHARED_LIBRARY" or drawn:
        fail(f"libvergence.so is linked by {rule.group(1)} with {drawn} in its link closure {closure}")
    print(f"libvergence.so needs {', '.join(needed)}; no scene, glTF, keyframe, stb or C++ symbol in its "
          f"{len(syms.splitlines())} symbols; linked as C over {len(closure)} libraries, none of them the scene's")


FORMATS_HOME = "tools/vgformats.py"
# Written so that this file does not match them itself.
FORMAT_CODE = [
    (re.compile(r"""[bBrRfFuU]{0,2}["']P[Ff](?:\\n|\s|["'])"""), "a PFM magic (Pf / PF)"),
    (re.compile(r"P[I]EH"), "the .flo magic"),
    (re.compile(r"202021\.25"), "the .flo magic's float"),
    (re.compile(r"^[ \t]*def\s+(?:\w+_)?(?:pfm|flo)(?:_\w+)?\s*\(", re.M | re.I), "a function named for PFM or .flo"),
    (re.compile(r"\bImage\.open\(|\bimread\(|\bzlib\.decompress\("), "a PNG decoder"),
]


DOC_LIMITS = {"docs/PERFORMANCE.md": 500, "docs/method.md": 500}
DIARY = re.compile(r"\b(?:[Ss]ince |[Ii]n |[Aa]t |[Oo]f )?(?:stop|session) \d{1,3}\b")


def case_docs(vergence):
    for path, limit in DOC_LIMITS.items():
        n = open(os.path.join(ROOT, path), encoding="utf-8").read().count("\n")
        if n >= limit:
            fail(f"{path} has {n} lines; it describes the present in under {limit} (history goes to git)")
    docs = ["README.md"] + sorted(os.path.join("docs", n) for n in os.listdir(os.path.join(ROOT, "docs"))
                                  if n.endswith(".md"))
    diary = []
    texts = [(p, open(os.path.join(ROOT, p), encoding="utf-8").read()) for p in docs]
    for path, text in texts + list(source_texts()):
        for m in DIARY.finditer(text):
            diary.append(f"{path}:{text[:m.start()].count(chr(10)) + 1}: {m.group(0)}")
    if diary:
        fail("docs and comments say what is true now, not when it became so:\n  " + "\n  ".join(diary))
    helps, quoted, wrong = {}, 0, []

    def help_of(words):
        key = " ".join(words)
        if key not in helps:
            p = subprocess.run([vergence] + words + ["--help"], capture_output=True, text=True, timeout=60, cwd=ROOT)
            helps[key] = p.stdout if p.returncode == 0 else None
        return helps[key]

    commands = re.findall(r"^  (\S+) {2,}", help_of([]) or "", re.M)
    for path in docs:
        text = open(os.path.join(ROOT, path), encoding="utf-8").read()
        for m in re.finditer(r"`vergence ([a-z-]+)((?: [^`]*)?)`", text):
            where = f"{path}:{text[:m.start()].count(chr(10)) + 1}"
            cmd, rest = m.group(1), m.group(2).split()
            if cmd not in commands:
                wrong.append(f"{where}: `vergence {cmd}` is no command (the binary has {', '.join(commands)})")
                continue
            words = [cmd]
            if rest:  # a mode, or alternatives of it ("hit\|preference" in a table): the first
                rest[0] = rest[0].replace("\\|", "|").split("|")[0].strip("[]")
            if rest and re.fullmatch(r"[a-z][a-z-]*", rest[0]) and help_of([cmd, rest[0]]) is not None \
                    and help_of([cmd, rest[0]]) != help_of([cmd]):
                words.append(rest[0])
            text_help = help_of(words) or ""
            quoted += 1
            for flag in re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", " ".join(rest)):
                if not re.search(r"(?<![\w-])" + re.escape(flag) + r"(?![\w-])", text_help):
                    wrong.append(f"{where}: `vergence {' '.join(words)}` has no {flag} (its --help lacks it)")
    if wrong:
        fail("the docs quote commands the binary does not have:\n  " + "\n  ".join(wrong))
    print(f"{len(docs)} docs: PERFORMANCE.md and method.md under their limits, no diary, "
          f"{quoted} quoted commands each the binary's, with their flags")


def case_formats():
    home = open(os.path.join(ROOT, FORMATS_HOME)).read()
    for name in ("read_pfm", "write_pfm", "read_flo", "write_flo", "read_png"):
        if not re.search(r"^def %s\(" % name, home, re.M):
            fail(f"{FORMATS_HOME} defines no {name}")
    found, checked = [], 0
    for top in ("tests", "tools"):
        for root, _, names in os.walk(os.path.join(ROOT, top)):
            for n in sorted(names):
                path = os.path.relpath(os.path.join(root, n), ROOT)
                if not n.endswith(".py") or path == FORMATS_HOME:
                    continue
                checked += 1
                text = open(os.path.join(ROOT, path), encoding="utf-8").read()
                for pattern, what in FORMAT_CODE:
                    for m in pattern.finditer(text):
                        line = text[:m.start()].count("\n") + 1
                        found.append(f"{path}:{line}: {what} ({m.group(0).strip()})")
    if found:
        fail(f"file formats read or written outside {FORMATS_HOME} (import it instead):\n  " + "\n  ".join(found))
    print(f"{checked} Python files under tests/ and tools/ leave PFM, .flo and PNG decoding to {FORMATS_HOME}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    build, case = os.path.abspath(sys.argv[1]), sys.argv[2]
    {"layers": case_layers, "circles": lambda: case_circles(build), "prefixes": lambda: case_prefixes(build),
     "libraries": case_libraries, "graph": lambda: case_graph(os.path.join(build, "game", "vergence")),
     "constants": case_constants, "barriers": case_barriers, "sdk": lambda: case_sdk(build), "names": case_names, "formats": case_formats,
     "docs": lambda: case_docs(os.path.join(build, "game", "vergence"))}[case]()
    print("ok")
