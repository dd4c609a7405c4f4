"""Reading the run's text files: ConfigError (file:line: problem + fix), read_text, and the
value parsers every file and option shares (true/false, one of a few words, seconds).

Every file the user gives (.ini, .dat, .yaml) must be UTF-8; a UTF-8 byte-order mark at its
start (Windows editors write one) is accepted and removed. Anything else is a ConfigError that
names the file, the line of the first bad byte and how to convert the file, never a traceback.
"""
import os
from typing import Any, Optional, Sequence

TRUE_WORDS = ('true', 'yes', 'on', '1')
FALSE_WORDS = ('false', 'no', 'off', '0')


class ConfigError(Exception):
    """A problem with the run's files or options, reported as `file:line: problem. fix`."""

    def __init__(self, message: str, path: Optional[str] = None, line: Optional[int] = None,
                 fix: Optional[str] = None) -> None:
        self.path, self.line, self.message, self.fix = path, line, message, fix
        where = ''
        if path:
            where = '%s:%s: ' % (path, line) if line else '%s: ' % path
        text = where + message
        if fix:
            text += '\n  fix: ' + fix
        super().__init__(text)


def read_text(path: str, what: str, fix_missing: Optional[str] = None) -> str:
    """The whole text of a UTF-8 file (a leading BOM removed); ConfigError on any problem."""
    if not os.path.exists(path):
        raise ConfigError('%s not found' % what, path,
                          fix=fix_missing or 'give an existing file (see docs/configuration.md) or create it')
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


def parse_bool(value: Any, path: Optional[str] = None, line: Optional[int] = None,
               key: Optional[str] = None) -> bool:
    word = str(value).strip().lower()
    if word in TRUE_WORDS:
        return True
    if word in FALSE_WORDS:
        return False
    raise ConfigError('%s"%s" is not true or false' % ('%s: ' % key if key else '', value),
                      path, line, fix='write true or false')


def choice(value: Any, choices: Sequence[str], what: str, path: Optional[str] = None,
           line: Optional[int] = None) -> str:
    word = str(value).strip().lower()
    if word not in choices:
        raise ConfigError('%s "%s" is not valid' % (what, value), path, line,
                          fix='use one of: ' + ', '.join(choices))
    return word


def positive_seconds(value: Any, what: str, path: Optional[str] = None, line: Optional[int] = None) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = -1.0
    if not number > 0 or number != number or number == float('inf'):
        raise ConfigError('%s "%s" is not a positive number of seconds' % (what, value), path, line,
                          fix='give a number of seconds greater than 0, e.g. 10')
    return number
