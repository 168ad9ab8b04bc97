"""Writing outputs so that a reader never sees half of one: a scratch file
beside the target, renamed over it when complete (a rename within one
folder is atomic on POSIX and Windows)."""

import os
import secrets

SCRATCH = ".partial"


def write_atomic(path, data):
    """Writes ``data`` (str or bytes) to ``path`` through a scratch file."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    # Created as open() would create the file (0666 less the umask), which
    # mkstemp's 0600 is not: the outputs are for the whole line to read.
    scratch = os.path.join(folder, f"{os.path.basename(path)}.{os.getpid()}."
                                   f"{secrets.token_hex(4)}{SCRATCH}")
    fd = os.open(scratch, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data.encode("utf-8") if isinstance(data, str) else data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(scratch, path)
    except BaseException:
        try:
            os.unlink(scratch)
        except OSError:
            pass
        raise


def remove_scratch(folder):
    """Removes scratch files a killed worker left in ``folder``; returns
    how many."""
    if not os.path.isdir(folder):
        return 0
    gone = 0
    for name in os.listdir(folder):
        if name.endswith(SCRATCH):
            os.unlink(os.path.join(folder, name))
            gone += 1
    return gone
