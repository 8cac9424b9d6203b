"""Is a slice of a random-walk table (a generator run with ROW, scene/tools/walk_rows.h) the table committed
under engine/scene/tables/?

    check_walk_table.py SLICE.inc COMMITTED.inc

Both files list the same arrays in the same order; every number the slice walked (not nan) must be
the committed one within a relative 3e-4 (and the slice must have walked some). Not digit for digit: the
walks call libm, whose x86-64 variants (FMA or not, chosen by the CPU) may differ in a last bit, and one
walk that branches differently moves a row's mean by about 1/walks (1e-5 and less); a change to a walk or
to its random numbers moves it by the walk's noise (1e-3 and more). Exit 0 if so, 1 with
the first differences if not (the committed table is stale: regenerate it with
engine/scene/tools/regenerate_tables.sh).
"""
import re
import sys

_NUMBER = re.compile(r"-?nan|-?inf|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def numbers(path):
    with open(path) as f:
        body = "\n".join(line for line in f if not line.lstrip().startswith("//"))
    body = re.sub(r"\[\d+\]", "", body)  # array sizes
    body = re.sub(r"\bk\w+", "", body)    # array names
    return _NUMBER.findall(body)


def _close(a, b):
    if a == b:
        return True
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return abs(x - y) <= REL_TOL * max(abs(x), abs(y)) + ABS_TOL


# The tables print 5 significant digits: a last-digit step is up to 1e-4 of the value.
REL_TOL, ABS_TOL = 3e-4, 1e-7


def main(slice_path, committed_path):
    walked, committed = numbers(slice_path), numbers(committed_path)
    if len(walked) != len(committed):
        print("%s has %d numbers, %s %d: not the same layout" % (slice_path, len(walked), committed_path, len(committed)))
        return 1
    compared = [(i, a, b) for i, (a, b) in enumerate(zip(walked, committed)) if "nan" not in a]
    wrong = [(i, a, b) for i, a, b in compared if not _close(a, b)]
    print("%s: %d of %d numbers walked, %d differ from %s" % (slice_path, len(compared), len(walked), len(wrong),
                                                              committed_path))
    for i, a, b in wrong[:10]:
        print("  number %d: walked %s, committed %s" % (i, a, b))
    return 0 if compared and not wrong else 1


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
