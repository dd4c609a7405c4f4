"""Reading the run's text files: ConfigError (file:line: problem + fix) and read_text.

Every file the user gives (.ini, .dat, .yaml) must be UTF-8; a UTF-8 byte-order mark at its
start (Windows editors write one) is accepted and removed. Anything else is a ConfigError that
names the file, the line of the first bad byte and how to convert the file, never a traceback.
"""
import os


class ConfigError(Exception):
    """A problem with the run's files or options, reported as `file:line: problem. fix`."""

    def __init__(self, message, path=None, line=None, fix=None):
        self.path, self.line, self.message, self.fix = path, line, message, fix
        where = ''
        if path:
            where = '%s:%s: ' % (path, line) if line else '%s: ' % path
        text = where + message
        if fix:
            text += '\n  fix: ' + fix
        super().__init__(text)


def read_text(path, what, fix_missing=None):
    """The whole text of a UTF-8 file (a leading BOM removed); ConfigError on any problem."""
    if not os.path.exists(path):
        raise ConfigError('%s not found' % what, path,
                          fix=fix_missing or 'give an existing file (see README, "Files") or create it')
    try:
        with open(path, 'rb') as f:
            raw = f.read()
    except OSError as e:
        raise ConfigError('cannot read %s: %s' % (what, e.strerror or e), path,
                          fix='check the file permissions and that it is a text file') from None
    try:
        return raw.decode('utf-8-sig')
    except UnicodeDecodeError as e:
        line = raw.count(b'\n', 0, e.start) + 1
        raise ConfigError('cannot read %s: not UTF-8 text (byte 0x%02x at offset %d)'
                          % (what, raw[e.start], e.start), path, line,
                          fix='save it as UTF-8 (e.g. "iconv -f latin1 -t utf-8 %s > fixed && mv fixed %s"),'
                              ' or check that it is the right file' % (os.path.basename(path),
                                                                      os.path.basename(path))) from None
