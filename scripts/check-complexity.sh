#!/usr/bin/env bash
# Fails on a function new over 120 lines or cyclomatic complexity 40, or worse than its line in
# scripts/complexity-baseline.txt (lizard over cpp/, python/, addon/). Prints the table.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 scripts/check_complexity.py "$@"
