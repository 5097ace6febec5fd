import os
import sys


def _interrupted():
    """One line and status 130 at once: the interpreter's teardown (numba, llvmlite) takes seconds more."""
    print("interrupted", file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(130)


try:
    from physics.cli import main  # inside: Ctrl-C while numba loads its cache is an interrupt, not a traceback

    sys.exit(main())
except BrokenPipeError:  # output piped into `head` and closed early: not an error worth a traceback
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    sys.exit(0)
except KeyboardInterrupt:
    _interrupted()
except SystemError as exc:  # Ctrl-C landing while a compiled call returned: numba reports it this way
    if not isinstance(exc.__context__, KeyboardInterrupt):
        raise
    _interrupted()
