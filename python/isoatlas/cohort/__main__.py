"""The isoatlas-cohort command (see isoatlas/cohort/__init__.py). Exit status: 0 when every subject
is done; otherwise the number of failed subjects (at most 100); 2 for a bad manifest, config or option
(one line, before any subject runs); 130 when stopped by Ctrl-C (the next run goes on from there)."""
import argparse
import sys

from .manifest import STAGES, InputError
from .runner import run_cohort


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line and exit 2, as the isoatlas command does
        print(f"isoatlas-cohort: error: {message}", file=sys.stderr)
        sys.exit(2)


def main(argv=None):
    parser = _Parser(prog="isoatlas-cohort", description="Segment, mesh and model every scan of a manifest on a Dask cluster.")
    parser.add_argument("manifest", help="CSV: id, volume, seeds (x,y,z,r;... world mm), optional target, width, alpha, edits, backend")
    parser.add_argument("--out", required=True, help="folder for DIR/ID/ products, cohort.csv and index.html")
    parser.add_argument("--workers", type=int, help="local worker processes, one thread each (default: the cores)")
    parser.add_argument("--scheduler", help="run on this existing Dask scheduler (tcp://host:8786) instead of a local cluster")
    parser.add_argument("--stages", default=",".join(STAGES), help=f"stages to run (default {','.join(STAGES)})")
    parser.add_argument("--config", help="JSON defaults for every subject (docs/cohort.md lists the settings)")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress or log lines")
    args = parser.parse_args(argv)
    try:
        rows, stopped = run_cohort(args.manifest, args.out, workers=args.workers, scheduler=args.scheduler, stages=args.stages,
                                   config=args.config, quiet=args.quiet)
    except InputError as e:
        print(f"isoatlas-cohort: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("isoatlas-cohort: stopped by Ctrl-C; run the same command again to go on", file=sys.stderr)
        return 130
    if stopped:
        return 130
    failed = sum(r["status"] != "done" for r in rows)
    if not args.quiet:
        print(f"isoatlas-cohort: {len(rows) - failed} of {len(rows)} subjects done, {failed} failed: {args.out}/cohort.csv, "
              f"{args.out}/index.html", file=sys.stderr)
    return min(failed, 100)


if __name__ == "__main__":
    sys.exit(main())
