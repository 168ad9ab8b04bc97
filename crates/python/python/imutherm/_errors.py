"""The engine's messages in Python's words.

The Rust library words its refusals for the command line, naming flags
(``--rate``, ``--unit``, ``--topic``, ...). A Python caller passed keyword
arguments, so the messages are rewritten to name those, and the file of an
``OSError`` is set on its ``filename``."""

import functools
import os
import re

from . import _imutherm

# Flag with its value -> the keyword argument with the value, as Python
# spells it. The flag's value ends at a colon, a semicolon or the line's end
# (crates/analysis/src/reading.rs, recording_options; crates/robotlogs/src/
# assemble.rs, choose and choose_temp; crates/robotlogs/src/lib.rs, read).
_FLAG_VALUE = [
    (re.compile(r"--rate (\S+?):"), r"rate=\1:"),
    (re.compile(r"--unit (\S+?):"), r"units entry '\1':"),
    (re.compile(r"--topic (\S+?)( in the log|:|;|$)"), r"topic='\1'\2"),
    (re.compile(r"--temp-topic (\S+?)( in the log|:|;|$)"), r"temp_topic='\1'\2"),
    (re.compile(r"--instance (\d+|N\b)"), r"instance=\1"),
    (re.compile(r"--instance all"), r"instance='all'"),
    # The temperature compensation (crates/analysis/src/error.rs and
    # compensation.rs; crates/thermal/src/firmware/mod.rs and px4.rs).
    (re.compile(r"`imutherm tcal fit --for (\w+)`"), r"`imutherm.tcal_fit(..., firmware='\1')`"),
    (re.compile(r"--order (\d+) or auto"), r"order=\1 or 'auto'"),
    (re.compile(r"--order (\d+)"), r"order=\1"),
    (re.compile(r"--for (\w+)"), r"firmware='\1'"),
    (re.compile(r"--bin-width (\S+?):"), r"bin_width=\1:"),
    (re.compile(r"--export (\w+)"), r"export='\1'"),
    (re.compile(r"without --rate-term"), r"with rate_term=False"),
]
_FLAG = [("--allow-partial", "allow_partial"), ("--temp-topic", "temp_topic"), ("--topic", "topic"), ("--instance", "instance"),
         ("--rate-term", "rate_term"), ("--rate", "rate"), ("--unit", "units"),
         ("--device-id", "device_id"), ("--order", "order"), ("--for", "firmware")]


def python_words(message):
    """``message`` with each command-line flag named as the keyword argument
    of :func:`imutherm.read` and its siblings."""
    for pattern, repl in _FLAG_VALUE:
        message = pattern.sub(repl, message)
    for flag, keyword in _FLAG:
        message = message.replace(flag, keyword)
    return message


def in_python_words(path_arg=None):
    """Decorates a function calling the engine: its ``ImuthermError``
    messages name keyword arguments, and an ``OSError`` left without a
    ``filename`` gets the file it names among those of the argument
    ``path_arg`` (``(position, name)``: a path, a recording or a list of
    them)."""
    def wrap(f):
        @functools.wraps(f)
        def call(*args, **kwargs):
            try:
                return f(*args, **kwargs)
            except _imutherm.ImuthermError as e:
                raise _imutherm.ImuthermError(python_words(str(e))) from None
            except OSError as e:
                if e.filename is None and path_arg is not None:
                    position, name = path_arg
                    given = kwargs[name] if name in kwargs else (
                        args[position] if len(args) > position else None)
                    e.filename = _file_named(given, str(e))
                raise
        return call
    return wrap


def _file_named(given, message):
    """The path among ``given`` that ``message`` names (the only one when a
    single path was given), or None."""
    if given is None:
        return None
    if isinstance(given, (str, bytes, os.PathLike)) or hasattr(given, "channels"):
        given = [given]
    paths = []
    for g in given:
        g = getattr(g, "file", g)
        try:
            paths.append(os.fspath(g))
        except TypeError:
            continue
    named = [p for p in paths if isinstance(p, str) and p in message]
    if named:
        return max(named, key=len)
    return paths[0] if len(paths) == 1 else None
