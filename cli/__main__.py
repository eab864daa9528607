"""The `softarm` console script (and `python -m softarm_cli`): stop requests are armed before the command line's
imports, which take a second or more, so that Ctrl-C at any moment says "interrupted" in one line and exits 130."""

import sys

from softarm_cli.stopping import ignore_requests, interrupt_as_ctrl_c


def main() -> int:
    interrupt_as_ctrl_c()
    try:
        from softarm_cli.main import main as run

        return run()
    except KeyboardInterrupt:  # a request while the command line loads, before it can answer one itself
        ignore_requests()
        print("interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
