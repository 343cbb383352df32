#!/usr/bin/python3
"""The file formats the Python tests and tools read and write (issue 41), in
one place: PFM and Middlebury .flo (read and write), 8-bit PNG (read; the
few tests that make PNG inputs encode them themselves) and vergence's curve
files (read).

Row order: every array these functions take or return is TOP-DOWN, row 0 the
top row of the image, as vergence holds images in memory (docs/formats.md:
"All images are row-major with the top row first in memory"). A PFM file
stores its rows from the bottom row up; read_pfm and write_pfm flip them, so a
caller never sees the file's order. A .flo file and a PNG are top-down already.
Index an array as a[y, x] with y down: vergence's messages name pixel (x, y)
that way (optimize's "at pixel (5, 0)" is a[0, 5], on the top row), and a
.flo's v and capture.json's clip space point down too (docs/formats.md).

    read_pfm(path, channels=None, byte_order=None)
                                   -> float32 (H, W) for 'Pf', (H, W, 3) for 'PF'
    write_pfm(path, array)            (H, W) or (H, W, 3); little-endian, scale -1.0
    encode_pfm(array)              -> the bytes write_pfm writes
    read_flo(path)                 -> float32 (H, W, 2): [..., 0] = u (x right), [..., 1] = v (y down)
    write_flo(path, flow)             (H, W, 2)
    encode_flo(flow)               -> the bytes write_flo writes
    read_png(path, channels=None)  -> uint8 (H, W, C), C = 1 grey, 3 RGB, 4 RGBA (8-bit PNGs only)
    read_ppm(path)                 -> uint8 (H, W, 3) (binary 8-bit PPM, as the example host writes)
    read_curve(path)               -> (1/near, 1/far, inv_depth, vergence): a curve file's nodes

A malformed file raises ValueError with the file's path in the message. The
formats (docs/formats.md):
  PFM: 'Pf' (1 channel) or 'PF' (3 channels), then width and height, then a
       scale whose sign gives the byte order (negative: little-endian), each
       on its own line; then float32 rows, bottom row first.
  .flo: the float 202021.25 (the bytes 'PIEH'), int32 width, int32 height,
       then (u, v) float32 pairs row by row from the top, little-endian.

Needs numpy (and PIL for read_png): Debian's /usr/bin/python3 has both.
Run it to check itself: python3 tools/vgformats.py (CTest: formats.python).
"""
import os
import struct

import numpy as np

PFM_MAGIC = {b"Pf": 1, b"PF": 3}
FLO_MAGIC = b"PIEH"      # the float 202021.25, little-endian
FLO_TAG = 202021.25
_MAX_SIDE = 1 << 20      # a width or height beyond this is a garbled header, not an image


def _read(path):
    with open(path, "rb") as f:
        return f.read()


# ---------------------------------------------------------------------------
# PFM
# ---------------------------------------------------------------------------

def _pfm_header(path, data):
    """(channels, width, height, dtype, offset of the first float)."""
    lines = data.split(b"\n", 3)
    if len(lines) < 4:
        raise ValueError(f"{path}: not a PFM (the header needs 3 lines: 'Pf' or 'PF', width height, scale)")
    magic, size, scale = (x.strip() for x in lines[:3])
    if magic not in PFM_MAGIC:
        raise ValueError(f"{path}: not a PFM (first line {magic[:16]!r}, want 'Pf' or 'PF')")
    try:
        w, h = (int(v) for v in size.split())
    except ValueError:
        raise ValueError(f"{path}: PFM size line {size[:32]!r} is not 'width height'") from None
    if not (0 < w <= _MAX_SIDE and 0 < h <= _MAX_SIDE):
        raise ValueError(f"{path}: PFM size {w}x{h} is not an image's")
    try:
        s = float(scale)
    except ValueError:
        raise ValueError(f"{path}: PFM scale line {scale[:32]!r} is not a number") from None
    if not (s != 0 and np.isfinite(s)):
        raise ValueError(f"{path}: PFM scale {scale.decode(errors='replace')} (want a nonzero number; "
                         "negative: little-endian)")
    offset = len(data) - len(lines[3])
    return PFM_MAGIC[magic], w, h, np.dtype("<f4" if s < 0 else ">f4"), offset


def read_pfm(path, channels=None, byte_order=None):
    """The PFM at path as float32, TOP-DOWN (row 0 = the image's top row; the
    file stores the bottom row first): shape (H, W) for a 'Pf' file, (H, W, 3)
    for 'PF'. Either byte order is read; channels (1 or 3) and byte_order ('<'
    little-endian, negative scale; '>' big-endian), when given, are required.
    ValueError naming the file on a malformed header, on the wrong channel
    count or byte order, or when the data is not exactly W x H x channels
    floats."""
    data = _read(path)
    ch, w, h, dtype, offset = _pfm_header(path, data)
    if channels is not None and ch != channels:
        raise ValueError(f"{path}: a {ch}-channel PFM, not {channels}-channel")
    if byte_order is not None and dtype.str[0] != byte_order:
        raise ValueError(f"{path}: a {'little' if dtype.str[0] == '<' else 'big'}-endian PFM, "
                         f"not {'little' if byte_order == '<' else 'big'}-endian")
    want, got = 4 * w * h * ch, len(data) - offset
    if got != want:
        raise ValueError(f"{path}: {got} bytes of PFM data for {w}x{h}x{ch} floats (want {want})")
    a = np.frombuffer(data, dtype=dtype, count=w * h * ch, offset=offset)
    a = a.reshape((h, w) if ch == 1 else (h, w, 3))
    return np.ascontiguousarray(a[::-1], dtype=np.float32)


def encode_pfm(array):
    """The PFM bytes of a TOP-DOWN (H, W) or (H, W, 3) array: 'Pf' or 'PF',
    little-endian (scale -1.0), rows written bottom row first."""
    a = np.asarray(array, dtype=np.float32)
    if a.ndim == 2:
        magic = b"Pf"
    elif a.ndim == 3 and a.shape[2] == 3:
        magic = b"PF"
    else:
        raise ValueError(f"a PFM holds (H, W) or (H, W, 3) floats, not shape {a.shape}")
    h, w = a.shape[:2]
    if not (h > 0 and w > 0):
        raise ValueError(f"a PFM of {w}x{h} pixels")
    return magic + b"\n%d %d\n-1.0\n" % (w, h) + np.ascontiguousarray(a[::-1], dtype="<f4").tobytes()


def write_pfm(path, array):
    """Writes a TOP-DOWN (H, W) or (H, W, 3) array as a little-endian PFM."""
    data = encode_pfm(array)
    with open(path, "wb") as f:
        f.write(data)


# ---------------------------------------------------------------------------
# Middlebury .flo
# ---------------------------------------------------------------------------

def read_flo(path):
    """The Middlebury .flo at path as float32 (H, W, 2), top-down (as the file):
    [..., 0] = u (pixels, x right), [..., 1] = v (pixels, y down). ValueError
    naming the file on a wrong magic, a bad size or data that is not exactly
    W x H pairs."""
    data = _read(path)
    if len(data) < 12 or data[:4] != FLO_MAGIC:
        raise ValueError(f"{path}: not a Middlebury .flo (first bytes {data[:4]!r}, want {FLO_MAGIC!r})")
    w, h = struct.unpack_from("<ii", data, 4)
    if not (0 < w <= _MAX_SIDE and 0 < h <= _MAX_SIDE):
        raise ValueError(f"{path}: .flo size {w}x{h} is not an image's")
    want, got = 8 * w * h, len(data) - 12
    if got != want:
        raise ValueError(f"{path}: {got} bytes of .flo data for {w}x{h} (u, v) pairs (want {want})")
    return np.frombuffer(data, dtype="<f4", count=2 * w * h, offset=12).reshape(h, w, 2).astype(np.float32)


def encode_flo(flow):
    """The .flo bytes of a top-down (H, W, 2) array of (u, v)."""
    a = np.asarray(flow, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 2 or not (a.shape[0] > 0 and a.shape[1] > 0):
        raise ValueError(f"a .flo holds (H, W, 2) floats (u, v), not shape {a.shape}")
    h, w = a.shape[:2]
    return FLO_MAGIC + struct.pack("<ii", w, h) + np.ascontiguousarray(a, dtype="<f4").tobytes()


def write_flo(path, flow):
    """Writes a top-down (H, W, 2) array of (u, v) as a Middlebury .flo
    (np.stack([u, v], axis=-1) makes one from two (H, W) arrays)."""
    data = encode_flo(flow)
    with open(path, "wb") as f:
        f.write(data)


# ---------------------------------------------------------------------------
# PNG
# ---------------------------------------------------------------------------

_PNG_MODES = {"L": 1, "RGB": 3, "RGBA": 4}


def read_png(path, channels=None):
    """An 8-bit grey, RGB or RGBA PNG as uint8 (H, W, C), top-down, C = 1, 3
    or 4 (a grey image keeps its channel axis). channels, when given, is
    required. ValueError naming the file for anything else (16-bit, palette,
    grey + alpha, not a PNG)."""
    from PIL import Image, UnidentifiedImageError
    try:
        with Image.open(path) as im:
            im.load()
            fmt, mode = im.format, im.mode
            a = np.asarray(im) if mode in _PNG_MODES else None
    except UnidentifiedImageError:
        raise ValueError(f"{path}: not an image PIL reads") from None
    if fmt != "PNG" or a is None:
        raise ValueError(f"{path}: not an 8-bit grey, RGB or RGBA PNG ({fmt}, mode {mode})")
    if a.ndim == 2:
        a = a[:, :, None]
    if channels is not None and a.shape[2] != channels:
        raise ValueError(f"{path}: a PNG of {a.shape[2]} channels, not {channels}")
    return np.ascontiguousarray(a, dtype=np.uint8)


def read_ppm(path):
    """A binary 8-bit PPM (P6) as uint8 (H, W, 3), top-down (the example host
    writes its eyes so). ValueError naming the file for anything else."""
    from PIL import Image, UnidentifiedImageError
    try:
        with Image.open(path) as im:
            im.load()
            fmt, mode = im.format, im.mode
            a = np.asarray(im) if mode == "RGB" else None
    except UnidentifiedImageError:
        raise ValueError(f"{path}: not an image PIL reads") from None
    if fmt != "PPM" or a is None:
        raise ValueError(f"{path}: not an 8-bit RGB PPM ({fmt}, mode {mode})")
    return np.ascontiguousarray(a, dtype=np.uint8)


# ---------------------------------------------------------------------------
# Curve files (vergence bake-curve, capture's frame_NNNN_curve.bin)
# ---------------------------------------------------------------------------

CURVE_MAGIC = b"VGCV"


def read_curve(path):
    """A curve file: 'VGCV', uint32 version 1, uint32 bins, then the
    vgx_curve_data struct of include/vergence/warp_shared.h (float 1/near,
    float 1/far, uint32 valid, uint32 pad, then `bins` floats of inverse depth
    and `bins` of vergence, arcmin), little-endian. Returns (1/near, 1/far,
    inv_depth, vergence), the nodes as float64 arrays of `bins`."""
    d = _read(path)
    if len(d) < 12 or d[:4] != CURVE_MAGIC:
        raise ValueError(f"{path}: not a curve file (no VGCV header)")
    version, bins = struct.unpack_from("<II", d, 4)
    if version != 1 or not 2 <= bins <= 1 << 16 or len(d) != 12 + 16 + 8 * bins:
        raise ValueError(f"{path}: curve version {version} with {bins} bins in {len(d)} bytes")
    near, far = struct.unpack_from("<ff", d, 12)
    nodes = np.frombuffer(d, "<f4", 2 * bins, 28).astype(np.float64)
    return near, far, nodes[:bins], nodes[bins:]


# ---------------------------------------------------------------------------
# Self-check (CTest formats.python)
# ---------------------------------------------------------------------------

def _self_check():
    import tempfile
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    assets = os.path.join(root, "..", "shared", "assets", "stereo")
    problems = []

    def check(ok, what):
        print(f"{'ok  ' if ok else 'FAIL'} {what}")
        if not ok:
            problems.append(what)

    def refused(read, path, what):
        """read(path) raises a ValueError that names the file."""
        try:
            read(path)
            check(False, what)
        except ValueError as e:
            check(path in str(e), what)

    with tempfile.TemporaryDirectory(prefix="vgformats_") as tmp:
        # PFM, one channel: 3 rows x 5 columns, no symmetry; the file's first
        # float is the bottom-left pixel, its last the top-right.
        a = (np.arange(15, dtype=np.float32).reshape(3, 5) * 1.5 - 4.0)
        a[0, 1] = np.inf  # PFM's unknown survives
        p = os.path.join(tmp, "one.pfm")
        write_pfm(p, a)
        raw = open(p, "rb").read()
        check(raw.startswith(b"Pf\n5 3\n-1.0\n"), "PFM 'Pf' header: width 5, height 3, little-endian")
        body = np.frombuffer(raw[len(b"Pf\n5 3\n-1.0\n"):], dtype="<f4")
        check(body[0] == a[2, 0] and body[-1] == a[0, 4] and np.array_equal(body[:5], a[2]),
              "PFM file rows bottom-up (its first row is the array's last)")
        b = read_pfm(p)
        check(b.dtype == np.float32 and b.shape == (3, 5) and np.array_equal(a, b),
              "PFM 1-channel round trip, top-down")
        check(np.array_equal(read_pfm(p, channels=1), a), "read_pfm(channels=1)")
        # Big-endian, as another writer may write it, with a header's stray spaces.
        big = os.path.join(tmp, "big.pfm")
        open(big, "wb").write(b"Pf \n5 3 \n1.0\n" + np.ascontiguousarray(a[::-1], dtype=">f4").tobytes())
        check(np.array_equal(read_pfm(big), a), "PFM big-endian (positive scale) read top-down")
        check(np.array_equal(read_pfm(big, byte_order=">"), a) and np.array_equal(read_pfm(p, byte_order="<"), a),
              "read_pfm(byte_order=) accepts the file's own")
        try:
            read_pfm(big, byte_order="<")
            check(False, "a big-endian PFM refused where little-endian is asked")
        except ValueError as e:
            check(big in str(e), "a big-endian PFM refused where little-endian is asked")
        # Three channels: the channels stay with their pixel.
        c = np.arange(2 * 4 * 3, dtype=np.float32).reshape(2, 4, 3)
        p3 = os.path.join(tmp, "three.pfm")
        write_pfm(p3, c)
        raw = open(p3, "rb").read()
        body = np.frombuffer(raw[len(b"PF\n4 2\n-1.0\n"):], dtype="<f4")
        check(raw.startswith(b"PF\n4 2\n-1.0\n") and np.array_equal(body[:3], c[1, 0]),
              "PFM 'PF' header and bottom-up rows")
        check(np.array_equal(read_pfm(p3), c) and read_pfm(p3).shape == (2, 4, 3), "PFM 3-channel round trip")
        # Refusals name the file.
        for name, data in (("magic.pfm", b"P6\n5 3\n-1.0\n" + bytes(60)), ("size.pfm", b"Pf\nx 3\n-1.0\n" + bytes(60)),
                           ("scale.pfm", b"Pf\n5 3\nzero\n" + bytes(60)), ("short.pfm", b"Pf\n5 3\n-1.0\n" + bytes(56)),
                           ("long.pfm", b"Pf\n5 3\n-1.0\n" + bytes(64)), ("empty.pfm", b"")):
            path = os.path.join(tmp, name)
            open(path, "wb").write(data)
            refused(read_pfm, path, f"malformed {name} refused")
        refused(lambda path: read_pfm(path, channels=1), p3, "a 3-channel PFM refused where 1 is asked")
        # .flo: top-down in the file; u and v interleaved per pixel.
        u = np.arange(12, dtype=np.float32).reshape(3, 4)
        f = np.stack([u, -u - 0.5], axis=-1)
        pf = os.path.join(tmp, "f.flo")
        write_flo(pf, f)
        raw = open(pf, "rb").read()
        check(raw[:4] == FLO_MAGIC and struct.unpack_from("<f", raw)[0] == FLO_TAG and
              struct.unpack_from("<ii", raw, 4) == (4, 3) and len(raw) == 12 + 8 * 12, ".flo header: PIEH, 4, 3")
        check(struct.unpack_from("<4f", raw, 12) == (f[0, 0, 0], f[0, 0, 1], f[0, 1, 0], f[0, 1, 1]),
              ".flo file top-down: the top-left pixel's (u, v) first, then its right neighbour's")
        g = read_flo(pf)
        check(g.dtype == np.float32 and g.shape == (3, 4, 2) and np.array_equal(f, g), ".flo round trip")
        for name, data in (("magic.flo", b"XIEH" + struct.pack("<ii", 4, 3) + bytes(96)),
                           ("short.flo", FLO_MAGIC + struct.pack("<ii", 4, 3) + bytes(90)),
                           ("zero.flo", FLO_MAGIC + bytes(20))):
            path = os.path.join(tmp, name)
            open(path, "wb").write(data)
            refused(read_flo, path, f"malformed {name} refused")
        # PNG: grey and RGB, top-left first.
        from PIL import Image
        rgb = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3) * 7
        pp = os.path.join(tmp, "rgb.png")
        Image.fromarray(rgb).save(pp)
        check(np.array_equal(read_png(pp, 3), rgb), "PNG RGB read as (H, W, 3), top row first")
        grey = np.array([[0, 10, 20], [30, 40, 50]], dtype=np.uint8)
        pg = os.path.join(tmp, "grey.png")
        Image.fromarray(grey).save(pg)
        check(np.array_equal(read_png(pg)[:, :, 0], grey) and read_png(pg).shape == (2, 3, 1), "PNG grey as (H, W, 1)")
        # A curve file of 4 bins, its nodes distinct, read back in place.
        pc = os.path.join(tmp, "curve.bin")
        nodes = np.arange(8, dtype="<f4") + 0.5
        with open(pc, "wb") as f:
            f.write(CURVE_MAGIC + struct.pack("<IIffII", 1, 4, 2.0, 0.25, 1, 0) + nodes.tobytes())
        near, far, q, v = read_curve(pc)
        check((near, far) == (2.0, 0.25) and list(q) == [0.5, 1.5, 2.5, 3.5] and list(v) == [4.5, 5.5, 6.5, 7.5],
              "curve file: 1/near, 1/far and the two node arrays in place")
        with open(pc, "r+b") as f:
            f.truncate(40)
        refused(read_curve, pc, "a cut curve file refused")
        try:
            read_png(pg, 3)
            check(False, "a grey PNG refused where RGB is asked")
        except ValueError as e:
            check(pg in str(e), "a grey PNG refused where RGB is asked")
        try:
            read_png(p)
            check(False, "a PFM refused as a PNG")
        except ValueError as e:
            check(p in str(e), "a PFM refused as a PNG")
        # PPM (P6), as the example host writes it.
        ppm = os.path.join(tmp, "rgb.ppm")
        open(ppm, "wb").write(b"P6\n3 2\n255\n" + rgb.tobytes())
        check(np.array_equal(read_ppm(ppm), rgb), "PPM read as (H, W, 3), top row first")
        refused(read_ppm, pp, "a PNG refused as a PPM")

    # Real files (../shared/assets; skipped where they are absent), their
    # orientation checked against the pictures they belong to: read top-down,
    # a disparity map's depth edges lie on the left image's edges, and a flow
    # carries frame 2 onto frame 3; upside down, neither holds.
    def edges(x):
        gy, gx = np.gradient(x.astype(np.float64))
        return np.hypot(gx, gy)

    ft = os.path.join(assets, "flyingthings3d_pair_from_RAFT-3D")
    if os.path.exists(os.path.join(ft, "disp1.pfm")):
        disp = os.path.join(ft, "disp1.pfm")
        d = read_pfm(disp, channels=1)
        check(d.shape == (540, 960) and np.isfinite(d).all() and 0 < d.min() < d.max() < 960,
              f"FlyingThings3D disp1.pfm: {d.shape[1]}x{d.shape[0]}, disparity {d.min():.2f}..{d.max():.2f} px")
        check(encode_pfm(d)[-4 * d.size:] == open(disp, "rb").read()[-4 * d.size:],
              "disp1.pfm's floats re-encoded are the file's, byte for byte")
        lum = edges(read_png(os.path.join(ft, "image1.png"))[:, :, :3].mean(axis=2))
        jumps = edges(d) > 1.0
        up, down = lum[jumps].mean(), lum[jumps[::-1]].mean()
        check(lum.shape == d.shape and up > 2 * down,
              f"disp1.pfm's depth edges on image1.png's edges: mean edge {up:.1f} there, {down:.1f} upside down")
    else:
        print(f"skip {ft}: absent")
    sintel = os.path.join(assets, "sintel_alley_2_flow_from_faldoi")
    if os.path.exists(os.path.join(sintel, "gt", "frame_0002.flo")):
        flo = os.path.join(sintel, "gt", "frame_0002.flo")
        fl = read_flo(flo)
        check(encode_flo(fl) == open(flo, "rb").read(), "frame_0002.flo re-encoded is the file, byte for byte")
        f2, f3 = (read_png(os.path.join(sintel, f"frame_{i:04d}.png"))[:, :, :3].mean(axis=2) for i in (2, 3))
        h, w = f2.shape

        def warp_error(flow):
            yy, xx = np.mgrid[0:h, 0:w]
            x3 = np.clip(np.round(xx + flow[..., 0]).astype(int), 0, w - 1)
            y3 = np.clip(np.round(yy + flow[..., 1]).astype(int), 0, h - 1)
            return float(np.abs(f2 - f3[y3, x3]).mean())
        up, down = warp_error(fl), warp_error(fl[::-1])
        check(fl.shape == (h, w, 2) and np.isfinite(fl).all() and up < 0.75 * down,
              f"Sintel frame_0002.flo ({w}x{h}) carries frame 2 onto frame 3: mean error {up:.2f} levels, "
              f"{down:.2f} upside down")
    else:
        print(f"skip {sintel}: absent")
    if problems:
        raise SystemExit(f"FAIL: {len(problems)} check(s) of tools/vgformats.py: {problems}")
    print("ok")


if __name__ == "__main__":
    _self_check()
