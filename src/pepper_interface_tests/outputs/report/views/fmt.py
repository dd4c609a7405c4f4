"""Numbers as the page shows them: never 'None' (unknown is '-' or 'not measured')."""
import math


def num(v, nd=2, unit=''):
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


def spread(s, nd=2, mid='mean', unit=''):
    """'min 1.00, mean 2.00, max 3.00' or 'not measured'."""
    if s is None or (s.min is None and s.mid is None and s.max is None):
        return 'not measured'
    return 'min %s, %s %s, max %s%s' % (num(s.min, nd), mid, num(s.mid, nd), num(s.max, nd),
                                        (' ' + unit) if unit else '')
