#!/usr/bin/env bash
# Lists what the sanitizers reported into LOG_DIR (their log_path files, one per process, not
# in subfolders): one line per distinct finding, with its count. Exit status 1 when there is any.
#
#   bash scripts/sanitizer-findings.sh LOG_DIR NAME    # NAME heads the listing ("sanitize", ...)
set -euo pipefail
logs=$1
name=$2
reports=$(find "$logs" -maxdepth 1 \( -name 'asan.*' -o -name 'ubsan.*' -o -name 'tsan.*' \) | sort)
[ -z "$reports" ] && exit 0
echo "$name: findings ($(echo "$reports" | wc -l) report files in $logs):"
# One line per distinct finding: the sanitizer's summary line, paths from cpp/ or python/ on.
# shellcheck disable=SC2086
cat $reports | grep -hE "^SUMMARY:|runtime error:" | sed -E 's/^[^:]*\/(cpp|python)\//\1\//' | sort | uniq -c | sort -rn
exit 1
