#!/usr/bin/env bash
# Installs the Debian 12 packages FFDShapeMatching needs to build, test and run, when any
# is missing. Runs apt-get as root, or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ccache python3 pkg-config
  libinsighttoolkit5-dev libgdcm-tools   # ITK 5.2.1 (gdcm tools silence ITK's config warnings)
  libvtk9-dev                            # VTK 9.1: STL/PLY/VTP, locators, rendering
  libeigen3-dev                          # Eigen 3.4
  googletest libgtest-dev                # GoogleTest 1.12
  libboost-graph-dev                     # Boost Graph's Boykov-Kolmogorov max-flow for the MRF optimizer
  libnanoflann-dev                       # nanoflann's k-d tree for the CPD method's nearest neighbours
  xvfb xauth                             # off-screen rendering of snapshots
  clang libclang-rt-14-dev               # sanitizer and libFuzzer build (Utilities/SanitizerAndFuzzBuild.sh)
  clang-format-14                        # the format check of CI (Utilities/CheckFormat.sh)
  snakemake python3-matplotlib           # the batch workflow (workflows/Snakefile) and its summary plot
  slurm-wlm munge                        # the workflow's Slurm test: a single-node Slurm on localhost
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "error: packages missing (${missing[*]}) and neither root nor sudo is available" >&2
  exit 1
fi
echo "Installing: ${missing[*]}" >&2
"${as_root[@]}" apt-get update -q
DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
