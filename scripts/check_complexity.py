"""Fails on a function that is new over the complexity limits or worse than its baseline.

Limits: 120 lines (lizard's "length", blank and comment lines included) and cyclomatic
complexity 40. Functions already over them are listed in scripts/complexity-baseline.txt,
one `path:function length ccn` per line; they may shrink, not grow, so the tree gets no new
long function while the listed ones are cut into named steps. A listed function that grew
or a new offender fails the check; a listed function that shrank or went under the limits
is reported so that its baseline line can be tightened or dropped.

Usage: python3 scripts/check_complexity.py [--write-baseline]
"""

from __future__ import annotations

import argparse
import csv
import io
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASELINE = ROOT / "scripts" / "complexity-baseline.txt"
SOURCES = ("cpp", "python", "addon")
EXCLUDED = ("*/build/*", "*/__pycache__/*")
MAX_LENGTH = 120
MAX_CCN = 40


def measure() -> dict[str, tuple[int, int]]:
    """Every function over a limit: `path:function` -> (length, ccn), the worst of overloads."""
    command = [sys.executable, "-m", "lizard", "--csv", "-l", "cpp", "-l", "python"]
    for pattern in EXCLUDED:
        command += ["-x", pattern]
    output = subprocess.run(command + list(SOURCES), cwd=ROOT, capture_output=True, text=True, check=True).stdout
    offenders: dict[str, tuple[int, int]] = {}
    # lizard's CSV columns: nloc, ccn, tokens, params, length, location, file, name, signature, start, end
    for row in csv.reader(io.StringIO(output)):
        ccn, length, path, name = int(row[1]), int(row[4]), row[6], row[7]
        if length <= MAX_LENGTH and ccn <= MAX_CCN:
            continue
        key = f"{path}:{name}"
        old = offenders.get(key, (0, 0))
        offenders[key] = (max(old[0], length), max(old[1], ccn))
    return offenders


def read_baseline() -> dict[str, tuple[int, int]]:
    baseline = {}
    for line in BASELINE.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            key, length, ccn = line.rsplit(None, 2)
            baseline[key] = (int(length), int(ccn))
    return baseline


def write_baseline(offenders: dict[str, tuple[int, int]]) -> None:
    lines = [f"# Functions over {MAX_LENGTH} lines or cyclomatic complexity {MAX_CCN} (scripts/check_complexity.py).",
             "# path:function length ccn. They may shrink, not grow; drop a line when its function is cut up."]
    lines += [f"{key} {length} {ccn}" for key, (length, ccn) in sorted(offenders.items())]
    BASELINE.write_text("\n".join(lines) + "\n")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write-baseline", action="store_true", help="record today's offenders as the baseline")
    args = parser.parse_args()
    offenders = measure()
    if args.write_baseline:
        write_baseline(offenders)
        print(f"check-complexity: {len(offenders)} offenders written to {BASELINE.relative_to(ROOT)}")
        return 0
    baseline = read_baseline()
    failures = 0
    print(f"{'length':>6} {'ccn':>4}  {'status':<18} function (limits: {MAX_LENGTH} lines, ccn {MAX_CCN})")
    for key in sorted(set(offenders) | set(baseline)):
        length, ccn = offenders.get(key, (0, 0))
        if key not in baseline:
            status, failures = "NEW", failures + 1
        elif key not in offenders:
            status, (length, ccn) = "within limits", baseline[key]
        elif length > baseline[key][0] or ccn > baseline[key][1]:
            status, failures = f"WORSE than {baseline[key][0]} {baseline[key][1]}", failures + 1
        elif (length, ccn) != baseline[key]:
            status = f"better than {baseline[key][0]} {baseline[key][1]}"
        else:
            status = "baseline"
        print(f"{length:>6} {ccn:>4}  {status:<18} {key}")
    if failures:
        print(f"check-complexity: {failures} function(s) new over the limits or worse than "
              f"{BASELINE.relative_to(ROOT)}: cut them into named steps", file=sys.stderr)
        return 1
    print(f"check-complexity: ok ({len(offenders)} functions over the limits, none new or worse)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
