# SPDX-License-Identifier: MIT
"""One command line over a family of the package's modules: `tools/NAME.py COMMAND ARGS...`
runs the main(argv) of the module COMMAND names as if it were a program of its own."""
import importlib

from . import errors


def run(doc, commands, argv):
    """commands: {COMMAND: a module of slamtools, by its full name}; argv as sys.argv. The
    module is imported only when its command runs, so that one command does not need what
    another needs (python3-unicorn), and its messages begin with `prog COMMAND:`."""
    prog = errors.prog_name()
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(doc.strip())
        return 0 if len(argv) >= 2 else errors.BAD_INPUT
    name = argv[1]
    if name not in commands:
        raise errors.ToolError("unknown command %r (%s)" % (name, ", ".join(commands)))
    label = "%s %s" % (prog, name)
    try:
        return importlib.import_module(commands[name]).main([label] + argv[2:])
    except errors.ToolError as e:
        e.prog = e.prog or label
        raise


def take_value(args, flag, what, default=None):
    """Removes `flag VALUE` from the list args and returns VALUE (default when the flag is
    not given); a flag without its value is bad input, `flag needs WHAT`."""
    if flag not in args:
        return default
    i = args.index(flag)
    if i + 1 >= len(args):
        raise errors.ToolError("%s needs %s" % (flag, what))
    value = args[i + 1]
    del args[i:i + 2]
    return value
