#!/usr/bin/env python3
"""Runs ffd-voxelization-peers on CGAL's test meshes, open patches and spheres; writes VOXELIZATION.md (+ .json).

Usage: voxelization_peers.py PATH/TO/ffd-voxelization-peers [--threads 1] [--voxel-sizes 1,0.5]
                             [--meshes fandisk_large,bunny00,...] [--patch-meshes bunny00,fandisk_large]
                             [--patch-radius 35] [--triangle-counts 5000,20000,80000,320000]
                             [--growth-mesh bunny00] [--growth-voxel-sizes 2,1,0.5,0.35,0.25]
                             [--repeat 5] [--work-dir DIR] [--output benchmark/VOXELIZATION.md]

Meshes: data/meshes/<name>.off from Debian's libcgal-demo (/usr/share/doc/libcgal-dev/data.tar.gz;
installed with apt-get when missing), each scaled so its largest side is 100 mm, plus UV spheres
(voxelization_timing.py's generator). Four parts, each one run of the program per mesh and grid (margin
3 mm), all peers of a task on the same triangles and grid, scored against one per-voxel reference (see
ffd-voxelization-peers.cxx):
  1. closed meshes at each voxel size (the module's exact-everywhere distance only up to
     --exact-sdf-max-voxels voxels, it is the slowest path);
  2. open patches: the triangles within --patch-radius mm of a vertex cut out of a mesh;
  3. growth with the triangle count: spheres at 1 mm, timing and memory only (no reference);
  4. growth with the voxel count: one mesh at --growth-voxel-sizes, timing and memory only.
The targets of issue #3 are evaluated from the measured data and written under the tables.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tarfile
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from voxelization_timing import write_sphere  # noqa: E402

ARCHIVE = "/usr/share/doc/libcgal-dev/data.tar.gz"
DEFAULT_MESHES = "fandisk_large,bunny00,diplodocus,cheese,elephant"
MODULE_OCC = ("occupancy", "module")
VOXEL_MODELLER = ("occupancy", "vtkVoxelModeller")
MODULE_SOLID = ("solid", "module")
ITK_BINARY = ("solid", "itk::TriangleMeshToBinaryImageFilter")
STENCIL = ("solid", "vtkPolyDataToImageStencil + vtkImageStencil")
MODULE_SDF = ("sdf", "module (exact in band, clamped)")
MODULE_EXACT = ("sdf", "module (exact everywhere)")
VTK_DISTANCE = ("sdf", "vtkImplicitPolyDataDistance (per voxel)")
MAURER = ("sdf", "itk binary + SignedMaurerDistanceMapImageFilter")


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


def sphere_mesh(triangles, work):
    # write_sphere makes 2 * segments * (rings - 1) triangles; segments = rings - 1 = sqrt(triangles / 2).
    side = max(3, int(round(math.sqrt(triangles / 2.0))))
    path = os.path.join(work, "sphere%d.off" % (2 * side * side))
    if not os.path.exists(path):
        write_sphere(path, segments=side, rings=side + 1)
    return path


def mesh_path(name, work):
    if name.startswith("sphere"):
        count = name[len("sphere"):]
        return sphere_mesh(int(count[:-1]) * 1000 if count.endswith("k") else int(count), work)
    return cgal_mesh(name, work)


def fmt_seconds(value):
    return "%.3g s" % value


def fmt_mb(value):
    return "" if value is None or value < 0 else "%.0f" % value if value >= 10 else "%.1f" % value


def find(run, key, threads):
    for r in run["results"]:
        if (r["task"], r["name"]) == key and r["threads"] == threads:
            return r
    return None


def run_title(run):
    name = os.path.basename(run["mesh"])
    if run.get("patch_radius", 0) > 0:
        name = "%s, open patch (%d of %d triangles within %g mm of a vertex)" % (
            name, run["triangles"], run["whole_mesh_triangles"], run["patch_radius"])
    return "%s, %s mm voxels (%s = %.2f M voxels, %d triangles, %s)" % (
        name, run["voxel_size"], "x".join(map(str, run["size"])), run["voxels"] / 1e6, run["triangles"],
        "closed" if run["closed"] else "open")


def detail_table(run):
    lines = ["### " + run_title(run), ""]
    if run["reference"]:
        lines.append("Reference: %d voxels inside%s (reference computed in %.1f s).\n" % (
            run["inside_voxels"], ", %d voxels where the patch decides inside/outside" % run["decided_voxels"]
            if run.get("patch_radius", 0) > 0 else "", run["reference_seconds"]))
    lines.append("| task | peer | threads | time | CPU time | ratio to fastest | M voxels/s | peak MB | "
                 "voxels disagreeing (far) | max abs sdf error (in band) | sdf sign errors |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|")
    results = run["results"]
    for task in ("occupancy", "solid", "sdf"):
        rows = [r for r in results if r["task"] == task]
        for threads in sorted({r["threads"] for r in rows}):
            same = [r for r in rows if r["threads"] == threads]
            fastest = min(r["seconds"] for r in same)
            for r in sorted(same, key=lambda r: r["seconds"]):
                seconds = fmt_seconds(r["seconds"]) + (" (est.)" if r["extrapolated"] else "")
                disagree = "" if r["disagree"] < 0 else "%d (%d)" % (r["disagree"], r["disagree_far"])
                error = "" if r["max_abs_error"] is None or r["max_abs_error"] < 0 else "%.3g (%.3g)" % (
                    r["max_abs_error"], r["max_abs_error_in_band"])
                signs = "" if r["sign_errors"] < 0 else str(r["sign_errors"])
                if r["extrapolated"] and r["sign_errors"] >= 0:
                    signs += " (of %d sampled)" % r["evaluated_voxels"]
                lines.append("| %s | %s | %d | %s | %s | %.2f | %.1f | %s | %s | %s | %s |" % (
                    task, r["name"], threads, seconds, fmt_seconds(r.get("cpu_seconds", 0)), r["seconds"] / fastest,
                    run["voxels"] / r["seconds"] / 1e6,
                    fmt_mb(r.get("peak_megabytes")), disagree, error, signs))
    lines.append("")
    return "\n".join(lines)


def growth_table(runs, label, value):
    """One row per run: time (and peak MB) of every peer."""
    keys = [MODULE_OCC, VOXEL_MODELLER, MODULE_SOLID, ITK_BINARY, STENCIL, MODULE_SDF, MAURER, VTK_DISTANCE]
    short = ["module occupancy", "vtkVoxelModeller", "module solid", "ITK binary", "VTK stencil",
             "module sdf (band)", "ITK binary + Maurer", "vtkImplicitPolyDataDistance"]
    present = [i for i, key in enumerate(keys) if any(find(run, key, run["results"][0]["threads"]) for run in runs)]
    lines = ["| %s | triangles | M voxels | %s | occupancy speed-up | module solid / ITK binary | "
             "sdf speed-up vs vtkImplicitPolyDataDistance | module sdf (band) / ITK binary |" % (
                 label, " | ".join(short[i] + " s (MB)" for i in present)),
             "|---|---|---|" + "---|" * len(present) + "---|---|---|---|"]
    for run in runs:
        threads = run["results"][0]["threads"]
        cells = []
        for i in present:
            r = find(run, keys[i], threads)
            cells.append("" if r is None else "%.3g%s (%s)" % (r["seconds"], "*" if r["extrapolated"] else "",
                                                               fmt_mb(r.get("peak_megabytes"))))
        pairs = [(VOXEL_MODELLER, MODULE_OCC), (MODULE_SOLID, ITK_BINARY), (VTK_DISTANCE, MODULE_SDF),
                 (MODULE_SDF, ITK_BINARY)]
        ratios = []
        for numerator, denominator in pairs:
            wall = ratio(run, numerator, denominator, threads)
            cpu = ratio(run, numerator, denominator, threads, "cpu_seconds")
            ratios.append("" if wall is None else "%.3g" % wall + ("" if cpu is None else " (%.3g)" % cpu))
        lines.append("| %s | %d | %.2f | %s | %s |" % (
            value(run), run["triangles"], run["voxels"] / 1e6, " | ".join(cells), " | ".join(ratios)))
    lines.append("")
    lines.append("Wall times in s, best of the runs; `*` estimated from sampled z slices; (MB) the peak RSS the peer "
                 "adds to the process (its output included); ratios of wall times (of CPU times in parentheses). "
                 "One thread.")
    lines.append("")
    return "\n".join(lines)


def ratio(run, numerator, denominator, threads, field="seconds"):
    a = find(run, numerator, threads)
    b = find(run, denominator, threads)
    if a is None or b is None or not b.get(field) or b[field] <= 0:
        return None
    return a[field] / b[field]


def span(values):
    values = [v for v in values if v is not None]
    if not values:
        return "not measured"
    return "%.2g-%.2g" % (min(values), max(values)) if len(values) > 1 else "%.2g" % values[0]


def targets(closed_runs, patch_runs):
    """The targets of issue #3, evaluated on the data: one row per run and thread count, then a summary."""
    lines = ["## Targets (evaluated by the script from the runs above)", "",
             "| mesh | voxel | threads | occupancy: vtkVoxelModeller / module (>= 10) | solid: module / ITK binary "
             "(<= 1) | solid: module disagreements (0) | sdf band: vtkImplicitPolyDataDistance / module (>= 50) | "
             "sdf band: module / ITK binary (<= 5) | sdf exact everywhere: vtkImplicitPolyDataDistance / module "
             "(>= 50) | sdf exact everywhere: module / ITK binary (<= 5) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    checks = {k: [] for k in ("occ", "solid_time", "solid_zero", "sdf_vtk", "sdf_itk", "exact_vtk", "exact_itk")}

    def cell(key, value, good, cpu=None):
        if value is None:
            return ""
        met = good(value)
        checks[key].append((value, met, cpu))
        return "%.3g%s %s" % (value, "" if cpu is None else " (CPU %.3g)" % cpu, "met" if met else "**not met**")

    for run in closed_runs:
        for threads in sorted({r["threads"] for r in run["results"]}):
            solid = find(run, MODULE_SOLID, threads)
            zero = ""
            if solid is not None and solid["disagree"] >= 0 and run["closed"]:
                checks["solid_zero"].append((solid["disagree"], solid["disagree"] == 0, None))
                zero = "%d %s" % (solid["disagree"], "met" if solid["disagree"] == 0 else "**not met**")
            lines.append("| %s | %s mm | %d | %s | %s | %s | %s | %s | %s | %s |" % (
                os.path.basename(run["mesh"]), run["voxel_size"], threads,
                cell("occ", ratio(run, VOXEL_MODELLER, MODULE_OCC, threads), lambda v: v >= 10,
                     ratio(run, VOXEL_MODELLER, MODULE_OCC, threads, "cpu_seconds")),
                cell("solid_time", ratio(run, MODULE_SOLID, ITK_BINARY, threads), lambda v: v <= 1,
                     ratio(run, MODULE_SOLID, ITK_BINARY, threads, "cpu_seconds")),
                zero,
                cell("sdf_vtk", ratio(run, VTK_DISTANCE, MODULE_SDF, threads), lambda v: v >= 50,
                     ratio(run, VTK_DISTANCE, MODULE_SDF, threads, "cpu_seconds")),
                cell("sdf_itk", ratio(run, MODULE_SDF, ITK_BINARY, threads), lambda v: v <= 5,
                     ratio(run, MODULE_SDF, ITK_BINARY, threads, "cpu_seconds")),
                cell("exact_vtk", ratio(run, VTK_DISTANCE, MODULE_EXACT, threads), lambda v: v >= 50,
                     ratio(run, VTK_DISTANCE, MODULE_EXACT, threads, "cpu_seconds")),
                cell("exact_itk", ratio(run, MODULE_EXACT, ITK_BINARY, threads), lambda v: v <= 5,
                     ratio(run, MODULE_EXACT, ITK_BINARY, threads, "cpu_seconds"))))
    lines.append("")

    def summary(key, text):
        found = checks[key]
        if not found:
            return "- %s: not measured." % text
        met = sum(1 for _, ok, _ in found if ok)
        cpu = [c for _, _, c in found if c is not None]
        return "- %s: met in %d of %d runs (measured %s%s)." % (
            text, met, len(found), span([v for v, _, _ in found]),
            "; in CPU time %s" % span(cpu) if cpu else "")

    lines.append("Summary over the closed meshes (wall-time ratios decide; CPU-time ratios, steadier on a loaded "
                 "machine, in parentheses; vtkImplicitPolyDataDistance's time estimated from sampled slices; one "
                 "thread):")
    lines.append("")
    lines.append(summary("occ", "Occupancy >= 10x faster than vtkVoxelModeller (time ratio vtkVoxelModeller / module)"))
    lines.append(summary("solid_time", "Solid no slower than itk::TriangleMeshToBinaryImageFilter (module / ITK)"))
    lines.append(summary("solid_zero", "Solid: zero disagreement with the reference on closed meshes (voxels)"))
    lines.append(summary("sdf_vtk", "Signed distance (exact in the band) >= 50x faster than "
                                    "vtkImplicitPolyDataDistance"))
    lines.append(summary("sdf_itk", "Signed distance (exact in the band) within 5x of "
                                    "TriangleMeshToBinaryImageFilter's time"))
    lines.append(summary("exact_vtk", "Signed distance exact everywhere >= 50x faster than "
                                      "vtkImplicitPolyDataDistance"))
    lines.append(summary("exact_itk", "Signed distance exact everywhere within 5x of "
                                      "TriangleMeshToBinaryImageFilter's time"))
    if patch_runs:
        lines.append("")
        lines.append("Open patches: solid voxels mislabelled far from the surface (farther than half a voxel diagonal, "
                     "where the patch decides inside/outside); target: fewer than both peers.")
        lines.append("")
        met_count = 0
        for run in patch_runs:
            for threads in sorted({r["threads"] for r in run["results"]})[:1]:
                far = {}
                for key, label in ((MODULE_SOLID, "module"), (ITK_BINARY, "ITK binary"), (STENCIL, "VTK stencil")):
                    r = find(run, key, threads)
                    far[label] = None if r is None or r["disagree"] < 0 else r["disagree_far"]
                met = far["module"] is not None and all(
                    far[p] is not None and far["module"] < far[p] for p in ("ITK binary", "VTK stencil"))
                met_count += met
                slower = ratio(run, MODULE_SOLID, ITK_BINARY, threads)
                occupancy = ratio(run, VOXEL_MODELLER, MODULE_OCC, threads)
                lines.append("- %s at %s mm: module %s, ITK binary %s, VTK stencil %s of %d decided voxels: %s. "
                             "Time there: solid module / ITK binary %s (target <= 1: %s), occupancy "
                             "vtkVoxelModeller / module %s (target >= 10: %s)." % (
                                 os.path.basename(run["mesh"]), run["voxel_size"], far["module"], far["ITK binary"],
                                 far["VTK stencil"], run["decided_voxels"], "met" if met else "**not met**",
                                 "%.3g" % slower if slower else "?", "met" if slower and slower <= 1 else "**not met**",
                                 "%.3g" % occupancy if occupancy else "?",
                                 "met" if occupancy and occupancy >= 10 else "**not met**"))
        lines.append("- Fewer far mislabelled voxels than both peers: met on %d of %d patches." % (
            met_count, len(patch_runs)))
    lines.append("")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program")
    parser.add_argument("--threads", default="1")
    parser.add_argument("--voxel-sizes", default="1,0.5")
    parser.add_argument("--meshes", default=DEFAULT_MESHES)
    parser.add_argument("--exact-sdf-max-voxels", type=float, default=2e6)
    parser.add_argument("--patch-meshes", default="bunny00,fandisk_large")
    parser.add_argument("--patch-radius", type=float, default=35.0)
    parser.add_argument("--patch-voxel-sizes", default="1")
    parser.add_argument("--triangle-counts", default="5000,20000,80000,320000")
    parser.add_argument("--growth-mesh", default="bunny00")
    parser.add_argument("--growth-voxel-sizes", default="2,1,0.5,0.35,0.25")
    parser.add_argument("--vtk-distance-voxels", type=int, default=100000)
    parser.add_argument("--growth-vtk-distance-voxels", type=int, default=50000)
    parser.add_argument("--growth-sdf-min-voxel-size", type=float, default=0.5)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--work-dir", default=None)
    parser.add_argument("--output", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                         "VOXELIZATION.md"))
    args = parser.parse_args()
    work = args.work_dir or tempfile.mkdtemp(prefix="ffd-voxelization-peers-")
    os.makedirs(work, exist_ok=True)
    began = time.time()

    def run_program(mesh, size, tag, extra):
        report = os.path.join(work, "%s-%s-%s.json" % (tag, os.path.basename(mesh)[:-4], size))
        command = [args.program, mesh, "--scale-to", "100", "--voxel-size", str(size), "--margin", "3",
                   "--threads", args.threads, "--repeat", str(args.repeat), "--json", report] + extra
        print(" ".join(command), flush=True)
        subprocess.run(command, check=True)
        with open(report) as handle:
            result = json.load(handle)
        result["part"] = tag
        return result

    def cells_of(mesh, size):
        # A rough voxel count from the scaled bounds (largest side 100 mm + 2 x 3 mm margin), for the exact-sdf cap.
        return (106.0 / float(size)) ** 3

    closed_runs = []
    for name in filter(None, args.meshes.split(",")):
        mesh = mesh_path(name, work)
        for size in args.voxel_sizes.split(","):
            extra = ["--vtk-distance-voxels", str(args.vtk_distance_voxels)]
            if cells_of(mesh, size) > args.exact_sdf_max_voxels:
                extra += ["--no-exact-sdf", "--reference-band"]
            closed_runs.append(run_program(mesh, size, "closed", extra))
    patch_runs = []
    for name in filter(None, args.patch_meshes.split(",")):
        mesh = mesh_path(name, work)
        for size in args.patch_voxel_sizes.split(","):
            patch_runs.append(run_program(mesh, size, "patch", ["--patch-radius", str(args.patch_radius),
                                                                "--no-exact-sdf", "--vtk-distance-voxels",
                                                                str(args.vtk_distance_voxels)]))
    quick = ["--no-reference", "--no-exact-sdf", "--vtk-distance-voxels", str(args.growth_vtk_distance_voxels)]
    triangle_runs = []
    for count in filter(None, args.triangle_counts.split(",")):
        triangle_runs.append(run_program(sphere_mesh(int(count), work), 1, "triangles", quick))
    voxel_runs = []
    if args.growth_mesh:
        mesh = mesh_path(args.growth_mesh, work)
        for size in args.growth_voxel_sizes.split(","):
            tasks = [] if float(size) >= args.growth_sdf_min_voxel_size else ["--tasks", "occupancy,solid"]
            voxel_runs.append(run_program(mesh, size, "voxels", quick + tasks))
    minutes = (time.time() - began) / 60.0

    command = ("python3 benchmark/voxelization_peers.py BUILD/benchmark/ffd-voxelization-peers --threads %s "
               "--voxel-sizes %s --meshes %s --patch-meshes %s --patch-radius %g --patch-voxel-sizes %s "
               "--triangle-counts %s --growth-mesh %s --growth-voxel-sizes %s --growth-sdf-min-voxel-size %g "
               "--exact-sdf-max-voxels %g --vtk-distance-voxels %d --growth-vtk-distance-voxels %d --repeat %d" % (
                   args.threads, args.voxel_sizes, args.meshes, args.patch_meshes, args.patch_radius,
                   args.patch_voxel_sizes, args.triangle_counts, args.growth_mesh, args.growth_voxel_sizes,
                   args.growth_sdf_min_voxel_size, args.exact_sdf_max_voxels, args.vtk_distance_voxels,
                   args.growth_vtk_distance_voxels, args.repeat))
    try:
        load = "%.1f, %.1f, %.1f" % os.getloadavg()
    except OSError:
        load = "unknown"
    all_runs = closed_runs + patch_runs + triangle_runs + voxel_runs
    with open(os.path.splitext(args.output)[0] + ".json", "w") as handle:
        json.dump({"command": command, "minutes": minutes, "runs": all_runs}, handle, indent=1)

    with open(args.output, "w") as out:
        out.write("# Voxelization: TriangleMeshToVoxelImageFilter and its peers\n\n")
        out.write("Written by `benchmark/voxelization_peers.py` (program `benchmark/ffd-voxelization-peers.cxx`, "
                  "data in `%s`); command:\n\n```\n%s\n```\n\n" % (
                      os.path.basename(os.path.splitext(args.output)[0] + ".json"), command))
        out.write("The run took %.1f min of wall time on %d cores (load average at its end: %s). The machine is "
                  "shared with other builds and jobs, so absolute times vary by up to 2x between runs: compare "
                  "the ratios within one table (one program run, peers timed back to back).\n\n" % (
                      minutes, os.cpu_count() or 0, load))
        out.write("Every mesh is scaled so its largest side is 100 mm; grid from its bounds with a 3 mm margin. "
                  "Times are wall-clock, best of %d runs (one run when over 2 s), from a fresh filter each time "
                  "(hierarchies and locators included). `ratio` is the time over the fastest peer of the same task "
                  "and thread count. *Peak MB* is what the peer adds to the process's peak resident memory "
                  "(Linux VmHWM, reset before each run) on top of what the program already holds (mesh, "
                  "references): its output image included.\n\n" % args.repeat)
        out.write("Accuracy against a per-voxel reference: inside = |generalized winding number| > 1/2 (module's "
                  "reference path, fast winding number with beta 2, every voxel on its own), distance = exact "
                  "point-to-triangle distance of every voxel. *Disagreeing* counts voxels whose label differs "
                  "from the reference, *far* those of them farther than half a voxel diagonal from the surface "
                  "(mislabelled regions rather than boundary voxels). Occupancy is scored against "
                  "distance <= half the voxel diagonal, the module's definition; vtkVoxelModeller marks a voxel "
                  "when the closest point of a triangle lies in the voxel's box, a slightly different rule, so "
                  "its disagreements near the surface are expected. The module's banded sdf is exact within "
                  "3 voxels and clamped beyond (its error outside the band is the clamp, by design). On grids of "
                  "more than %.3g M voxels the module's exact-everywhere distance is not run and the reference "
                  "distance is exact only up to twice the band (bounded queries), so only errors in the band are "
                  "given. vtkImplicitPolyDataDistance is evaluated on whole z slices of at most %d voxels "
                  "(%d in the growth runs) and its time scaled to the grid (est.). The growth runs have no "
                  "reference (timing and memory only); the voxel-count growth times the signed distance only "
                  "down to %g mm.\n\n" % (args.exact_sdf_max_voxels / 1e6, args.vtk_distance_voxels,
                                         args.growth_vtk_distance_voxels, args.growth_sdf_min_voxel_size))
        out.write("Open patches (the module's main use: a region cut out of a larger mesh): the triangles whose "
                  "centroid lies within %g mm of the vertex nearest to the centre of the bounding box's +x face; "
                  "the grid covers the whole mesh. There inside/outside is scored only where the patch decides it: "
                  "voxels nearer to the patch than to the rest of the mesh by more than half a voxel diagonal, "
                  "whose right label is the whole mesh's inside (the side of the patch they lie on); occupancy "
                  "is scored everywhere against the distance to the patch.\n\n" % args.patch_radius)
        out.write("The targets of issue #3, evaluated on these runs, are summarised in the notes at the end "
                  "([Targets](#targets-evaluated-by-the-script-from-the-runs-above)).\n\n")
        out.write("\n## Growth with the triangle count (UV spheres, 1 mm voxels)\n\n")
        out.write(growth_table(triangle_runs, "sphere", lambda run: os.path.basename(run["mesh"])[:-4]))
        out.write("\n## Growth with the voxel count (%s)\n\n" % args.growth_mesh)
        out.write(growth_table(voxel_runs, "voxel size", lambda run: "%g mm" % run["voxel_size"]))
        out.write("\n## Closed meshes\n\n")
        out.write("\n".join(detail_table(run) for run in closed_runs))
        out.write("\n## Open patches\n\n")
        out.write("\n".join(detail_table(run) for run in patch_runs))
        out.write("\n")
        out.write(targets(closed_runs, patch_runs))
    print("wrote", args.output, "in %.1f min" % minutes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
