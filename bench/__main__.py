"""python -m bench [names ...] [--quick] [--json PATH] [--against SIDES]: run the suite.

python -m bench                       # everything; JSON in bench/results/<time>.json
python -m bench vector scene          # some of them
python -m bench vector --against envpool,gymnasium   # the vector comparison with others
python -m bench suite --against envpool,gymnasium    # the Control Suite's, with others
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
    parser.add_argument(
        "--against",
        default="",
        help="the vector and suite benchmarks also run these, comma-separated: envpool, gymnasium "
        "(envpool: pip install -e '.[bench]')",
    )
    args = parser.parse_args(argv)
    options = {"against": tuple(filter(None, args.against.split(",")))} if args.against else {}
    try:
        report = suite.run(args.names or None, args.quick, args.json, options)
    except (KeyError, ValueError) as e:
        parser.error(str(e))
    return int(any(entry["error"] for entry in report["benchmarks"].values()))


if __name__ == "__main__":
    sys.exit(main())
