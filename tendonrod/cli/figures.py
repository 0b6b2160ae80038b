"""``tendonrod figures --out DIR``: the paper's figures regenerated, with index.md."""

from __future__ import annotations

import os
import sys
import time
import traceback

from ._common import EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_OK


def _cmd_figures(args) -> int:
    from tendonrod._extras import optional_import
    from tendonrod.paper.figures import fast_mode, figure_registry

    args.fast = bool(args.fast or fast_mode())  # --fast or TENDONROD_FAST=1
    registry = figure_registry()
    keys = list(registry)
    if args.only:
        wanted = [k.strip() for k in args.only.split(",") if k.strip()]
        unknown = [k for k in wanted if k not in registry]
        if unknown:
            print(
                f"tendonrod figures: error: --only: unknown figure(s) {', '.join(unknown)}; "
                f"known: {', '.join(keys)}",
                file=sys.stderr,
            )
            return EXIT_BAD_INPUT
        keys = wanted
    if args.list:
        for k in keys:
            print(f"{k}: {registry[k].caption}")
        return EXIT_OK
    from tendonrod.paper.figures import parse_formats, write_figure

    try:
        formats = parse_formats(args.format)
    except ValueError as exc:
        print(f"tendonrod figures: error: --format: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    matplotlib = optional_import("matplotlib", "the figures command")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.out, exist_ok=True)
    lines = [
        "# tendonrod: the paper's figures, regenerated",
        "",
        f"Command: `python -m tendonrod figures --out {args.out}{' --fast' if args.fast else ''}"
        f"{' --format ' + ','.join(formats) if formats != ('png',) else ''}`  ",
        "Paper: *Continuum Robot Deflection under External Loads and Prescribed Tendon "
        "Displacements*.  Nondimensional compliance sigma = 12 EI delta / (F L^3) (the "
        "paper's definition) unless a label says otherwise.",
        "",
    ]
    failed = []
    t_all = time.perf_counter()
    for k in keys:
        entry = registry[k]
        t0 = time.perf_counter()
        try:
            fig = entry.make(fast=args.fast)
        except Exception as exc:  # noqa: BLE001 - one figure's failure must not lose the others
            failed.append(k)
            print(f"  {k}: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
            if args.verbose:
                traceback.print_exc()
            lines.append(f"- **{k}** — FAILED ({type(exc).__name__}: {exc})")
            continue
        names = write_figure(fig, args.out, k, formats, dpi=args.dpi)
        plt.close(fig)
        dt = time.perf_counter() - t0
        print(f"  {', '.join(names)}  ({dt:.1f} s)")
        # the index shows the first format a browser draws (PNG or SVG), links the others
        shown = next((n for n in names if n.endswith((".png", ".svg"))), None)
        lines += [f"## {k}", ""]
        if shown:
            lines += [f"![{k}]({shown})", ""]
        others = [n for n in names if n != shown]
        if others:
            lines += ["Also: " + ", ".join(f"[{n}]({n})" for n in others), ""]
        lines += [entry.caption, ""]
        notes = getattr(fig, "_tendonrod_notes", None)
        if notes:
            lines += [notes, ""]
    lines.append(
        f"_{len(keys) - len(failed)} figures in {time.perf_counter() - t_all:.0f} s"
        f"{' (fast setting)' if args.fast else ''}._"
    )
    with open(os.path.join(args.out, "index.md"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    print(
        f"wrote {len(keys) - len(failed)} figures and index.md to {args.out}"
        + (f"; FAILED: {', '.join(failed)}" if failed else "")
    )
    return EXIT_OK if not failed else EXIT_NOT_CONVERGED
