"""``tendonrod bench ...``: the benchmark suites (tendonrod.bench.main's arguments)."""

from __future__ import annotations

import sys

from ._common import EXIT_BAD_INPUT


def _cmd_bench(args) -> int:
    return _bench(list(args.bench_args))


def _bench(argv) -> int:
    from tendonrod._extras import MissingExtraError

    try:
        from tendonrod import bench
    except MissingExtraError:
        raise
    except ImportError as exc:
        print(
            f"tendonrod bench: error: the benchmark suites are not available ({exc})",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    try:
        rc = bench.main(list(argv))
    except MissingExtraError:
        raise
    except SystemExit as exc:  # its argparse: --help (0), usage errors (2)
        return int(exc.code or 0)
    return int(rc or 0)
