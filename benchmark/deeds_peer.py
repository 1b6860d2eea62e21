"""The file formats around deeds (deedsBCV, Heinrich et al.; an image peer given by DEEDS_EXE, built outside the
repository): MetaImage in, NIfTI-1 (.nii.gz) for deeds, and deeds' control-grid displacements back to a MetaImage
displacement field that ffd-benchmark-tool's apply-field and score read.

deeds reads float NIfTI images of one size and works in voxel units, ignoring spacing and orientation. It writes
<stem>_displacements.dat: three float32 arrays (u, v, w) on its last control grid, m1 x n1 x o1 nodes with
m1 = m // step (step = its last grid spacing), the first axis fastest; u moves along the image's second axis, v
along its first, w along its third; node g sits on voxel g * (m / m1) of the full image, and deeds fills the full
field trilinearly between nodes, holding the last node's value beyond it. The displacement maps a fixed voxel x to
the moving voxel x + d(x), the direction of elastix's field.

Plain Python (struct, zlib, gzip, array): the benchmark needs no NumPy.
"""

import array
import gzip
import os
import struct
import zlib

NIFTI_HEADER_BYTES = 348
NIFTI_DATA_OFFSET = 352


def read_metaimage(path):
    """A MetaImage (.mha with LOCAL data, or .mhd + raw): its header (dict of strings) and values (array of float or
    double; channels interleaved)."""
    with open(path, "rb") as data:
        content = data.read()
    header = {}
    position = 0
    while True:
        end = content.index(b"\n", position)
        key, _, value = content[position:end].decode().partition("=")
        header[key.strip()] = value.strip()
        position = end + 1
        if key.strip() == "ElementDataFile":
            break
    if header["ElementDataFile"] == "LOCAL":
        raw = content[position:]
    else:
        with open(os.path.join(os.path.dirname(path), header["ElementDataFile"]), "rb") as data:
            raw = data.read()
    if header.get("CompressedData", "False").lower() == "true":
        raw = zlib.decompress(raw)
    kinds = {"MET_FLOAT": "f", "MET_DOUBLE": "d"}
    if header.get("ElementType") not in kinds:
        raise ValueError("%s: element type %s is not float or double" % (path, header.get("ElementType")))
    values = array.array(kinds[header["ElementType"]])
    values.frombytes(raw)
    if header.get("BinaryDataByteOrderMSB", "False").lower() == "true" or \
            header.get("ElementByteOrderMSB", "False").lower() == "true":
        values.byteswap()
    expected = image_size(header)
    channels = int(header.get("ElementNumberOfChannels", "1"))
    if len(values) != expected[0] * expected[1] * expected[2] * channels:
        raise ValueError("%s: %d values for %s voxels of %d channels" % (path, len(values), expected, channels))
    return header, values


def image_size(header):
    size = [int(v) for v in header["DimSize"].split()]
    if len(size) != 3 or int(header.get("NDims", "3")) != 3:
        raise ValueError("not a 3-D image (DimSize %s)" % header["DimSize"])
    return size


def write_nifti_gz(path, header, values):
    """The scalar MetaImage (header, values) as a gzipped NIfTI-1 float image of the same voxels, first axis fastest
    (deeds reads only the size, the data type and the voxels)."""
    size = image_size(header)
    if len(values) != size[0] * size[1] * size[2]:
        raise ValueError("%s: a scalar image of %s voxels needs %d values, got %d" % (
            path, size, size[0] * size[1] * size[2], len(values)))
    spacing = [float(v) for v in header.get("ElementSpacing", "1 1 1").split()]
    nifti = bytearray(NIFTI_DATA_OFFSET)
    struct.pack_into("<i", nifti, 0, NIFTI_HEADER_BYTES)
    struct.pack_into("<8h", nifti, 40, 3, size[0], size[1], size[2], 1, 1, 1, 1)
    struct.pack_into("<2h", nifti, 70, 16, 32)  # datatype float32, 32 bits per voxel
    struct.pack_into("<8f", nifti, 76, 1.0, spacing[0], spacing[1], spacing[2], 1.0, 1.0, 1.0, 1.0)
    struct.pack_into("<f", nifti, 108, float(NIFTI_DATA_OFFSET))
    struct.pack_into("<f", nifti, 112, 1.0)  # scl_slope
    struct.pack_into("<B", nifti, 123, 2)  # xyzt_units: millimetres
    nifti[344:348] = b"n+1\0"
    data = array.array("f", values)
    if struct.pack("=i", 1) != struct.pack("<i", 1):
        data.byteswap()
    with gzip.open(path, "wb", compresslevel=1) as out:
        out.write(bytes(nifti))
        out.write(data.tobytes())


def direction_matrix(header):
    values = [float(v) for v in header.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split()]
    # MetaImage writes the direction column by column: the image axis a's direction is values[3a:3a+3].
    return [[values[3 * a + r] for a in range(3)] for r in range(3)]


def deeds_grid_field(displacements_path, fixed_header, grid_step, output_path):
    """deeds' control-grid displacements (voxel units, its axis order) as a MetaImage displacement field in mm on
    the fixed image's frame: one node per deeds node, spacing (m / m1) voxels, origin at voxel 0, and one more
    node per axis repeating the last, so that linear interpolation over the field equals deeds' own filling of the
    full image (including its hold beyond the last node). Returns the field's node counts."""
    size = image_size(fixed_header)
    nodes = [n // grid_step for n in size]
    if min(nodes) < 1:
        raise ValueError("a %d-voxel deeds grid does not fit a %s image" % (grid_step, size))
    count = nodes[0] * nodes[1] * nodes[2]
    flow = array.array("f")
    with open(displacements_path, "rb") as data:
        flow.frombytes(data.read())
    if struct.pack("=i", 1) != struct.pack("<i", 1):
        flow.byteswap()
    if len(flow) != 3 * count:
        raise ValueError("%s has %d values; a %s grid (every %d voxels of %s) needs %d" % (
            os.path.basename(displacements_path), len(flow), nodes, grid_step, size, 3 * count))
    spacing = [float(v) for v in fixed_header.get("ElementSpacing", "1 1 1").split()]
    direction = direction_matrix(fixed_header)
    # deeds' arrays per ITK image axis: axis 0 moves by v, axis 1 by u, axis 2 by w.
    per_axis = [flow[count:2 * count], flow[0:count], flow[2 * count:3 * count]]
    out_nodes = [n + 1 for n in nodes]
    field = array.array("f", bytes(4 * 3 * out_nodes[0] * out_nodes[1] * out_nodes[2]))
    position = 0
    for k in range(out_nodes[2]):
        kk = min(k, nodes[2] - 1)
        for j in range(out_nodes[1]):
            jj = min(j, nodes[1] - 1)
            row = (kk * nodes[1] + jj) * nodes[0]
            for i in range(out_nodes[0]):
                node = row + min(i, nodes[0] - 1)
                voxels = [per_axis[a][node] * spacing[a] for a in range(3)]
                for r in range(3):
                    field[position + r] = sum(direction[r][a] * voxels[a] for a in range(3))
                position += 3
    node_spacing = [spacing[a] * size[a] / nodes[a] for a in range(3)]
    text = ["ObjectType = Image", "NDims = 3", "BinaryData = True", "BinaryDataByteOrderMSB = False",
            "CompressedData = False",
            "TransformMatrix = " + fixed_header.get("TransformMatrix", "1 0 0 0 1 0 0 0 1"),
            "Offset = " + fixed_header.get("Offset", "0 0 0"),
            "ElementSpacing = " + " ".join("%.17g" % s for s in node_spacing),
            "DimSize = " + " ".join(str(n) for n in out_nodes),
            "ElementNumberOfChannels = 3", "ElementType = MET_FLOAT", "ElementDataFile = LOCAL"]
    if struct.pack("=i", 1) != struct.pack("<i", 1):
        field.byteswap()
    temporary = output_path + ".partial"
    with open(temporary, "wb") as out:
        out.write(("\n".join(text) + "\n").encode())
        out.write(field.tobytes())
    os.replace(temporary, output_path)
    return nodes


def deeds_grid_step(options_text):
    """The grid spacing (voxels) of deeds' last level from its options: -l levels (default 5) and -G spacings
    (default 8x7x6x5x4x3x2x2x2x2), each followed by its value as deeds reads them."""
    spacings = [8, 7, 6, 5, 4, 3, 2, 2, 2, 2]
    levels = 5
    words = options_text.split()
    for index, word in enumerate(words[:-1]):
        if word == "-G":
            given = [int(v) for v in words[index + 1].split("x")]
            spacings[:len(given)] = given
        elif word == "-l":
            levels = int(words[index + 1])
    if not 1 <= levels <= len(spacings) or spacings[levels - 1] < 1:
        raise ValueError("deeds options '%s': no grid spacing for level %d" % (options_text, levels))
    return spacings[levels - 1]
