#!/usr/bin/env python3
"""Writes the seed corpus of the libFuzzer target into fuzz/corpus/ (or the directory given).

Each seed is a 24-byte header (see InputLayout in DelaunayImageToMeshFuzzer.cxx and fuzz/README.md) followed by
one byte per voxel, x fastest. The seeds cover what the randomized GoogleTest covers (blobs, several labels,
sheets and lines, single voxels, objects on the border, thin images, gray images with an iso-value) and every
special parameter code (invalid and extreme delta, rho, sigma and vertex caps), so that fuzzing starts from
every branch of the decoder.
"""
import math
import pathlib
import sys

REFLECT, SHORT, FLOAT_ISO, SELECT, REPEAT, SHIFT, MERGE = 1, 4, 6, 8, 16, 32, 64


def header(size=(8, 8, 8), spacing=(50, 50, 50), angles=(0, 0, 0), flags=0, origin=(0, 0, 0), labels=1,
           delta=20000, rho=100, sigma=0, cap=2000, mask=0, iso=128, scale=1, levels=0):
    return bytes([(s - 1) % 16 for s in size] + list(spacing) + list(angles) + [flags] +
                 [o & 0xFF for o in origin] + [(labels - 1) % 8, delta & 0xFF, delta >> 8, rho, sigma,
                                              cap & 0xFF, cap >> 8, mask, iso, scale & 0xFF, levels])


def voxels(size, label_of):
    nx, ny, nz = size
    return bytes(label_of(x, y, z) for z in range(nz) for y in range(ny) for x in range(nx))


def ball(size, center, radius, label=1):
    return voxels(size, lambda x, y, z: label if math.dist((x, y, z), center) <= radius else 0)


def seeds():
    s8 = (8, 8, 8)
    yield "ball", header() + ball(s8, (3.5, 3.5, 3.5), 3)
    yield "ball-oblique-anisotropic", header(spacing=(20, 60, 90), angles=(30, 70, 200), origin=(-9, 4, 17)) + \
        ball(s8, (3.5, 3.5, 3.5), 3)
    yield "ball-reflected", header(angles=(10, 20, 30), flags=REFLECT) + ball(s8, (3.5, 3.5, 3.5), 3)
    yield "two-touching-labels", header(labels=2) + voxels(
        s8, lambda x, y, z: (1 if x < 4 else 2) if math.dist((x, y, z), (3.5, 3.5, 3.5)) <= 3.2 else 0)
    yield "eight-labels", header(size=(12, 12, 6), labels=8) + voxels(
        (12, 12, 6), lambda x, y, z: 1 + (x // 3 + 4 * (y // 6)) % 8 if 0 < z < 5 else 0)
    yield "sheet", header(size=(10, 10, 5)) + voxels((10, 10, 5), lambda x, y, z: 1 if z == 2 else 0)
    yield "line", header(size=(12, 5, 5)) + voxels((12, 5, 5), lambda x, y, z: 1 if y == 2 and z == 2 else 0)
    yield "single-voxel", header(size=(5, 5, 5), delta=8000) + voxels(
        (5, 5, 5), lambda x, y, z: 1 if (x, y, z) == (2, 2, 2) else 0)
    yield "whole-image", header(size=(4, 5, 6)) + voxels((4, 5, 6), lambda x, y, z: 1)
    yield "border-touching", header(flags=SHIFT) + ball(s8, (0, 0, 7), 5)
    yield "thin-image", header(size=(9, 9, 1)) + ball((9, 9, 1), (4, 4, 0), 3.5)
    yield "salt-and-pepper-repeated", header(size=(10, 10, 10), labels=3, flags=REPEAT) + \
        bytes([1, 0, 0, 2, 0, 3, 0, 0, 0, 1, 0])
    yield "short-negative-labels", header(flags=SHORT, labels=2, scale=-100) + voxels(
        s8, lambda x, y, z: (1 + (x > 3)) if math.dist((x, y, z), (3.5, 3.5, 3.5)) <= 3 else 0)
    yield "selected-labels", header(flags=SELECT, labels=3, mask=0b101) + voxels(
        s8, lambda x, y, z: 1 + (x + y + z) % 3 if math.dist((x, y, z), (3.5, 3.5, 3.5)) <= 3 else 0)
    yield "merged-labels", header(flags=MERGE | SELECT, labels=3, mask=0b011) + voxels(
        s8, lambda x, y, z: 1 + (x + y + z) % 3 if math.dist((x, y, z), (3.5, 3.5, 3.5)) <= 3 else 0)
    yield "nothing-selected", header(flags=SELECT, labels=2, mask=0b100) + ball(s8, (3.5, 3.5, 3.5), 3)
    yield "gray-iso-value", header(flags=FLOAT_ISO, iso=100) + voxels(
        s8, lambda x, y, z: max(0, 255 - int(60 * math.dist((x, y, z), (3.5, 3.5, 3.5)))))
    yield "empty", header()
    body = ball(s8, (3.5, 3.5, 3.5), 3)
    for name, delta in (("auto", 0), ("negative", 1), ("nan", 2), ("infinite", 3), ("tiny", 4), ("huge", 5),
                        ("denormal", 6), ("small", 3000), ("large", 60000)):
        yield "delta-" + name, header(delta=delta) + body
    for name, rho in (("half", 0), ("nan", 1), ("infinite", 2), ("one", 3), ("million", 4), ("three", 220)):
        yield "rho-" + name, header(rho=rho) + body
    for name, sigma in (("negative", 251), ("31", 252), ("nan", 253), ("30", 254), ("tiny", 255), ("15", 221)):
        yield "sigma-" + name, header(sigma=sigma) + body
    for name, cap in (("zero", 0), ("seven", 7), ("eight", 8), ("hundred", 100)):
        yield "cap-" + name, header(cap=cap) + body
    for name, levels in (("none", 9), ("ten", 7), ("eleven", 8)):
        yield "manifold-levels-" + name, header(levels=levels) + body
    for name, code in (("micrometre", 250), ("metre", 251), ("tenth", 252), ("thirty-seven", 253)):
        yield "spacing-" + name, header(spacing=(code, 50, 50)) + body


def main():
    directory = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent / "corpus")
    directory.mkdir(parents=True, exist_ok=True)
    for name, data in seeds():
        (directory / ("seed-" + name)).write_bytes(data)


if __name__ == "__main__":
    main()
