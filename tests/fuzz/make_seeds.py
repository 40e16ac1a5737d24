#!/usr/bin/env python3
"""Seed corpora of the fuzz targets, from the project's own files (scripts/fuzz.sh calls this).

make_seeds.py SOURCE_DIR LOG_DIR OUT_DIR [MORE_LOG_DIRS...]
  SOURCE_DIR: the repository (scenarios/, setups, options, vehicles)
  LOG_DIR:    a short log recorded by `statebench record` (its files, cut to a few rows); more
              logs (another lidar file format) add their own seeds
  OUT_DIR:    gets fuzz_config/, fuzz_log_reader/ and fuzz_estimators/ seed folders
"""
import glob
import math
import os
import random
import struct
import sys


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


def config_seeds(src, out):
    groups = [
        (0, "scenarios/paper/*.yaml"), (0, "scenarios/extra/*.yaml"),
        (1, "scenarios/setups/*.yaml"), (2, "scenarios/setups/*.yaml"),
        (3, "scenarios/estimators/factor_graph*.yaml"), (4, "scenarios/estimators/ekf*.yaml"),
        (5, "scenarios/vehicles/*.yaml"),
    ]
    n = 0
    for parser, pattern in groups:
        for path in sorted(glob.glob(os.path.join(src, pattern))):
            with open(path, "rb") as f:
                text = f.read()
            if parser == 0:  # relative setup paths must still resolve from the scratch folder
                text = text.replace(b"../setups/", (src + "/scenarios/setups/").encode())
            write(os.path.join(out, "fuzz_config", "%03d" % n), bytes([parser]) + text)
            n += 1


def head(path, lines):
    with open(path, "rb") as f:
        return b"".join(f.readline() for _ in range(lines))


def small_pcd(path, points):
    """The PCD cut to its first `points` points (binary data, 22 bytes each)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"DATA binary\n") + len(b"DATA binary\n")
    header = data[:end].decode()
    lines = []
    for line in header.splitlines():
        key = line.split(" ")[0]
        if key in ("WIDTH", "POINTS"):
            line = "%s %d" % (key, points)
        lines.append(line)
    return ("\n".join(lines) + "\n").encode() + data[end:end + 22 * points]


def zstd_raw_frame(content):
    """One zstd frame holding `content` as a single raw (stored) block: single segment, 4-byte
    content size, no checksum (RFC 8878, section 3.1.1)."""
    block_header = 1 | (len(content) << 3)  # last block, type raw
    return (struct.pack("<IBI", 0xFD2FB528, 0xA0, len(content)) +
            struct.pack("<I", block_header)[:3] + content)


def small_sweep(points):
    """A sweep file (docs/log-format.md) of `points` points whose field planes are a fixed byte
    pattern: any planes decode to some points, so the seed reaches the whole reader."""
    sizes = [4, 2, 4, 4, 4, 4]  # t ring x y z intensity
    frames = [zstd_raw_frame(bytes((7 * i + f) % 251 for i in range(size * points)))
              for f, size in enumerate(sizes)]
    header = b"SBSWEEP\0" + struct.pack("<II", 1, points)
    return header + struct.pack("<6I", *[len(f) for f in frames]) + b"".join(frames)


def small_packets(points):
    """A lidar packets file (docs/log-format.md) of a 4-channel, 8-column lidar holding its first
    `points` beams (at most 32), range words and intensity bytes a fixed pattern. Its direction
    checksum is the reader's: Python's math.cos and math.sin are the C library's, and the
    directions are LidarBeamModel::Direction's double operations."""
    channels, columns, rate, azimuth0 = 4, 8, 10.0, math.pi
    elevations = [-0.25, -0.125, 0.0, 0.125]
    step = 2.0 * math.pi / columns
    checksum = 0xcbf29ce484222325
    for c in range(columns):
        a = azimuth0 + (-step) * c  # clockwise
        for e in elevations:
            for v in (math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)):
                for byte in struct.pack("<d", v):
                    checksum = ((checksum ^ byte) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    masks = bytearray(columns)
    for k in range(points):
        masks[k // channels] |= 1 << (k % channels)
    header = (b"SBLIDPK\0" + struct.pack("<IIIQBBHIdd", 1, points, 0, checksum, 0, 1, channels,
                                         columns, rate, azimuth0) +
              struct.pack("<%dd" % channels, *elevations))
    words = struct.pack("<%dI" % points, *[0x60000000 + 977 * k for k in range(points)])
    return header + bytes(masks) + words + bytes((7 * k) % 101 for k in range(points))


def small_sweep_file(path, points):
    if path.endswith(".packets"):
        return small_packets(points)
    return small_sweep(points) if path.endswith(".sweep") else small_pcd(path, points)


def log_seeds(log, out, prefix=""):
    files = [("log.yaml", open(os.path.join(log, "log.yaml"), "rb").read()),
             ("setup.yaml", open(os.path.join(log, "setup.yaml"), "rb").read()),
             ("truth.csv", head(os.path.join(log, "truth.csv"), 4))]
    for csv in sorted(glob.glob(os.path.join(log, "*", "*.csv"))):
        rel = os.path.relpath(csv, log)
        files.append((rel, head(csv, 4)))
        folder = csv[:-4]
        if os.path.isdir(folder):  # a lidar: its first sweeps, 8 points each
            for sweep in sorted(os.listdir(folder))[:3]:
                files.append((os.path.relpath(os.path.join(folder, sweep), log),
                              small_sweep_file(os.path.join(folder, sweep), 8)))
    whole = b"".join(b"== " + name.encode() + b"\n" + content for name, content in files)
    write(os.path.join(out, "fuzz_log_reader", prefix + "whole_log"), whole)
    # One seed per file beside the manifest, so mutations reach every parser early.
    manifest = files[0]
    for i, (name, content) in enumerate(files[1:]):
        part = b"== %s\n%s== %s\n%s" % (manifest[0].encode(), manifest[1], name.encode(), content)
        write(os.path.join(out, "fuzz_log_reader", prefix + "part_%02d" % i), part)


def estimator_seeds(out):
    """Records after the clean prefix (fuzz_estimators.cpp's layout): IMU samples of a car at
    rest, fixes near the drive's origin, encoders, a tiny scan."""
    rnd = random.Random(7)
    for which in range(3):
        b = bytes([which, 15])
        for k in range(60):
            kind = k % 8
            sensor = {0: 0, 1: 1, 2: 3, 3: 6, 4: 4, 5: 5, 6: 7, 7: 8}[kind]
            b += struct.pack("<BBhh", kind, sensor, 10, 2)
            if kind == 0:
                b += struct.pack("<6d", 0.001, -0.002, 0.01, 0.1, 0.0, 9.81)
            elif kind == 1:
                b += struct.pack("<3d", 45.478 + rnd.random() * 1e-5, 9.227, 121.4)
                b += struct.pack("<9d", 4e-4, 0, 0, 0, 4e-4, 0, 0, 0, 1.6e-3) + bytes([3])
            elif kind == 2:
                b += struct.pack("<4d", 0.1, 0.0, 0.01, 0.02)
            elif kind == 3:
                b += struct.pack("<4d", 20.0, 20.0, 20.0, 20.0)
            elif kind == 4:
                b += struct.pack("<d", 8.0)
            elif kind == 5:
                b += struct.pack("<d", 0.1)
            elif kind == 6:
                b += bytes([4]) + b"".join(struct.pack("<5fH", 5.0 + i, 1.0, 0.5, 10.0, 0.01 * i, i)
                                           for i in range(4))
            else:
                b += struct.pack("<6d", 8.0, 0, 0, 0, 0, 0.1)
                b += struct.pack("<36d", *[0.01 if i % 7 == 0 else 0.0 for i in range(36)])
        write(os.path.join(out, "fuzz_estimators", "drive_%d" % which), b)


def main():
    src, log, out = sys.argv[1:4]
    config_seeds(src, out)
    log_seeds(log, out)
    for i, more in enumerate(sys.argv[4:]):
        log_seeds(more, out, "log%d_" % (i + 2))
    estimator_seeds(out)


if __name__ == "__main__":
    main()
