#!/usr/bin/env bash
# Installs everything cgdem needs on a fresh Debian 12 machine and builds Kokkos 3.4.1
# (OpenMP + Serial) into third_party/kokkos-install. Every step is skipped when already done,
# so the README's commands can call this unconditionally.
#
# Why build Kokkos ourselves: Debian's binary libtrilinos-kokkos-dev has the Serial backend only;
# the Kokkos sources inside Debian's trilinos source package (13.2.0 ships Kokkos 3.4.1) give us OpenMP.
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
prefix="$repo/third_party/kokkos-install"
work="$repo/third_party/kokkos-build"

sudo_cmd=()
if [ "$(id -u)" != 0 ]; then sudo_cmd=(sudo); fi
apt_get() { DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get -y -q "$@"; }

packages=(build-essential cmake ninja-build pkg-config dpkg-dev xz-utils clang-format
          libtbb-dev libeigen3-dev libhdf5-dev hdf5-tools libgtest-dev libgmock-dev libbenchmark-dev
          libyaml-cpp-dev libassimp-dev libopenmpi-dev openmpi-bin
          python3-matplotlib python3-h5py python3-numpy)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing: ${missing[*]}"
  apt_get update
  apt_get install --no-install-recommends "${missing[@]}"
fi

if [ -f "$prefix/lib/cmake/Kokkos/KokkosConfig.cmake" ] || [ -f "$prefix/lib64/cmake/Kokkos/KokkosConfig.cmake" ]; then
  echo "[setup] Kokkos already installed in $prefix"
  exit 0
fi

# Enable deb-src for the Debian entries this machine already has (deb822 or one-line format).
if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "[setup] enabling deb-src entries"
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    "${sudo_cmd[@]}" sed -i 's/^Types: deb$/Types: deb deb-src/' /etc/apt/sources.list.d/debian.sources
  fi
  if [ -f /etc/apt/sources.list ] && grep -qE '^deb ' /etc/apt/sources.list; then
    grep -E '^deb ' /etc/apt/sources.list | sed 's/^deb /deb-src /' | "${sudo_cmd[@]}" tee /etc/apt/sources.list.d/cgdem-deb-src.list >/dev/null
  fi
  apt_get update
fi

mkdir -p "$work"
cd "$work"
if ! ls trilinos_*.orig.tar.* >/dev/null 2>&1; then
  echo "[setup] downloading Debian's trilinos source package (Kokkos 3.4.1 is inside)"
  apt-get source --download-only trilinos
fi
tarball=$(ls trilinos_*.orig.tar.* | head -n 1)
if [ ! -d kokkos-src ]; then
  echo "[setup] extracting packages/kokkos from $tarball"
  tar -xf "$tarball" --wildcards '*/packages/kokkos/*'
  mv ./*/packages/kokkos kokkos-src
fi
grep -E 'set\(Kokkos_VERSION_(MAJOR|MINOR|PATCH)' kokkos-src/CMakeLists.txt | head -n 3 || true

cmake -S kokkos-src -B build -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" \
  -DCMAKE_CXX_STANDARD=17 -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON \
  -DKokkos_ENABLE_TESTS=OFF -DKokkos_ENABLE_EXAMPLES=OFF -DBUILD_SHARED_LIBS=OFF
cmake --build build --parallel "$(nproc)"
cmake --install build
echo "[setup] Kokkos installed in $prefix"
