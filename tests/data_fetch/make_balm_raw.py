#!/usr/bin/env python3
"""Test fixture: turns converted BALM scans (fullN.pcd x y z intensity, poses.txt, times.txt)
back into the upstream layout scripts/fetch-data.sh converts: alidarPose.csv (4 lines of 4
comma-terminated numbers per scan, the last "0,0,0,<time>") and PCDs with normals, written
independently of scripts/balm_convert.py. Scan 0 becomes binary with PCL's field layout
(x y z _ intensity normals _ curvature), scan 1 binary_compressed (LZF, literal runs only),
scan 2 ascii, the others binary with 8 fields.
Usage: make_balm_raw.py CONVERTED_DIR RAW_DIR N"""
import os
import struct
import sys


def read_xyzi(path):
    with open(path, "rb") as f:
        data = f.read()
    at = data.index(b"DATA binary\n") + len(b"DATA binary\n")
    header = data[:at].decode("ascii")
    n = int([l for l in header.splitlines() if l.startswith("POINTS")][0].split()[1])
    viewpoint = [l for l in header.splitlines() if l.startswith("VIEWPOINT")][0]
    assert "FIELDS x y z intensity" in header, path
    return [struct.unpack_from("<4f", data, at + 16 * i) for i in range(n)], viewpoint


def normal_of(i):  # any numbers: the converter must drop them
    return (0.25 * (i % 3), -0.5, 1.0 / (1 + i % 7), 0.125)


def write(path, points, viewpoint, mode):
    n = len(points)
    if mode == "pcl":  # PCL's PointXYZINormal in memory: padding fields "_"
        fields, size, typ, count = "x y z _ intensity normal_x normal_y normal_z _ curvature", \
            "4 4 4 1 4 4 4 4 1 4", "F F F U F F F F U F", "1 1 1 4 1 1 1 1 4 1"
    else:
        fields, size, typ, count = "x y z intensity normal_x normal_y normal_z curvature", \
            "4 4 4 4 4 4 4 4", "F F F F F F F F", "1 1 1 1 1 1 1 1"
    data_mode = {"pcl": "binary", "plain": "binary"}.get(mode, mode)
    head = (f"# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS {fields}\n"
            f"SIZE {size}\nTYPE {typ}\nCOUNT {count}\nWIDTH {n}\nHEIGHT 1\n{viewpoint}\n"
            f"POINTS {n}\nDATA {data_mode}\n").encode("ascii")
    if mode == "ascii":
        body = "".join(" ".join(repr(v) for v in p + normal_of(i)) + "\n"
                       for i, p in enumerate(points)).encode("ascii")
    elif mode == "pcl":
        body = b"".join(struct.pack("<3f4s4f4sf", *p[:3], b"\0" * 4, p[3], *normal_of(i)[:3],
                                    b"\0" * 4, normal_of(i)[3]) for i, p in enumerate(points))
    elif mode == "plain":
        body = b"".join(struct.pack("<8f", *p, *normal_of(i)) for i, p in enumerate(points))
    else:  # binary_compressed: every field's column in turn, LZF literal runs of <= 32 bytes
        cols = [struct.pack(f"<{n}f", *[p[k] for p in points]) for k in range(4)]
        cols += [struct.pack(f"<{n}f", *[normal_of(i)[k] for i in range(n)]) for k in range(4)]
        raw = b"".join(cols)
        lzf = b"".join(bytes([len(raw[j:j + 32]) - 1]) + raw[j:j + 32]
                       for j in range(0, len(raw), 32))
        body = struct.pack("<II", len(lzf), len(raw)) + lzf
    with open(path, "wb") as f:
        f.write(head + body)


def main(src, dst, n):
    os.makedirs(dst, exist_ok=True)
    poses = [l.split() for l in open(os.path.join(src, "poses.txt")) if l.strip()]
    times = [l.strip() for l in open(os.path.join(src, "times.txt")) if l.strip()]
    with open(os.path.join(dst, "alidarPose.csv"), "w") as f:
        for p, t in zip(poses, times):
            for row in range(3):
                f.write("".join(v + "," for v in p[4 * row:4 * row + 4]) + "\n")
            f.write(f"0.000000,0.000000,0.000000,{t},\n")
    for i in range(n):
        points, viewpoint = read_xyzi(os.path.join(src, f"full{i}.pcd"))
        mode = {0: "pcl", 1: "binary_compressed", 2: "ascii"}.get(i, "plain")
        write(os.path.join(dst, f"full{i}.pcd"), points, viewpoint, mode)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]))
