"""Configurations kept in files next to the model: the configurator's own small JSON, FeatureIDE's
XML configuration format and the UVL language server's ``.uvl.json``.  Pure text in, text out:
the hosts read and write the files (inside the workspace).

=========  ==========================  ====================================================
format     file                        content
=========  ==========================  ====================================================
json       ``NAME.config.json``        ``{"model": "generic.tvl", "decisions": {"A": true,
                                       "B": false}, "selected": [...]}`` -- your decisions
                                       (what is implied is derived again when loaded)
featureide ``NAME.xml``                FeatureIDE's configuration: ``<configuration>`` with
                                       one ``<feature name manual automatic/>`` per feature
                                       (manual: your decisions; automatic: what they imply)
uvl        ``NAME.uvl.json``           uvls (the UVL language server): ``{"file":
                                       "model.uvl", "config": {"A": true, "B": false}}``
=========  ==========================  ====================================================

Loading any of them gives decisions; feature names the model does not have are reported, not
guessed.
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass, field
from typing import Iterable, Mapping, Optional, Sequence

FORMATS = ("json", "featureide", "uvl")
SUFFIX = {"json": ".config.json", "featureide": ".xml", "uvl": ".uvl.json"}
MAX_CONFIG_BYTES = 4 * 1024 * 1024
MAX_LISTED = 200


class ConfigError(ValueError):
    """The text is not a configuration this module reads (the message says why)."""


@dataclass
class Loaded:
    decisions: dict[str, bool]
    format: str
    unknown: list[str] = field(default_factory=list)     # names the model does not have
    ignored: list[str] = field(default_factory=list)     # entries that are not a selection


def file_name(name: str, fmt: str) -> str:
    """The file a configuration called ``name`` is saved to (letters, digits, ``-_.`` kept)."""
    if fmt not in FORMATS:
        raise ConfigError(f"format must be one of {', '.join(FORMATS)}")
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", name.strip()).strip("._") or "configuration"
    return stem[:80] + SUFFIX[fmt]


def format_of(path: str) -> Optional[str]:
    low = path.lower()
    if low.endswith(".uvl.json"):
        return "uvl"
    if low.endswith(".config.json"):
        return "json"
    if low.endswith(".xml"):
        return "featureide"
    if low.endswith(".json"):
        return "json"
    return None


# ------------------------------------------------------------------ writing

def render(fmt: str, model_file: str, names: Sequence[str], decisions: Mapping[str, bool],
           implied: Mapping[str, bool]) -> str:
    """The text of a configuration: ``names`` every feature in model order, ``decisions`` yours,
    ``implied`` what they imply."""
    if fmt == "json":
        selected = [n for n in names if decisions.get(n, implied.get(n, False)) is True]
        return json.dumps({"model": os.path.basename(model_file), "decisions": dict(decisions),
                           "complete": all(n in decisions or n in implied for n in names),
                           "selected": selected}, indent=2) + "\n"
    if fmt == "uvl":
        config = {n: decisions.get(n, implied.get(n)) for n in names
                  if n in decisions or n in implied}
        return json.dumps({"file": os.path.basename(model_file), "config": config}, indent=2) + "\n"
    if fmt == "featureide":
        from xml.sax.saxutils import quoteattr

        def word(v: Optional[bool]) -> str:
            return "undefined" if v is None else "selected" if v else "unselected"
        lines = ['<?xml version="1.0" encoding="UTF-8" standalone="no"?>', "<configuration>"]
        for n in names:
            lines.append(f"\t<feature automatic=\"{word(implied.get(n))}\" manual=\"{word(decisions.get(n))}\" "
                         f"name={quoteattr(n)}/>")
        lines.append("</configuration>")
        return "\n".join(lines) + "\n"
    raise ConfigError(f"format must be one of {', '.join(FORMATS)}")


# ------------------------------------------------------------------ reading

def parse(text: str, path: str, known: Mapping[str, str]) -> Loaded:
    """Decisions from a configuration file's text; ``known``: every name the model accepts
    (short and long) -> the session's name."""
    if len(text) > MAX_CONFIG_BYTES:
        raise ConfigError(f"the file has {len(text):,} characters, more than a configuration "
                          f"tvl-lsp reads ({MAX_CONFIG_BYTES:,})")
    fmt = format_of(path)
    stripped = text.lstrip()
    if fmt == "featureide" or stripped.startswith("<"):
        return _featureide(text, known)
    if fmt is None and not stripped.startswith("{"):
        return _plain(text, known)
    try:
        data = json.loads(text)
    except ValueError as e:
        raise ConfigError(f"not JSON: {e}") from None
    if not isinstance(data, dict):
        raise ConfigError("a configuration is a JSON object")
    if isinstance(data.get("config"), dict):
        return _pairs(data["config"].items(), known, "uvl")
    if isinstance(data.get("decisions"), dict):
        return _pairs(data["decisions"].items(), known, "json")
    if isinstance(data.get("selected"), list):
        sel = {str(x) for x in data["selected"]}
        return _pairs(((n, n in sel) for n in known if known[n] == n), known, "json")
    raise ConfigError('no "decisions" (tvl-lsp) or "config" (uvls) object in this JSON')


def _pairs(items: Iterable, known: Mapping[str, str], fmt: str) -> Loaded:
    out = Loaded({}, fmt)
    for k, v in items:
        k = str(k)
        if not isinstance(v, bool):
            out.ignored.append(k)
            continue
        name = known.get(k)
        if name is None:
            out.unknown.append(k)
            continue
        out.decisions[name] = v
    return out


def _featureide(text: str, known: Mapping[str, str]) -> Loaded:
    if re.search(r"<!(DOCTYPE|ENTITY)", text, re.I):
        raise ConfigError("a configuration with a DOCTYPE or entities is not read")
    from lxml import etree
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False)
    try:
        root = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError as e:
        raise ConfigError(f"not XML: {e}") from None
    if root.tag != "configuration":
        raise ConfigError(f"the root element is <{root.tag}>, not FeatureIDE's <configuration>")
    out = Loaded({}, "featureide")
    for el in root.iter("feature"):
        name = el.get("name")
        if not name:
            continue
        manual = el.get("manual")
        if manual is None and el.get("automatic") is None:
            manual = "selected"  # FeatureIDE's older format lists the selected features only
        if manual not in ("selected", "unselected"):
            continue
        got = known.get(name)
        if got is None:
            out.unknown.append(name)
            continue
        out.decisions[got] = manual == "selected"
    return out


def _plain(text: str, known: Mapping[str, str]) -> Loaded:
    """FeatureIDE's ``.config``: one selected feature per line (the others excluded)."""
    out = Loaded({}, "featureide")
    sel = set()
    for line in text.splitlines():
        n = line.strip()
        if not n or n.startswith("#"):
            continue
        got = known.get(n)
        if got is None:
            out.unknown.append(n)
        else:
            sel.add(got)
    if not sel and out.unknown:
        raise ConfigError("none of its lines names a feature of this model")
    for n in dict.fromkeys(known.values()):
        out.decisions[n] = n in sel
    return out


def is_configuration(text: str, path: str) -> bool:
    """Is this file's text a configuration this module reads (so saving over it loses nothing
    but an older configuration)?"""
    try:
        if format_of(path) == "featureide":
            return "<configuration" in text[:2000]
        data = json.loads(text)
    except ValueError:
        return False
    return isinstance(data, dict) and (isinstance(data.get("decisions"), dict) or isinstance(data.get("config"), dict))


def listed(folder: str, model_file: str) -> list[dict]:
    """Configuration files in ``folder`` (next to the model): ``{path, name, format}``, newest
    first."""
    out = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return []
    stem = os.path.basename(model_file)
    for e in entries:
        if len(out) >= MAX_LISTED:
            break
        if not e.is_file(follow_symlinks=False) or e.name == stem:
            continue
        fmt = format_of(e.name)
        if fmt is None or e.name.endswith((".launch.xml", "package.xml")) or e.name.endswith(".launch"):
            continue
        if fmt == "featureide" and not _looks_like_configuration(e.path):
            continue
        try:
            mtime = e.stat(follow_symlinks=False).st_mtime
        except OSError:
            continue
        out.append({"path": e.path, "name": e.name, "format": fmt, "mtime": mtime})
    out.sort(key=lambda x: (-x["mtime"], x["name"]))
    return out


def _looks_like_configuration(path: str) -> bool:
    from ..base.files import read_head_text
    head = read_head_text(path, 400) or ""
    return "<configuration" in head
