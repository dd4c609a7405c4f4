"""Each family's values: the frozen dataclass its check hands over (one leaf module per family).

A family's values are what its check measured (its "values" in the JSON) and what the report
plots (fields made with codec.series: its "series" in the JSON). They are written to the JSON
and read back from it by the generic rules of codec.py (no code per family), rendered by the
report's view of the family, and registered on the family's row (sensors/families.py
`Family.values`). The modules here import nothing but codec.py and this module's shared types,
so every stage may import them.
"""
from dataclasses import dataclass
from typing import Optional, Tuple

from ...codec import nullable

# one point of a time series: (seconds into the window, value or None when not finite)
Point = Tuple[float, Optional[float]]


@dataclass(frozen=True)
class Spread:
    """min / mean / max of a quantity (base.Acc); each None when no finite value was seen."""
    min: Optional[float] = nullable()
    mean: Optional[float] = nullable()
    max: Optional[float] = nullable()
