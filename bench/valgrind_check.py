"""Judge a valgrind memcheck XML report (written by bench/valgrind.sh).

    python bench/valgrind_check.py REPORT.xml [--ours SUBSTRING ...]

Counts every error valgrind reported, by kind, and splits them into
- ours:    a frame of the stack lies in our code (the object file
           tendonrod/_core*.so, or a source file under csrc/ or tendonrod/);
- foreign: everything else (CPython, NumPy, glibc).
Fails (exit 1) on
- any error of ours (invalid access, use of uninitialised memory, bad free,
  overlap, and definite leaks: valgrind is run with
  --errors-for-leak-kinds=definite, so only definite leaks appear as errors);
- any invalid read/write/free anywhere that bench/valgrind.supp does not
  suppress (an invalid access in CPython or NumPy may still be caused by us,
  e.g. by a bad reference count).
Foreign uninitialised-value reports and foreign definite leaks are printed but
do not fail: CPython 3.11 has a known uninitialised-read false positive in
maybe_small_long that cascades through the interpreter, and NumPy/CPython
keep some objects alive for the life of the process by design.
"""

import argparse
import collections
import sys
import xml.etree.ElementTree as ET

INVALID = {
    "InvalidRead",
    "InvalidWrite",
    "InvalidFree",
    "MismatchedFree",
    "InvalidJump",
    "InvalidMemPool",
    "Overlap",
    "FishyValue",
}


def frames(err):
    out = []
    for st in err.findall("stack"):
        for f in st.iter("frame"):
            out.append(
                (
                    f.findtext("fn") or "?",
                    f.findtext("obj") or "?",
                    (f.findtext("dir") or "") + "/" + (f.findtext("file") or ""),
                    f.findtext("line") or "",
                )
            )
    return out


def is_ours(fr, ours):
    fn, obj, path, _ = fr
    return any(o in obj or o in path for o in ours)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("report")
    ap.add_argument(
        "--ours", action="append", default=["tendonrod/_core", "/csrc/", "/tendonrod/_core.c"]
    )
    a = ap.parse_args(argv)
    root = ET.parse(a.report).getroot()
    counts = collections.Counter()
    bad = []
    for err in root.iter("error"):
        kind = err.findtext("kind")
        fr = frames(err)
        ours = any(is_ours(f, a.ours) for f in fr)
        counts[(kind, "ours" if ours else "foreign")] += 1
        if ours or kind in INVALID:
            what = err.findtext("what") or (
                err.find("xwhat").findtext("text") if err.find("xwhat") is not None else ""
            )
            bad.append((kind, what, fr[:12]))
    supp = sum(int(p.findtext("count")) for p in root.iter("pair") if p.find("count") is not None)
    print("valgrind report:", a.report)
    if not counts:
        print("  no errors reported")
    for (kind, who), n in sorted(counts.items()):
        print(f"  {kind:24s} {who:8s} {n}")
    print(f"  suppressed (bench/valgrind.supp): {supp}")
    for kind, what, fr in bad:
        print(f"\nFAIL {kind}: {what}")
        for fn, obj, path, line in fr:
            print(f"    {fn}  ({obj.rsplit('/', 1)[-1]} {path.rsplit('/', 1)[-1]}:{line})")
    if bad:
        print(f"\nvalgrind: {len(bad)} error(s) in our code or invalid accesses")
        return 1
    print("valgrind: clean (no invalid access; no error or definite leak in our code)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
