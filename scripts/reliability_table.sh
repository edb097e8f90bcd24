#!/bin/sh
# Rewrites the hostile-input table in README.md's Reliability section from what the executable prints: runs the
# hostile-input suite (tests/cli/hostile_cli_test.cpp) with TERRACAST_RELIABILITY_TABLE set, which makes it
# write each case's row instead of checking it against the README, and splices the rows between the table's
# markers. Run after changing a message; the suite then checks every row.
#   scripts/reliability_table.sh [BUILD_DIR]
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
rows=$(mktemp -d)
trap 'rm -rf "$rows"' EXIT
TERRACAST_RELIABILITY_TABLE=$rows "$build/tests/terracast_tests" "[hostile]" >/dev/null
/usr/bin/env python3 - "$here/README.md" "$rows" <<'PY'
import pathlib, sys
readme, rows = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
begin, end = "<!-- hostile-cases:begin -->\n", "<!-- hostile-cases:end -->\n"
text = readme.read_text()
if begin not in text or end not in text:
    sys.exit(f"{readme}: the markers {begin.strip()} and {end.strip()} are missing")
table = "| case | command | exit | message |\n|---|---|---|---|\n"
for part in sorted(rows.glob("*.md")):
    table += part.read_text()
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
readme.write_text(head + begin + table + end + tail)
print(f"{readme}: {table.count(chr(10)) - 2} cases")
PY
