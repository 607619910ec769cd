#!/usr/bin/python3
"""What a test run did not check: every skipped test with its reason, from ctest's JUnit report (docs/testing.md,
"What a green run did not check"). tools/test.sh runs it after ctest.

    tools/test_report.py build/test-results.xml

Lists the tests ctest reports as skipped (a GoogleTest GTEST_SKIP, a SKIP_RETURN_CODE such as a regression
case without digests for this machine) with the reason their output gives, and the pytest tests skipped inside a
ctest test that passed (pytest.ini has pytest print "SKIPPED [n] file:line: reason"). Exit status 0, or 2
when the report cannot be read.
"""

import re
import sys
import xml.etree.ElementTree as ElementTree

PYTEST_SKIP = re.compile(r"^SKIPPED \[(\d+)\] (.*)$")


def skip_reason(output, message):
    """The reason a skipped test's output gives: GoogleTest's line after "Skipped", a "SKIP:" line, else ctest's."""
    lines = [line.strip() for line in output.splitlines()]
    for i, line in enumerate(lines):
        if line.endswith(": Skipped") and i + 1 < len(lines) and lines[i + 1]:
            return lines[i + 1]
        if "SKIP:" in line:
            return line.split("SKIP:", 1)[1].strip()
    return message or "no reason given"


def report(path):
    """(skipped ctest tests [(name, reason)], pytest skips inside passed tests [(ctest name, count, reason)], total)."""
    root = ElementTree.parse(path).getroot()
    skipped, pytest_skips, total = [], [], 0
    for case in root.iter("testcase"):
        total += 1
        name = case.get("name")
        output = case.findtext("system-out") or ""
        skip = case.find("skipped")
        if case.get("status") in ("notrun", "disabled") or skip is not None:
            skipped.append((name, skip_reason(output, skip.get("message") if skip is not None else "")))
            continue
        if case.get("status") != "run":
            continue
        for line in output.splitlines():
            match = PYTEST_SKIP.match(line.strip())
            if match:
                pytest_skips.append((name, int(match.group(1)), match.group(2)))
    return skipped, pytest_skips, total


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        skipped, pytest_skips, total = report(sys.argv[1])
    except (OSError, ElementTree.ParseError) as e:
        print(f"test_report: cannot read {sys.argv[1]}: {e}", file=sys.stderr)
        return 2
    n_pytest = sum(count for _, count, _ in pytest_skips)
    if not skipped and not pytest_skips:
        print(f"Skipped: none of {total} tests, and no pytest test inside them.")
        return 0
    print(f"Skipped: {len(skipped)} of {total} tests, and {n_pytest} pytest test(s) inside tests that passed "
          "(docs/testing.md says why each may skip):")
    for name, reason in skipped:
        print(f"  {name}: {reason}")
    for name, count, reason in pytest_skips:
        print(f"  {name}: {count} pytest test(s): {reason}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
