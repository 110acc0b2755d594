# SPDX-License-Identifier: MIT
"""The one error type of the tools, and the one way a script ends on it.

A tool raises ToolError for anything a user can cause, with a message that names what is
wrong (the file, the line) and the exit status the tools promise: 2 for bad input or
options (BAD_INPUT, the default), 1 for a failure while running (FAILED). main() runs a
script's entry point and turns the error into `prog: message` on stderr and that status,
so that no user ever meets a traceback for their own mistake.
"""
import os
import sys

BAD_INPUT = 2
FAILED = 1


class ToolError(Exception):
    """Bad input (exit_code 2) or a failure while running (exit_code 1). prog, when set,
    replaces the script's name before the message (telemetry.py's `telemetry view`)."""

    def __init__(self, message, exit_code=BAD_INPUT, prog=None):
        super().__init__(message)
        self.exit_code = exit_code
        self.prog = prog


def prog_name():
    """The running script's name without .py, as its messages begin."""
    return os.path.splitext(os.path.basename(sys.argv[0]))[0]


def report(e, prog=None):
    """Prints a ToolError as every tool does; returns its exit status."""
    print("%s: %s" % (e.prog or prog or prog_name(), e), file=sys.stderr)
    return e.exit_code


def main(entry, *args, prog=None):
    """Runs entry(*args) and exits with what it returns (None is 0). A ToolError is
    `prog: message` and its status; running out of memory (the tools bound what input may
    ask for, so this is the last word) is a message and 1; Ctrl-C is 130 without a
    traceback; a reader that closed the pipe (| head) ends the output quietly."""
    try:
        code = entry(*args)
    except ToolError as e:
        code = report(e, prog)
    except MemoryError:
        print("%s: out of memory" % (prog or prog_name()), file=sys.stderr)
        code = FAILED
    except KeyboardInterrupt:
        code = 130
    except BrokenPipeError:
        # Python would complain again when it flushes stdout at exit.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        code = 0
    sys.exit(code or 0)
