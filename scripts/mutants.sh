#!/bin/sh
# The mutation check: plants each bug of scripts/mutants.txt in turn (one plausible slip per subsystem: a flipped
# sign, sine for cosine, an off-by-one bound, a dropped nodata test, a wrong exponent), rebuilds, runs the tests
# meant to catch it (stopping at the first that fails), and restores the file. Fails, naming them, if any planted
# bug survives (its tests pass).
#   scripts/mutants.sh [BUILD_DIR] [--sample N]   (N mutants chosen by the commit, so successive commits rotate)
# The build folder must be configured; it is rebuilt clean at the end.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=$here/build
sample=0
while [ $# -gt 0 ]; do
    case $1 in
        --sample) sample=$2; shift 2 ;;
        *) build=$(cd "$1" && pwd); shift ;;
    esac
done
seed=$(git -C "$here" rev-parse --short=8 HEAD 2>/dev/null || echo 0)
exec /usr/bin/env python3 - "$here" "$build" "$sample" "$seed" <<'PY'
import pathlib, re, subprocess, sys
here, build, sample, seed = pathlib.Path(sys.argv[1]), sys.argv[2], int(sys.argv[3]), sys.argv[4]
mutants, cur = [], None
for line in (here / "scripts/mutants.txt").read_text().splitlines():
    if not line.strip() or line.startswith("#"):
        continue
    key, _, value = line.partition(": ")
    if key == "name":
        cur = {"name": value}
        mutants.append(cur)
    else:
        cur[key] = value.replace("\\n", "\n")
# Every entry must still apply, sampled or not, so that a change to the code cannot leave one behind unnoticed.
for m in mutants:
    count = (here / m["file"]).read_text().count(m["from"])
    if count != 1:
        sys.exit(f"mutants.txt: '{m['name']}': the text to replace occurs {count} times in {m['file']}")
if sample > 0:
    start = int(seed, 16) % len(mutants) if re.fullmatch("[0-9a-f]+", seed) else 0
    mutants = [mutants[(start + k) % len(mutants)] for k in range(min(sample, len(mutants)))]
def build_all():
    return subprocess.run(["cmake", "--build", build, "-j2"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
survivors = []
for m in mutants:
    path = here / m["file"]
    text = path.read_text()
    try:
        path.write_text(text.replace(m["from"], m["to"]))
        if build_all() != 0:
            print(f"caught (does not build): {m['name']}", flush=True)
            continue
        # A caught bug needs one failing test: the rest are not run (a survivor runs them all).
        r = subprocess.run(["ctest", "--test-dir", build, "-j2", "--timeout", "600", "--stop-on-failure", "-R", m["tests"]],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        ran = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
        if ran is None or ran.group(2) == "0":
            sys.exit(f"mutants.txt: '{m['name']}': the regex {m['tests']!r} selects no test")
        if r.returncode == 0:
            survivors.append(m["name"])
            print(f"SURVIVED: {m['name']} ({ran.group(2)} tests ran)", flush=True)
        else:
            print(f"caught: {m['name']} ({ran.group(1)} of the first {ran.group(2)} tests run failed)", flush=True)
    finally:
        path.write_text(text)
if build_all() != 0:
    sys.exit("the restored tree does not build")
print(f"{len(mutants) - len(survivors)} of {len(mutants)} planted bugs caught")
sys.exit(1 if survivors else 0)
PY
