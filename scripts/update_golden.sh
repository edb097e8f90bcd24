#!/bin/sh
# Rewrites the golden images (tests/golden/*.png) from the current renderer: runs the tests tagged [golden]
# with TERRACAST_UPDATE_GOLDEN=1, where each writes its reference and reports a failure on purpose, then runs
# them again without it, which must pass. Look at the pictures (git diff shows which changed) before committing.
#   scripts/update_golden.sh [BUILD_DIR]
set -eu
build=${1:-$(cd "$(dirname "$0")/.." && pwd)/build}
TERRACAST_UPDATE_GOLDEN=1 "$build/tests/terracast_tests" "[golden]" >/dev/null || true
"$build/tests/terracast_tests" "[golden]"
