#!/bin/sh
# Build mipcast's ParaView representation plugin against the installed ParaView.
#   plugin/representation/build.sh [BUILD_DIR] [extra cmake arguments...]
# BUILD_DIR defaults to build/paraview-representation in the repository (ignored by git).
# ParaView's CMake package is found through CMAKE_PREFIX_PATH or -DParaView_DIR=...
# (Debian: /usr/lib/x86_64-linux-gnu/cmake/paraview-5.11, found by default).
# Prints the path of the plugin library on its last line.
set -e
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build/paraview-representation}
[ $# -gt 0 ] && shift
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >"$build.configure.log" 2>&1 \
  || { mkdir -p "$build"; cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "${MIPCAST_BUILD_JOBS:-2}"
find "$build" -name "MipcastRepresentation.so" -path "*plugins*" | head -n 1
