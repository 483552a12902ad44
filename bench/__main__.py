"""python -m bench [names ...] [--quick] [--json PATH]: run the benchmark suite.

python -m bench                       # everything; JSON in bench/results/<time>.json
python -m bench vector scene          # some of them
python -m bench --quick --json /tmp/smoke.json   # tiny budgets: checks the plumbing
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from bench import suite


def main(argv: list[str] | None = None) -> int:
    """Parse the command line, run, and return 1 if a benchmark failed."""
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__.splitlines()[0])
    parser.add_argument(
        "names",
        nargs="*",
        metavar="name",
        help=f"benchmarks to run (default: all): {', '.join(suite.BENCHMARKS)}",
    )
    parser.add_argument("--quick", action="store_true", help="tiny budgets, for smoke tests")
    parser.add_argument(
        "--json",
        type=Path,
        default=None,
        help="where to write the results (default: bench/results/<time>.json)",
    )
    args = parser.parse_args(argv)
    try:
        report = suite.run(args.names or None, quick=args.quick, json_path=args.json)
    except KeyError as e:
        parser.error(str(e))
    return int(any(entry["error"] for entry in report["benchmarks"].values()))


if __name__ == "__main__":
    sys.exit(main())
