#!/usr/bin/python3
"""Mutation check of a test: apply one plausible edit to the code, rebuild, run the named tests, put the file
back, and say whether the tests caught the edit (docs/testing.md, "Checking that a test can fail").

    tools/mutate.py FILE --from OLD --to NEW (--ctest REGEX | --pytest NODE ...) [--build build]
                    [--target T ... | --no-build] [--name TEXT]

FILE is relative to the repository root; OLD must occur exactly once in it. --ctest runs `ctest -R REGEX`
in the build tree; --pytest runs pytest on the given node ids (clients/python/tests/x.py::test_y) against the
build's Python package and hadald. --target names the build targets to rebuild (default: everything);
--no-build rebuilds nothing (a Python file the tests import from the source tree). The file is restored (and
rebuilt) whatever happens. Exit status: 0 caught (at least one test failed), 1
survived (every test passed), 2 the edit could not be made or a test could not be run.
"""

import argparse
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def build(build_dir, targets):
    if targets is None:
        return subprocess.CompletedProcess([], 0, "")
    command = ["cmake", "--build", build_dir, "-j2"]
    for target in targets:
        command += ["--target", target]
    return subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


def run_tests(args):
    """(status, output): status 0 every test passed, 1 some failed, 2 none ran."""
    if args.ctest:
        run = subprocess.run(["ctest", "--test-dir", args.build, "-R", args.ctest, "--output-on-failure", "-j2"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if "No tests were found" in run.stdout:
            return 2, run.stdout
        return (0 if run.returncode == 0 else 1), run.stdout
    build_dir = os.path.abspath(args.build)
    env = dict(os.environ, PYTHONPATH=os.path.join(build_dir, "python"), HADALD=os.path.join(build_dir, "bin/hadald"),
               HADAL_VIEWER=os.path.join(build_dir, "bin/hadal-viewer"), HADAL_SOURCE_DIR=ROOT,
               HADAL_ARTIFACTS=os.path.join(build_dir, "test-artifacts/mutate"),
               ROS_LOCALHOST_ONLY="1")
    run = subprocess.run(["/usr/bin/python3", "-m", "pytest", "-q", "-p", "no:cacheprovider", *args.pytest],
                         cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if run.returncode in (0, 1):
        return run.returncode, run.stdout
    return 2, run.stdout  # collection errors, no tests, interrupted


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file")
    parser.add_argument("--from", dest="old", required=True, help="the text to replace (exactly once in FILE)")
    parser.add_argument("--to", dest="new", required=True, help="what to put there")
    tests = parser.add_mutually_exclusive_group(required=True)
    tests.add_argument("--ctest", help="ctest -R regular expression of the tests to run")
    tests.add_argument("--pytest", nargs="+", help="pytest node ids (paths relative to the repository root)")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    builds = parser.add_mutually_exclusive_group()
    builds.add_argument("--target", action="append", default=[], help="build target to rebuild (repeatable)")
    builds.add_argument("--no-build", action="store_true", help="rebuild nothing")
    parser.add_argument("--name", help="what the mutation is, for the report")
    args = parser.parse_args()
    if args.no_build:
        args.target = None

    path = os.path.join(ROOT, args.file)
    try:
        with open(path) as f:
            original = f.read()
    except OSError as e:
        print(f"mutate: error: {e}", file=sys.stderr)
        return 2
    occurrences = original.count(args.old)
    if occurrences != 1:
        print(f"mutate: error: --from occurs {occurrences} times in {args.file} (must be exactly once)",
              file=sys.stderr)
        return 2
    if args.old == args.new:
        print("mutate: error: --from and --to are the same", file=sys.stderr)
        return 2
    line = original[:original.index(args.old)].count("\n") + 1
    name = args.name or f"{args.file}:{line}: {args.old!r} -> {args.new!r}"

    # The unmutated tests must pass first, or a failure says nothing about the mutation.
    built = build(args.build, args.target)
    if built.returncode != 0:
        print(built.stdout[-3000:])
        print("mutate: error: the unmutated tree does not build", file=sys.stderr)
        return 2
    status, output = run_tests(args)
    if status != 0:
        print(output[-3000:])
        print("mutate: error: the tests do not pass (or none ran) without the mutation", file=sys.stderr)
        return 2

    try:
        with open(path, "w") as f:
            f.write(original.replace(args.old, args.new))
        built = build(args.build, args.target)
        if built.returncode != 0:
            print(built.stdout[-3000:])
            print(f"mutate: {name}: does not compile (not a mutation a test must catch)", file=sys.stderr)
            return 2
        status, output = run_tests(args)
    finally:
        with open(path, "w") as f:
            f.write(original)
        build(args.build, args.target)

    if status == 2:
        print(output[-3000:])
        print(f"mutate: error: {name}: the tests did not run", file=sys.stderr)
        return 2
    failed = [l.strip() for l in output.splitlines()
              if ("***Failed" in l or "FAILED" in l or "Exception" in l) and "tests failed" not in l]
    if status == 1:
        print(f"mutate: CAUGHT {name}")
        for l in failed[:20]:
            print(f"  {l}")
        return 0
    print(f"mutate: SURVIVED {name}: every test passed")
    return 1


if __name__ == "__main__":
    sys.exit(main())
