"""Numbers and text as the page shows them: never 'None' (unknown is '-' or 'not measured')."""
import math
import re
from typing import Any

from ....results import printable


def num(v: Any, nd: int = 2, unit: str = '') -> str:
    if v is None:
        return '-'
    if isinstance(v, float):
        if math.isnan(v):
            return 'NaN'
        if math.isinf(v):
            return '-inf' if v < 0 else 'inf'
        text = '%.*f' % (nd, v)
        if text.startswith('-') and not text.strip('-0.'):
            text = text[1:]         # -0.0001 to 3 places: 0.000, not -0.000
    else:
        text = str(v)
    return text + ((' ' + unit) if unit else '')


def spread(s: Any, nd: int = 2, mid: str = 'mean', unit: str = '') -> str:
    """'min 1.00, mean 2.00, max 3.00' or 'not measured'; `s` has min, max and `mid` (a family's
    Spread, or its MedianSpread with mid='median')."""
    centre = getattr(s, mid, None)
    if s is None or (s.min is None and centre is None and s.max is None):
        return 'not measured'
    return 'min %s, %s %s, max %s%s' % (num(s.min, nd), mid, num(centre, nd), num(s.max, nd),
                                        (' ' + unit) if unit else '')


_NONE = re.compile(r'(?<![\w+/=])None(?![\w+/=])')


def clean(text: Any) -> str:
    """Text for the page: None -> '-', Python's 'None' inside a message -> '-', control
    characters shown as \\xNN instead of breaking the layout."""
    if text is None:
        return '-'
    return printable(_NONE.sub('-', str(text)), one_line=False)
