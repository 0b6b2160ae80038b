"""What moved in the golden outputs: tests/data/golden.npz against golden_cases.capture().

Prints, per family (the key's first part: solve, at, batch, sweep, path, actuate, ...),
the largest relative change of a float key (max |new - old| / max |old| over the
key's finite entries, the scale tests/test_golden.py uses) with the key that has it,
then every non-float key that changed (status, nit, messages, verdicts), old -> new.
With --write, replaces only the keys that changed (the fingerprint too) and saves the
file again (np.savez_compressed); every other key keeps its stored bits.

    PYTHONPATH=$PWD python bench/golden_diff.py [--write]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import golden_cases as G  # noqa: E402

# keys that are round-off themselves (a converged residual's norm, a target distance, a
# truncation estimate): their relative change is reported apart
NOISE = ("residual_norm", "residual", "distance", "truncation")


def rel_change(old: np.ndarray, new: np.ndarray) -> float:
    if not np.array_equal(np.isnan(old), np.isnan(new)):
        return np.inf
    fin = np.isfinite(old)
    if not np.array_equal(old[~fin], new[~fin]):
        return np.inf
    if not fin.any():
        return 0.0
    scale = np.max(np.abs(old[fin]))
    d = np.max(np.abs(new[fin] - old[fin]))
    return 0.0 if d == 0.0 else (d / scale if scale > 0 else np.inf)


def main() -> None:
    with np.load(G.GOLDEN) as f:
        stored = {k: f[k] for k in f.files}
    current = G.capture()
    changed, worst, noise, other = {}, {}, {}, []
    for key, new in current.items():
        old = stored.get(key)
        if old is None or old.shape != new.shape or old.dtype != new.dtype:
            changed[key] = new
            other.append(f"{key}: shape/dtype changed or new")
            continue
        if old.dtype.kind == "f":
            if np.array_equal(old.view(np.uint8), new.view(np.uint8)):
                continue
            r = rel_change(old, new)
            changed[key] = new
            fam = key.split("/", 1)[0]
            table = noise if key.rsplit("/", 1)[-1] in NOISE else worst
            if r > table.get(fam, (-1.0, ""))[0]:
                table[fam] = (r, key)
        elif not np.array_equal(old, new):
            changed[key] = new
            other.append(f"{key}: {old.ravel()[:4]} -> {new.ravel()[:4]}")
    print(f"{len(changed)} of {len(current)} keys changed\n")
    print("| family | largest relative change | key | residual norms: largest | key |")
    print("|---|---|---|---|---|")
    for fam in sorted({k.split("/", 1)[0] for k in current}):
        r, key = worst.get(fam, (0.0, "(bitwise the same)"))
        rn, keyn = noise.get(fam, (0.0, "(bitwise the same)"))
        print(f"| {fam} | {r:.2g} | `{key}` | {rn:.2g} | `{keyn}` |")
    print("\nnon-float keys changed:")
    for line in other:
        print("  " + line)
    if "--write" in sys.argv[1:]:
        for k, v in G.fingerprint().items():
            stored[f"__fingerprint__/{k}"] = np.array(v)
        stored.update(changed)
        np.savez_compressed(G.GOLDEN, **stored)
        print(f"replaced {len(changed)} keys in {G.GOLDEN}")


if __name__ == "__main__":
    main()
