"""The building blocks a sensor view returns; the template turns them into HTML.

Views never write HTML: they return these plain objects, and templates/report.html.j2 renders
each one with autoescaping on, so a hostile frame id or reason is shown as text, never run.
Inline content (`Para.parts`, table cells, KV values) is a string, a `Span`, or a list of both.
"""
from dataclasses import dataclass, field
from typing import Any, List, Optional, Union


@dataclass
class Span:
    """Inline text: optionally bold, coloured (cls: 'fail-text', 'warn-text', 'muted') or a link."""
    text: Any
    cls: str = ''
    strong: bool = False
    href: Optional[str] = None
    kind: str = 'span'


@dataclass
class Heading:
    text: str
    kind: str = 'h3'


@dataclass
class Para:
    parts: Any
    cls: str = ''
    kind: str = 'p'


@dataclass
class Table:
    head: List[str]
    rows: List[List[Any]]
    numeric: List[int] = field(default_factory=list)   # right-aligned column indexes
    kind: str = 'table'


@dataclass
class KV:
    rows: List[Any]            # [(key, value)]
    kind: str = 'kv'


@dataclass
class Image:
    src: str                   # a data: URI (plots, stills)
    alt: str
    cls: str = 'plot'
    href: Optional[str] = None
    caption: Any = None
    kind: str = 'img'


@dataclass
class Media:
    tag: str                   # 'video' or 'audio'
    src: str                   # data: URI or a relative link to the file next to the report
    caption: Any
    kind: str = 'media'


@dataclass
class Row:
    items: List[Any]
    kind: str = 'row'


@dataclass
class Details:
    summary: str
    blocks: List[Any]
    kind: str = 'details'


# what a view returns, one item a block of the section
Block = Union[Heading, Para, Table, KV, Image, Media, Row, Details]


def span_list(*parts: Any) -> List[Any]:
    return [p for p in parts if p not in (None, '')]
