#!/usr/bin/env bash
# Set-up for `make demo` and `make test` on a fresh Debian machine.
# Installs the Debian packages the project needs (when root and apt are there),
# builds .venv from the machine's python3 with pinned dependencies, and exposes
# Debian's pyopenvdb module (only that module) inside the virtual environment.
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON=${PYTHON:-python3}
VENV=.venv
# libcairo2 for the drawings; calculix-ccx: the solver the FEA tests run; the libraries after it
# are those the PyPI gmsh wheel links (GLU, X cursor / fonts / Xinerama) even when it runs headless.
DEB_PACKAGES=(python3-openvdb libegl1 libgl1-mesa-dri libcairo2 calculix-ccx libglu1-mesa libxcursor1 libxft2
              libxinerama1 libfontconfig1 libgomp1)

missing=()
for pkg in "${DEB_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "setup: installing Debian packages: ${missing[*]}"
        apt-get update -qq >/dev/null
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
    else
        echo "setup: cannot install ${missing[*]} (needs root and apt-get); continuing without openvdb"
    fi
fi

if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
    "$VENV/bin/python" -m pip install -q --upgrade pip
fi
"$VENV/bin/python" -m pip install -q -c constraints.txt -e ".[test]"

# Expose Debian's pyopenvdb module alone; all of dist-packages would shadow the venv's numpy.
site=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
tag=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
for dir in /usr/lib/python3/dist-packages /usr/lib/python3.*/dist-packages; do
    if [ -f "$dir/pyopenvdb$tag" ]; then
        ln -sf "$dir/pyopenvdb$tag" "$site/pyopenvdb$tag"
        break
    fi
done
"$VENV/bin/python" -c 'import pyopenvdb' 2>/dev/null || echo "setup: pyopenvdb is not importable; openvdb features are off"
# Byte-compile the project's modules: the first run after set-up reads them instead of compiling
# 70 modules' source (0.1 s of `implicad mesh`), and so does every run where bytecode is not written.
"$VENV/bin/python" -m compileall -q -j 0 implicit spatial parametric >/dev/null \
    || echo "setup: the modules could not be byte-compiled; the first run compiles them"
# Compile the numba kernels of the evaluator, the mesher and mass properties once, into numba's
# on-disk cache: later processes, the first `implicad mesh` after set-up included, load them.
"$VENV/bin/python" tools/prime_kernels.py \
    || echo "setup: the numba kernels could not be compiled; the first runs will compile them"
touch "$VENV/.installed"
