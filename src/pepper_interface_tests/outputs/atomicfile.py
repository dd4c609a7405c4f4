"""One way to write a results file whole: `write_atomic(path, text)`; and one way to say that a
results file could not be written: `write_error(run, path, error)`.

The text goes to a temporary file in the same folder (so the rename cannot cross file systems),
is flushed and fsync'ed, gets the permissions an ordinary `open(path, 'w')` would give (0666
minus the umask: results are meant to be shared; mkstemp alone would leave 0600), and is renamed
over `path`. A reader sees the old file or the new one, never half of one, also after a power
cut. On any error the temporary file is removed and OSError is raised naming `path` (not the
temporary name), so the caller's message points at the file the user knows.
"""
import os
import sys
import tempfile

from .. import results


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomic(path: str, text: str) -> None:
    """Replace `path` with `text` (UTF-8; unencodable characters backslash-escaped)."""
    folder = os.path.dirname(path) or '.'
    fd, tmp = tempfile.mkstemp(prefix='.tmp-%s.' % os.path.basename(path), dir=folder)
    try:
        with os.fdopen(fd, 'w', encoding='utf-8', errors='backslashreplace') as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException as e:     # also KeyboardInterrupt: never leave the temporary file
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(e, OSError):
            raise OSError(e.errno, e.strerror, path) from e
        raise


def write_error(run: results.RunResult, path: str, error: Exception) -> None:
    """Record and name a results file that could not be written."""
    text = '%s: %s' % (path, getattr(error, 'strerror', None) or error)
    if text not in run.write_errors:
        run.write_errors.append(text)
        sys.stderr.write('sensorTest: error: cannot write %s (free some space or choose another '
                         '--output-dir)\n' % text)
        sys.stderr.flush()
