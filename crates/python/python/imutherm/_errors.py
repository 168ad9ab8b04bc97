"""The file of an engine's ``OSError``.

The engine's messages already name settings by the keyword arguments of
:func:`imutherm.read` and its siblings (``rate=``, ``units entry``,
``topic=``, ...): the extension module names them so when it loads
(crates/python/src/naming.rs). What is left to do here is to set the file
of an ``OSError`` on its ``filename``."""

import functools
import os


def names_the_file(path_arg=None):
    """Decorates a function calling the engine: an ``OSError`` left without
    a ``filename`` gets the file it names among those of the argument
    ``path_arg`` (``(position, name)``: a path, a recording or a list of
    them)."""
    def wrap(f):
        @functools.wraps(f)
        def call(*args, **kwargs):
            try:
                return f(*args, **kwargs)
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
