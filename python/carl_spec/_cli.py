"""The `carl-spec` command that `pip install carl-spec` puts on PATH: the Rust command line, run
in this process (the same program as the `carl-spec` binary that `cargo install` builds)."""

from __future__ import annotations

import signal
import sys


def main() -> None:
    # A command line ends on Ctrl-C; Python's own SIGINT handler would wait for the native call.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    from . import _core

    sys.exit(_core.cli_main(["carl-spec", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
