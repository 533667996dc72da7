#!/usr/bin/env python3
"""A PCD folder with KITTI poses.txt (sensor -> world) as OctoMap's plain-text scan log
(NODE x y z roll pitch yaw, then world-frame points), for log2graph and graph2tree -g.
Usage: pcd_to_octomap_log.py FOLDER OUT.log [MAX_SCANS]"""
import os
import re
import struct
import sys


def natural_key(name):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


def read_pcd_xyz(path):
    with open(path, "rb") as f:
        header = {}
        while True:
            line = f.readline().decode("ascii").strip()
            if not line or line.startswith("#"):
                continue
            key, _, value = line.partition(" ")
            header[key] = value.split()
            if key == "DATA":
                break
        fields, sizes, types = header["FIELDS"], header["SIZE"], header["TYPE"]
        if header["DATA"][0] != "binary" or any(t != "F" or s != "4" for t, s in zip(types, sizes)):
            sys.exit(f"{path}: only binary float PCDs are supported")
        n = int(header["POINTS"][0])
        stride = 4 * len(fields)
        data = f.read(n * stride)
        ix, iy, iz = (fields.index(a) for a in "xyz")
        values = struct.unpack(f"<{n * len(fields)}f", data)
        k = len(fields)
        return [(values[i * k + ix], values[i * k + iy], values[i * k + iz]) for i in range(n)]


def main():
    folder, out = sys.argv[1], sys.argv[2]
    max_scans = int(sys.argv[3]) if len(sys.argv) > 3 else None
    scans = sorted((f for f in os.listdir(folder) if f.endswith(".pcd")), key=natural_key)
    with open(os.path.join(folder, "poses.txt")) as f:
        poses = [list(map(float, line.split())) for line in f if line.strip()]
    if max_scans:
        scans = scans[:max_scans]
    with open(out, "w") as log:
        for name, p in zip(scans, poses):
            r = (p[0:3], p[4:7], p[8:11])
            t = (p[3], p[7], p[11])
            log.write(f"NODE {t[0]} {t[1]} {t[2]} 0 0 0\n")
            for x, y, z in read_pcd_xyz(os.path.join(folder, name)):
                if x != x or y != y or z != z:  # NaN
                    continue
                w = [r[i][0] * x + r[i][1] * y + r[i][2] * z + t[i] for i in range(3)]
                log.write(f"{w[0]:.4f} {w[1]:.4f} {w[2]:.4f}\n")


if __name__ == "__main__":
    main()
