"""What the subcommands share: the exit codes, the scene file read, --plot's check,
--sliding's override."""

from __future__ import annotations

import sys

EXIT_OK = 0
EXIT_NOT_CONVERGED = 1
EXIT_BAD_INPUT = 2
EXIT_MISSING_DEPENDENCY = 3
EXIT_CODES = (
    "Exit codes: 0 ok; 1 did not converge / a figure failed; 2 bad input; 3 an optional "
    "dependency is not installed (the message names the extra to install)."
)


def _require_plot(args) -> None:
    """With --plot, matplotlib must be there before the solve starts (else exit 3)."""
    if args.plot:
        from tendonrod._extras import optional_import

        optional_import("matplotlib.pyplot", "--plot")


def _with_sliding(spec, sliding):
    """``spec`` with every tendon's sliding direction set to ``sliding`` ("in" / "out"),
    or unchanged when it is None (the command line's --sliding over the file's)."""
    import dataclasses

    if sliding is None:
        return spec
    return dataclasses.replace(spec, scene=dataclasses.replace(spec.scene, sliding=sliding))


def _read_spec(command: str, path: str, sliding):
    """The scene file at ``path`` with the command line's ``--sliding`` over its own, or
    None after one error line on stderr naming the command (the caller exits 2)."""
    from tendonrod.scenefile import SceneFileError, load_scene

    try:
        spec = load_scene(path)
    except SceneFileError as exc:
        print(f"tendonrod {command}: error: {exc}", file=sys.stderr)
        return None
    except OSError as exc:
        print(
            f"tendonrod {command}: error: cannot read scene file {path!r}: {exc.strerror or exc}",
            file=sys.stderr,
        )
        return None
    return _with_sliding(spec, sliding)
