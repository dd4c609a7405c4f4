"""Numbers as the page shows them: never 'None' (unknown is '-' or 'not measured')."""
import math
from typing import Any, Optional

from ..values import Spread


def num(v: Any, nd: int = 2, unit: str = '') -> str:
    if v is None:
        return '-'
    if isinstance(v, float):
        if math.isnan(v):
            return 'NaN'
        if math.isinf(v):
            return '-inf' if v < 0 else 'inf'
        text = '%.*f' % (nd, v)
    else:
        text = str(v)
    return text + ((' ' + unit) if unit else '')


def spread(s: Optional[Spread], nd: int = 2, mid: str = 'mean', unit: str = '') -> str:
    """'min 1.00, mean 2.00, max 3.00' or 'not measured'."""
    if s is None or (s.min is None and s.mid is None and s.max is None):
        return 'not measured'
    return 'min %s, %s %s, max %s%s' % (num(s.min, nd), mid, num(s.mid, nd), num(s.max, nd),
                                        (' ' + unit) if unit else '')
