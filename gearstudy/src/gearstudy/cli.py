"""Command line: ``gearstudy sweep STUDY.toml`` and ``gearstudy plot RESULTS``."""

from __future__ import annotations

import argparse
import sys

from .units import StudyError


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="gearstudy", description=__doc__)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("sweep", help="run the points of a study file not yet in its results")
    s.add_argument("study", help="study file (TOML), see docs/studies.md")
    s.add_argument("--out", help="results directory (default out/studies/<study name>)")
    s.add_argument("--fmu", help="the .fmu (default: [study] fmu, else target/fmu/GearedRotor.fmu)")
    s.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://host:8786")
    s.add_argument("--workers", type=int, help="local worker processes (default: one per core)")
    s.add_argument("--serial", action="store_true", help="run in this process, without Dask")
    s.add_argument("--max-points", type=int, help="run at most this many new points now")
    s.add_argument("--overwrite", action="store_true",
                   help="delete the rows already in the results directory first")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")
    s.add_argument("--plot", action="store_true", help="draw the maps afterwards")
    q = sub.add_parser("plot", help="draw the maps of a results directory")
    q.add_argument("results", help="results directory written by sweep")
    q.add_argument("--out", help="directory for the PNGs (default: the results directory)")
    q.add_argument("--x", help="first axis (default omega1 if varied)")
    q.add_argument("--y", help="second axis of the efficiency map (default T_load if varied)")
    t = sub.add_parser("table", help="print a column over two varied variables as text")
    t.add_argument("results", help="results directory written by sweep")
    t.add_argument("column", nargs="?", default="efficiency", help="default: efficiency")
    t.add_argument("--x", help="columns of the table (default omega1 if varied)")
    t.add_argument("--y", help="rows of the table (default T_load if varied)")
    t.add_argument("--format", default="{:.6g}", help="Python format of a value (default {:.6g})")
    a = p.parse_args(argv)
    if a.cmd == "sweep" and a.workers is not None and a.workers < 1:
        p.error(f"--workers {a.workers}: give at least 1 worker process")
    if a.cmd == "sweep" and a.max_points is not None and a.max_points < 0:
        p.error(f"--max-points {a.max_points}: give a number >= 0")
    from . import plot, sweep

    try:
        if a.cmd == "sweep":
            summary = sweep(
                a.study,
                out=a.out,
                fmu=a.fmu,
                scheduler=a.scheduler,
                workers=a.workers,
                serial=a.serial,
                max_points=a.max_points,
                overwrite=a.overwrite,
                progress=False if a.no_progress else None,
            )
            print(summary)
            if a.plot:
                for f in plot(summary.out):
                    print(f"wrote {f}")
            return 1 if summary.failed and summary.failed == summary.ran else 0
        if a.cmd == "table":
            from .tables import format_table

            print(format_table(a.results, a.column, x=a.x, y=a.y, fmt=a.format))
            return 0
        for f in plot(a.results, out_dir=a.out, x=a.x, y=a.y):
            print(f"wrote {f}")
        return 0
    except StudyError as e:
        print(f"gearstudy: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("gearstudy: interrupted; a rerun continues with the points not yet written",
              file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
