"""``Node(parameters=[...])`` of a Python launch file as the walker's parameter actions:
dictionaries (nested ones flattened with ``.``, values typed as launch_ros types them) and
parameter files (a path, a substitution, ``ParameterFile(path, allow_substs=...)``)."""

from __future__ import annotations

from ..ros2 import actions as A
from ..ros2 import subst as S
from .values import LObj, PathObj, Unknown


def convert_params(conv, v, e, o) -> list:
    if v is None:
        return []
    if isinstance(v, Unknown) or not isinstance(v, (list, tuple)):
        u = v if isinstance(v, Unknown) else Unknown("parameters that are not a list", getattr(o, "where", None))
        return [A.ParamFileA(conv.value(u, e, None, "", hard=False), e, False)]
    out: list = []
    shown = []
    for item in v:
        if isinstance(item, dict):
            ps: list = []
            _dict_params(conv, item, "", e, ps, 0)
            out.append(ps)
            shown.append("{" + ", ".join(S.plain(p.name.parts) for p in ps) + "}")
        elif isinstance(item, LObj) and item.cls == "ParameterFile":
            allow = item.get("allow_substs", False)
            if not isinstance(allow, bool):
                allow = conv.value(allow, e, None, "", hard=False)
            pv = conv.value(item.get("param_file"), e, None, "", hard=False)
            out.append(A.ParamFileA(pv, e, allow))
            shown.append(S.plain(pv.parts))
        elif isinstance(item, PathObj):
            pv = conv.value(item.path, e, None, "", hard=False)
            out.append(A.ParamFileA(pv, e, False))
            shown.append(item.path)
        else:
            pv = conv.value(item, e, None, "", hard=False)
            out.append(A.ParamFileA(pv, e, False))
            shown.append(S.plain(pv.parts))
    if shown:
        conv.attr(e, o, "parameters", ", ".join(shown))
    return out


def _dict_params(conv, d: dict, prefix: str, e, out: list, depth: int) -> None:
    if depth > 20:
        return
    for k, v in d.items():
        if isinstance(k, Unknown):
            continue
        if not isinstance(k, str):
            name = conv.value(k, e, None, "", hard=False)
        else:
            name = conv.value(prefix + str(k), e, None, "", hard=False)
        if isinstance(v, dict):
            if isinstance(k, str):
                _dict_params(conv, v, prefix + str(k) + ".", e, out, depth + 1)
            continue
        val = _param_value(conv, v, e)
        typ = None
        if isinstance(val, tuple) and len(val) == 2 and val[0] == "__str__":
            typ, val = "str", val[1]
        out.append(A.ParamA(name, e, val, typ))


def _param_value(conv, v, e):
    """launch_ros' normalize + evaluate of one parameter value."""
    if isinstance(v, bool) or isinstance(v, (int, float)) and not isinstance(v, str):
        return v
    if isinstance(v, str):
        # launch_ros writes a string with yaml.dump and reads it back: it stays the string
        return ("__str__", conv.value(str(v), e, None, "", hard=False))
    if isinstance(v, LObj) and v.cls == "ParameterValue":
        inner = v.get("value")
        vt = v.get("value_type")
        if getattr(vt, "name", None) == "str" or vt is str:
            return ("__str__", conv.value(inner, e, None, "", hard=False))
        return _param_value(conv, inner, e)
    if isinstance(v, (list, tuple)):
        if not v:
            return conv.value(Unknown("an empty list parameter (launch_ros refuses it)"), e, None, "", hard=False)
        kinds = {type(x) for x in v}
        if kinds <= {int}:
            return [int(x) for x in v]
        if kinds <= {int, float} and bool not in kinds:
            return [float(x) for x in v]
        if kinds == {bool}:
            return list(v)
        if all(isinstance(x, str) and not isinstance(x, LObj) for x in v):
            return [str(x) for x in v]
        if any(isinstance(x, LObj) for x in v) and all(isinstance(x, (str, LObj)) for x in v):
            return conv.value(list(v), e, None, "", hard=False, typed=True)
        return conv.value(Unknown("a list parameter of mixed values"), e, None, "", hard=False)
    if isinstance(v, LObj):
        return conv.value(v, e, None, "", hard=False, typed=True)
    if isinstance(v, PathObj):
        return v.path
    return conv.value(v if isinstance(v, Unknown) else Unknown(f"a parameter value of type {type(v).__name__}"),
                      e, None, "", hard=False)
