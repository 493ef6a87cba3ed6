"""What the script tests share: checks that each print a line and are counted, and the exit status.

    sys.dont_write_bytecode = True
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
    from script_checks import check, finish
"""
import sys

failures = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


def finish():
    """Exits 1 naming how many checks failed, or 0."""
    print(f"{len(failures)} check(s) failed")
    sys.exit(1 if failures else 0)
