#!/usr/bin/env bash
# Installs the Debian 12 (or 13) packages FFDShapeMatching needs to build, test and run, when any
# is missing. Runs apt-get as root, or through sudo.
set -euo pipefail

# The release decides the names: Debian 12 (bookworm) is the main configuration; Debian 13 (trixie) is CI's
# second one (Utilities/DebianTrixieBuild.sh), which builds and tests with GCC only.
codename=$(. /etc/os-release 2>/dev/null && echo "${VERSION_CODENAME:-}")
packages=(
  build-essential cmake ccache python3 pkg-config
  libinsighttoolkit5-dev libgdcm-tools   # ITK (5.2.1 on Debian 12, 5.4.3 on 13; gdcm tools silence ITK's config warnings)
  libvtk9-dev                            # VTK (9.1 on Debian 12, 9.3 on 13): STL/PLY/VTP, locators, rendering
  googletest libgtest-dev                # GoogleTest
  libboost-graph-dev                     # Boost Graph's Boykov-Kolmogorov max-flow for the MRF optimizer
  libnanoflann-dev                       # nanoflann's k-d tree for the CPD method's nearest neighbours
  xvfb xauth                             # off-screen rendering of snapshots
  snakemake python3-matplotlib           # the batch workflow (workflows/Snakefile) and its summary plot
  slurm-wlm munge                        # the workflow's Slurm test: a single-node Slurm on localhost
)
if [ "$codename" = trixie ]; then
  packages+=(libfftw3-dev)               # Debian 13's ITK links FFTW, without depending on its -dev package
else
  packages+=(
    clang libclang-rt-14-dev             # sanitizer and libFuzzer build (Utilities/SanitizerAndFuzzBuild.sh)
    clang-format-14                      # the format check of CI (Utilities/CheckFormat.sh)
  )
fi

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
