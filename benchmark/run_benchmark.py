#!/usr/bin/env python3
"""The paper's experiment (Tables 2 and 3) for the module's methods and the peers, from one command.

Usage: benchmark/run.sh [options]   (or python3 benchmark/run_benchmark.py [options]); see benchmark/README.md.

Steps: install missing Debian packages (elastix, plastimatch, libcgal-demo, gnuplot-nox, time), build the
project (cmake in ./build), extract the CGAL meshes, generate the cases (mesh x regime x seed) with
ffd-benchmark-tool, run every method (ffd-match --method ...) and every peer (elastix, plastimatch) with
/usr/bin/time -v per stage, score every result with ffd-benchmark-tool, and write RESULTS.md, results.json
and the PNG charts into the results folder (default: benchmark/).
"""

import argparse
import datetime
import json
import math
import os
import platform
import re
import shutil
import array
import statistics
import subprocess
import sys
import tarfile
import time

import deeds_peer
import posed_cases

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CGAL_DATA = "/usr/share/doc/libcgal-dev/data.tar.gz"
ALL_MESHES = ["fandisk_large", "bunny00", "diplodocus", "cheese"]
# Meshes of the same archive that no default was chosen on, for checking a choice on shapes it was not made on
# (run on request: --meshes armadillo,camel,...).
HELD_OUT_MESHES = ["armadillo", "camel", "turbine", "bull", "homer"]
ALL_REGIMES = ["paper", "smooth", "short", "posed"]
# "short" (the smooth regime's noise smoothed over half the length) is a second noise model, run on request.
# "posed" is the smooth regime's case (same source, target and truth) with the target posed by a similarity drawn
# from the seed (posed_cases.random_pose), run on request.
DEFAULT_REGIMES = ["paper", "smooth"]
ALL_METHODS = ["go", "mrf", "par", "go+par", "mrf+par", "go+cpd"]
# Image peers given by an environment variable (built outside the repository; benchmark/README.md, "deeds").
GIVEN_IMAGE_PEERS = {"deeds": "DEEDS_EXE"}
IMAGE_PEERS = ["elastix", "plastimatch-mi", "plastimatch-mse"] + list(GIVEN_IMAGE_PEERS)
# Point-set peers: programs that are not installed by the benchmark, given by an environment variable
# (benchmark/README.md, "Point-set peers"); nothing of them is in the repository.
POINT_PEERS = {"bcpd": "BCPD_EXE", "nicp": "NICP_EXE"}
# Every peer that runs only when its program is given, and the variable that gives it.
GIVEN_PEERS = dict(POINT_PEERS, **GIVEN_IMAGE_PEERS)
ALL_PEERS = IMAGE_PEERS + list(POINT_PEERS)
# deeds' options after -F, -M and -O, for the benchmark's 1 mm images of about 70^3 voxels: 3 levels of control
# grids 6, 5 and 4 voxels apart (the module's grid 20 is about 5 voxels apart), searches up to 8, 3 and 2 voxels.
# Its own defaults (5 levels, grids 8x7x6x5x4, searches up to 40 voxels, for abdominal CT) ended further from the
# truth on all 8 seed-1 cases, a smoother set on average (benchmark/README.md, "deeds"). FFD_DEEDS_OPTIONS
# replaces them ("" for its defaults).
DEEDS_OPTIONS = os.environ.get("FFD_DEEDS_OPTIONS", "-l 3 -G 6x5x4 -L 4x3x2 -Q 2x1x1")
# BCPD's settings for roughly aligned shapes (-g0.1 -ux as its README recommends them; outlier probability 0.1,
# beta 1.2, lambda 50; similarity + non-rigid) with its variational-Bayes acceleration (Nystrom + KD tree, the
# values of its -A option); FFD_BCPD_OPTIONS replaces them.
BCPD_OPTIONS = os.environ.get("FFD_BCPD_OPTIONS", "-w0.1 -b1.2 -l50 -g0.1 -ux -Tsrn -K70 -J300 -p -d7 -e0.15 -f0.2")
# BCPD's settings for shapes far apart: its README's "gamma around 2 to 10 if your target point set is largely
# rotated", each point set normalized on its own (-ue, its default); the rest as above. FFD_BCPD_POSED_OPTIONS
# replaces them.
BCPD_POSED_OPTIONS = os.environ.get("FFD_BCPD_POSED_OPTIONS",
                                    "-w0.1 -b1.2 -l50 -g3 -ue -Tsrn -K70 -J300 -p -d7 -e0.15 -f0.2")
# The pose stage of ffd-match's methods per regime (--initial-transform); regimes not named here use none.
POSE_STAGE = {"posed": "similarity"}
PACKAGES = ["elastix", "plastimatch", "libcgal-demo", "gnuplot-nox", "time"]
SMOKE_MESH = "smoke-torus"
# The posed smoke case's mesh: the smoke torus with a one-sided lobe, so that no rotation maps it onto itself (the
# smoke torus has a 3-fold axis and in-plane half-turn symmetries: a pose is not defined on it).
SMOKE_POSED_MESH = "smoke-lobed-torus"


def log(message):
    print("run_benchmark: " + message, file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------------------------
# Setup: packages, build, meshes


def install_packages():
    missing = []
    for package in PACKAGES:
        status = subprocess.run(["dpkg-query", "-W", "-f=${Status}", package], capture_output=True, text=True)
        if "install ok installed" not in status.stdout:
            missing.append(package)
    if not missing:
        return
    prefix = [] if os.geteuid() == 0 else (["sudo"] if shutil.which("sudo") else None)
    if prefix is None:
        log("missing packages %s and neither root nor sudo: continuing without them" % " ".join(missing))
        return
    log("installing " + " ".join(missing))
    environment = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(prefix + ["apt-get", "update", "-q"], check=True, env=environment)
    subprocess.run(prefix + ["apt-get", "install", "-y", "-q", "--no-install-recommends"] + missing, check=True,
                   env=environment)


def build_project(build_dir, install, portable):
    """Release build of the programs, for this machine's processor unless portable (the timings' configuration,
    recorded in RESULTS.md by build_configuration)."""
    if install:
        subprocess.run(["bash", os.path.join(ROOT, "Utilities", "InstallDependencies.sh")], check=True)
    subprocess.run(["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
                    "-DFFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE=" + ("OFF" if portable else "ON")], check=True)
    jobs = str(os.cpu_count() or 2)
    subprocess.run(["cmake", "--build", build_dir, "-j" + jobs, "--target", "ffd-match", "ffd-voxelize",
                    "ffd-benchmark-tool"], check=True)


def build_configuration(build_dir):
    """The build type and instruction set of the build in build_dir, from its CMake cache (None without one)."""
    values = {}
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as cache:
            for line in cache:
                match = re.match(r"(CMAKE_BUILD_TYPE|FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE):\w+=(.*)", line)
                if match:
                    values[match.group(1)] = match.group(2).strip()
    except OSError:
        return None
    native = values.get("FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE", "OFF").upper() in ("ON", "1", "TRUE", "YES")
    return "%s, %s" % (values.get("CMAKE_BUILD_TYPE") or "no build type",
                       "-march=native (FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE)" if native else "portable")


def extract_meshes(names, folder):
    os.makedirs(folder, exist_ok=True)
    paths = {}
    wanted = {"data/meshes/%s.off" % name: name for name in names if name not in (SMOKE_MESH, SMOKE_POSED_MESH)}
    if wanted:
        if not os.path.exists(CGAL_DATA):
            raise SystemExit("run_benchmark: %s is missing (Debian package libcgal-demo)" % CGAL_DATA)
        with tarfile.open(CGAL_DATA) as archive:
            for member in archive.getmembers():
                if member.name in wanted:
                    name = wanted[member.name]
                    path = os.path.join(folder, name + ".off")
                    with archive.extractfile(member) as data, open(path, "wb") as out:
                        out.write(data.read())
                    paths[name] = path
        for name in wanted.values():
            if name not in paths:
                raise SystemExit("run_benchmark: %s.off is not in %s" % (name, CGAL_DATA))
    if SMOKE_MESH in names:
        paths[SMOKE_MESH] = write_torus(os.path.join(folder, SMOKE_MESH + ".off"))
    if SMOKE_POSED_MESH in names:
        paths[SMOKE_POSED_MESH] = write_torus(os.path.join(folder, SMOKE_POSED_MESH + ".off"), lobe=0.35)
    return paths


def write_torus(path, major=30.0, minor=12.0, segments=48, rings=24, lobe=0.0):
    """A bumpy torus (2,304 triangles), the smoke case's mesh: made here, so the smoke case needs no download.
    lobe > 0 adds two swellings of the tube along the ring, of relative heights lobe (at u = 0.7 rad) and lobe / 2
    (at u = 1.9 rad): no rotation maps that torus onto itself."""

    def swelling(u, centre):
        distance = math.atan2(math.sin(u - centre), math.cos(u - centre))
        return math.exp(-(distance / 0.5) ** 2)

    points = []
    for i in range(segments):
        u = 2.0 * math.pi * i / segments
        for j in range(rings):
            v = 2.0 * math.pi * j / rings
            r = minor * (1.0 + 0.15 * math.sin(3.0 * u) * math.cos(2.0 * v)
                         + lobe * (swelling(u, 0.7) + 0.5 * swelling(u, 1.9)))
            points.append(((major + r * math.cos(v)) * math.cos(u), (major + r * math.cos(v)) * math.sin(u),
                           r * math.sin(v)))
    triangles = []
    for i in range(segments):
        for j in range(rings):
            a = i * rings + j
            b = ((i + 1) % segments) * rings + j
            c = ((i + 1) % segments) * rings + (j + 1) % rings
            d = i * rings + (j + 1) % rings
            triangles += [(a, b, c), (a, c, d)]
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(points), len(triangles)))
        out.writelines("%.9g %.9g %.9g\n" % p for p in points)
        out.writelines("3 %d %d %d\n" % t for t in triangles)
    return path


# ------------------------------------------------------------------------------------------------
# Running and timing


class Stage:
    """One timed process: wall time (s), peak resident memory (MB), exit code, the end of its output."""

    def __init__(self, name, seconds, peak_mb, returncode, output, cpu_seconds=None):
        self.name = name
        self.seconds = seconds
        self.peak_mb = peak_mb
        self.returncode = returncode
        self.output = output
        self.cpu_seconds = cpu_seconds  # user + system time: less noisy than wall time on a shared machine

    def ok(self):
        return self.returncode == 0

    def record(self):
        return {"stage": self.name, "seconds": self.seconds, "cpu_seconds": self.cpu_seconds, "peak_mb": self.peak_mb,
                "exit_code": self.returncode}

    def reason(self):
        lines = [line for line in self.output.splitlines() if line.strip() and not line.startswith("$ ")]
        errors = [line for line in lines if "error" in line.lower()]
        if self.returncode > 128 or self.returncode < 0:
            text = "killed by signal %d" % (self.returncode - 128 if self.returncode > 128 else -self.returncode)
        else:
            text = (errors or lines or ["no output"])[-1].strip()
        return "%s failed (exit %d): %s" % (self.name, self.returncode, text[:200])


TIME = os.access("/usr/bin/time", os.X_OK)


def run(name, command, log_path, environment=None, timeout=3600):
    """Runs command under /usr/bin/time -v (or os.wait4 when it is missing); output goes to log_path."""
    time_path = log_path + ".time"
    full = (["/usr/bin/time", "-v", "-o", time_path] + command) if TIME else command
    start = time.monotonic()
    with open(log_path, "w") as out:
        out.write("$ " + " ".join(command) + "\n")
        out.flush()
        process = subprocess.Popen(full, stdout=out, stderr=subprocess.STDOUT, env=environment)
        try:
            _, status, usage = os.wait4(process.pid, 0)
            process.returncode = os.waitstatus_to_exitcode(status)
        except KeyboardInterrupt:
            process.kill()
            raise
    wall = time.monotonic() - start
    peak_mb = usage.ru_maxrss / 1024.0
    cpu = usage.ru_utime + usage.ru_stime
    returncode = process.returncode
    if TIME and os.path.exists(time_path):
        with open(time_path) as timing:
            text = timing.read()
        match = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", text)
        if match:
            wall = int(match.group(1) or 0) * 3600 + int(match.group(2)) * 60 + float(match.group(3))
        times = [re.search(r"%s time \(seconds\): ([\d.]+)" % kind, text) for kind in ("User", "System")]
        if all(times):
            cpu = sum(float(t.group(1)) for t in times)
        match = re.search(r"Maximum resident set size \(kbytes\): (\d+)", text)
        if match:
            peak_mb = int(match.group(1)) / 1024.0
        match = re.search(r"Exit status: (\d+)", text)
        if match:
            returncode = int(match.group(1))
        match = re.search(r"Command terminated by signal (\d+)", text)
        if match:
            returncode = 128 + int(match.group(1))
    with open(log_path) as logged:
        output = logged.read()[-4000:]
    return Stage(name, wall, peak_mb, returncode, output, cpu)


def read_json(path):
    try:
        with open(path) as data:
            return json.load(data)
    except (OSError, ValueError):
        return None


def tool_version(command, pattern):
    try:
        text = subprocess.run(command, capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    match = re.search(pattern, text)
    return match.group(1) if match else text.strip()[:80] or None


def package_version(package):
    result = subprocess.run(["dpkg-query", "-W", "-f=${Version}", package], capture_output=True, text=True)
    return result.stdout.strip() or None


# ------------------------------------------------------------------------------------------------
# Peers


def grid_spacing(target_path, grid, voxel_size):
    """The control-point spacing of ffd-match's grid: grid points over the target's bounds + its image margin
    (band 2 voxels + 2 voxels), i.e. (extent + 8 voxels) / (grid - 3) per axis."""
    low = [float("inf")] * 3
    high = [float("-inf")] * 3
    with open(target_path) as mesh:
        tokens = mesh.read().split()
    assert tokens[0] == "OFF", target_path
    count = int(tokens[1])
    for i in range(count):
        for d in range(3):
            value = float(tokens[4 + 3 * i + d])
            low[d] = min(low[d], value)
            high[d] = max(high[d], value)
    margin = 4.0 * voxel_size
    return [(high[d] - low[d] + 2.0 * margin) / (grid - 3) for d in range(3)]


# The parts of elastix's parameter maps that its B-spline stage and the posed regime's affine stage share.
_ELASTIX_HEAD = """(FixedInternalImagePixelType "float")
(MovingInternalImagePixelType "float")
(FixedImageDimension 3)
(MovingImageDimension 3)
(UseDirectionCosines "true")
(Registration "MultiResolutionRegistration")
(Interpolator "BSplineInterpolator")
(ResampleInterpolator "FinalBSplineInterpolator")
(Resampler "DefaultResampler")
(FixedImagePyramid "FixedSmoothingImagePyramid")
(MovingImagePyramid "MovingSmoothingImagePyramid")
(Optimizer "AdaptiveStochasticGradientDescent")
"""
_ELASTIX_SAMPLING = """(HowToCombineTransforms "Compose")
(NumberOfResolutions {resolutions})
(MaximumNumberOfIterations {iterations})
(ImageSampler "RandomCoordinate")
(NumberOfSpatialSamples {samples})
(NewSamplesEveryIteration "true")
(UseRandomSampleRegion "false")
(ErodeMask "false")
(BSplineInterpolationOrder 1)
(FinalBSplineInterpolationOrder 3)
(AutomaticParameterEstimation "true")
"""
_ELASTIX_OUTPUT = """(DefaultPixelValue 0)
(WriteResultImage "false")
(ResultImageFormat "mha")
(RandomSeed {seed})
"""

ELASTIX_PARAMETERS = ("// B-spline registration of the unsigned distance images of the meshes (benchmark/README.md).\n"
                      + _ELASTIX_HEAD + """(Transform "BSplineTransform")
(Metric "AdvancedMattesMutualInformation")
(NumberOfHistogramBins 32)
(FinalGridSpacingInPhysicalUnits {spacing})
(GridSpacingSchedule {schedule})
""" + _ELASTIX_SAMPLING + """(AutomaticTransformInitialization "false")
""" + _ELASTIX_OUTPUT)

# The affine stage that precedes the B-spline stage in the posed regime (elastix's usual affine + B-spline
# pipeline): moving image's centre onto the fixed image's centre to start, then an affine transform.
ELASTIX_AFFINE_PARAMETERS = ("// Affine registration of the unsigned distance images, before the B-spline stage.\n"
                             + _ELASTIX_HEAD + """(Transform "AffineTransform")
(Metric "AdvancedMattesMutualInformation")
(NumberOfHistogramBins 32)
(AutomaticScalesEstimation "true")
(AutomaticTransformInitialization "true")
(AutomaticTransformInitializationMethod "GeometricalCenter")
""" + _ELASTIX_SAMPLING + _ELASTIX_OUTPUT)

PLASTIMATCH_COMMAND = """# B-spline registration of the unsigned distance images of the meshes (benchmark/README.md).
[GLOBAL]
fixed={fixed}
moving={moving}
fixed_roi={mask}
vf_out={field}

[STAGE]
xform=bspline
impl=plastimatch
optim=lbfgsb
threading=openmp
metric={metric}
regularization_lambda={regularization}
max_its={iterations}
convergence_tol=1e-5
grad_tol=1e-4
grid_spac={coarse}
res=2 2 2

[STAGE]
max_its={fine_iterations}
grid_spac={spacing}
res=1 1 1
"""


def peer_images(case, work, tools, voxel_size, threads, smoke):
    """Voxelizes both meshes with ffd-voxelize on one common grid, the target's bounds + 8 voxels (as ffd-match's
    fixed image, so a peer's B-spline grid at the module's spacing has the module's number of control points):
    unsigned distance (sdf mode, band 5 voxels) of each mesh, and a band mask around the target surface that
    restricts the metric's samples. In the posed regime the source is far from the target's grid: it gets a grid of
    its own (its bounds + 8 voxels, same voxel size)."""
    folder = os.path.join(work, "images")
    os.makedirs(folder, exist_ok=True)
    fixed = os.path.join(folder, "target.mha")
    moving = os.path.join(folder, "source.mha")
    mask = os.path.join(folder, "target-band.mha")
    band = "%g" % (5.0 * voxel_size)
    stages = []
    common = ["--threads", str(threads)]
    stages.append(run("voxelize-target", [tools["ffd-voxelize"], case["target"], fixed, "--mode", "sdf", "--unsigned",
                                          "--voxel-size", "%g" % voxel_size, "--margin", "%g" % (8 * voxel_size),
                                          "--band-width", band] + common, os.path.join(folder, "voxelize-target.log")))
    if stages[-1].ok():
        geometry = ["--reference", fixed] if case["regime"] != "posed" else \
            ["--voxel-size", "%g" % voxel_size, "--margin", "%g" % (8 * voxel_size)]
        stages.append(run("voxelize-source", [tools["ffd-voxelize"], case["source"], moving, "--mode", "sdf",
                                              "--unsigned", "--band-width", band] + geometry + common,
                          os.path.join(folder, "voxelize-source.log")))
    if stages[-1].ok():
        stages.append(run("voxelize-mask", [tools["ffd-voxelize"], case["target"], mask, "--mode", "band",
                                            "--reference", fixed, "--band-width", band] + common,
                          os.path.join(folder, "voxelize-mask.log")))
    return {"fixed": fixed, "moving": moving, "mask": mask, "stages": stages}


def run_elastix(case, images, folder, tools, options):
    spacing = grid_spacing(case["target"], options.grid, options.voxel_size)
    resolutions = 1 if options.smoke else 3
    parameters = os.path.join(folder, "elastix-bspline.txt")
    with open(parameters, "w") as out:
        out.write(ELASTIX_PARAMETERS.format(
            spacing=" ".join("%.4f" % s for s in spacing),
            schedule=" ".join(" ".join([str(2 ** (resolutions - 1 - level))] * 3) for level in range(resolutions)),
            resolutions=resolutions, iterations=200 if options.smoke else 500, samples=2048, seed=case["seed"] + 1))
    maps = ["-p", parameters]
    if case["regime"] == "posed":
        affine = os.path.join(folder, "elastix-affine.txt")
        with open(affine, "w") as out:
            out.write(ELASTIX_AFFINE_PARAMETERS.format(resolutions=resolutions,
                                                       iterations=200 if options.smoke else 500, samples=2048,
                                                       seed=case["seed"] + 1))
        maps = ["-p", affine] + maps
    stages = [run("register", ["elastix", "-f", images["fixed"], "-m", images["moving"], "-fMask", images["mask"]]
                  + maps + ["-out", folder, "-threads", str(options.threads)], os.path.join(folder, "register.log"))]
    field = os.path.join(folder, "deformationField.mha")
    if stages[-1].ok():
        # The last map's parameters name the earlier maps' as their initial transform: the field is the whole.
        last = os.path.join(folder, "TransformParameters.%d.txt" % (len(maps) // 2 - 1))
        stages.append(run("field", ["transformix", "-def", "all", "-tp", last,
                                    "-out", folder, "-threads", str(options.threads)], os.path.join(folder, "field.log")))
        if stages[-1].ok() and not os.path.exists(field):
            alternatives = [name for name in os.listdir(folder) if name.startswith("deformationField.")
                            and not name.endswith(".raw")]
            if alternatives:
                field = os.path.join(folder, alternatives[0])
    return stages, field


def read_elastix_affine(path):
    """The affine stage of elastix's TransformParameters file: y = M (x - c) + t + c (M row-major)."""
    with open(path) as text:
        content = text.read()
    values = [float(v) for v in re.search(r"\(TransformParameters ([^)]*)\)", content).group(1).split()]
    centre = [float(v) for v in re.search(r"\(CenterOfRotationPoint ([^)]*)\)", content).group(1).split()]
    if len(values) != 12 or len(centre) != 3:
        raise ValueError("%s: not a 3-D affine transform" % path)
    return [values[0:3], values[3:6], values[6:9]], values[9:12], centre


def invert_affine(matrix, translation, centre):
    """x = M^-1 (y - t - c) + c, as (M^-1, offset): x = M^-1 y + offset."""
    (a, b, c), (d, e, f), (g, h, i) = matrix
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    inverse = [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
               [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
               [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]
    shifted = [translation[k] + centre[k] for k in range(3)]
    offset = [centre[r] - sum(inverse[r][k] * shifted[k] for k in range(3)) for r in range(3)]
    return inverse, offset


def read_mha_field(path):
    """A 3-D vector image of MetaImage format (header + LOCAL or separate data): header lines and the values."""
    header, values = deeds_peer.read_metaimage(path)
    if int(header.get("ElementNumberOfChannels", "1")) != 3:
        raise ValueError("%s is not a 3-D displacement field" % path)
    return header, values


def precondition_field(field, affine_file, source, folder):
    """For the posed regime: the inverse of elastix's whole transform T (x -> x + u(x), its field) at a source vertex
    p starts at p, far outside the fixed image's domain where u is 0, and stops there at once. This writes the
    source mapped by the inverse of elastix's own affine stage, A^-1(p), and the field of A^-1 o T, whose inverse
    at A^-1(p) is T's inverse at p and starts inside the domain. Returns the two paths."""
    inverse, offset = invert_affine(*read_elastix_affine(affine_file))
    header, values = read_mha_field(field)
    size = [int(v) for v in header["DimSize"].split()]
    spacing = [float(v) for v in header["ElementSpacing"].split()]
    origin = [float(v) for v in header.get("Offset", header.get("Origin", "0 0 0")).split()]
    direction = [float(v) for v in header.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split()]
    # MetaImage's TransformMatrix is column-major: physical = origin + D (index * spacing), D[r][c] = m[c * 3 + r].
    d = [[direction[c * 3 + r] for c in range(3)] for r in range(3)]
    out = array.array("f", bytes(4 * len(values)))
    index = 0
    for k in range(size[2]):
        for j in range(size[1]):
            for i in range(size[0]):
                step = (i * spacing[0], j * spacing[1], k * spacing[2])
                x = [origin[r] + d[r][0] * step[0] + d[r][1] * step[1] + d[r][2] * step[2] for r in range(3)]
                y = [x[r] + values[index + r] for r in range(3)]
                for r in range(3):
                    out[index + r] = (inverse[r][0] * y[0] + inverse[r][1] * y[1] + inverse[r][2] * y[2]
                                      + offset[r] - x[r])
                index += 3
    preconditioned = os.path.join(folder, "field-after-affine-inverse.mha")
    with open(preconditioned, "wb") as data:
        for key in ("ObjectType", "NDims", "BinaryData", "BinaryDataByteOrderMSB", "CompressedData",
                    "TransformMatrix", "Offset", "CenterOfRotation", "AnatomicalOrientation", "ElementSpacing",
                    "DimSize", "ElementNumberOfChannels"):
            value = {"BinaryDataByteOrderMSB": "False", "CompressedData": "False"}.get(key, header.get(key))
            if value is not None:
                data.write(("%s = %s\n" % (key, value)).encode())
        data.write(b"ElementType = MET_FLOAT\nElementDataFile = LOCAL\n")
        if sys.byteorder == "big":
            out.byteswap()
        data.write(out.tobytes())
    vertices, faces = read_off(source)
    moved = [tuple(sum(inverse[r][k] * v[k] for k in range(3)) + offset[r] for r in range(3)) for v in vertices]
    mapped_source = os.path.join(folder, "source-after-affine-inverse.off")
    write_off(mapped_source, moved, faces)
    return preconditioned, mapped_source


PLASTIMATCH_LAMBDA = os.environ.get("FFD_PLASTIMATCH_LAMBDA", "0.005")


def run_plastimatch(case, images, folder, tools, options, metric):
    spacing = grid_spacing(case["target"], options.grid, options.voxel_size)
    command = os.path.join(folder, "plastimatch-bspline.txt")
    field = os.path.join(folder, "vf.mha")
    with open(command, "w") as out:
        out.write(PLASTIMATCH_COMMAND.format(
            fixed=images["fixed"], moving=images["moving"], mask=images["mask"], field=field, metric=metric,
            iterations=30 if options.smoke else 100, fine_iterations=20 if options.smoke else 40, regularization=PLASTIMATCH_LAMBDA, coarse=" ".join("%.4f" % (2 * s) for s in spacing),
            spacing=" ".join("%.4f" % s for s in spacing)))
    environment = dict(os.environ, OMP_NUM_THREADS=str(options.threads))
    stages = [run("register", ["plastimatch", "register", command], os.path.join(folder, "register.log"),
                  environment=environment)]
    if stages[-1].ok() and not os.path.exists(field):
        stages[-1].returncode = 1
        stages[-1].output += "\nerror: plastimatch wrote no vector field"
    return stages, field


def run_deeds(case, images, folder, options):
    """deeds on the peers' images: both converted to NIfTI (deeds' only format), its control-grid displacements
    converted back to a displacement field on the fixed image's frame (deeds_peer.py). deeds has no mask."""
    program = os.environ[GIVEN_IMAGE_PEERS["deeds"]]
    start = time.monotonic()
    nifti = {}
    for role in ("fixed", "moving"):
        header, values = deeds_peer.read_metaimage(images[role])
        nifti[role] = os.path.join(folder, role + ".nii.gz")
        deeds_peer.write_nifti_gz(nifti[role], header, values)
        if role == "fixed":
            fixed_header = header
    stages = [Stage("convert", time.monotonic() - start, 0.0, 0, "", time.monotonic() - start)]
    stem = os.path.join(folder, "deeds")
    displacements = stem + "_displacements.dat"
    if os.path.exists(displacements):
        os.remove(displacements)  # an earlier run's output must not be taken for this one's
    environment = dict(os.environ, OMP_NUM_THREADS=str(options.threads))
    stages.append(run("register", [program, "-F", nifti["fixed"], "-M", nifti["moving"], "-O", stem]
                      + DEEDS_OPTIONS.split(), os.path.join(folder, "register.log"), environment=environment))
    field = os.path.join(folder, "deeds-field.mha")
    if stages[-1].ok():
        start = time.monotonic()
        returncode, output = 0, ""
        try:
            if not os.path.exists(displacements):
                raise ValueError("deeds wrote no %s" % os.path.basename(displacements))
            deeds_peer.deeds_grid_field(displacements, fixed_header, deeds_peer.deeds_grid_step(DEEDS_OPTIONS), field)
        except (OSError, ValueError) as error:
            returncode, output = 1, "error: deeds' displacements: %s" % error
        stages.append(Stage("field", time.monotonic() - start, 0.0, returncode, output, time.monotonic() - start))
    return stages, field


# Point-set peers (bcpd, nicp): the vertices of both meshes in, the deformed source vertices (in the source's
# order) out; the deformed source is those vertices with the source's triangles.


def read_off(path):
    """Vertices (list of 3-tuples) and the face lines of an OFF file (counts on the header line or the next)."""
    with open(path) as mesh:
        lines = [line.split("#")[0].strip() for line in mesh]
    lines = [line for line in lines if line]
    if not lines or not lines[0].startswith("OFF"):
        raise ValueError("%s is not an OFF file" % path)
    header = lines[0][3:].split()
    rest = 1
    if not header:
        header = lines[1].split()
        rest = 2
    vertex_count, face_count = int(header[0]), int(header[1])
    vertices = [tuple(float(v) for v in line.split()[:3]) for line in lines[rest:rest + vertex_count]]
    faces = lines[rest + vertex_count:rest + vertex_count + face_count]
    if len(vertices) != vertex_count or len(faces) != face_count:
        raise ValueError("%s is truncated" % path)
    return vertices, faces


def write_off(path, vertices, faces):
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(vertices), len(faces)))
        out.writelines("%.9g %.9g %.9g\n" % tuple(v) for v in vertices)
        out.writelines(face + "\n" for face in faces)


def read_points(path, count, what):
    """count rows of 3 numbers (BCPD's output: tab- or space-separated)."""
    with open(path) as data:
        rows = [line.replace(",", " ").split() for line in data if line.strip()]
    if len(rows) != count or any(len(row) < 3 for row in rows):
        raise ValueError("%s has %d rows of points, the source has %d vertices" % (what, len(rows), count))
    return [tuple(float(v) for v in row[:3]) for row in rows]


def bcpd_options(regime, options):
    """BCPD's options: for shapes far apart in the posed regime, for roughly aligned shapes otherwise."""
    if regime == "posed":
        return getattr(options, "bcpd_posed_options", BCPD_POSED_OPTIONS)
    return getattr(options, "bcpd_options", BCPD_OPTIONS)


def run_point_peer(case, peer, tools, options):
    folder = os.path.join(case["folder"], "peers", peer)
    os.makedirs(folder, exist_ok=True)
    variable = POINT_PEERS[peer]
    program = os.environ.get(variable)
    if not program:
        return result_record(case, peer, "peer", [], None, "not run", "not run: %s not given" % variable)
    if shutil.which(program) is None:
        return result_record(case, peer, "peer", [], None, "failed",
                             "%s=%s is not an executable program" % (variable, program))
    environment = dict(os.environ, OMP_NUM_THREADS=str(options.threads), OPENBLAS_NUM_THREADS="1")
    deformed = os.path.join(folder, "deformed.off")
    # The conversions (OFF -> point lists, points -> OFF) run here in Python: timed, no peak memory of their own.
    start = time.monotonic()
    source_vertices, source_faces = read_off(case["source"])
    stages = []
    if peer == "bcpd":
        target_vertices, _ = read_off(case["target"])
        x_path = os.path.join(folder, "X.txt")
        y_path = os.path.join(folder, "Y.txt")
        for path, vertices in ((x_path, target_vertices), (y_path, source_vertices)):
            with open(path, "w") as out:
                out.writelines("%.9g\t%.9g\t%.9g\n" % v for v in vertices)
        stages.append(Stage("convert", time.monotonic() - start, 0.0, 0, "", time.monotonic() - start))
        prefix = os.path.join(folder, "bcpd_")
        output = prefix + "y.txt"
        # X = target (fixed), Y = source (moving): BCPD moves Y onto X and writes the moved Y in Y's order.
        command = [program, "-x", x_path, "-y", y_path, "-o", prefix, "-r", str(case["seed"] + 1)] + \
            bcpd_options(case["regime"], options).split()
    else:
        stages.append(Stage("convert", time.monotonic() - start, 0.0, 0, "", time.monotonic() - start))
        output = os.path.join(folder, "nicp-output.off")
        command = [program, case["source"], case["target"], output]
    if os.path.exists(output):
        os.remove(output)  # an earlier run's output must not be taken for this one's
    stages.append(run("register", command, os.path.join(folder, "register.log"), environment=environment))
    extra = {"register_seconds": stages[-1].seconds, "command": " ".join(command)}
    if not stages[-1].ok():
        return result_record(case, peer, "peer", stages, None, "failed", stages[-1].reason(), extra)
    start = time.monotonic()
    try:
        if peer == "bcpd":
            moved = read_points(output, len(source_vertices), "BCPD's output %s" % os.path.basename(output))
        else:
            moved, _ = read_off(output)
            if len(moved) != len(source_vertices):
                raise ValueError("%s's output has %d vertices, the source has %d" % (variable, len(moved),
                                                                                      len(source_vertices)))
        if not all(math.isfinite(c) for v in moved for c in v):
            raise ValueError("%s's output has a non-finite coordinate" % variable)
        write_off(deformed, moved, source_faces)
    except (OSError, ValueError) as error:
        return result_record(case, peer, "peer", stages, None, "failed", "%s: %s" % (peer, error), extra)
    stages.append(Stage("convert-back", time.monotonic() - start, 0.0, 0, "", time.monotonic() - start))
    # No transform or field: min det J is not defined for a point-set result and is reported as "–".
    score_stage, scores = score(case, deformed, folder, tools, [])
    stages.append(score_stage)
    if scores is None:
        return result_record(case, peer, "peer", stages, None, "failed", score_stage.reason(), extra)
    return result_record(case, peer, "peer", stages, scores, "ok", None, extra)


# ------------------------------------------------------------------------------------------------
# One case


def make_case(mesh_name, mesh_path, regime, seed, work, tools, options):
    folder = os.path.join(work, "cases", "%s-%s-%d" % (mesh_name, regime, seed))
    inputs = os.path.join(folder, "inputs")
    truth = os.path.join(folder, "truth")
    os.makedirs(inputs, exist_ok=True)
    os.makedirs(truth, exist_ok=True)
    # The posed regime's case is the smooth regime's case of the same mesh and seed, its target then posed.
    generated = "smooth" if regime == "posed" else regime
    stage = run("case", [tools["ffd-benchmark-tool"], "case", "--mesh", mesh_path, "--out-dir", inputs, "--truth-dir",
                         truth, "--regime", generated, "--seed", str(seed), "--fraction", "%g" % options.fraction,
                         "--grid", str(options.grid)], os.path.join(folder, "case.log"))
    if not stage.ok():
        raise RuntimeError("case generation failed for %s %s %d: %s" % (mesh_name, regime, seed, stage.reason()))
    case = {"mesh": mesh_name, "regime": regime, "seed": seed, "folder": folder,
            "source": os.path.join(inputs, "source.off"), "target": os.path.join(inputs, "target.off"),
            "truth": os.path.join(truth, "truth.txt"), "true_transform": os.path.join(truth, "T_true.tfm"),
            "description": read_json(os.path.join(truth, "case.json"))}
    if regime == "posed":
        case["pose"] = pose_target(case, truth)
        case["description"] = dict(case["description"] or {}, regime="posed", generated_as="smooth",
                                   pose=case["pose"])
        with open(os.path.join(truth, "case.json"), "w") as out:
            json.dump(case["description"], out, indent=1)
    return case


def pose_target(case, truth):
    """Poses the case's target in place by the similarity drawn from its seed, about the target's centroid: the
    aligned target is kept in the truth folder (no method sees it), the truth's correspondences stay valid, and
    true errors are in the posed target's units (the aligned errors times the scale). T_true stays the aligned
    case's noise (the Par methods' templates)."""
    aligned = os.path.join(truth, "target-aligned.off")
    os.replace(case["target"], aligned)
    diagonal = posed_cases.bounding_box_diagonal(aligned)
    pose = posed_cases.random_pose(case["seed"], diagonal)
    pose["centre"] = posed_cases.pose_mesh(aligned, case["target"], pose["rotation_axis"],
                                           pose["rotation_angle_degrees"], pose["scale"], pose["shift"])
    pose["target_diagonal"] = diagonal
    pose["direction"] = "aligned target to posed target: x -> centre + shift + scale R (x - centre)"
    with open(os.path.join(truth, "pose.json"), "w") as out:
        json.dump(pose, out, indent=1)
    return pose


def score(case, deformed, folder, tools, extra):
    output = os.path.join(folder, "score.json")
    stage = run("score", [tools["ffd-benchmark-tool"], "score", "--deformed", deformed, "--target", case["target"],
                          "--truth", case["truth"], "--output", output] + extra, os.path.join(folder, "score.log"))
    return stage, (read_json(output) if stage.ok() else None)


def result_record(case, name, kind, stages, scores, status, reason=None, extra=None):
    record = {"mesh": case["mesh"], "regime": case["regime"], "seed": case["seed"], "name": name, "kind": kind,
              "status": status, "reason": reason, "stages": [stage.record() for stage in stages],
              "seconds_total": sum(stage.seconds for stage in stages if stage.name != "score"),
              "peak_mb": max([stage.peak_mb for stage in stages if stage.name != "score"] or [0.0]),
              "cpu_seconds_total": sum(stage.cpu_seconds or 0.0 for stage in stages if stage.name != "score"),
              "scores": scores}
    if case.get("pose"):
        record["pose"] = case["pose"]  # the drawn pose of a posed case
    if extra:
        record.update(extra)
    return record


def run_method(case, method, tools, options):
    folder = os.path.join(case["folder"], "methods", method.replace("+", "-"))
    os.makedirs(folder, exist_ok=True)
    deformed = os.path.join(folder, "deformed.off")
    transform = os.path.join(folder, "transform.tfm")
    report = os.path.join(folder, "report.json")
    command = [tools["ffd-match"], "--source", case["source"], "--target", case["target"], "--method", method,
               "--output", deformed, "--transform-out", transform, "--report", report, "--grid", str(options.grid),
               "--voxel-size", "%g" % options.voxel_size, "--threads", str(options.threads),
               "--seed", str(case["seed"] + 1)]
    if case["regime"] in POSE_STAGE:
        command += ["--initial-transform", POSE_STAGE[case["regime"]]]
    if "par" in method:
        # The paper's protocol: the true noise directions per control point, magnitudes unknown.
        command += ["--templates", case["true_transform"], "--template-split", "control-point"]
    stage = run("match", command, os.path.join(folder, "match.log"))
    if not stage.ok():
        text = stage.output
        match = re.search(r"ffd-match: error: (.*(?:not available yet|is not available).*)", text)
        if match:
            return result_record(case, method, "method", [], None, "not run", "not run: " + match.group(1).strip())
        return result_record(case, method, "method", [stage], None, "failed", stage.reason())
    score_stage, scores = score(case, deformed, folder, tools, ["--transform", transform])
    report_data = read_json(report) or {}
    if scores is not None and scores.get("min_jacobian_determinant") is None:
        scores["min_jacobian_determinant"] = report_data.get("min_jacobian_determinant")
        scores["jacobian_from"] = "ffd-match report"
    seconds = report_data.get("seconds", {})
    extra = {"register_seconds": seconds.get("register"), "stage_seconds": seconds}
    if report_data.get("pose"):
        extra["pose_found"] = report_data["pose"]
    if scores is None:
        return result_record(case, method, "method", [stage, score_stage], None, "failed", score_stage.reason(), extra)
    return result_record(case, method, "method", [stage, score_stage], scores, "ok", None, extra)


def run_peer(case, peer, images, tools, options):
    if peer in GIVEN_IMAGE_PEERS:
        variable = GIVEN_IMAGE_PEERS[peer]
        if not os.environ.get(variable):
            return result_record(case, peer, "peer", [], None, "not run", "not run: %s not given" % variable)
        if case["regime"] == "posed":
            return result_record(case, peer, "peer", [], None, "not run",
                                 "not run: deeds needs both images on one grid (the posed source has its own)")
        if shutil.which(os.environ[variable]) is None:
            return result_record(case, peer, "peer", [], None, "failed",
                                 "%s=%s is not an executable program" % (variable, os.environ[variable]))
    else:
        executable = "elastix" if peer == "elastix" else "plastimatch"
        if shutil.which(executable) is None:
            return result_record(case, peer, "peer", [], None, "not run", "not run: %s is not installed" % executable)
    folder = os.path.join(case["folder"], "peers", peer)
    os.makedirs(folder, exist_ok=True)
    stages = list(images["stages"])
    if not all(stage.ok() for stage in stages):
        failed = [stage for stage in stages if not stage.ok()][0]
        return result_record(case, peer, "peer", stages, None, "failed", failed.reason())
    if peer == "deeds":
        register_stages, field = run_deeds(case, images, folder, options)
    elif peer == "elastix":
        register_stages, field = run_elastix(case, images, folder, tools, options)
    else:
        register_stages, field = run_plastimatch(case, images, folder, tools, options, peer.split("-")[1])
    stages += register_stages
    register_seconds = sum(stage.seconds for stage in register_stages if stage.name == "register")
    extra = {"register_seconds": register_seconds}
    if not all(stage.ok() for stage in register_stages):
        failed = [stage for stage in register_stages if not stage.ok()][0]
        return result_record(case, peer, "peer", stages, None, "failed", failed.reason(), extra)
    deformed = os.path.join(folder, "deformed.off")
    apply_report = os.path.join(folder, "apply.json")
    apply_source, apply_field = case["source"], field
    if peer == "elastix" and case["regime"] == "posed":
        start = time.monotonic()
        try:
            apply_field, apply_source = precondition_field(field, os.path.join(folder, "TransformParameters.0.txt"),
                                                           case["source"], folder)
        except (OSError, ValueError, KeyError, AttributeError) as error:
            return result_record(case, peer, "peer", stages, None, "failed", "elastix's field: %s" % error, extra)
        stages.append(Stage("precondition", time.monotonic() - start, 0.0, 0, "", time.monotonic() - start))
    stages.append(run("apply", [tools["ffd-benchmark-tool"], "apply-field", "--source", apply_source, "--field",
                                apply_field, "--output", deformed, "--report", apply_report],
                      os.path.join(folder, "apply.log")))
    if not stages[-1].ok():
        return result_record(case, peer, "peer", stages, None, "failed", stages[-1].reason(), extra)
    extra["apply"] = read_json(apply_report)
    score_stage, scores = score(case, deformed, folder, tools, ["--field", field])
    stages.append(score_stage)
    if scores is None:
        return result_record(case, peer, "peer", stages, None, "failed", score_stage.reason(), extra)
    # The images are large: keep only the scores once a peer has been scored.
    if not options.keep_images:
        for name in os.listdir(folder):
            if name.endswith((".mha", ".raw", ".mhd", ".nii", ".nii.gz", ".dat")):
                os.remove(os.path.join(folder, name))
    return result_record(case, peer, "peer", stages, scores, "ok", None, extra)


def run_start(case, tools):
    """The unmatched start: the source itself scored as the deformed source."""
    folder = os.path.join(case["folder"], "start")
    os.makedirs(folder, exist_ok=True)
    stage, scores = score(case, case["source"], folder, tools, [])
    return result_record(case, "start", "start", [], scores, "ok" if scores else "failed",
                         None if scores else stage.reason())


# ------------------------------------------------------------------------------------------------
# Tables and charts


def spread(values):
    values = [v for v in values if v is not None and not (isinstance(v, float) and math.isnan(v))]
    if not values:
        return None, None, 0
    mean = sum(values) / len(values)
    deviation = statistics.stdev(values) if len(values) > 1 else 0.0
    return mean, deviation, len(values)


def fmt(values, digits=2, show_spread=True):
    mean, deviation, n = spread(values)
    if mean is None:
        return "–"
    if show_spread and n > 1:
        return "%.*f ± %.*f" % (digits, mean, digits, deviation)
    return "%.*f" % (digits, mean)


def summarize(records, mesh, regime, name):
    rows = [r for r in records if r["mesh"] == mesh and r["regime"] == regime and r["name"] == name]
    ok = [r for r in rows if r["status"] == "ok"]
    summary = {"rows": rows, "ok": ok}
    for key, getter in {
        "true_mean": lambda r: r["scores"]["true_error"]["mean"],
        "true_median": lambda r: r["scores"]["true_error"]["median"],
        "true_p95": lambda r: r["scores"]["true_error"]["p95"],
        "true_max": lambda r: r["scores"]["true_error"]["max"],
        "mdh": lambda r: r["scores"]["mean_directed_hausdorff"],
        "hausdorff": lambda r: r["scores"]["symmetric_hausdorff_region"],
        "min_det": lambda r: r["scores"]["min_jacobian_determinant"],
        "register": lambda r: r.get("register_seconds"),
        "total": lambda r: r["seconds_total"],
        "cpu": lambda r: r.get("cpu_seconds_total"),
        "peak": lambda r: r["peak_mb"],
    }.items():
        summary[key] = [getter(r) for r in ok]
    return summary


def status_text(summary):
    rows = summary["rows"]
    bad = [r for r in rows if r["status"] != "ok"]
    if not bad:
        return ""
    reasons = sorted(set(r["reason"] or r["status"] for r in bad))
    prefix = "%d/%d: " % (len(bad), len(rows)) if summary["ok"] else ""
    return prefix + "; ".join(reasons)


def ratio_text(numerator, denominator):
    a = spread(numerator)[0]
    b = spread(denominator)[0]
    if a is None or b is None or b <= 0:
        return "–"
    return "%.2f" % (a / b)


def write_results(records, options, versions, results_dir, charts):
    names = ["start"] + options.methods + options.peers
    meshes = options.meshes
    lines = []
    add = lines.append
    add("# FFDShapeMatching benchmark results")
    add("")
    add("Generated by `benchmark/run.sh` (benchmark/run_benchmark.py) on %s UTC; protocol and column meanings in "
        "[README.md](README.md)." % datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M"))
    add("")
    add("Run: meshes %s; regimes %s; seeds %s; grid %d³ control points; voxel %g mm; region fraction %g; %d threads; "
        "machine %s, %d cores.%s" % (", ".join(meshes), ", ".join(options.regimes), options.seed_list, options.grid,
                                     options.voxel_size, options.fraction, options.threads, platform.machine(),
                                     os.cpu_count() or 0, " **Smoke run.**" if options.smoke else ""))
    if options.note:
        add("")
        add(options.note)
    add("")
    add("Versions: " + ", ".join("%s %s" % (k, v) for k, v in versions.items() if v))
    given_peers = [p for p in options.peers if p in GIVEN_PEERS]
    point_peers = [p for p in given_peers if p in POINT_PEERS]
    programs = getattr(options, "point_peer_programs", None) or {}
    if point_peers:
        texts = []
        for peer in point_peers:
            variable = POINT_PEERS[peer]
            given = programs.get(peer)
            text = "%s = `$%s` (%s)" % (peer, variable, ("`%s`" % given) if given else "not given: not run")
            if peer == "bcpd":
                text += ", options `%s`" % getattr(options, "bcpd_options", BCPD_OPTIONS)
            texts.append(text)
        add("")
        add("Point-set peers (built outside the repository, README.md): " + "; ".join(texts) + ". They return the "
            "deformed source vertices, not a transform: their min det J is not defined and shows \"–\".")
    for peer in [p for p in given_peers if p in GIVEN_IMAGE_PEERS]:
        given = programs.get(peer)
        add("")
        add("Image peer %s = `$%s` (%s, built outside the repository, README.md), options `%s`, on the peers' images "
            "converted to NIfTI; it has no mask option, and its field is read from its control grid "
            "(deeds_peer.py)." % (peer, GIVEN_IMAGE_PEERS[peer], ("`%s`" % given) if given else "not given: not run",
                                 DEEDS_OPTIONS or "its defaults"))
    add("")
    add("Every figure is the mean ± standard deviation over the seeds that ran (n in the last column). "
        "\"best peer\" = the peer configuration with the lowest mean true error on that mesh and regime; "
        "ratios are this row / best peer (true error) and this row / best peer (registration time).")
    for regime in options.regimes:
        add("")
        add("## Table 2 form — %s regime" % regime)
        add("")
        pose_stage = (getattr(options, "pose_stage", None) or POSE_STAGE).get(regime)
        if pose_stage:
            add("ffd-match methods run with `--initial-transform %s` in this regime (a pose stage before the "
                "deformation); peers with their settings for shapes far apart (see the posed table below)."
                % pose_stage)
            add("")
        add("| mesh | method | true error mean (mm) | median | p95 | max | MDH (mm) | sym. Hausdorff (mm) | min det J "
            "| register (s) | total (s) | total CPU (s) | peak RSS (MB) | err / best peer | time / best peer | n |")
        add("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for mesh in meshes:
            summaries = {name: summarize(records, mesh, regime, name) for name in names}
            peers = [p for p in options.peers if summaries[p]["ok"]]
            best = min(peers, key=lambda p: spread(summaries[p]["true_mean"])[0]) if peers else None
            for name in names:
                s = summaries[name]
                if not s["rows"]:
                    continue
                label = name + (" (best peer)" if name == best else "")
                if not s["ok"]:
                    add("| %s | %s | %s |  |  |  |  |  |  |  |  |  |  |  |  | 0 |" % (mesh, label, status_text(s)))
                    continue
                note = status_text(s)
                add("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %d%s |" % (
                    mesh, label, fmt(s["true_mean"]), fmt(s["true_median"]), fmt(s["true_p95"]), fmt(s["true_max"]),
                    fmt(s["mdh"]), fmt(s["hausdorff"]), fmt(s["min_det"]),
                    fmt(s["register"], 1) if name != "start" else "", fmt(s["total"], 1) if name != "start" else "",
                    fmt(s["cpu"], 1) if name != "start" else "",
                    fmt(s["peak"], 0, False) if name != "start" else "",
                    ratio_text(s["true_mean"], summaries[best]["true_mean"]) if best else "–",
                    ratio_text(s["register"], summaries[best]["register"]) if best and name != "start" else "",
                    len(s["ok"]), (" (" + note + ")") if note else ""))
    if "posed" in options.regimes:
        write_posed_table(records, options, add)
    refinements = [m for m in options.methods if "+par" in m]
    if refinements:
        add("")
        add("## Table 3 form — Par refinement of the voxel methods")
        add("")
        add("True error mean (mm) and total time (s) of each voxel method, of Par alone, and of the voxel method "
            "refined by Par (templates = the true noise directions per control point, the paper's protocol).")
        for regime in options.regimes:
            add("")
            add("**%s regime**" % regime)
            add("")
            add("| mesh | " + " | ".join("%s error | %s time" % (m, m) for m in ["go", "mrf", "par"] + refinements)
                + " |")
            add("|---|" + "---|---|" * (3 + len(refinements)))
            for mesh in meshes:
                cells = []
                for m in ["go", "mrf", "par"] + refinements:
                    s = summarize(records, mesh, regime, m)
                    if s["ok"]:
                        cells += [fmt(s["true_mean"]), fmt(s["total"], 1)]
                    else:
                        cells += [status_text(s) or "–", ""]
                add("| %s | %s |" % (mesh, " | ".join(cells)))
    failures = [r for r in records if r["status"] == "failed"]
    add("")
    add("## Failures")
    add("")
    if failures:
        for r in failures:
            add("- %s %s seed %d, %s: %s" % (r["mesh"], r["regime"], r["seed"], r["name"], r["reason"]))
    else:
        add("None: every configured method or peer that could run, ran and was scored.")
    if charts:
        add("")
        add("## Charts: accuracy vs time")
        add("")
        add("Mean true error (mm) against total wall time (s), one point per method or peer (mean over seeds).")
        for chart in charts:
            add("")
            add("![%s](%s)" % (os.path.basename(chart), os.path.relpath(chart, results_dir)))
    add("")
    with open(os.path.join(results_dir, "RESULTS.md"), "w") as out:
        out.write("\n".join(lines))


def find_record(records, mesh, regime, seed, name):
    for r in records:
        if r["mesh"] == mesh and r["regime"] == regime and r["seed"] == seed and r["name"] == name:
            return r
    return None


def true_error(record):
    if record is None or record["status"] != "ok":
        return None
    return record["scores"]["true_error"]["mean"]


def posed_ratio(records, record):
    """posed true error / (scale x the same method's or peer's smooth-regime true error on the same seed)."""
    posed = true_error(record)
    aligned = true_error(find_record(records, record["mesh"], "smooth", record["seed"], record["name"]))
    if posed is None or not aligned or not record.get("pose"):
        return None
    return posed / (record["pose"]["scale"] * aligned)


POSED_GOAL = 1.25  # issue 18: posed true error <= 1.25 x scale x aligned, and no folding


def write_posed_table(records, options, add):
    # Only the methods and peers that ran posed (merged tables also hold other regimes' methods and peers).
    names = [n for n in options.methods + options.peers
             if any(r["regime"] == "posed" and r["name"] == n for r in records)]
    stage = (getattr(options, "pose_stage", None) or POSE_STAGE).get("posed", "none")
    add("")
    add("## Posed regime: matching from any pose")
    add("")
    add("Each case is the smooth regime's case of the same mesh and seed (same source, target and truth) with the "
        "target posed about its centroid by a similarity drawn from the seed (benchmark/posed_cases.py, "
        "random_pose: rotation angle uniform in [0, 180]° about a uniform axis, scale log-uniform in [0.5, 2], "
        "shift uniform up to the target's bounding-box diagonal in a uniform direction). True errors are in the "
        "posed target's units. ffd-match methods run with `--initial-transform %s`; elastix with an affine stage "
        "(centres of the images aligned to start) before its B-spline stage, the source voxelized on a grid of its "
        "own; BCPD with `%s`. ratio = posed true error / (scale × the same method's or peer's smooth-regime true "
        "error on the same seed); the goal (issue 18) is ratio ≤ %.2f and min det J > 0. Pose error (methods): "
        "rotation angle of R_found R_drawn and scale_found × scale_drawn − 1 (the found pose maps target to "
        "source)." % (stage, getattr(options, "bcpd_posed_options", BCPD_POSED_OPTIONS), POSED_GOAL))
    add("")
    header = "| mesh | seed | pose drawn: angle, scale, shift | start (mm) |"
    rule = "|---|---|---|---|"
    for name in names:
        if name in options.methods:
            header += " %s (mm) | ratio | min det J | pose error |" % name
            rule += "---|---|---|---|"
        else:
            header += " %s (mm) | ratio | min det J |" % name
            rule += "---|---|---|"
    add(header)
    add(rule)
    met = {name: [0, 0] for name in names}
    for mesh in options.meshes:
        seeds = sorted(set(r["seed"] for r in records if r["mesh"] == mesh and r["regime"] == "posed"))
        column_values = {name: ([], []) for name in names}
        starts = []
        for seed in seeds:
            start = find_record(records, mesh, "posed", seed, "start")
            pose = (start or {}).get("pose")
            cells = [mesh, str(seed), "%.1f°, %.3f, %.1f mm" % (pose["rotation_angle_degrees"], pose["scale"],
                                                              pose["shift_length"]) if pose else "–"]
            starts.append(true_error(start))
            cells.append("%.2f" % starts[-1] if starts[-1] is not None else "–")
            for name in names:
                r = find_record(records, mesh, "posed", seed, name)
                value = true_error(r)
                if value is None:
                    reason = (r or {}).get("reason") or (r or {}).get("status") or "no record"
                    cells += [reason[:120], "", ""] + ([""] if name in options.methods else [])
                    continue
                ratio = posed_ratio(records, r)
                det = r["scores"].get("min_jacobian_determinant")
                column_values[name][0].append(value)
                if ratio is not None:
                    column_values[name][1].append(ratio)
                cells += ["%.3f" % value, "%.2f" % ratio if ratio is not None else "– (no aligned run)",
                          "%.3f" % det if isinstance(det, (int, float)) and math.isfinite(det) else "–"]
                if ratio is not None:
                    met[name][1] += 1
                    folded = isinstance(det, (int, float)) and math.isfinite(det) and det <= 0
                    met[name][0] += ratio <= POSED_GOAL and not folded
                if name in options.methods:
                    found = r.get("pose_found")
                    if found and pose:
                        angle, scale = posed_cases.pose_error(pose, found)
                        cells.append("%.2f°, %+.2f %%" % (angle, 100.0 * scale))
                    else:
                        cells.append("–")
            add("| " + " | ".join(cells) + " |")
        if len(seeds) > 1:
            cells = [mesh, "mean", "", fmt(starts, 2, False)]
            for name in names:
                values, ratios = column_values[name]
                cells += [fmt(values, 3, False), "%s (max %.2f)" % (fmt(ratios, 2, False), max(ratios))
                          if ratios else "–", ""] + ([""] if name in options.methods else [])
            add("| " + " | ".join("**%s**" % c if c else c for c in cells) + " |")
    add("")
    add("Goal met (ratio ≤ %.2f, no folding), of the cases with an aligned run: %s." % (POSED_GOAL, "; ".join(
        "%s %d/%d" % (name, met[name][0], met[name][1]) for name in names)))


def write_charts(records, options, results_dir):
    if shutil.which("gnuplot") is None:
        log("gnuplot is missing: no charts")
        return []
    folder = os.path.join(results_dir, "charts")
    os.makedirs(folder, exist_ok=True)
    charts = []
    for mesh in options.meshes:
        data_path = os.path.join(folder, "%s.dat" % mesh)
        blocks = []
        for regime in options.regimes:
            points = []
            for name in options.methods + options.peers:
                s = summarize(records, mesh, regime, name)
                error = spread(s["true_mean"])[0]
                seconds = spread(s["total"])[0]
                if error is not None and seconds is not None:
                    points.append("%s %.4f %.4f" % (name, max(seconds, 0.01), error))
            start = spread(summarize(records, mesh, regime, "start")["true_mean"])[0]
            blocks.append((regime, points, start))
        if not any(points for _, points, _ in blocks):
            continue
        with open(data_path, "w") as out:
            for regime, points, _ in blocks:
                out.write("# %s\n%s\n\n\n" % (regime, "\n".join(points) if points else "none 1 0"))
        png = os.path.join(folder, "%s.png" % mesh)
        plots = []
        for index, (regime, points, start) in enumerate(blocks):
            if not points:
                continue
            plots.append("'%s' index %d using 2:3 with points pt %d ps 1.6 title '%s'" % (data_path, index,
                                                                                          7 + 2 * index, regime))
            plots.append("'%s' index %d using 2:3:1 with labels offset 0.8,0.6 font ',8' notitle" % (data_path, index))
            if start is not None:
                plots.append("%.4f with lines dt 2 title '%s: unmatched start'" % (start, regime))
        script = "\n".join([
            "set terminal png size 800,560",
            "set output '%s'" % png,
            "set title 'Accuracy vs time: %s'" % mesh,
            "set xlabel 'total wall time (s), log scale'",
            "set ylabel 'mean true vertex error (mm)'",
            "set logscale x",
            "set yrange [0:%.4f]" % (1.15 * max([float(p.split()[2]) for _, points, _ in blocks for p in points]
                                                + [start for _, _, start in blocks if start is not None])),
            "set offsets graph 0.15, graph 0.15, 0, 0",
            "set grid",
            "set key outside bottom center horizontal",
            "plot " + ", ".join(plots),
        ])
        result = subprocess.run(["gnuplot"], input=script, text=True, capture_output=True)
        if result.returncode == 0 and os.path.exists(png):
            charts.append(png)
        else:
            log("gnuplot failed for %s: %s" % (mesh, result.stderr.strip()[:300]))
    return charts


# ------------------------------------------------------------------------------------------------
# Smoke check


def check_smoke(records, results_dir, charts):
    problems = []
    go = [r for r in records if r["name"] == "go"]
    start = [r for r in records if r["name"] == "start"]
    if not go or go[0]["status"] != "ok":
        problems.append("go did not run: %s" % (go[0]["reason"] if go else "no record"))
    elif not start or start[0]["status"] != "ok":
        problems.append("the start was not scored")
    else:
        before = start[0]["scores"]["true_error"]["mean"]
        after = go[0]["scores"]["true_error"]["mean"]
        mdh_before = start[0]["scores"]["mean_directed_hausdorff"]
        mdh_after = go[0]["scores"]["mean_directed_hausdorff"]
        log("smoke: go true error %.3f -> %.3f mm, MDH %.3f -> %.3f mm" % (before, after, mdh_before, mdh_after))
        if not (before > 0.5 and after < before and mdh_after < mdh_before):
            problems.append("go did not improve the start (true error %.3f -> %.3f, MDH %.3f -> %.3f)" %
                            (before, after, mdh_before, mdh_after))
        if not go[0]["seconds_total"] > 0 or not go[0]["peak_mb"] > 0:
            problems.append("go has no time or memory figure")
    for r in records:
        if r["name"] in ("mrf", "par", "go+par", "mrf+par", "go+cpd"):
            value = r["scores"]["true_error"]["mean"] if r["status"] == "ok" else None
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                problems.append("%s did not run or has no true error: %s" % (r["name"], r.get("reason", "")))
            else:
                log("smoke: %s true error %.3f mm" % (r["name"], value))
        if r["name"] in GIVEN_PEERS:
            variable = GIVEN_PEERS[r["name"]]
            if os.environ.get(variable):
                value = r["scores"]["true_error"]["mean"] if r["status"] == "ok" else None
                if not (isinstance(value, (int, float)) and math.isfinite(value)):
                    problems.append("%s did not run or has no true error: %s" % (r["name"], r.get("reason", "")))
                elif r["name"] in POINT_PEERS and r["scores"].get("min_jacobian_determinant") is not None:
                    problems.append("%s has a min det J, but it returns no transform" % r["name"])
                else:
                    log("smoke: %s true error %.3f mm" % (r["name"], value))
            elif r["status"] != "not run" or r["reason"] != "not run: %s not given" % variable:
                problems.append("%s without %s: %s (expected 'not run: %s not given')" % (
                    r["name"], variable, r["reason"], variable))
        if r["name"] == "elastix" and r["status"] == "ok":
            value = r["scores"]["true_error"]["mean"]
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                problems.append("elastix's true error is not a number")
    text = open(os.path.join(results_dir, "RESULTS.md")).read()
    if "| true error mean (mm) |" not in text or "| %s | go |" % SMOKE_MESH not in text:
        problems.append("RESULTS.md lacks the go row")
    for peer, variable in GIVEN_PEERS.items():
        if not os.environ.get(variable) and "| %s | %s | not run: %s not given |" % (SMOKE_MESH, peer, variable) \
                not in text:
            problems.append("RESULTS.md does not say that %s was not run (%s not given)" % (peer, variable))
    for chart in charts:
        with open(chart, "rb") as data:
            if data.read(8) != b"\x89PNG\r\n\x1a\n":
                problems.append("%s is not a PNG" % chart)
    if shutil.which("gnuplot") and not charts:
        problems.append("no chart was drawn")
    if problems:
        for problem in problems:
            log("smoke check: " + problem)
        return False
    log("smoke check passed")
    print("benchmark smoke check passed")
    return True


# Tolerances of the posed smoke check, about twice what the lobed torus gives at grid 8 and 2 mm voxels (rotation
# error 2.4°, scale error 1.3 %, ratio 0.85; benchmark/README.md).
POSED_SMOKE_ROTATION_DEGREES = 5.0
POSED_SMOKE_SCALE = 0.03


def check_smoke_posed(records, results_dir):
    """The posed smoke case: go+cpd from the drawn pose succeeds, its pose stage recovers the drawn rotation and
    scale, it does not fold, and it reaches the aligned run's accuracy (ratio <= POSED_GOAL)."""
    problems = []
    mesh = SMOKE_POSED_MESH
    posed = find_record(records, mesh, "posed", 1, "go+cpd")
    start = find_record(records, mesh, "posed", 1, "start")
    aligned = find_record(records, mesh, "smooth", 1, "go+cpd")
    if posed is None or posed["status"] != "ok":
        problems.append("the posed go+cpd run failed: %s" % (posed or {}).get("reason"))
    elif true_error(start) is None or true_error(aligned) is None:
        problems.append("the posed start or the aligned go+cpd run has no true error")
    else:
        before, after = true_error(start), true_error(posed)
        ratio = posed_ratio(records, posed)
        det = posed["scores"].get("min_jacobian_determinant")
        found = posed.get("pose_found")
        log("smoke posed: drawn pose %.2f°, scale %.4f; true error %.3f -> %.3f mm (aligned %.3f mm), ratio %.2f, "
            "min det J %s" % (posed["pose"]["rotation_angle_degrees"], posed["pose"]["scale"], before, after,
                              true_error(aligned), ratio, det))
        if not found:
            problems.append("the posed run's report has no pose block")
        else:
            angle, scale = posed_cases.pose_error(posed["pose"], found)
            log("smoke posed: pose found %.2f°, scale %.4f: rotation error %.2f°, scale error %+.2f %%" % (
                found["rotation_angle_degrees"], found["scale"], angle, 100.0 * scale))
            if not angle < POSED_SMOKE_ROTATION_DEGREES:
                problems.append("rotation error %.2f° >= %g°" % (angle, POSED_SMOKE_ROTATION_DEGREES))
            if not abs(scale) < POSED_SMOKE_SCALE:
                problems.append("scale error %.2f %% >= %g %%" % (100.0 * scale, 100.0 * POSED_SMOKE_SCALE))
        if not (isinstance(det, (int, float)) and math.isfinite(det) and det > 0):
            problems.append("min det J %s: folded or missing" % det)
        if not (before > 10.0 and ratio is not None and ratio <= POSED_GOAL):
            problems.append("posed / (scale x aligned) = %s > %.2f (start %.3f mm)" % (ratio, POSED_GOAL, before))
    text = open(os.path.join(results_dir, "RESULTS.md")).read()
    if "## Posed regime" not in text or "| %s | 1 |" % mesh not in text:
        problems.append("RESULTS.md lacks the posed table's row")
    if problems:
        for problem in problems:
            log("smoke check: " + problem)
        return False
    log("posed smoke check passed")
    print("benchmark posed smoke check passed")
    return True


# ------------------------------------------------------------------------------------------------


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", default=",".join(ALL_MESHES), help="comma-separated CGAL mesh names")
    parser.add_argument("--regimes", default=",".join(DEFAULT_REGIMES),
                        help="paper, smooth (default both) and short (smooth noise over half the length)")
    parser.add_argument("--seeds", type=int, default=3, help="seeds per mesh and regime (default 3)")
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--methods", default=",".join(ALL_METHODS), help="ffd-match methods")
    parser.add_argument("--peers", default=",".join(ALL_PEERS),
                        help="elastix, plastimatch-mi, plastimatch-mse, deeds (needs DEEDS_EXE), "
                        "bcpd (needs BCPD_EXE), nicp (needs NICP_EXE)")
    parser.add_argument("--grid", type=int, default=20, help="control points per axis (default 20)")
    parser.add_argument("--voxel-size", type=float, default=1.0)
    parser.add_argument("--fraction", type=float, default=0.6, help="region = this fraction of each axis")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--smoke", action="store_true",
                        help="one small generated mesh, grid 8, 2 mm voxels, 1 seed, smooth regime, every method + elastix")
    parser.add_argument("--smoke-posed", action="store_true",
                        help="the posed regime's smoke check: a generated lobed torus, grid 8, 2 mm voxels, seed 1, "
                        "regimes smooth and posed, method go+cpd, no peers")
    parser.add_argument("--build-dir", default=os.environ.get("FFD_BUILD_DIR", os.path.join(ROOT, "build")))
    parser.add_argument("--skip-install", action="store_true", help="do not install missing Debian packages")
    parser.add_argument("--skip-build", action="store_true", help="use the programs already in --build-dir")
    parser.add_argument("--portable-build", action="store_true",
                        help="build without -march=native (default: for this machine's processor, "
                             "FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE=ON)")
    parser.add_argument("--ffd-match", help="path of ffd-match (default: BUILD/apps/ffd-match)")
    parser.add_argument("--ffd-voxelize", help="path of ffd-voxelize (default: BUILD/apps/ffd-voxelize)")
    parser.add_argument("--ffd-benchmark-tool", help="default: BUILD/benchmark/ffd-benchmark-tool")
    parser.add_argument("--work-dir", default=None, help="cases and logs (default: BUILD/benchmark-work)")
    parser.add_argument("--results-dir", default=HERE, help="RESULTS.md, results.json, charts/ (default benchmark/)")
    parser.add_argument("--keep-images", action="store_true", help="keep the peers' images and fields")
    parser.add_argument("--note", default="", help="a sentence added to RESULTS.md (e.g. why fewer seeds)")
    parser.add_argument("--tables-only", metavar="RESULTS_JSON",
                        help="only rewrite RESULTS.md, results.json and the charts from the results.json of earlier "
                        "runs (comma-separated files are merged)")
    options = parser.parse_args()
    if options.smoke:
        options.meshes = SMOKE_MESH
        options.regimes = "smooth"
        options.seeds = 1
        options.methods = "go,mrf,par,go+par,mrf+par,go+cpd"
        options.peers = ("elastix," if shutil.which("elastix") else "") + ",".join(GIVEN_PEERS)
        options.grid = 8
        options.voxel_size = 2.0
        options.note = options.note or (
            "Smoke run: one generated torus, grid 8, 2 mm voxels, 1 seed, smooth regime, every method, elastix "
            "(when installed: %s) and the peers given by a variable (when given: %s)." % (
                "yes" if shutil.which("elastix") else "no",
                ", ".join("%s %s" % (v, "yes" if os.environ.get(v) else "no") for v in GIVEN_PEERS.values())))
    if options.smoke_posed:
        options.smoke = True  # the smoke case's iteration counts for peers
        options.meshes = SMOKE_POSED_MESH
        options.regimes = "smooth,posed"
        options.seeds = 1
        options.first_seed = 1
        options.methods = "go+cpd"
        options.peers = ""
        options.grid = 8
        options.voxel_size = 2.0
        options.note = options.note or ("Posed smoke run: one generated lobed torus, grid 8, 2 mm voxels, seed 1, "
                                        "smooth and posed regimes, go+cpd.")
    options.meshes = [m for m in options.meshes.split(",") if m]
    options.regimes = [r for r in options.regimes.split(",") if r]
    options.methods = [m for m in options.methods.split(",") if m]
    options.peers = [p for p in options.peers.split(",") if p]
    for value, known, what in ((options.regimes, ALL_REGIMES, "regime"), (options.methods, ALL_METHODS, "method"),
                               (options.peers, ALL_PEERS, "peer"),
                               (options.meshes, ALL_MESHES + HELD_OUT_MESHES + [SMOKE_MESH, SMOKE_POSED_MESH], "mesh")):
        for item in value:
            if item not in known:
                parser.error("unknown %s '%s' (known: %s)" % (what, item, ", ".join(known)))
    if options.seeds < 1 or options.grid < 4 or not options.voxel_size > 0:
        parser.error("--seeds >= 1, --grid >= 4 and --voxel-size > 0 are required")
    options.seed_list = ", ".join(str(options.first_seed + i) for i in range(options.seeds))
    options.bcpd_options = BCPD_OPTIONS
    options.bcpd_posed_options = BCPD_POSED_OPTIONS
    options.pose_stage = POSE_STAGE
    options.point_peer_programs = {peer: os.environ.get(variable) or None for peer, variable in GIVEN_PEERS.items()}
    return options


def tables_only(options):
    """RESULTS.md and charts from the results.json of earlier runs (comma-separated: records are merged, a later
    file's record replacing an earlier one of the same mesh, regime, seed and method; the settings are the first
    file's, with the union of the methods, peers and seeds)."""
    records = {}
    versions = {}
    first = None
    for path in options.tables_only.split(","):
        data = read_json(path)
        if data is None:
            raise SystemExit("run_benchmark: cannot read %s" % path)
        if first is None:
            first = data
            for key in ("meshes", "regimes", "methods", "peers", "grid", "voxel_size", "fraction", "threads",
                        "smoke"):
                setattr(options, key, data["options"][key])
            options.note = options.note or data["options"].get("note", "")
            options.bcpd_options = data["options"].get("bcpd_options", BCPD_OPTIONS)
            options.bcpd_posed_options = data["options"].get("bcpd_posed_options", BCPD_POSED_OPTIONS)
            options.pose_stage = data["options"].get("pose_stage", POSE_STAGE)
            options.point_peer_programs = {}
        else:
            for key in ("meshes", "regimes", "methods", "peers"):
                getattr(options, key).extend(v for v in data["options"][key] if v not in getattr(options, key))
            if "posed" in data["options"]["regimes"]:
                options.bcpd_posed_options = data["options"].get("bcpd_posed_options", options.bcpd_posed_options)
                options.pose_stage = data["options"].get("pose_stage", options.pose_stage)
        # The point-set peers' programs of the runs that had them.
        for peer, program in (data["options"].get("point_peer_programs") or {}).items():
            if program and not options.point_peer_programs.get(peer):
                options.point_peer_programs[peer] = program
        for record in data["records"]:
            records[(record["mesh"], record["regime"], record["seed"], record["name"])] = record
        # The versions of every merged run: a program that changed between runs lists each version.
        for key, value in data.get("versions", {}).items():
            if value is None:
                continue  # the program was not there in that run
            known = versions.setdefault(key, value).split(", ")
            known.extend(v for v in value.split(", ") if v not in known)
            versions[key] = ", ".join(known)
    records = list(records.values())
    options.seed_list = ", ".join(str(seed) for seed in sorted(set(r["seed"] for r in records)))
    results_dir = os.path.abspath(options.results_dir)
    os.makedirs(results_dir, exist_ok=True)
    with open(os.path.join(results_dir, "results.json"), "w") as out:
        json.dump({"options": {k: v for k, v in vars(options).items()}, "versions": versions,
                   "records": records}, out, indent=1)
    charts = write_charts(records, options, results_dir)
    write_results(records, options, versions, results_dir, charts)
    log("wrote %s and %d charts" % (os.path.join(results_dir, "RESULTS.md"), len(charts)))
    return 0


def main():
    options = parse_arguments()
    if options.tables_only:
        return tables_only(options)
    build_dir = os.path.abspath(options.build_dir)
    if not options.skip_install:
        install_packages()
    if not options.skip_build:
        build_project(build_dir, not options.skip_install, options.portable_build)
    tools = {
        "ffd-match": options.ffd_match or os.path.join(build_dir, "apps", "ffd-match"),
        "ffd-voxelize": options.ffd_voxelize or os.path.join(build_dir, "apps", "ffd-voxelize"),
        "ffd-benchmark-tool": options.ffd_benchmark_tool or os.path.join(build_dir, "benchmark", "ffd-benchmark-tool"),
    }
    for name, path in tools.items():
        if not os.access(path, os.X_OK):
            raise SystemExit("run_benchmark: %s not found at %s (build it or pass --%s)" % (name, path, name))
    work = os.path.abspath(options.work_dir or os.path.join(build_dir, "benchmark-work"))
    results_dir = os.path.abspath(options.results_dir)
    os.makedirs(work, exist_ok=True)
    os.makedirs(results_dir, exist_ok=True)
    versions = {
        "elastix": tool_version(["elastix", "--version"], r"elastix version: (\S+)") if shutil.which("elastix") else None,
        "plastimatch": tool_version(["plastimatch", "--version"], r"plastimatch version (\S+)")
        if shutil.which("plastimatch") else None,
        "elastix (Debian)": package_version("elastix"),
        "plastimatch (Debian)": package_version("plastimatch"),
        "ITK (Debian)": package_version("libinsighttoolkit5-dev"),
        "bcpd": tool_version([os.environ["BCPD_EXE"], "-v"], r"BCPD version (\S+)")
        if "bcpd" in options.peers and os.environ.get("BCPD_EXE") and shutil.which(os.environ["BCPD_EXE"]) else None,
        "FFDShapeMatching": subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True,
                                           text=True).stdout.strip() or None,
        "FFDShapeMatching build": build_configuration(build_dir),
    }
    meshes = extract_meshes(options.meshes, os.path.join(work, "meshes"))
    records = []
    results_json = os.path.join(results_dir, "results.json")
    for mesh in options.meshes:
        for regime in options.regimes:
            for index in range(options.seeds):
                seed = options.first_seed + index
                log("case %s %s seed %d" % (mesh, regime, seed))
                try:
                    case = make_case(mesh, meshes[mesh], regime, seed, work, tools, options)
                except RuntimeError as error:
                    log(str(error))
                    placeholder = {"mesh": mesh, "regime": regime, "seed": seed}
                    for name in ["start"] + options.methods + options.peers:
                        records.append(result_record(placeholder, name, "case", [], None, "failed", str(error)))
                    continue
                records.append(run_start(case, tools))
                for method in options.methods:
                    record = run_method(case, method, tools, options)
                    records.append(record)
                    log("  %-16s %s" % (method, describe(record)))
                image_peers = [p for p in options.peers if p in IMAGE_PEERS
                               and (p not in GIVEN_IMAGE_PEERS or os.environ.get(GIVEN_IMAGE_PEERS[p]))]
                images = None  # the given image peers that are not given need none
                if image_peers:
                    images = peer_images(case, case["folder"], tools, options.voxel_size, options.threads,
                                         options.smoke)
                for peer in options.peers:
                    if peer in POINT_PEERS:
                        record = run_point_peer(case, peer, tools, options)
                    else:
                        record = run_peer(case, peer, images, tools, options)
                    records.append(record)
                    log("  %-16s %s" % (peer, describe(record)))
                if image_peers and not options.keep_images:
                    shutil.rmtree(os.path.join(case["folder"], "images"), ignore_errors=True)
                with open(results_json, "w") as out:
                    json.dump({"options": {k: v for k, v in vars(options).items()}, "versions": versions,
                               "records": records}, out, indent=1)
                # Tables and charts after every case, so that an interrupted run still leaves its figures.
                charts = write_charts(records, options, results_dir)
                write_results(records, options, versions, results_dir, charts)
    log("wrote %s, %s and %d charts" % (os.path.join(results_dir, "RESULTS.md"), results_json, len(charts)))
    if options.smoke_posed:
        return 0 if check_smoke_posed(records, results_dir) else 1
    if options.smoke:
        return 0 if check_smoke(records, results_dir, charts) else 1
    return 0


def describe(record):
    if record["status"] != "ok":
        return record["reason"] if record["status"] == "not run" else "failed: " + (record["reason"] or "")
    scores = record["scores"]
    return "true error %.3f mm (p95 %.3f), MDH %.3f mm, min det J %s, %.1f s, %.0f MB" % (
        scores["true_error"]["mean"], scores["true_error"]["p95"], scores["mean_directed_hausdorff"],
        "%.3f" % scores["min_jacobian_determinant"] if isinstance(scores.get("min_jacobian_determinant"), (int, float))
        else "–", record["seconds_total"], record["peak_mb"])


if __name__ == "__main__":
    sys.exit(main())
