#!/usr/bin/env python3
"""BALM benchmark_realworld (as in hku-mars/BALM, datas/benchmark_realworld) to the layout the
programs read: fullN.pcd with x y z intensity only (binary PCD v0.7), KITTI poses.txt and
times.txt from alidarPose.csv. Standard library only; no network (scripts/fetch-data.sh
downloads). Usage: balm_convert.py RAW_DIR OUT_DIR [SCANS]  (SCANS: first N, default all)

alidarPose.csv: per scan 4 lines of 4 comma-separated numbers: the rows of [R|t] (sensor ->
world), then "0,0,0,<time stamp>". The numbers are copied as text, so nothing is rounded."""
import os
import re
import struct
import sys


class ConversionError(Exception):
    pass


def read_poses(path):
    with open(path, "r", encoding="ascii") as f:
        tokens = [t for t in re.split(r"[,\s]+", f.read()) if t]
    if not tokens or len(tokens) % 16:
        raise ConversionError(f"{path}: {len(tokens)} numbers, expected 16 per scan")
    poses, times = [], []
    for i in range(0, len(tokens), 16):
        block = tokens[i:i + 16]
        try:
            values = [float(t) for t in block]
        except ValueError as e:
            raise ConversionError(f"{path}: scan {i // 16}: {e}") from None
        if values[12:15] != [0.0, 0.0, 0.0]:
            raise ConversionError(f"{path}: scan {i // 16}: 4th row is not 0,0,0,<time>")
        poses.append(" ".join(block[:12]))
        times.append(block[15])
    return poses, times


def lzf_decompress(data, size):
    out = bytearray()
    i = 0
    while i < len(data):
        ctrl = data[i]
        i += 1
        if ctrl < 32:  # literal run of ctrl + 1 bytes
            out += data[i:i + ctrl + 1]
            i += ctrl + 1
            continue
        length = ctrl >> 5
        if length == 7:
            length += data[i]
            i += 1
        ref = len(out) - ((ctrl & 0x1F) << 8) - data[i] - 1
        i += 1
        if ref < 0:
            raise ConversionError("corrupt LZF data")
        for _ in range(length + 2):  # may overlap itself: byte by byte
            out.append(out[ref])
            ref += 1
    if len(out) != size:
        raise ConversionError(f"LZF data gives {len(out)} bytes, expected {size}")
    return bytes(out)


FORMATS = {("F", 4): "f", ("F", 8): "d", ("U", 1): "B", ("U", 2): "H", ("U", 4): "I",
           ("I", 1): "b", ("I", 2): "h", ("I", 4): "i"}


def read_pcd(path):
    """(x, y, z, intensity) float tuples in file order; intensity 0 if the file has none."""
    with open(path, "rb") as f:
        raw = f.read()
    header, pos = {}, 0
    while "DATA" not in header:
        end = raw.find(b"\n", pos)
        if end < 0:
            raise ConversionError(f"{path}: header without DATA line")
        line = raw[pos:end].decode("ascii", "replace").strip()
        pos = end + 1
        if line and not line.startswith("#"):
            key, _, value = line.partition(" ")
            header[key] = value.split()
    try:
        fields, sizes, types = header["FIELDS"], [int(s) for s in header["SIZE"]], header["TYPE"]
        counts = [int(c) for c in header.get("COUNT", ["1"] * len(fields))]
        n = int(header["POINTS"][0])
    except (KeyError, ValueError, IndexError):
        raise ConversionError(f"{path}: incomplete PCD header") from None
    if not (len(fields) == len(sizes) == len(types) == len(counts)):
        raise ConversionError(f"{path}: FIELDS, SIZE, TYPE and COUNT differ in length")
    for name in ("x", "y", "z"):
        if name not in fields:
            raise ConversionError(f"{path}: no field {name}")
    wanted = ["x", "y", "z"] + (["intensity"] if "intensity" in fields else [])
    for name in wanted:
        k = fields.index(name)
        if (types[k], sizes[k]) not in FORMATS or counts[k] != 1:
            raise ConversionError(f"{path}: field {name} has an unsupported type")
    mode = header["DATA"][0]
    if mode == "ascii":
        columns = []  # column of each field's first value
        c = 0
        for cnt in counts:
            columns.append(c)
            c += cnt
        lines = [l.split() for l in raw[pos:].decode("ascii").splitlines() if l.strip()]
        if len(lines) != n:
            raise ConversionError(f"{path}: {len(lines)} points, header says {n}")
        idx = [columns[fields.index(f)] for f in wanted]
        points = [tuple(float(l[i]) for i in idx) for l in lines]
    elif mode in ("binary", "binary_compressed"):
        widths = [s * c for s, c in zip(sizes, counts)]
        data = raw[pos:]
        if mode == "binary_compressed":  # field by field (structure of arrays)
            if len(data) < 8:
                raise ConversionError(f"{path}: truncated compressed data")
            csize, usize = struct.unpack_from("<II", data, 0)
            data = lzf_decompress(data[8:8 + csize], usize)
            offsets, o = [], 0
            for w in widths:
                offsets.append(o)
                o += w * n
            stride_of = lambda k: widths[k]
        else:  # point by point
            offsets, o = [], 0
            for w in widths:
                offsets.append(o)
                o += w
            stride_of = lambda k: sum(widths)
        if len(data) < sum(widths) * n:
            raise ConversionError(f"{path}: {len(data)} data bytes, {n} points need "
                                  f"{sum(widths) * n}")
        cols = []
        for name in wanted:
            k = fields.index(name)
            fmt = "<" + FORMATS[(types[k], sizes[k])]
            stride = stride_of(k)
            cols.append([struct.unpack_from(fmt, data, offsets[k] + j * stride)[0]
                         for j in range(n)])
        points = list(zip(*cols))
    else:
        raise ConversionError(f"{path}: DATA {mode} is not supported")
    if len(wanted) == 3:
        points = [p + (0.0,) for p in points]
    viewpoint = header.get("VIEWPOINT", ["0", "0", "0", "1", "0", "0", "0"])
    return points, viewpoint


def write_pcd(path, points, viewpoint):
    n = len(points)
    head = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\n"
            "SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
            f"WIDTH {n}\nHEIGHT 1\nVIEWPOINT {' '.join(viewpoint)}\nPOINTS {n}\nDATA binary\n")
    body = b"".join(struct.pack("<4f", *p) for p in points)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(head.encode("ascii") + body)
    os.replace(tmp, path)


def convert(raw_dir, out_dir, scans=0):
    poses, times = read_poses(os.path.join(raw_dir, "alidarPose.csv"))
    if scans:
        if scans > len(poses):
            raise ConversionError(f"{raw_dir}: {scans} scans asked, alidarPose.csv has {len(poses)}")
        poses, times = poses[:scans], times[:scans]
    os.makedirs(out_dir, exist_ok=True)
    for i in range(len(poses)):
        src = os.path.join(raw_dir, f"full{i}.pcd")
        if not os.path.isfile(src):
            raise ConversionError(f"{src}: missing (alidarPose.csv lists {len(poses)} scans)")
        points, viewpoint = read_pcd(src)
        write_pcd(os.path.join(out_dir, f"full{i}.pcd"), points, viewpoint)
    with open(os.path.join(out_dir, "poses.txt"), "w", encoding="ascii") as f:
        f.write("".join(p + "\n" for p in poses))
    with open(os.path.join(out_dir, "times.txt"), "w", encoding="ascii") as f:
        f.write("".join(t + "\n" for t in times))
    return len(poses)


def main(argv):
    if len(argv) not in (3, 4) or argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        scans = int(argv[3]) if len(argv) == 4 else 0
        if scans < 0:
            raise ValueError
    except ValueError:
        print(f"balm_convert.py: SCANS must be a count, got {argv[3]!r}", file=sys.stderr)
        return 2
    try:
        n = convert(argv[1], argv[2], scans)
    except (ConversionError, OSError) as e:
        print(f"balm_convert.py: {e}", file=sys.stderr)
        return 1
    print(f"balm_convert.py: {n} scans -> {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
