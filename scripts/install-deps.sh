#!/usr/bin/env bash
# Installs everything animanifold needs on a fresh Debian machine (idempotent).
# System libraries come from Debian's packages, Python tools from PyPI.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build
  pybind11-dev libeigen3-dev libsuitesparse-dev libcgal-dev
  # CHOLMOD's supernodal factorisation on optimised BLAS; the OpenMP build shares the core's
  # OpenMP runtime, so one thread setting governs both (no oversubscription).
  libopenblas0-openmp
  libtet1.5-dev libqhull-dev libosd-dev libgtest-dev
  blender python3-numpy
  xvfb  # a virtual screen for the test that runs Morph Selected in a real Blender window
  libopenvdb-dev  # only for the opt-in peer of bench/bench_morph.py (~5 MB with its -dev deps)
)
PIP_PACKAGES=(
  "numpy<2" pytest hypothesis matplotlib scipy scikit-build-core pybind11
  "pytest-xdist>=2.5"  # scripts/test.sh runs the Python tests on both cores (--dist loadgroup: 2.5)
  lizard  # the complexity check (scripts/check-complexity.sh)
  "pybind11-stubgen==3.0.0"  # pinned: its output is compared with the committed _core.pyi
  "bpy>=4.5,<4.6"
  openjd-cli  # Open Job Description: validates and runs the farm/openjd job bundles locally (tests)
  atheris  # the fuzz targets in tests/fuzz (scripts/fuzz.sh)
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "install-deps: apt packages: ${missing[*]}"
  log=$(mktemp)
  if ! { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
         --no-install-recommends "${missing[@]}"; } > "$log" 2>&1; then
    tail -40 "$log"; echo "install-deps: apt-get failed (full log: $log)" >&2; exit 1
  fi
  rm -f "$log"
fi

PYTHON="${PYTHON:-python3}"
if ! "$PYTHON" - <<'PY' 2>/dev/null
import importlib.metadata as md, sys
need = {"numpy": lambda v: int(v.split(".")[0]) < 2, "pytest": None, "pytest-xdist": lambda v: tuple(map(int, v.split(".")[:2])) >= (2, 5), "hypothesis": None,
        "matplotlib": None, "scipy": None, "scikit-build-core": None, "pybind11": None, "lizard": None,
        "pybind11-stubgen": lambda v: v == "3.0.0",
        "bpy": lambda v: v.startswith("4.5"), "openjd-cli": None, "atheris": None}
for name, ok in need.items():
    v = md.version(name)
    if ok and not ok(v):
        sys.exit(1)
PY
then
  echo "install-deps: pip packages: ${PIP_PACKAGES[*]}"
  "$PYTHON" -m pip install --quiet --disable-pip-version-check "${PIP_PACKAGES[@]}"
fi
echo "install-deps: done"
