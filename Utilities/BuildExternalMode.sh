#!/usr/bin/env bash
# Configures, builds and tests FFDShapeMatching in ITK's external-module mode
# (include(ITKModuleExternal)), against Debian's installed ITK 5.2.1 completed with the
# CMake module scripts of the same ITK release.
#
# Debian's libinsighttoolkit5-dev ships no ITKModuleExternal.cmake; the scripts come from
# Debian's source package insighttoolkit5 (same release), fetched once with apt-get source
# into a cache folder outside the repository. Only CMake/ and two Python utilities are
# extracted; nothing of it is committed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Utilities/InstallDependencies.sh

cache=${FFD_ITK_SCRIPTS_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/ffdshapematching/itk-5.2.1}
build=${FFD_EXTERNAL_BUILD_DIR:-build-external}
if [ ! -f "$cache/CMake/ITKModuleExternal.cmake" ]; then
  if [ "$(id -u)" -eq 0 ]; then as_root=(); else as_root=(sudo); fi
  if ! grep -rqs '^Types:.*deb-src\|^deb-src ' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
      "${as_root[@]}" tee /etc/apt/sources.list.d/ffdshapematching-src.sources >/dev/null
  fi
  "${as_root[@]}" apt-get update -q
  download=$(mktemp -d)
  (cd "$download" && apt-get source --download-only -q insighttoolkit5 >/dev/null 2>&1)
  mkdir -p "$cache.partial"
  tar -xJf "$download"/insighttoolkit5_5.2.1.orig.tar.xz -C "$cache.partial" --strip-components=1 \
    --wildcards '*/CMake/*' '*/Utilities/Maintenance/BuildHeaderTest.py' '*/Utilities/Doxygen/mcdoc.py'
  rm -rf "$download" "$cache"
  mv "$cache.partial" "$cache"
fi

# A writable ITK_DIR: Debian's configuration, with ITK_CMAKE_DIR pointed at the scripts
# (Debian's ITKConfig.cmake sets it as a plain variable, so it is re-pointed afterwards).
itk_dir="$PWD/$build/itk-config"
mkdir -p "$itk_dir"
cat > "$itk_dir/ITKConfig.cmake" <<CONFIG
include(/usr/lib/cmake/ITK-5.2/ITKConfig.cmake)
set(ITK_CMAKE_DIR "$cache/CMake")
CONFIG
cat > "$itk_dir/ITKConfigVersion.cmake" <<CONFIG
include(/usr/lib/cmake/ITK-5.2/ITKConfigVersion.cmake)
CONFIG

cmake -S . -B "$build/build" -DCMAKE_BUILD_TYPE=Release -DITK_DIR="$itk_dir" \
  -DITK_USE_KWSTYLE=OFF -DITK_USE_CLANG_FORMAT=OFF -DBUILD_TESTING=ON
cmake --build "$build/build" -j"$(nproc 2>/dev/null || echo 2)"
(cd "$build/build" && ctest -j"$(nproc 2>/dev/null || echo 2)" --output-on-failure)
