"""Where ros2/launch types a value as YAML, and how: ``launch/utilities/type_utils.py``
(``coerce_to_type``, ``get_typed_value``, ``is_instance_of_valid_type``,
``normalize_typed_substitution``, ``perform_typed_substitution``),
``launch/frontend/type_utils.py`` (``get_data_type_from_identifier``),
``launch/frontend/parse_substitution.py`` (``parse_if_substitutions``) and launch_ros'
``evaluate_parameter_dict`` (``<set_parameter>``), mirrored with their messages.

The places launch types a value, and what this module gives them:

- an XML attribute read with a data type (``get_attr(name, data_type=..., can_be_str=True)``):
  :func:`coerce` with ``can_be_str=True`` (YAML that fails stays a string);
- a ``<param value>`` of a node: typed at parse time as above, then ``ParameterValue``
  normalises it (:func:`normalize_param`: a scalar must be of the ``type`` given; a list's items
  of one type), and when the node is executed a value with substitutions is typed once
  substituted with ``can_be_str=False`` (:func:`perform_typed`): ``value="$(var v)"`` with ``v``
  ``[`` fails there (``yaml.safe_load() failed``), and so do a map, a mixed list, ``null``;
- a ``<set_parameter value>``: the substituted text through ``yaml.safe_load`` and launch_ros'
  allowed types (:func:`evaluate_set_parameter`);
- ``<arg>`` defaults and values, ``<let>`` values, node ``args``: never typed (strings).

Errors are raised as launch raises them: ``ValueError`` / ``TypeError`` with launch's message.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ...base import yamlsafe

_SCALARS = (int, float, bool, str)


@dataclass(frozen=True)
class ListOf:
    """launch's ``typing.List[T]`` data type."""
    item: type

    def __str__(self) -> str:
        return f"typing.List[{self.item.__name__}]"


# launch.frontend.type_utils.get_data_type_from_identifier ('yaml': no type, YAML rules)
TYPE_IDS: dict[str, Any] = {"str": str, "bool": bool, "float": float, "int": int,
                            "list_of_str": ListOf(str), "list_of_bool": ListOf(bool),
                            "list_of_float": ListOf(float), "list_of_int": ListOf(int), "yaml": None}


def data_type_of(identifier: Any):
    """The data type of a ``type=`` identifier; ValueError (launch's message) for another."""
    if not isinstance(identifier, str) or identifier not in TYPE_IDS:
        raise ValueError(f"Got invalid type identifier '{identifier}'")
    return TYPE_IDS[identifier]


def type_text(data_type) -> str:
    """``str(data_type)`` as launch prints it in its messages."""
    if data_type is None:
        return "None"
    if isinstance(data_type, ListOf):
        return str(data_type)
    if isinstance(data_type, tuple):
        return "(" + ", ".join(type_text(t) for t in data_type) + ")"
    return f"<class '{data_type.__name__}'>"


def valid_value(value: Any, can_be_str: bool = False) -> bool:
    """``is_instance_of_valid_type``: a scalar, or a list of one scalar type (strings mixed in
    when ``can_be_str``); an empty list is valid."""
    if isinstance(value, list):
        if not value:
            return True
        member = next((type(x) for x in value if type(x) is not str), str)
        if member not in _SCALARS:
            return False
        ok = (member, str) if can_be_str else member
        return all(isinstance(x, ok) for x in value)
    return isinstance(value, _SCALARS)


def is_instance_of(value: Any, data_type, can_be_str: bool = False) -> bool:
    """``is_instance_of``."""
    if data_type is None:
        return valid_value(value, can_be_str)
    item, is_list = (data_type.item, True) if isinstance(data_type, ListOf) else (data_type, False)
    ok = (str, item) if can_be_str else item
    if not is_list:
        return isinstance(value, ok)
    return isinstance(value, list) and all(isinstance(x, ok) for x in value)


def coerce(value: str, data_type=None, can_be_str: bool = False) -> Any:
    """``coerce_to_type(value, data_type, can_be_str=...)``: the typed value, or ValueError
    with launch's message."""
    def as_yaml(v: str, error_msg: str):
        if not v:
            return v
        try:
            out = yamlsafe.safe_load(v)
        except yamlsafe.YamlTooBig:
            raise
        except Exception as err:
            if can_be_str:
                return v
            raise ValueError(f"{error_msg}: yaml.safe_load() failed\n{err}") from None
        if not valid_value(out, can_be_str):
            raise ValueError(f"{error_msg}: output type is not allowed, got {type(out)}")
        return out

    if data_type is None:
        return as_yaml(value, f"Failed to convert '{value}' using yaml rules")
    if isinstance(data_type, ListOf):
        valid = (str, data_type.item) if can_be_str else data_type.item
        msg = f"Cannot convert value '{value}' to a list of '{type_text(valid)}'"
        out = as_yaml(value, msg)
        if not isinstance(out, list):
            raise ValueError(msg)
        if not all(isinstance(x, valid) for x in out):
            raise ValueError(f"{msg}, got {out}")
        return out
    if data_type is str:
        return value
    if data_type in (int, float):
        try:
            return data_type(value)
        except ValueError:
            if can_be_str:
                return value
            raise
    if data_type is bool:
        v = "true" if value == "1" else "false" if value == "0" else value
        out = as_yaml(v, f"Failed to convert '{v}' to '{type_text(bool)}'")
        if isinstance(out, (str, bool) if can_be_str else bool):
            return out
        raise ValueError(f"Cannot convert value '{v}' to '{type_text(bool)}'")
    raise ValueError(f"data_type is invalid. Got {data_type}")


def uniform(items: list, kind) -> None:
    """``parse_if_substitutions`` of a list: its items' types do not mix; ``kind(x)``: ``str`` for
    a string item without substitutions, None for one with (no type), else the item's type.
    ValueError otherwise."""
    kinds = {k for k in map(kind, items) if k is not None}
    if len(kinds) > 1:
        raise ValueError("The result is a non-uniform list")


def normalize_scalar(value: Any, data_type) -> None:
    """``normalize_typed_substitution`` of a value without substitutions (``ParameterValue``
    is built at parse time): TypeError when it is not of the type given."""
    if isinstance(value, _SCALARS) and not is_instance_of(value, data_type):
        raise TypeError(f"value='{value}' is not an instance of {type_text(data_type)}")


def perform_typed(text: str, data_type) -> Any:
    """``perform_typed_substitution`` of a value with substitutions, once substituted
    (``coerce_to_type`` with ``can_be_str=False``): the value, or ValueError."""
    return coerce(text, data_type, can_be_str=False)


_ALLOWED = ("Allowed value types are bytes, bool, int, float, str, Sequence[bool], Sequence[int], Sequence[float], "
            "Sequence[str]. Got {} for \"{}\". If the parameter is meant to be a string, try wrapping it in "
            "launch_ros.parameter_descriptions.ParameterValue(value, value_type=str)")


def evaluate_set_parameter(name: str, text: str) -> Any:
    """launch_ros' ``evaluate_parameter_dict`` of a value given as substitutions (what
    ``<set_parameter value>`` is): the value, or TypeError with launch_ros' message."""
    if not text:
        text = "''"
    try:
        v = yamlsafe.safe_load(text)
    except yamlsafe.YamlTooBig:
        raise
    except Exception:
        raise TypeError(f"Unable to parse the value of parameter {name} as yaml. If the parameter is meant to be a "
                        "string, try wrapping it in launch_ros.parameter_descriptions.ParameterValue(value, "
                        "value_type=str)") from None
    if type(v) in (bool, int, float, str, bytes):
        return v
    if isinstance(v, list):
        if not v or type(v[0]) not in (bool, int, float, str) or not all(isinstance(x, type(v[0])) for x in v):
            raise TypeError("Expected a non-empty sequence, with items of uniform type. Allowed sequence item types "
                            f"are bool, int, float, str. Got inconsistent input for \"{name}\"")
        return v
    raise TypeError(_ALLOWED.format(type(v), name))


