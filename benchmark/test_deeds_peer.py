#!/usr/bin/env python3
"""Checks deeds_peer.py, the benchmark's adapter to deeds, without deeds: the NIfTI it writes (read back byte by
byte), its reading of deeds' options, and its displacement field against deeds' own filling of the full image
(re-derived here: voxel i of an axis of m voxels sits at grid coordinate i * m1 / m, trilinear between nodes, the
last node held beyond), on two image frames, one of them rotated. Prints "deeds adapter check passed"."""

import array
import gzip
import math
import os
import struct
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deeds_peer  # noqa: E402

problems = []


def check(condition, text):
    if not condition:
        problems.append(text)


def write_metaimage(path, size, spacing, offset, matrix, values, channels=1, element="MET_FLOAT"):
    text = ["ObjectType = Image", "NDims = 3", "BinaryData = True", "BinaryDataByteOrderMSB = False",
            "CompressedData = False", "TransformMatrix = " + " ".join("%g" % v for v in matrix),
            "Offset = " + " ".join("%g" % v for v in offset), "ElementSpacing = " + " ".join("%g" % v for v in spacing),
            "DimSize = " + " ".join(str(v) for v in size), "ElementNumberOfChannels = %d" % channels,
            "ElementType = " + element, "ElementDataFile = LOCAL"]
    with open(path, "wb") as out:
        out.write(("\n".join(text) + "\n").encode())
        out.write(array.array("f" if element == "MET_FLOAT" else "d", values).tobytes())


def deeds_full_field(flow, size, nodes):
    """deeds' full-image field (u, v, w per voxel) from its grid arrays, as its upsampling computes it."""
    m, n, o = size
    m1, n1, o1 = nodes
    count = m1 * n1 * o1

    def at(component, i, j, k):
        i = min(max(i, 0), m1 - 1)
        j = min(max(j, 0), n1 - 1)
        k = min(max(k, 0), o1 - 1)
        return flow[component * count + i + j * m1 + k * m1 * n1]

    full = {}
    for k in range(o):
        for j in range(n):
            for i in range(m):
                y, x, z = i / (m / m1), j / (n / n1), k / (o / o1)
                yi, xi, zi = math.floor(y), math.floor(x), math.floor(z)
                dy, dx, dz = y - yi, x - xi, z - zi
                values = []
                for component in range(3):
                    total = 0.0
                    for a in (0, 1):
                        for b in (0, 1):
                            for c in (0, 1):
                                weight = (dy if a else 1 - dy) * (dx if b else 1 - dx) * (dz if c else 1 - dz)
                                total += weight * at(component, yi + a, xi + b, zi + c)
                    values.append(total)
                full[(i, j, k)] = values
    return full


def interpolate_field(header, values, point):
    """Trilinear interpolation of a MetaImage vector field at a physical point (as ITK's linear interpolator)."""
    size = deeds_peer.image_size(header)
    spacing = [float(v) for v in header["ElementSpacing"].split()]
    offset = [float(v) for v in header["Offset"].split()]
    direction = deeds_peer.direction_matrix(header)
    relative = [point[r] - offset[r] for r in range(3)]
    # index = D^T (p - o) / spacing (D orthonormal)
    index = [sum(direction[r][a] * relative[r] for r in range(3)) / spacing[a] for a in range(3)]
    base = [math.floor(v + 1e-9) for v in index]
    fraction = [index[a] - base[a] for a in range(3)]
    result = [0.0, 0.0, 0.0]
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                weight = (fraction[0] if a else 1 - fraction[0]) * (fraction[1] if b else 1 - fraction[1]) * \
                    (fraction[2] if c else 1 - fraction[2])
                if weight == 0.0:
                    continue
                node = [base[0] + a, base[1] + b, base[2] + c]
                if any(not 0 <= node[d] < size[d] for d in range(3)):
                    raise ValueError("point %s outside the field" % (point,))
                flat = node[0] + size[0] * (node[1] + size[1] * node[2])
                for d in range(3):
                    result[d] += weight * values[3 * flat + d]
    return result


def check_field(folder, name, size, spacing, offset, matrix, step):
    header_path = os.path.join(folder, name + ".mha")
    write_metaimage(header_path, size, spacing, offset, matrix, [0.0] * (size[0] * size[1] * size[2]))
    header, _ = deeds_peer.read_metaimage(header_path)
    nodes = [s // step for s in size]
    count = nodes[0] * nodes[1] * nodes[2]
    flow = array.array("f", [((7 * c + 3 * i) % 11 - 5) * 0.25 for c in range(3) for i in range(count)])
    dat = os.path.join(folder, name + "_displacements.dat")
    with open(dat, "wb") as out:
        out.write(flow.tobytes())
    field_path = os.path.join(folder, name + "-field.mha")
    returned = deeds_peer.deeds_grid_field(dat, header, step, field_path)
    check(returned == nodes, "%s: nodes %s, expected %s" % (name, returned, nodes))
    field_header, field = deeds_peer.read_metaimage(field_path)
    check(deeds_peer.image_size(field_header) == [n + 1 for n in nodes], "%s: field size %s" % (
        name, field_header["DimSize"]))
    check(not os.path.exists(field_path + ".partial"), "%s: a partial file is left" % name)
    full = deeds_full_field(flow, size, nodes)
    direction = deeds_peer.direction_matrix(header)
    worst = 0.0
    for (i, j, k), (u, v, w) in full.items():
        # deeds' voxel displacement per ITK axis: axis 0 by v, axis 1 by u, axis 2 by w; then in mm and rotated.
        voxels = [v * spacing[0], u * spacing[1], w * spacing[2]]
        expected = [sum(direction[r][a] * voxels[a] for a in range(3)) for r in range(3)]
        index = [i * spacing[0], j * spacing[1], k * spacing[2]]
        point = [offset[r] + sum(direction[r][a] * index[a] for a in range(3)) for r in range(3)]
        got = interpolate_field(field_header, field, point)
        worst = max(worst, max(abs(got[d] - expected[d]) for d in range(3)))
    check(worst < 1e-5, "%s: the field differs from deeds' own by %g mm" % (name, worst))
    print("%s: %d voxels, field = deeds' own within %.1e mm" % (name, len(full), worst))
    with open(dat, "wb") as out:
        out.write(flow[:-1].tobytes())
    try:
        deeds_peer.deeds_grid_field(dat, header, step, field_path)
        problems.append("%s: a short displacement file was accepted" % name)
    except ValueError as error:
        check("needs" in str(error), "%s: unclear error for a short file: %s" % (name, error))


def main():
    with tempfile.TemporaryDirectory() as folder:
        # NIfTI: header fields deeds reads, and the voxels in order.
        size = [5, 4, 3]
        values = [0.5 * i - 7.0 for i in range(60)]
        source = os.path.join(folder, "image.mha")
        write_metaimage(source, size, [1.5, 1.0, 2.0], [3, -4, 5], [1, 0, 0, 0, 1, 0, 0, 0, 1], values)
        header, read = deeds_peer.read_metaimage(source)
        check(list(read) == values, "read_metaimage changed the values")
        nifti = os.path.join(folder, "image.nii.gz")
        deeds_peer.write_nifti_gz(nifti, header, read)
        with gzip.open(nifti, "rb") as data:
            content = data.read()
        check(struct.unpack_from("<i", content, 0)[0] == 348, "sizeof_hdr is not 348")
        check(list(struct.unpack_from("<8h", content, 40)) == [3, 5, 4, 3, 1, 1, 1, 1], "wrong dim")
        check(list(struct.unpack_from("<2h", content, 70)) == [16, 32], "not float32")
        check(list(struct.unpack_from("<4f", content, 76)) == [1.0, 1.5, 1.0, 2.0], "wrong pixdim")
        check(struct.unpack_from("<f", content, 108)[0] == 352.0, "vox_offset is not 352")
        check(content[344:348] == b"n+1\0", "wrong magic")
        check(len(content) == 352 + 4 * 60, "wrong length %d" % len(content))
        check(list(struct.unpack_from("<60f", content, 352)) == values, "the voxels differ")
        # Bad inputs: a value count that does not match, an integer image.
        try:
            deeds_peer.write_nifti_gz(nifti, header, read[:-1])
            problems.append("write_nifti_gz accepted too few values")
        except ValueError:
            pass
        short = os.path.join(folder, "short.mha")
        write_metaimage(short, [5, 4, 4], [1, 1, 1], [0, 0, 0], [1, 0, 0, 0, 1, 0, 0, 0, 1], values)
        integer = os.path.join(folder, "integer.mha")
        write_metaimage(integer, size, [1, 1, 1], [0, 0, 0], [1, 0, 0, 0, 1, 0, 0, 0, 1], values)
        with open(integer, "rb") as data:
            text = data.read().replace(b"MET_FLOAT", b"MET_SHORT")
        with open(integer, "wb") as out:
            out.write(text)
        for path in (short, integer):
            try:
                deeds_peer.read_metaimage(path)
                problems.append("read_metaimage accepted %s" % os.path.basename(path))
            except ValueError:
                pass
        # deeds' options: the last level's grid spacing.
        for text, expected in (("", 4), ("-l 3 -G 6x5x4 -L 4x3x2 -Q 2x1x1", 4), ("-l 2 -G 6x5x4", 5),
                               ("-G 9", 4), ("-a 3 -l 1", 8), ("-l 7", 2)):
            got = deeds_peer.deeds_grid_step(text)
            check(got == expected, "deeds_grid_step('%s') = %s, expected %d" % (text, got, expected))
        for text in ("-l 0", "-l 11", "-l 2 -G 6x0"):
            try:
                deeds_peer.deeds_grid_step(text)
                problems.append("deeds_grid_step accepted '%s'" % text)
            except ValueError:
                pass
        # The field: an axis-aligned frame, and a rotated one with anisotropic voxels (grid steps 4 and 3).
        check_field(folder, "aligned", [9, 8, 5], [1.0, 1.0, 1.0], [2.0, -3.0, 1.5], [1, 0, 0, 0, 1, 0, 0, 0, 1], 4)
        check_field(folder, "rotated", [10, 7, 6], [2.0, 1.0, 0.5], [-1.0, 4.0, 2.0], [0, 1, 0, -1, 0, 0, 0, 0, 1], 3)
    if problems:
        for problem in problems:
            print("deeds adapter check: " + problem)
        return 1
    print("deeds adapter check passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
