#!/bin/sh
# Runs valgrind's memcheck on a small `render` and a small `scene` (tiny pictures, one thread) and fails on
# any invalid access, use of uninitialised memory, or memory definitely or indirectly lost.
# Usage: scripts/valgrind.sh [BUILD_DIR]   (default: build; a build without sanitizers)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
terracast="$build/terracast"
[ -x "$terracast" ] || { echo "valgrind.sh: no $terracast; build first" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

check() {
  name=$1
  shift
  # Still-reachable and possibly-lost blocks are what the libraries keep for the process's lifetime (thread
  # pools, driver registries); only leaks with no pointer left count, and every error fails the run. No
  # suppressions are needed: Embree, TBB, GDAL and OpenImageIO report nothing on these runs.
  if valgrind --tool=memcheck --leak-check=full --show-leak-kinds=definite,indirect \
       --errors-for-leak-kinds=definite,indirect --error-exitcode=99 \
       --log-file="$out/$name.log" "$terracast" "$@" >/dev/null 2>&1; then
    echo "valgrind: $name: $(grep -E 'ERROR SUMMARY' "$out/$name.log" | sed 's/^==[0-9]*== //')"
  else
    echo "valgrind: $name failed (exit $?):" >&2
    cat "$out/$name.log" >&2
    exit 1
  fi
}

check render render "$here/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif" \
  -o "$out/render.png" --size 48x32 --threads 1 -q
check scene scene "$here/data-samples/spheres-on-terrain.toml" -o "$out/scene.png" --size 48x32 --threads 1 -q
[ -s "$out/render.png" ] && [ -s "$out/scene.png" ]
