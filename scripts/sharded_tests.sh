#!/bin/sh
# Runs the whole Catch2 suite of a build in a few processes (shards) instead of one per test case, JOBS at a
# time: under the sanitizers a process costs 1.5 s to start and to check for leaks at exit, which one process
# per test case pays 350 times. Each shard's output is shown when it fails. The test cases tagged [heavy] (the
# ones that take tens of seconds under the sanitizers) each get a shard of their own, started first, so that no
# shard holding several of them is left running alone at the end.
# Usage: scripts/sharded_tests.sh BUILD_DIR [SHARDS] [JOBS] [EXCLUDE]
#   EXCLUDE: an extended regular expression; test cases whose names match it are left out.
set -eu
build=$(cd "${1:?usage: sharded_tests.sh BUILD_DIR [SHARDS] [JOBS] [EXCLUDE]}" && pwd)
shards=${2:-16}
jobs=${3:-2}
exclude=${4:-}
runner="$build/tests/terracast_tests"
[ -x "$runner" ] || { echo "sharded_tests.sh: no $runner" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The test cases CTest would run (hidden ones stay hidden), dealt round-robin into the shards' name files, with
# the characters Catch reads as test-spec syntax escaped.
"$runner" --list-test-names-only | sed '/^$/d' >"$work/names"
if [ -n "$exclude" ]; then
  grep -Ev -- "$exclude" "$work/names" >"$work/kept" || true
  mv "$work/kept" "$work/names"
fi
total=$(wc -l <"$work/names")
[ "$total" -gt 0 ] || { echo "sharded_tests.sh: no test cases to run" >&2; exit 2; }
"$runner" --list-test-names-only "[heavy]" | sed '/^$/d' >"$work/heavy"
sed 's/[],[*~\\"]/\\&/g' "$work/names" | awk -v n="$shards" -v dir="$work" -v heavyList="$work/heavy" '
  BEGIN { while ((getline name < heavyList) > 0) { gsub(/[],[*~\\"]/, "\\\\&", name); heavy[name] = 1 } }
  $0 in heavy { print > (dir "/heavy-" sprintf("%02d", h++) ".txt"); next }
  { print > (dir "/shard-" (k++ % n) ".txt") }'

# One shard: its test cases in one process, from the build folder (as CTest runs them); a line per shard, and
# its whole output when it fails. Catch reports each test case's seconds (-d yes), so that the slowest can be
# listed at the end.
cat >"$work/run-shard" <<'EOF'
#!/bin/sh
list=$1 runner=$2 build=$3
log=${list%.txt}.log
start=$(date +%s)
if (cd "$build" && "$runner" -d yes -f "$list") >"$log" 2>&1; then
  echo "shard $(basename "$list" .txt): $(wc -l <"$list") test cases passed in $(( $(date +%s) - start )) s"
else
  echo "shard $(basename "$list" .txt) FAILED after $(( $(date +%s) - start )) s:"
  cat "$log"
  exit 1
fi
EOF
chmod +x "$work/run-shard"
start=$(date +%s)
if { ls "$work"/heavy-*.txt 2>/dev/null || true; ls "$work"/shard-*.txt; } |
  xargs -P "$jobs" -I{} "$work/run-shard" {} "$runner" "$build"; then
  echo "sharded_tests.sh: $total test cases in $(ls "$work"/*.txt | wc -l) shards passed in $(( $(date +%s) - start )) s; the slowest:"
  # Catch's duration lines read "<seconds> s: <test case name>".
  cat "$work"/shard-*.log | grep -E '^[0-9]+\.[0-9]+ s: ' | sort -rn | head -12 | sed 's/^/  /'
else
  echo "sharded_tests.sh: a shard failed (its output is above)" >&2
  exit 1
fi
