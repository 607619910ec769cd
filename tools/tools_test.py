"""The test tooling tested (docs/testing.md): tools/test_report.py lists skipped tests with their reasons from a
JUnit report such as ctest writes, and tools/mutate.py tells a caught mutation from one that survived and puts
the file back either way."""

import os
import subprocess
import textwrap

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PYTHON = "/usr/bin/python3"

# As `ctest --output-junit` writes it (CMake 3.25): a GTEST_SKIP, a SKIP_RETURN_CODE, a failure, a pass with
# pytest skips in its output, and a pass without.
JUNIT = textwrap.dedent("""\
    <?xml version="1.0" encoding="UTF-8"?>
    <testsuite name="build" tests="5" failures="1" disabled="0" skipped="2">
      <testcase name="FastMathTest.Avx512" classname="FastMathTest.Avx512" status="notrun">
        <skipped message="SKIP_REGULAR_EXPRESSION_MATCHED"/>
        <system-out>[ RUN      ] FastMathTest.Avx512
    /src/fast_math_test.cc:115: Skipped
    this CPU has no AVX-512: nothing to compare
    [  SKIPPED ] FastMathTest.Avx512 (0 ms)
    </system-out>
      </testcase>
      <testcase name="regression.default" classname="regression.default" status="notrun">
        <skipped message="SKIP_RETURN_CODE=77"/>
        <system-out>record.sh: SKIP: no digests of case default recorded on a machine like this one
    </system-out>
      </testcase>
      <testcase name="broken" classname="broken" status="fail"><failure message=""/><system-out>boom
    SKIPPED [1] not.py:1: a failed test's skips are not listed
    </system-out></testcase>
      <testcase name="python.pytest" classname="python.pytest" status="run"><system-out>....s.
    =========================== short test summary info ============================
    SKIPPED [2] test_gymnasium.py:6: could not import 'gymnasium': No module named 'gymnasium'
    5 passed, 2 skipped in 3.0s
    </system-out></testcase>
      <testcase name="plain" classname="plain" status="run"><system-out>ok</system-out></testcase>
    </testsuite>
    """)


def test_report_lists_each_skip_with_its_reason(tmp_path):
    report = tmp_path / "results.xml"
    report.write_text(JUNIT)
    run = subprocess.run([PYTHON, os.path.join(ROOT, "tools/test_report.py"), str(report)], capture_output=True,
                         text=True, check=True)
    lines = run.stdout.splitlines()
    assert lines[0].startswith("Skipped: 2 of 5 tests, and 2 pytest test(s) inside tests that passed"), run.stdout
    assert lines[1:] == [
        "  FastMathTest.Avx512: this CPU has no AVX-512: nothing to compare",
        "  regression.default: no digests of case default recorded on a machine like this one",
        "  python.pytest: 2 pytest test(s): test_gymnasium.py:6: could not import 'gymnasium': No module named "
        "'gymnasium'",
    ], run.stdout
    report.write_text(JUNIT.replace('status="notrun"', 'status="run"').replace("<skipped", "<x")
                      .replace("SKIPPED [", "NOTED ["))
    run = subprocess.run([PYTHON, os.path.join(ROOT, "tools/test_report.py"), str(report)], capture_output=True,
                         text=True, check=True)
    assert run.stdout == "Skipped: none of 5 tests, and no pytest test inside them.\n"
    run = subprocess.run([PYTHON, os.path.join(ROOT, "tools/test_report.py"), str(tmp_path / "none.xml")],
                         capture_output=True, text=True)
    assert run.returncode == 2 and "cannot read" in run.stderr


def mutate(*args):
    return subprocess.run([PYTHON, os.path.join(ROOT, "tools/mutate.py"), "tools/test_report.py", "--no-build",
                           "--pytest", "tools/tools_test.py::test_report_lists_each_skip_with_its_reason", *args],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)


def test_mutate_tells_caught_from_survived_and_restores_the_file():
    path = os.path.join(ROOT, "tools/test_report.py")
    with open(path) as f:
        original = f.read()
    # GoogleTest's reason is the line after "Skipped": take the line itself instead, and the test above fails.
    caught = mutate("--from", "return lines[i + 1]", "--to", "return lines[i]")
    assert caught.returncode == 0 and "mutate: CAUGHT tools/test_report.py:" in caught.stdout, \
        caught.stdout + caught.stderr
    # A change of wording in the usage text: no test can catch it.
    survived = mutate("--from", "Exit status 0, or 2", "--to", "Exit status 0 or 2")
    assert survived.returncode == 1 and "mutate: SURVIVED" in survived.stdout, survived.stdout + survived.stderr
    # An edit that cannot be made is an error, never a verdict.
    missing = mutate("--from", "text that is not there", "--to", "x")
    assert missing.returncode == 2 and "occurs 0 times" in missing.stderr, missing.stderr
    with open(path) as f:
        assert f.read() == original
