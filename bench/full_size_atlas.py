#!/usr/bin/env python3
"""An atlas-like label image of full size (a probe for issue #18; bench/README.md, the e6e463a section).

    /usr/bin/python3 bench/full_size_atlas.py OUTPUT.nrrd [--labels 116] [--seed 7]

181 x 217 x 181 voxels of 1 mm, the grid of a 1 mm MNI atlas (7.1 M voxels), where the bench's own atlas phantom
has 1 M. LABELS regions fill an ellipsoid of 136 x 168 x 132 mm: each is the Voronoi cell of a random seed, so that
every region touches several others along interfaces, triple curves and quadruple points. Background (0) outside.
The image is written as raw NRRD (uint8; uint16 beyond 255 labels, a parcellation of hundreds of regions),
identity direction, origin 0, so CGAL's `delaunay-bench-cgal-mesh` reads it too (uint8 only). About half a minute
and 1 GB of memory in NumPy; beyond 255 labels the cells come from SciPy's k-d tree (exact nearest seed).

The script once added a jitter of up to +-0.7 mm per voxel to the distances, meant to make the interfaces jagged
at the voxel scale. It was the same for every seed at a voxel, so it never changed which seed was nearest: the
cells are exact Voronoi cells, and every measurement made with this script was made on them.
"""
import argparse

import numpy as np

SIZE = (181, 217, 181)  # x, y, z voxels of 1 mm
SEMI_AXES = np.array([68.0, 84.0, 66.0])  # mm


def atlas(labels, seed):
    """The label volume, indexed [z, y, x]."""
    random = np.random.default_rng(seed)
    centre = np.array(SIZE) / 2.0
    seeds = []
    while len(seeds) < labels:
        point = random.uniform(-1.0, 1.0, 3)
        if (point**2).sum() < 0.9:  # inside the ellipsoid, away from its skin
            seeds.append(centre + point * SEMI_AXES)
    z, y, x = np.meshgrid(*(np.arange(n) for n in reversed(SIZE)), indexing="ij")
    points = np.stack([x, y, z], -1).reshape(-1, 3).astype(np.float32)
    inside = (((points - centre) / SEMI_AXES) ** 2).sum(1) < 1.0
    if labels > 255:
        from scipy.spatial import cKDTree

        label = (cKDTree(np.array(seeds)).query(points)[1] + 1).astype(np.uint16)
    else:
        nearest = np.full(len(points), np.inf, np.float32)
        label = np.zeros(len(points), np.uint8)
        for index, site in enumerate(np.array(seeds, np.float32)):
            distance = np.sqrt(((points - site) ** 2).sum(1))
            closer = distance < nearest
            nearest[closer] = distance[closer]
            label[closer] = index + 1
    label[~inside] = 0
    return label.reshape(tuple(reversed(SIZE)))


def write_nrrd(path, volume):
    """Raw NRRD, 1 mm voxels, identity direction, origin 0, little-endian beyond a byte."""
    header = (
        f"NRRD0004\ntype: {'uint8' if volume.dtype == np.uint8 else 'uint16'}\ndimension: 3\n"
        "space: left-posterior-superior\n"
        f"sizes: {SIZE[0]} {SIZE[1]} {SIZE[2]}\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
        "kinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: (0,0,0)\n\n"
    )
    with open(path, "wb") as file:
        file.write(header.encode())
        file.write(np.ascontiguousarray(volume.astype(volume.dtype.newbyteorder("<"))).tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output")
    parser.add_argument("--labels", type=int, default=116, help="regions, 1 to 65535 (default 116)")
    parser.add_argument("--seed", type=int, default=7, help="the random stream's seed (default 7)")
    arguments = parser.parse_args()
    if not 1 <= arguments.labels <= 65535:
        parser.error(f"--labels {arguments.labels}: must be 1 to 65535 (uint8 or uint16 labels)")
    volume = atlas(arguments.labels, arguments.seed)
    write_nrrd(arguments.output, volume)
    print(f"{arguments.output}: {len(np.unique(volume)) - 1} labels, {(volume > 0).sum()} tissue voxels")


if __name__ == "__main__":
    main()
