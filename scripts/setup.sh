#!/usr/bin/env bash
# Install obscura's build dependencies from Debian 12 (bookworm) packages.
# Idempotent: when everything is already installed it does nothing and needs
# no network. Runs as root directly, or through sudo otherwise.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git python3 python3-matplotlib
  libopenexr-dev libimath-dev
  libopenimageio-dev openimageio-tools
  libopencolorio-dev
  libglm-dev nlohmann-json3-dev zlib1g-dev
  libosmesa6-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libembree-dev libtinyobjloader-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev libtbb-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-openimageio
  slurm-wlm munge python3-distributed
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$pkg")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all ${#PACKAGES[@]} build dependencies are installed"
  exit 0
fi

if ! command -v apt-get >/dev/null 2>&1; then
  echo "setup: apt-get not found; install these packages by hand: ${missing[*]}" >&2
  exit 1
fi

SUDO=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO=(sudo)
  else
    echo "setup: not root and sudo is not available; as root run: apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi

echo "setup: installing ${missing[*]}"
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y -qq -o Dpkg::Use-Pty=0 --no-install-recommends "${missing[@]}"
echo "setup: done"
