"""`python -m composer`: the command-line tool (see `composer.cli`)."""

from composer.cli import main

raise SystemExit(main())
