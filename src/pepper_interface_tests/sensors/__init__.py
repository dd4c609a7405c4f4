"""One module per sensor family; the family registry (families.py) says which Check judges a
sensor and what the family is (its traits)."""
from typing import TYPE_CHECKING, Type

from .families import family

if TYPE_CHECKING:
    from .base import Check


def check_class(name: str) -> Type['Check']:
    """The Check class of family `name`."""
    return family(name).check_class()
