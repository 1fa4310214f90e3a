"""A probe image like the segmentation of a whole abdominal CT volume: a body label that fills the field of view (cut
by the image's top and bottom, as a CT slab is), organs inside it that touch, a thin vessel, jagged boundaries and
a little speckle, on a fine anisotropic grid. Not a bench image: it shows where the set-up's passes over every voxel
cost most (bench/README.md, "At 1e3134b"), since the object's box, to which the oracle crops, is the whole image.

    /usr/bin/python3 bench/body_ct_probe.py OUTPUT.nrrd [--size 480 400 200] [--spacing 0.62 0.62 1.33]
        [--scale 3.4] [--jitter 0.7] [--seed 5] [--oblique]

The image is written as NRRD with uint8 labels: 0 background, 1 body, 2 liver, 3 and 4 kidneys, 5 spleen, 6 a
vessel 2.2 x scale mm across. Its direction is the identity (delaunay-bench-cgal-mesh needs it), or with --oblique
the grid turned by 17 degrees about z and then 9 degrees about x. The same arguments give the same voxels.
The smaller probes of bench/README.md, "At 1e3134b": --size 150 120 56 --scale 1 --oblique with --seed 1 (abd1),
--seed 2 --jitter 1.6 (abd2) and --seed 3 --jitter 1.6 (abd3).
"""
import argparse
import gzip

import numpy


def ellipsoid_level(x, y, z, center, radii):
    """Signed distance-like level of a point against an ellipsoid: negative inside, about mm near the surface."""
    normalised = numpy.sqrt(sum(((axis - c) / r) ** 2 for axis, c, r in zip((x, y, z), center, radii)))
    return (normalised - 1.0) * min(radii)


def make_labels(size, spacing, scale, jitter_voxels, seed):
    random = numpy.random.default_rng(seed)
    x, y, z = numpy.meshgrid(*[numpy.arange(n) * s for n, s in zip(size, spacing)], indexing="ij")
    center = numpy.array([n * s / 2.0 for n, s in zip(size, spacing)])
    jitter = random.uniform(-jitter_voxels, jitter_voxels, size=size) * spacing[0]

    def organ(offset, radii):
        return ellipsoid_level(x, y, z, center + numpy.array(offset) * scale, numpy.array(radii) * scale) + jitter

    labels = numpy.zeros(size, numpy.uint8)
    body = organ((0, 0, 0), (44, 34, 60))
    labels[body < 0] = 1
    labels[organ((-14, -4, 4), (20, 16, 18)) < 0] = 2
    labels[organ((22, -8, 8), (8, 7, 12)) < 0] = 5
    labels[organ((-12, 12, -4), (5, 6, 11)) < 0] = 3
    labels[organ((14, 12, -4), (5, 6, 11)) < 0] = 4
    vessel = numpy.sqrt((x - center[0] + 2 * scale) ** 2 + (y - center[1] + 6 * scale) ** 2) - 1.1 * scale
    labels[(vessel + 0.5 * jitter < 0) & (body < 0)] = 6
    speckle = (random.random(size) < 0.002) & (labels > 0)
    labels[speckle] = random.integers(1, 7, size=int(speckle.sum()))
    return labels


def grid_directions(spacing, oblique):
    """The physical step of each grid axis: its spacing times its direction (a column of the direction matrix)."""
    rotation = numpy.eye(3)
    if oblique:
        about_z, about_x = numpy.radians(17.0), numpy.radians(9.0)
        rotation = (numpy.array([[numpy.cos(about_z), -numpy.sin(about_z), 0.0],
                                 [numpy.sin(about_z), numpy.cos(about_z), 0.0], [0.0, 0.0, 1.0]])
                    @ numpy.array([[1.0, 0.0, 0.0], [0.0, numpy.cos(about_x), -numpy.sin(about_x)],
                                   [0.0, numpy.sin(about_x), numpy.cos(about_x)]]))
    return [tuple(float(value) for value in rotation[:, axis] * spacing[axis]) for axis in range(3)]


def write_nrrd(path, labels, spacing, oblique):
    size = labels.shape
    directions = " ".join("({!r},{!r},{!r})".format(*step) for step in grid_directions(spacing, oblique))
    header = ("NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\n"
              f"sizes: {size[0]} {size[1]} {size[2]}\n"
              f"space directions: {directions}\n"
              "kinds: domain domain domain\nendian: little\nencoding: gzip\nspace origin: (-41.5,17.25,-203.0)\n\n")
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        # NRRD's first axis is the fastest: numpy's last in C order.
        file.write(gzip.compress(numpy.ascontiguousarray(labels.transpose(2, 1, 0)).tobytes(), mtime=0))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output")
    parser.add_argument("--size", type=int, nargs=3, default=[480, 400, 200])
    parser.add_argument("--spacing", type=float, nargs=3, default=[0.62, 0.62, 1.33])
    parser.add_argument("--scale", type=float, default=3.4,
                        help="the anatomy's size: the body's half-axes are 44, 34 and 60 times this (mm); 3.4 makes "
                             "it a little wider than the default field of view along x and cut by it along z")
    parser.add_argument("--jitter", type=float, default=0.7,
                        help="boundaries move by up to this many in-plane voxels, voxel by voxel")
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--oblique", action="store_true", help="an oblique direction instead of the identity")
    arguments = parser.parse_args()
    labels = make_labels(tuple(arguments.size), numpy.array(arguments.spacing), arguments.scale, arguments.jitter,
                         arguments.seed)
    write_nrrd(arguments.output, labels, arguments.spacing, arguments.oblique)
    counts = {int(value): int((labels == value).sum()) for value in numpy.unique(labels)}
    print(f"{arguments.output}: {labels.size} voxels, labels {counts}")


if __name__ == "__main__":
    main()
