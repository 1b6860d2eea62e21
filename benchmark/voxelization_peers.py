#!/usr/bin/env python3
"""Runs ffd-voxelization-peers on CGAL's test meshes and a 50k-triangle sphere; writes VOXELIZATION.md.

Usage: voxelization_peers.py PATH/TO/ffd-voxelization-peers [--threads 1,2] [--voxel-sizes 1,0.5]
                             [--meshes fandisk_large,bunny00,...] [--repeat 3] [--work-dir DIR]
                             [--output benchmark/VOXELIZATION.md]

Meshes: data/meshes/<name>.off from Debian's libcgal-demo (/usr/share/doc/libcgal-dev/data.tar.gz;
installed with apt-get when missing), each scaled so its largest side is 100 mm, plus the sphere of
voxelization_timing.py (50,000 triangles). Every mesh is voxelized at each voxel size (margin 3 mm) by
the module and its ITK and VTK peers, for each thread count, against one per-voxel reference (see
ffd-voxelization-peers.cxx). The table gives each time as a ratio to the fastest peer of the same task,
and the accuracy: voxels that disagree with the reference (and how many of them lie farther than half
a voxel diagonal from the surface), and the largest signed-distance error.
"""

import argparse
import json
import os
import subprocess
import sys
import tarfile
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from voxelization_timing import write_sphere  # noqa: E402

ARCHIVE = "/usr/share/doc/libcgal-dev/data.tar.gz"
DEFAULT_MESHES = "fandisk_large,bunny00,diplodocus,cheese,elephant,sphere50k"


def cgal_mesh(name, work):
    path = os.path.join(work, name + ".off")
    if os.path.exists(path):
        return path
    if not os.path.exists(ARCHIVE):
        subprocess.run(["apt-get", "install", "-y", "libcgal-demo"], check=True)
    with tarfile.open(ARCHIVE) as archive:
        member = archive.getmember("data/meshes/%s.off" % name)
        with archive.extractfile(member) as source, open(path, "wb") as target:
            target.write(source.read())
    return path


def fmt_seconds(value):
    return "%.3g s" % value


def table(runs):
    lines = []
    for run in runs:
        lines.append("### %s, %s mm voxels (%s voxels, %d triangles, %d inside by the reference)\n"
                     % (os.path.basename(run["mesh"]), run["voxel_size"], "x".join(map(str, run["size"])),
                        run["triangles"], run["inside_voxels"]))
        lines.append("| task | peer | threads | time | ratio to fastest | voxels disagreeing (far) | "
                     "max abs sdf error (in band) | sdf sign errors |")
        lines.append("|---|---|---|---|---|---|---|---|")
        results = run["results"]
        for task in ("occupancy", "solid", "sdf"):
            rows = [r for r in results if r["task"] == task]
            for threads in sorted({r["threads"] for r in rows}):
                same = [r for r in rows if r["threads"] == threads]
                fastest = min(r["seconds"] for r in same)
                for r in sorted(same, key=lambda r: r["seconds"]):
                    time = fmt_seconds(r["seconds"]) + (" (est.)" if r["extrapolated"] else "")
                    disagree = "" if r["disagree"] < 0 else "%d (%d)" % (r["disagree"], r["disagree_far"])
                    error = "" if r["max_abs_error"] is None or r["max_abs_error"] < 0 else "%.3g (%.3g)" % (
                        r["max_abs_error"], r["max_abs_error_in_band"])
                    signs = "" if r["sign_errors"] < 0 else str(r["sign_errors"])
                    if r["extrapolated"]:
                        signs += " (of %d sampled)" % r["evaluated_voxels"]
                    lines.append("| %s | %s | %d | %s | %.2f | %s | %s | %s |" % (
                        task, r["name"], threads, time, r["seconds"] / fastest, disagree, error, signs))
        lines.append("")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program")
    parser.add_argument("--threads", default="1,2")
    parser.add_argument("--voxel-sizes", default="1,0.5")
    parser.add_argument("--meshes", default=DEFAULT_MESHES)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--work-dir", default=None)
    parser.add_argument("--output", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                         "VOXELIZATION.md"))
    args = parser.parse_args()
    work = args.work_dir or tempfile.mkdtemp(prefix="ffd-voxelization-peers-")
    os.makedirs(work, exist_ok=True)

    runs = []
    for name in args.meshes.split(","):
        if name == "sphere50k":
            mesh = os.path.join(work, "sphere50k.off")
            write_sphere(mesh)
        else:
            mesh = cgal_mesh(name, work)
        for size in args.voxel_sizes.split(","):
            report = os.path.join(work, "%s-%s.json" % (name, size))
            command = [args.program, mesh, "--scale-to", "100", "--voxel-size", size, "--margin", "3",
                       "--threads", args.threads, "--repeat", str(args.repeat), "--json", report]
            print(" ".join(command), flush=True)
            subprocess.run(command, check=True)
            with open(report) as handle:
                runs.append(json.load(handle))

    with open(args.output, "w") as out:
        out.write("# Voxelization: TriangleMeshToVoxelImageFilter and its peers\n\n")
        out.write("Written by `benchmark/voxelization_peers.py` (program `benchmark/ffd-voxelization-peers.cxx`); "
                  "command: `python3 benchmark/voxelization_peers.py BUILD/benchmark/ffd-voxelization-peers "
                  "--threads %s --voxel-sizes %s --meshes %s`.\n\n" % (args.threads, args.voxel_sizes, args.meshes))
        out.write("Every mesh is scaled so its largest side is 100 mm; grid from its bounds with a 3 mm margin. "
                  "Times are wall-clock, best of %d runs (one run when over 2 s), from a fresh filter each time; "
                  "the machine is shared, so compare ratios within one table rather than absolute times. "
                  "`ratio` is the time over the fastest peer of the same task and thread count.\n\n" % args.repeat)
        out.write("Accuracy against a per-voxel reference: inside = |generalized winding number| > 1/2 (module's "
                  "reference path, fast winding number with beta 2, every voxel on its own), distance = exact "
                  "point-to-triangle distance of every voxel. *Disagreeing* counts voxels whose label differs "
                  "from the reference, *far* those of them farther than half a voxel diagonal from the surface "
                  "(mislabelled regions rather than boundary voxels). Occupancy is scored against "
                  "distance <= half the voxel diagonal, the module's definition; vtkVoxelModeller marks a voxel "
                  "when the closest point of a triangle lies in the voxel's box, a slightly different rule, so "
                  "its disagreements near the surface are expected. The module's banded sdf is exact within "
                  "3 voxels and clamped beyond (its error outside the band is the clamp, by design); "
                  "vtkImplicitPolyDataDistance is evaluated on whole z slices of at most 300,000 voxels and its "
                  "time scaled to the grid (est.).\n\n")
        out.write(table(runs))
    print("wrote", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
