"""Typed values <-> JSON, for every family's values dataclass (one generic rule, no per-family code).

`to_json(obj)` writes a dataclass as a JSON object of its fields (nested dataclasses, lists,
tuples and dicts alike), an Enum as its value, a float NaN as null. `from_json(cls, data)` reads
it back by the fields' types: null -> NaN for a `float` (not `Optional[float]`) field or list
item, an Enum from its value, a dict's int keys from their JSON text, a missing key -> the
field's default. Field metadata (made by the helpers below) says how a field is written:
- `optional()`: written only when not None (a value the check measures only in some runs);
- `optional_number()`: the same for a float whose NaN says "there, but unknown": NaN is written
  as null and a null read back as NaN (not None: None is not written);
- `nullable()`: written as null when None (None says something: e.g. "no microphone listened");
- `series(key)`: a time series or plot data: written under the sensor's "series" key, not its
  "values" (`split` / `join`), under the JSON name `key` when given (`series_optional(key)`:
  the same, None and not written until there is something to plot).
A field of another kind (a plain default) is always written. `from_json` raises `CodecError`
naming the field when `data` does not fit the type (with `strict`, also for an unknown key:
what a check hands over must match its dataclass; a file read back may have more).
"""
import dataclasses
import math
from enum import Enum
from typing import Any, Dict, Optional, Tuple, Type, TypeVar, Union, get_args, get_origin, get_type_hints

T = TypeVar('T')
OMIT, SERIES, NAME, NAN = 'omit_none', 'series', 'json_name', 'null_is_nan'


class CodecError(ValueError):
    """Data that does not fit a values dataclass (names the field)."""


def optional(**kw: Any) -> Any:
    """A field written only when it is not None (default None)."""
    return dataclasses.field(default=None, metadata={OMIT: True}, **kw)


def optional_number() -> Any:
    """A float field written only when it is not None (default None); NaN written as null and
    read back as NaN."""
    return dataclasses.field(default=None, metadata={OMIT: True, NAN: True})


def nullable() -> Any:
    """A field written as null when it is None (default None)."""
    return dataclasses.field(default=None)


def series(key: Optional[str] = None) -> Any:
    """A list field written under the sensor's "series" key (as `key` when given)."""
    return dataclasses.field(default_factory=list, metadata={SERIES: True, NAME: key})


def series_optional(key: Optional[str] = None) -> Any:
    """A `series` field that is None (and not written) until the check has something to plot."""
    return dataclasses.field(default=None, metadata={SERIES: True, NAME: key, OMIT: True})


def json_name(f: 'dataclasses.Field') -> str:
    return f.metadata.get(NAME) or f.name


def to_json(obj: Any) -> Any:
    """`obj` (a dataclass, Enum, list, tuple, dict or plain value) as JSON-ready data."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {json_name(f): to_json(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                if not (f.metadata.get(OMIT) and getattr(obj, f.name) is None)}
    if isinstance(obj, Enum):
        return obj.value
    if isinstance(obj, float) and math.isnan(obj):
        return None
    if isinstance(obj, (list, tuple)):
        return [to_json(v) for v in obj]
    if isinstance(obj, dict):
        return {k: to_json(v) for k, v in obj.items()}
    return obj


def split(obj: Any) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """A family's values as (its "values" object, its "series" object) in a sensor's JSON."""
    values: Dict[str, Any] = {}
    plots: Dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if f.metadata.get(OMIT) and v is None:
            continue
        (plots if f.metadata.get(SERIES) else values)[json_name(f)] = to_json(v)
    return values, plots


def join(cls: Type[T], values: Any, plots: Any, strict: bool = False) -> T:  # cls: a dataclass
    """`split` read back: the family's values from a sensor's "values" and "series" objects (a
    value and a series may share a JSON name: the sonar's range_m)."""
    values = values if isinstance(values, dict) else {}
    plots = plots if isinstance(plots, dict) else {}
    if strict:
        for src, is_series in ((values, False), (plots, True)):
            known = {json_name(f) for f in dataclasses.fields(cls)  # type: ignore[arg-type]
                     if bool(f.metadata.get(SERIES)) == is_series}
            unknown = [k for k in src if k not in known]
            if unknown:
                raise CodecError('%s has no %s %s' % (cls.__name__, 'series' if is_series else 'field',
                                                       ', '.join(map(str, unknown))))
    hints = get_type_hints(cls)
    kwargs = {}
    for f in dataclasses.fields(cls):  # type: ignore[arg-type]
        src = plots if f.metadata.get(SERIES) else values
        if json_name(f) in src:
            kwargs[f.name] = _field_value(f, hints[f.name], src[json_name(f)], strict,
                                          '%s.%s' % (cls.__name__, json_name(f)))
    try:
        return cls(**kwargs)
    except TypeError as e:        # a required field missing
        raise CodecError('%s: %s' % (cls.__name__, e)) from None


def from_json(tp: Any, data: Any, strict: bool = False, where: str = '') -> Any:
    """`data` (as `to_json` wrote it) read back as type `tp`."""
    where = where or getattr(tp, '__name__', str(tp))
    if tp is Any:
        return data
    origin, args = get_origin(tp), get_args(tp)
    if origin is Union:
        if data is None and type(None) in args:
            return None
        inner = [a for a in args if a is not type(None)]
        for i, a in enumerate(inner):
            try:
                return from_json(a, data, strict, where)
            except CodecError:
                if i == len(inner) - 1:
                    raise
    if dataclasses.is_dataclass(tp):
        return _dataclass(tp, data, strict, where)
    if isinstance(tp, type) and issubclass(tp, Enum):
        try:
            return tp(data)
        except ValueError:
            raise CodecError('%s: %r is not one of %s' % (where, data, [e.value for e in tp])) from None
    if origin in (list, tuple):
        if not isinstance(data, (list, tuple)):
            raise CodecError('%s: expected a list, got %r' % (where, data))
        if origin is tuple and args and args[-1] is not Ellipsis:
            if len(args) != len(data):
                raise CodecError('%s: expected %d items, got %d' % (where, len(args), len(data)))
            return tuple(from_json(a, v, strict, where) for a, v in zip(args, data))
        item = args[0] if args else Any
        out = [from_json(item, v, strict, '%s[%d]' % (where, i)) for i, v in enumerate(data)]
        return tuple(out) if origin is tuple else out
    if origin is dict:
        if not isinstance(data, dict):
            raise CodecError('%s: expected an object, got %r' % (where, data))
        key_t, val_t = args if args else (Any, Any)
        return {_key(key_t, k, where): from_json(val_t, v, strict, '%s.%s' % (where, k)) for k, v in data.items()}
    return _plain(tp, data, where)


def _field_value(f: 'dataclasses.Field', tp: Any, data: Any, strict: bool, where: str) -> Any:
    if data is None and f.metadata.get(NAN):
        return math.nan
    return from_json(tp, data, strict, where)


def _dataclass(cls, data, strict, where):
    if not isinstance(data, dict):
        raise CodecError('%s: expected an object, got %r' % (where, data))
    hints = get_type_hints(cls)
    fields = {json_name(f): f for f in dataclasses.fields(cls)}
    if strict:
        unknown = [k for k in data if k not in fields]
        if unknown:
            raise CodecError('%s has no field %s' % (where, ', '.join(map(str, unknown))))
    kwargs = {f.name: _field_value(f, hints[f.name], data[key], strict, '%s.%s' % (where, key))
              for key, f in fields.items() if key in data}
    try:
        return cls(**kwargs)
    except TypeError as e:        # a required field missing
        raise CodecError('%s: %s' % (where, e)) from None


def _key(tp, k, where):
    if tp is int and isinstance(k, str):
        try:
            return int(k)
        except ValueError:
            raise CodecError('%s: key %r is not a whole number' % (where, k)) from None
    return k


def _plain(tp, data, where):
    if tp is float:
        if data is None:
            return math.nan
        if isinstance(data, (int, float)) and not isinstance(data, bool):
            return data          # an int stays one: written back as it was read
    elif tp is bool:
        if isinstance(data, bool):
            return data
    elif tp is int:
        if isinstance(data, int) and not isinstance(data, bool):
            return data
    elif tp is str:
        if isinstance(data, str):
            return data
    elif tp is type(None):
        if data is None:
            return None
    else:
        return data
    raise CodecError('%s: expected %s, got %r' % (where, getattr(tp, '__name__', tp), data))
